#include "core/method_harness.h"

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
  auto member = [&](const MethodRow& r) {
    return r.family == family && (mechanism.empty() || r.mechanism == mechanism) && std::isfinite(r.error_median);
  };
  std::vector<std::size_t> front;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    if (!member(rows[i])) continue;
    bool dominated = false;
    for (std::size_t j = 0; j < rows.size() && !dominated; ++j) {
      if (j == i || !member(rows[j]) || rows[j].mechanism != rows[i].mechanism) continue;
      const bool no_worse = rows[j].seconds_per_evaluation <= rows[i].seconds_per_evaluation &&
                            rows[j].error_median <= rows[i].error_median;
      const bool better = rows[j].seconds_per_evaluation < rows[i].seconds_per_evaluation ||
                          rows[j].error_median < rows[i].error_median;
      dominated = no_worse && better;
    }
    if (!dominated) front.push_back(i);
  }
  std::sort(front.begin(), front.end(), [&](std::size_t a, std::size_t b) {
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
