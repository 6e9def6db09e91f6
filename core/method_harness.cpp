#include "core/method_harness.h"

#include <map>

#include "core/pareto.h"

#include <Eigen/Eigenvalues>
#include <Eigen/SVD>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

namespace linkscape::methods {

using Eigen::Matrix3d;
using Eigen::Vector3d;

Vector3d reference_singular_values(const Matrix3d& J) {
  const Eigen::Matrix<long double, 3, 3> A = J.cast<long double>();
  const Eigen::Matrix<long double, 3, 1> s = A.jacobiSvd().singularValues();
  return s.cast<double>();
}

double condition_number_normal_equations(const Matrix3d& J) {
  const Eigen::SelfAdjointEigenSolver<Matrix3d> eig(J.transpose() * J, Eigen::EigenvaluesOnly);
  const Vector3d l = eig.eigenvalues();  // ascending
  if (!(l(0) > 0)) return std::numeric_limits<double>::infinity();
  return std::sqrt(l(2) / l(0));
}

std::vector<std::size_t> pareto_front(const std::vector<MethodRow>& rows, const std::string& family,
                                      const std::string& mechanism) {
  // Each device's methods form their own front (core/pareto.h).
  std::map<std::string, std::vector<std::size_t>> members;
  for (std::size_t i = 0; i < rows.size(); ++i)
    if (rows[i].family == family && (mechanism.empty() || rows[i].mechanism == mechanism) &&
        std::isfinite(rows[i].error_median))
      members[rows[i].mechanism].push_back(i);
  std::vector<std::size_t> front;
  for (const auto& [device, indices] : members) {
    std::vector<double> seconds, error;
    for (std::size_t i : indices) {
      seconds.push_back(rows[i].seconds_per_evaluation);
      error.push_back(rows[i].error_median);
    }
    const std::vector<bool> on_front = non_dominated(seconds, error, false);
    for (std::size_t k = 0; k < indices.size(); ++k)
      if (on_front[k]) front.push_back(indices[k]);
  }
  std::stable_sort(front.begin(), front.end(), [&](std::size_t a, std::size_t b) {
    return rows[a].seconds_per_evaluation < rows[b].seconds_per_evaluation;
  });
  return front;
}

double median_pass_seconds(int repeats, const std::function<void()>& pass) {
  using Clock = std::chrono::steady_clock;
  pass();
  std::vector<double> t;
  for (int i = 0; i < std::max(1, repeats); ++i) {
    const auto start = Clock::now();
    pass();
    t.push_back(std::chrono::duration<double>(Clock::now() - start).count());
  }
  std::sort(t.begin(), t.end());
  return t[t.size() / 2];
}

double percentile(std::vector<double> v, double fraction) {
  if (v.empty()) return std::numeric_limits<double>::quiet_NaN();
  const std::size_t k = std::min(v.size() - 1, std::size_t(fraction * double(v.size() - 1) + 0.5));
  std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(k), v.end());
  return v[k];
}

void fill_statistics(MethodRow& row, const std::vector<double>& errors) {
  row.samples = errors.size();
  row.error_median = percentile(errors, 0.5);
  row.error_p99 = percentile(errors, 0.99);
  row.error_max = errors.empty() ? std::numeric_limits<double>::quiet_NaN()
                                 : *std::max_element(errors.begin(), errors.end());
}

}  // namespace linkscape::methods
