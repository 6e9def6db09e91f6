#include "gui/figures/slice_figure.h"

#include <QFont>
#include <QImage>
#include <QFontMetricsF>
#include <QPainter>
#include <QPainterPath>
#include <vtkImageData.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <cstring>
#include <stdexcept>

#include "gui/figures/painted_file.h"
#include "gui/figures/plot_axes.h"

namespace linkscape::gui {
namespace {

const char* axis_name(Axis a) { return a == Axis::X ? "x" : a == Axis::Y ? "y" : "z"; }

QImage slice_qimage(const Field& field, const render::SliceStyle& style) {
  vtkSmartPointer<vtkImageData> rgba = render::render_slice_rgba(field, style);
  int dims[3];
  rgba->GetDimensions(dims);
  QImage image(dims[0], dims[1], QImage::Format_RGBA8888);
  const auto* src = static_cast<const unsigned char*>(rgba->GetScalarPointer());
  for (int row = 0; row < dims[1]; ++row)  // VTK row 0 is the bottom
    std::memcpy(image.scanLine(dims[1] - 1 - row), src + std::size_t(row) * dims[0] * 4, std::size_t(dims[0]) * 4);
  return image;
}

// The slice's contours and reach boundary as vector paths over the plot:
// smooth at any zoom, in PNG, SVG and PDF alike. Sample (i, j) sits at the
// centre of the image's pixel (i, j).
void draw_lines(QPainter& p, const QRectF& plot, int nu, int nv, const render::SliceLines& lines) {
  auto to_plot = [&](double u, double v) {
    return QPointF(plot.left() + (u + 0.5) / nu * plot.width(), plot.bottom() - (v + 0.5) / nv * plot.height());
  };
  auto path_of = [&](const std::vector<render::SliceSegment>& segments) {
    QPainterPath path;
    for (const render::SliceSegment& s : segments) {
      path.moveTo(to_plot(s.u0, s.v0));
      path.lineTo(to_plot(s.u1, s.v1));
    }
    return path;
  };
  p.save();
  p.setClipRect(plot);
  p.setBrush(Qt::NoBrush);
  for (const auto& [level, segments] : lines.contours) {
    p.setPen(QPen(Qt::white, 1.6, Qt::SolidLine, Qt::RoundCap, Qt::RoundJoin));
    p.drawPath(path_of(segments));
  }
  p.setPen(QPen(QColor(60, 60, 60), 2.2, Qt::SolidLine, Qt::RoundCap, Qt::RoundJoin));
  p.drawPath(path_of(lines.boundary));
  p.restore();
}

void draw(QPainter& p, const QSize& page, const Field& field, const render::SliceStyle& style, const QImage& image) {
  const Grid& g = field.grid;
  const Axis normal = render::slice_normal(g);
  const auto [u, v] = Grid::slice_axes(normal);
  const int iu = int(u), iv = int(v), in = int(normal);
  const double u0 = g.origin(iu), u1 = u0 + g.dims[iu] * g.spacing(iu);
  const double v0 = g.origin(iv), v1 = v0 + g.dims[iv] * g.spacing(iv);
  const double position = g.origin(in) + 0.5 * g.spacing(in);
  const QString unit = QString::fromStdString(field.length_unit);

  p.fillRect(QRect(QPoint(0, 0), page), Qt::white);
  p.setRenderHint(QPainter::Antialiasing);
  QFont font("DejaVu Sans");
  font.setPixelSize(std::max(11, page.height() / 55));
  p.setFont(font);
  const int fh = p.fontMetrics().height();

  // Plot area keeps the data's aspect ratio; the right margin holds the
  // colour bar and the legend's longest line ("reach boundary").
  const int left = 5 * fh, right = 12 * fh, top = 4 * fh, bottom = 4 * fh;
  const double avail_w = page.width() - left - right, avail_h = page.height() - top - bottom;
  const double aspect = (u1 - u0) / (v1 - v0);
  const double w = std::min(avail_w, avail_h * aspect), h = w / aspect;
  const QRectF plot(left + (avail_w - w) / 2, top + (avail_h - h) / 2, w, h);
  p.drawImage(plot, image);
  const render::SliceLines lines = render::slice_lines(field, style);
  draw_lines(p, plot, g.dims[iu], g.dims[iv], lines);
  p.setPen(QPen(Qt::black, 1));
  p.drawRect(plot);

  // Title: mechanism, parameters, what is shown; subtitle: how it was computed.
  // A six-DOF model has two dozen parameters: the title names the design
  // lengths, the subtitle the orientation and grip held fixed; the .vti and
  // CSV exports keep them all.
  const bool six_dof = !field.cond_orientation.empty();
  auto value = [&](const char* key) { return field.parameters.contains(key) ? field.parameters.at(key) : 0.0; };
  // PATHOS-II's design lengths where the model has them; other six-DOF
  // models (described ones) name all of their own.
  static const std::set<std::string> design = {"l0", "l2", "l3", "lp"};
  const bool pathos_design = std::any_of(design.begin(), design.end(), [&](const std::string& k) {
    return field.parameters.contains(k);
  });
  static const std::set<std::string> held = {"rx", "ry", "rz", "h0"};
  QString params;
  for (const auto& [k, val] : field.parameters) {
    if (six_dof && (pathos_design ? !design.contains(k) : held.contains(k))) continue;
    // Each parameter's own unit where the field gives it (an angle is not a
    // length), else the length unit (the compiled devices' are lengths).
    const auto own = field.parameter_units.find(k);
    const QString u = own != field.parameter_units.end() ? QString::fromStdString(own->second) : unit;
    params += QString("%1 = %2%3, ").arg(QString::fromStdString(k)).arg(val).arg(u.isEmpty() ? QString() : " " + u);
  }
  params.chop(2);
  const auto g4 = [](double v) { return QString::number(v, 'g', 4); };
  const QString grip = field.parameters.contains("h0") ? QString(", grip %1 %2").arg(g4(value("h0")), unit) : QString();
  const QString how = six_dof ? QString("IK at (rx, ry, rz) = (%1, %2, %3) deg%4")
                                    .arg(g4(value("rx")), g4(value("ry")), g4(value("rz")), grip)
                              : QString("%1 IK, branch %2").arg(QString::fromStdString(field.method)).arg(field.branch);
  QFont title_font = font;
  title_font.setBold(true);
  p.setFont(title_font);
  // A described device's title names every parameter: it shrinks to the page.
  draw_fitting(p, QRectF(0.5 * fh, 0.6 * fh, page.width() - fh, 1.5 * fh),
             QString("%1 (%2): %3 on the plane %4 = %5 %6")
                 .arg(QString::fromStdString(field.mechanism), params, QString::fromStdString(render::field_title(field, style.field)), axis_name(normal))
                 .arg(position)
                 .arg(unit));
  p.setFont(font);
  // A haptic field says how it was computed (torque rating, data source).
  const Field::NamedArray* extra = field.extra(style.field);
  draw_fitting(p, QRectF(0.5 * fh, 2.0 * fh, page.width() - fh, 1.2 * fh),
             QString("%1, %2 x %3 samples%4")
                 .arg(how)
                 .arg(g.dims[iu])
                 .arg(g.dims[iv])
                 .arg(extra ? "; " + QString::fromStdString(extra->description).section(';', 0, 0) : QString()));
  if (extra && !extra->description.empty()) {
    QFont small = font;
    small.setPixelSize(std::max(9, font.pixelSize() * 3 / 4));
    p.setFont(small);
    p.drawText(QRectF(0, page.height() - 1.3 * fh, page.width(), fh), Qt::AlignCenter,
               QString::fromStdString(extra->description).section(';', 1).trimmed());
    p.setFont(font);
  }

  // Axes with ticks in the model's unit.
  for (double t : render::nice_ticks(u0, u1, 6)) {
    const double x = plot.left() + (t - u0) / (u1 - u0) * plot.width();
    p.drawLine(QPointF(x, plot.bottom()), QPointF(x, plot.bottom() + 0.4 * fh));
    p.drawText(QRectF(x - 3 * fh, plot.bottom() + 0.5 * fh, 6 * fh, fh), Qt::AlignHCenter, QString::number(t));
  }
  for (double t : render::nice_ticks(v0, v1, 6)) {
    const double y = plot.bottom() - (t - v0) / (v1 - v0) * plot.height();
    p.drawLine(QPointF(plot.left() - 0.4 * fh, y), QPointF(plot.left(), y));
    p.drawText(QRectF(plot.left() - 4.5 * fh, y - fh / 2.0, 4 * fh, fh), Qt::AlignRight | Qt::AlignVCenter, QString::number(t));
  }
  p.drawText(QRectF(plot.left(), plot.bottom() + 1.7 * fh, plot.width(), fh), Qt::AlignHCenter,
             QString("%1 (%2)").arg(axis_name(u), unit));
  p.save();
  p.translate(plot.left() - 4 * fh, plot.center().y());
  p.rotate(-90);
  p.drawText(QRectF(-plot.height() / 2, -fh, plot.height(), fh), Qt::AlignHCenter, QString("%1 (%2)").arg(axis_name(v), unit));
  p.restore();

  // Colour bar.
  // Colour bar over the top 70 % of the plot height, legend below it.
  const QRectF bar(plot.right() + 1.5 * fh, plot.top(), 1.2 * fh, 0.7 * plot.height());
  const int steps = 256;
  for (int i = 0; i < steps; ++i) {
    const auto c = render::colour_of((i + 0.5) / steps, style.colour_map);
    const QRectF cell(bar.left(), bar.bottom() - (i + 1) * bar.height() / steps, bar.width(), bar.height() / steps + 0.5);
    p.fillRect(cell, QColor::fromRgbF(c[0], c[1], c[2]));
  }
  p.drawRect(bar);
  const bool log = render::uses_log_scale(style);
  for (double t : render::colour_bar_ticks(*style.min, *style.max, log)) {
    const double y = bar.bottom() - render::normalised_value(t, style) * bar.height();
    p.drawLine(QPointF(bar.right(), y), QPointF(bar.right() + 0.4 * fh, y));
    p.drawText(QRectF(bar.right() + 0.6 * fh, y - fh / 2.0, 4 * fh, fh), Qt::AlignLeft | Qt::AlignVCenter, QString::number(t));
  }
  // To the page's edge: haptic titles ("reflected inertia (kg)") are long.
  p.drawText(QRectF(bar.left() - fh, bar.top() - 1.5 * fh, page.width() - bar.left(), fh), Qt::AlignLeft,
             QString::fromStdString(render::field_title(field, style.field)) + (log ? " (log)" : ""));

  // Legend under the bar; line swatches sit on a mid-tone so white shows.
  double y = bar.bottom() + 2.5 * fh;
  auto legend_line = [&](const QColor& colour, int width, const QString& text) {
    p.fillRect(QRectF(bar.left(), y - 0.4 * fh, 1.5 * fh, 0.8 * fh), QColor::fromRgbF(0.13, 0.57, 0.55));
    p.setPen(QPen(colour, width));
    p.drawLine(QPointF(bar.left(), y), QPointF(bar.left() + 1.5 * fh, y));
    p.setPen(Qt::black);
    p.drawText(QRectF(bar.left() + 2 * fh, y - fh / 2.0, page.width() - bar.left() - 2 * fh, fh),
               Qt::AlignLeft | Qt::AlignVCenter, text);
    y += 1.2 * fh;
  };
  // The legend names only the lines the plot has.
  QStringList levels;
  for (const auto& [level, segments] : lines.contours)
    if (!segments.empty()) levels << QString::number(level);
  if (!levels.isEmpty()) legend_line(QColor(255, 255, 255), 3,
                QString::fromStdString(render::field_title(field, render::contour_field(style.field))) + " = " +
                    levels.join(", "));
  if (!lines.boundary.empty()) legend_line(QColor(60, 60, 60), 3, "reach boundary");
  p.fillRect(QRectF(bar.left(), y - 0.4 * fh, 1.5 * fh, 0.8 * fh), QColor::fromRgbF(0.85, 0.85, 0.85));
  p.drawText(QRectF(bar.left() + 2 * fh, y - fh / 2.0, 8 * fh, fh), Qt::AlignLeft | Qt::AlignVCenter, "unreachable");
}

}  // namespace

void write_slice_figure(const Field& field, const render::SliceStyle& style_in, const std::filesystem::path& path) {
  const render::SliceStyle style = render::resolved_style(field, style_in);
  // The image carries the colours; the lines are drawn over it as paths.
  render::SliceStyle colours_only = style;
  colours_only.contour_levels.clear();
  colours_only.draw_reach_boundary = false;
  const QImage image = slice_qimage(field, colours_only);
  write_painted(path, QSize(1400, 1050), "Linkscape slice", [&](QPainter& p, const QRectF& area) {
    draw(p, area.size().toSize(), field, style, image);
  });
}

}  // namespace linkscape::gui
