// A plot's frame and axes for the painted charts: data coordinates mapped
// into a rectangle, a box, ticks at round numbers (render::nice_ticks) with
// their labels, and the two axis titles.
#pragma once

#include <QPointF>
#include <QRectF>
#include <QString>

class QPainter;

namespace linkscape::gui {

struct PlotFrame {
  QRectF plot;            // the drawing area, pixels
  double x0, x1, y0, y1;  // the data range shown

  QPointF at(double x, double y) const {
    return {plot.left() + (x - x0) / (x1 - x0) * plot.width(), plot.bottom() - (y - y0) / (y1 - y0) * plot.height()};
  }
};

// The box, about `ticks` round-number ticks per axis with labels, and the
// axis titles (the y title turned upright), in the painter's font.
void draw_axes(QPainter& p, const PlotFrame& frame, const QString& x_title, const QString& y_title, int ticks = 6);

// `text` centred in `box` in the painter's font (a pixel size), made smaller
// (to two thirds at most) where it is wider than the box, then elided in the
// middle: a title naming every parameter of two devices still fits.
void draw_fitting(QPainter& p, const QRectF& box, const QString& text);

}  // namespace linkscape::gui
