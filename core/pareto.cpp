#include "core/pareto.h"

#include <algorithm>
#include <optional>

namespace linkscape {

std::vector<bool> non_dominated(const std::vector<double>& x, const std::vector<double>& y, bool larger_y_is_better) {
  // Sorted by x (then by y, best first), a point is on the front when its y
  // beats every y before it.
  std::vector<std::size_t> order(x.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  auto better = [&](double a, double b) { return larger_y_is_better ? a > b : a < b; };
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return x[a] < x[b] || (x[a] == x[b] && better(y[a], y[b]));
  });
  std::vector<bool> front(x.size(), false);
  std::optional<double> best_y;
  std::optional<double> last_x;
  for (std::size_t k = 0; k < order.size(); ++k) {
    const std::size_t i = order[k];
    // Equal to the previous front point in both: not dominated either.
    const bool tie = k > 0 && front[order[k - 1]] && x[i] == *last_x && y[i] == *best_y;
    if (!best_y || better(y[i], *best_y) || tie) {
      front[i] = true;
      best_y = y[i];
      last_x = x[i];
    }
  }
  return front;
}

}  // namespace linkscape
