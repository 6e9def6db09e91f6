// A grid symmetric about y = 0 and the mirror images of its rows: a device
// that is its own mirror image in y samples the rows of the lower half and
// stores each also at its image (the compiled Delta, described devices in
// SIMD lanes).
#pragma once

#include <cstddef>
#include <optional>

#include "core/field_sampling.h"

namespace linkscape::detail {

// Rows along x, more than one of them in y, and every row's y the negative
// of its image's, bit for bit.
inline bool mirrors_in_y(const Grid& g) {
  if (g.dims[0] < 2 || g.dims[1] < 2) return false;
  const int n = g.dims[1];
  for (int j = 0; j < n; ++j)
    if (g.point(0, j, 0).y() != -g.point(0, n - 1 - j, 0).y()) return false;
  return true;
}

// A row of such a grid: rows of the upper half are left to their images
// (`sampled` false); a row of the lower half also fills its `image`, whose
// samples lie `by` after its own; a row on y = 0 has none.
struct RowImage {
  bool sampled = true;
  std::optional<GridRow> image;
  std::ptrdiff_t by = 0;
};

inline RowImage image_in_y(const Grid& g, const GridRow& row) {
  const int j = row.start[1], mirror_j = g.dims[1] - 1 - j;
  RowImage r;
  r.sampled = j <= mirror_j;
  if (j < mirror_j) {
    r.by = std::ptrdiff_t(mirror_j - j) * g.dims[0];
    GridRow image = row;
    image.start[1] = mirror_j;
    image.index += std::size_t(r.by);
    r.image = image;
  }
  return r;
}

}  // namespace linkscape::detail
