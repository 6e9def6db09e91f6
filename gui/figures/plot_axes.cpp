#include "gui/figures/plot_axes.h"

#include <QFont>
#include <QFontMetricsF>
#include <QPainter>

#include <algorithm>

#include "render/slice_image.h"

namespace linkscape::gui {

void draw_axes(QPainter& p, const PlotFrame& f, const QString& x_title, const QString& y_title, int ticks) {
  const double fh = QFontMetricsF(p.font()).height();
  p.setPen(QPen(Qt::black, 1));
  p.drawRect(f.plot);
  for (double x : render::nice_ticks(f.x0, f.x1, ticks)) {
    const QPointF a = f.at(x, f.y0);
    p.drawLine(a, a + QPointF(0, 0.3 * fh));
    p.drawText(QRectF(a.x() - 2 * fh, a.y() + 0.4 * fh, 4 * fh, fh), Qt::AlignCenter, QString::number(x));
  }
  for (double y : render::nice_ticks(f.y0, f.y1, ticks)) {
    const QPointF a = f.at(f.x0, y);
    p.drawLine(a, a - QPointF(0.3 * fh, 0));
    p.drawText(QRectF(a.x() - 4.4 * fh, a.y() - fh / 2, 4 * fh, fh), Qt::AlignRight | Qt::AlignVCenter, QString::number(y));
  }
  p.drawText(QRectF(f.plot.left(), f.plot.bottom() + 1.5 * fh, f.plot.width(), fh), Qt::AlignCenter, x_title);
  p.save();
  p.translate(f.plot.left() - 4.2 * fh, f.plot.center().y());
  p.rotate(-90);
  p.drawText(QRectF(-f.plot.height() / 2, -fh / 2, f.plot.height(), fh), Qt::AlignCenter, y_title);
  p.restore();
}

// `text` centred in `box` in the painter's font, made smaller (to two
// thirds at most) where it is wider than the box, then elided in the middle.
void draw_fitting(QPainter& p, const QRectF& box, const QString& text) {
  const QFont original = p.font();
  QFont font = original;
  const int smallest = std::max(8, original.pixelSize() * 2 / 3);
  while (QFontMetricsF(font).horizontalAdvance(text) > box.width() && font.pixelSize() > smallest)
    font.setPixelSize(font.pixelSize() - 1);
  p.setFont(font);
  p.drawText(box, Qt::AlignCenter, QFontMetricsF(font).elidedText(text, Qt::ElideMiddle, box.width()));
  p.setFont(original);
}

}  // namespace linkscape::gui
