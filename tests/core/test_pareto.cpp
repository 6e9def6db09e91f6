// One Pareto front (core/pareto.h) behind the method charts' fronts: each
// device's methods of a family, none both faster and more accurate.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "core/method_harness.h"

namespace linkscape {
namespace {

TEST(MethodPareto, EachDevicesFrontIsTheMethodsNoOtherOfItsOwnBeatsOnBoth) {
  std::mt19937 random(5);
  for (int trial = 0; trial < 30; ++trial) {
    std::vector<methods::MethodRow> rows;
    for (int i = 0; i < 30; ++i) {
      methods::MethodRow r;
      r.mechanism = i % 2 ? "delta" : "pathos2";
      r.family = i % 3 ? "ik" : "fk";
      r.seconds_per_evaluation = double(random() % 6);  // ties on purpose
      r.error_median = random() % 7 == 0 ? std::nan("") : double(random() % 6);
      rows.push_back(r);
    }
    for (const std::string mechanism : {"", "delta"}) {
      const std::vector<std::size_t> front = methods::pareto_front(rows, "ik", mechanism);
      for (std::size_t a = 0; a < rows.size(); ++a) {
        const auto& ra = rows[a];
        const bool member = ra.family == "ik" && (mechanism.empty() || ra.mechanism == mechanism) &&
                            std::isfinite(ra.error_median);
        bool dominated = false;
        for (const auto& rb : rows)
          dominated = dominated || (rb.family == "ik" && rb.mechanism == ra.mechanism && std::isfinite(rb.error_median) &&
                                    rb.seconds_per_evaluation <= ra.seconds_per_evaluation &&
                                    rb.error_median <= ra.error_median &&
                                    (rb.seconds_per_evaluation < ra.seconds_per_evaluation || rb.error_median < ra.error_median));
        const bool on_front = std::count(front.begin(), front.end(), a) > 0;
        EXPECT_EQ(on_front, member && !dominated) << "trial " << trial << " row " << a;
      }
      for (std::size_t k = 1; k < front.size(); ++k)  // drawn left to right
        EXPECT_LE(rows[front[k - 1]].seconds_per_evaluation, rows[front[k]].seconds_per_evaluation);
    }
  }
}

}  // namespace
}  // namespace linkscape
