// A publication figure of a field slice: the colour-mapped image with axes in
// the model's unit, a colour bar, a legend and a title naming the mechanism
// and its parameters. Drawn with QPainter, so it needs a QGuiApplication but
// no display (the offscreen platform will do).
#pragma once

#include <filesystem>
#include <string>

#include "core/field.h"
#include "render/slice_image.h"

namespace linkscape::gui {

// Writes PNG, SVG or PDF by the extension of `path`, atomically. Throws
// std::invalid_argument for another extension or a non-slice field.
void write_slice_figure(const Field& field, const render::SliceStyle& style, const std::filesystem::path& path);

}  // namespace linkscape::gui
