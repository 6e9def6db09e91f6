#include "core/size_text.h"

#include <charconv>
#include <optional>
#include <stdexcept>
#include <vector>

namespace linkscape {
namespace {

// Whole numbers separated by 'x', digits only; none on anything else.
std::optional<std::vector<int>> numbers_by_x(std::string_view text) {
  std::vector<int> out;
  for (std::size_t start = 0;;) {
    const std::size_t end = std::min(text.find('x', start), text.size());
    const std::string_view part = text.substr(start, end - start);
    int value = 0;
    if (part.empty() || part.front() < '0' || part.front() > '9') return std::nullopt;
    const auto [stop, error] = std::from_chars(part.data(), part.data() + part.size(), value);
    if (error != std::errc() || stop != part.data() + part.size()) return std::nullopt;
    out.push_back(value);
    if (end == text.size()) return out;
    start = end + 1;
  }
}

}  // namespace

std::array<int, 2> parse_width_height(std::string_view text, const std::string& option, PixelLimits limits) {
  const auto v = numbers_by_x(text);
  const bool fits = v && v->size() == 2 && (*v)[0] >= limits.min_width && (*v)[1] >= limits.min_height &&
                    (limits.max_side == 0 || ((*v)[0] <= limits.max_side && (*v)[1] <= limits.max_side));
  if (fits) return {(*v)[0], (*v)[1]};
  std::string range;
  if (limits.max_side > 0)
    range = " from " + std::to_string(limits.min_width) + "x" + std::to_string(limits.min_height) + " to " +
            std::to_string(limits.max_side) + "x" + std::to_string(limits.max_side);
  throw std::invalid_argument(option + " expects WIDTHxHEIGHT" + range + ", got '" + std::string(text) + "'");
}

std::array<int, 3> parse_grid_size(std::string_view text, const std::string& option) {
  const auto v = numbers_by_x(text);
  if (v && v->size() == 1 && v->front() >= 2) return {v->front(), v->front(), v->front()};
  if (v && v->size() == 3 && (*v)[0] >= 2 && (*v)[1] >= 2 && (*v)[2] >= 2) return {(*v)[0], (*v)[1], (*v)[2]};
  throw std::invalid_argument(option + " expects N or NXxNYxNZ (each >= 2), got '" + std::string(text) + "'");
}

}  // namespace linkscape
