// Shared pieces of the tests of the described five-bar and Stewart platform:
// the shipped files read with a JSON reader of their own (the design values
// and travels, independently of the preset loader), the device made through
// the registry, task vectors by coordinate name, and error measures.
#pragma once

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <fstream>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <numbers>
#include <sstream>
#include <stdexcept>
#include <string>

#include "core/mechanism.h"
#include "core/preset.h"

namespace linkscape::described_test {

inline std::string asset_path(const std::string& file) {
  return std::string(LINKSCAPE_TEST_ASSETS) + "/mechanisms/" + file;
}

inline nlohmann::json read_asset(const std::string& file) {
  std::ifstream in(asset_path(file));
  if (!in) throw std::runtime_error("cannot read " + asset_path(file));
  return nlohmann::json::parse(in);
}

inline std::shared_ptr<const Mechanism> load_device(const std::string& file) {
  return make_mechanism(load_preset(asset_path(file)));
}

inline int index_of_name(const std::vector<Quantity>& list, const std::string& name) {
  for (std::size_t i = 0; i < list.size(); ++i)
    if (list[i].name == name) return int(i);
  return -1;
}

inline int measure_index(const Mechanism& m, const std::string& name) {
  const auto& items = m.info().measures;
  for (std::size_t i = 0; i < items.size(); ++i)
    if (items[i].name == name) return int(i);
  return -1;
}

// Wraps an angle difference into (-pi, pi].
inline constexpr double kDeg = std::numbers::pi / 180.0;

inline double angle_difference(double a, double b) { return std::remainder(a - b, 2 * std::numbers::pi); }

// The planar triangle devices' (3-RRR, 3-RPR): the unit vector at an angle,
// and a pose (x, y, rz) as the device's task (x, y, the plane's z, rz).
inline Eigen::Vector2d unit_at(double angle) { return {std::cos(angle), std::sin(angle)}; }
inline Eigen::VectorXd planar_task(const Eigen::Vector3d& pose) {
  Eigen::VectorXd x(4);
  x << pose.x(), pose.y(), 0.0, pose.z();
  return x;
}

// 2-norm condition number from an SVD.
template <typename Matrix>
double svd_condition(const Matrix& j) {
  const Eigen::MatrixXd matrix = j;
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(matrix);
  const auto s = svd.singularValues();
  return s(0) / s(s.size() - 1);
}

// A measured number for RecordProperty, in scientific notation.
inline std::string scientific(double value) {
  std::ostringstream out;
  out.precision(3);
  out << std::scientific << value;
  return out.str();
}

// The IK status the geometry expects: unreachable where a leg cannot reach,
// out-of-limits where an actuator leaves its travel, else ok (or singular,
// skipped). Counts each and returns true where the numbers are to be compared.
struct Verdicts {
  int ok = 0, out_of_limits = 0, unreachable = 0;
  bool check(const IkResult& res, bool reaches, bool in_travel, int pose) {
    const Status expected = !reaches ? Status::Unreachable : !in_travel ? Status::OutOfLimits : Status::Ok;
    if (expected == Status::Ok && res.status == Status::Singular) return false;
    EXPECT_EQ(res.status, expected) << "pose " << pose;
    (expected == Status::Ok ? ok : expected == Status::OutOfLimits ? out_of_limits : unreachable)++;
    return expected == Status::Ok && res.status == Status::Ok;
  }
};

}  // namespace linkscape::described_test
