// Sizes typed as text (core/size_text.h): WIDTHxHEIGHT and grid resolutions,
// read one way for the slice command, the window's options and its dialog.
#include <gtest/gtest.h>

#include <stdexcept>

#include "core/size_text.h"

namespace linkscape {
namespace {

TEST(SizeText, WidthHeightReadsDigitsAndTheLetterXOnly) {
  EXPECT_EQ(parse_width_height("512x256", "--size"), (std::array<int, 2>{512, 256}));
  EXPECT_EQ(parse_width_height("1x1", "--size"), (std::array<int, 2>{1, 1}));
  for (const char* bad : {"", "x", "512", "512x", "x512", "512x256x2", " 512x256", "512x256 ", "+512x256", "-1x5",
                          "0x5", "5x0", "5X5", "5.0x5", "99999999999x5", "5xx5", "512x256junk"})
    EXPECT_THROW(parse_width_height(bad, "--size"), std::invalid_argument) << "'" << bad << "'";
}

TEST(SizeText, LimitsAreNamedInTheMessage) {
  const PixelLimits window{64, 48, 8192};
  EXPECT_EQ(parse_width_height("8192x48", "--view-size", window), (std::array<int, 2>{8192, 48}));
  try {
    parse_width_height("8193x600", "--view-size", window);
    FAIL() << "accepted a side over the limit";
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(), "--view-size expects WIDTHxHEIGHT from 64x48 to 8192x8192, got '8193x600'");
  }
  EXPECT_THROW(parse_width_height("63x600", "--view-size", window), std::invalid_argument);
  try {
    parse_width_height("12", "--size");
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(), "--size expects WIDTHxHEIGHT, got '12'");
  }
}

TEST(SizeText, GridSizeIsACubeOrThreeSidesOfAtLeastTwo) {
  EXPECT_EQ(parse_grid_size("64", "--resolution"), (std::array<int, 3>{64, 64, 64}));
  EXPECT_EQ(parse_grid_size("8x16x2", "--resolution"), (std::array<int, 3>{8, 16, 2}));
  for (const char* bad : {"", "1", "8x16", "8x16x1", "8x16x2x2", "-8", "8.5", "8x16x", "abc"})
    EXPECT_THROW(parse_grid_size(bad, "--resolution"), std::invalid_argument) << "'" << bad << "'";
}

}  // namespace
}  // namespace linkscape
