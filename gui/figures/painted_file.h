// One way to write a QPainter drawing to disk: PNG, SVG or PDF chosen by the
// file's extension, written atomically. Needs a QGuiApplication (the
// offscreen platform will do: no display).
#pragma once

#include <QRectF>
#include <QSize>
#include <QString>
#include <filesystem>
#include <functional>

class QPainter;

namespace linkscape::gui {

// Paints `draw` on a white page of `page` pixels (PDF: 96 dpi, same size in
// points * 4/3). Throws std::invalid_argument for another extension and
// std::runtime_error if the file cannot be written.
void write_painted(const std::filesystem::path& path, QSize page, const QString& title,
                   const std::function<void(QPainter&, const QRectF&)>& draw);

}  // namespace linkscape::gui
