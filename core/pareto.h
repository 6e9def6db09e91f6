// The Pareto front of points (x, y): x smaller is better, y smaller or larger
// is better. One definition for every front the program draws or marks: the
// method charts (time against error), fit's chart and sweep's table (size
// against the worst measure).
#pragma once

#include <vector>

namespace linkscape {

// Whether each point is non-dominated: no other point is no worse in both
// and better in one. Points equal in both are on the front together. The
// values are expected finite. O(n log n).
std::vector<bool> non_dominated(const std::vector<double>& x, const std::vector<double>& y, bool larger_y_is_better);

}  // namespace linkscape
