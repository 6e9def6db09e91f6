// Sizes typed as text, one reading each for the whole program:
// WIDTHxHEIGHT (images, windows, slices) and N or NXxNYxNZ (3-D grids).
// Only decimal digits and the letter x: no sign, space or unit.
#pragma once

#include <array>
#include <string>
#include <string_view>

namespace linkscape {

struct PixelLimits {
  int min_width = 1, min_height = 1;
  int max_side = 0;  // 0: none
};

// Throws std::invalid_argument "`option` expects WIDTHxHEIGHT[ from AxB to
// CxC], got 'text'" for anything else or a size outside `limits`.
std::array<int, 2> parse_width_height(std::string_view text, const std::string& option, PixelLimits limits = {});

// N (a cube) or NXxNYxNZ, each >= 2. Throws std::invalid_argument
// "`option` expects N or NXxNYxNZ (each >= 2), got 'text'".
std::array<int, 3> parse_grid_size(std::string_view text, const std::string& option);

}  // namespace linkscape
