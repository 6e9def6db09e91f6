#include "gui/figures/method_chart.h"

#include <QFont>
#include <QFontMetricsF>
#include <QPainter>
#include <QPainterPath>

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <stdexcept>

#include "gui/figures/painted_file.h"
#include "gui/figures/plot_axes.h"

namespace linkscape::gui {
namespace {

// Tableau 10: distinct under common colour-vision deficiencies.
const QColor kPalette[] = {QColor(31, 119, 180), QColor(255, 127, 14), QColor(44, 160, 44),
                           QColor(214, 39, 40),  QColor(148, 103, 189), QColor(140, 86, 75),
                           QColor(227, 119, 194), QColor(127, 127, 127)};
constexpr double kErrorFloor = kExactErrorFloor;

QString superscript(int k) {
  static const QString digits[] = {"⁰", "¹", "²", "³", "⁴", "⁵", "⁶", "⁷", "⁸", "⁹"};
  QString s = k < 0 ? "⁻" : "";
  for (QChar c : QString::number(std::abs(k))) s += digits[c.digitValue()];
  return s;
}

}  // namespace

QString decade_label(int k) { return k == 0 ? "1" : k == 1 ? "10" : "10" + superscript(k); }

namespace {

QString time_label(int k) {  // 10^k seconds
  static const char* units[] = {"ns", "µs", "ms", "s"};
  if (k < -9 || k > 1) return decade_label(k) + " s";
  const int group = (k + 9) / 3, within = (k + 9) % 3;
  return QString::number(int(std::pow(10, within))) + " " + units[std::min(group, 3)];
}

// A log-log panel: maps data to pixels, draws frame, decade grid and labels.
struct LogPanel {
  QRectF plot;
  double x0, x1, y0, y1;  // log10 ranges

  QPointF at(double x, double y) const {
    const double lx = std::log10(std::max(x, 1e-300)), ly = std::log10(std::max(y, 1e-300));
    return {plot.left() + (lx - x0) / (x1 - x0) * plot.width(),
            plot.bottom() - (std::clamp(ly, y0, y1) - y0) / (y1 - y0) * plot.height()};
  }

  void draw_axes(QPainter& p, double fh, const QString& title, const QString& x_label, const QString& y_label,
                 const std::function<QString(int)>& x_tick) const {
    p.setPen(QPen(QColor(225, 225, 225), 1));
    const int xstep = (x1 - x0) > 8 ? 2 : 1, ystep = (y1 - y0) > 10 ? 2 : 1;
    for (int k = int(std::ceil(x0)); k <= int(std::floor(x1)); ++k) {
      const double x = plot.left() + (k - x0) / (x1 - x0) * plot.width();
      p.drawLine(QPointF(x, plot.top()), QPointF(x, plot.bottom()));
    }
    for (int k = int(std::ceil(y0)); k <= int(std::floor(y1)); ++k) {
      const double y = plot.bottom() - (k - y0) / (y1 - y0) * plot.height();
      p.drawLine(QPointF(plot.left(), y), QPointF(plot.right(), y));
    }
    p.setPen(QPen(Qt::black, 1));
    p.drawRect(plot);
    for (int k = int(std::ceil(x0)); k <= int(std::floor(x1)); ++k) {
      const double x = plot.left() + (k - x0) / (x1 - x0) * plot.width();
      p.drawLine(QPointF(x, plot.bottom()), QPointF(x, plot.bottom() + 0.35 * fh));
      if ((k - int(std::ceil(x0))) % xstep == 0)
        p.drawText(QRectF(x - 3 * fh, plot.bottom() + 0.4 * fh, 6 * fh, fh), Qt::AlignHCenter, x_tick(k));
    }
    for (int k = int(std::ceil(y0)); k <= int(std::floor(y1)); ++k) {
      const double y = plot.bottom() - (k - y0) / (y1 - y0) * plot.height();
      p.drawLine(QPointF(plot.left() - 0.35 * fh, y), QPointF(plot.left(), y));
      if ((k - int(std::ceil(y0))) % ystep == 0)
        p.drawText(QRectF(plot.left() - 3.6 * fh, y - fh / 2, 3.1 * fh, fh), Qt::AlignRight | Qt::AlignVCenter,
                   decade_label(k));
    }
    p.drawText(QRectF(plot.left(), plot.bottom() + 1.4 * fh, plot.width(), fh), Qt::AlignHCenter, x_label);
    p.save();
    p.translate(plot.left() - 3.9 * fh, plot.center().y());
    p.rotate(-90);
    p.drawText(QRectF(-plot.height() / 2, -fh, plot.height(), fh), Qt::AlignHCenter, y_label);
    p.restore();
    QFont bold = p.font();
    bold.setBold(true);
    p.save();
    p.setFont(bold);
    p.drawText(QRectF(plot.left(), plot.top() - 1.3 * fh, plot.width(), fh), Qt::AlignLeft, title);
    p.restore();
  }
};

void draw_marker(QPainter& p, QPointF c, int shape, double r, const QColor& colour) {
  p.setPen(QPen(colour.darker(130), 1.2));
  p.setBrush(colour);
  switch (shape % 5) {
    case 0: p.drawEllipse(c, r, r); break;
    case 1: p.drawRect(QRectF(c.x() - r, c.y() - r, 2 * r, 2 * r)); break;
    case 2: p.drawPolygon(QPolygonF({c + QPointF(0, -1.2 * r), c + QPointF(1.1 * r, 0.8 * r), c + QPointF(-1.1 * r, 0.8 * r)})); break;
    case 3: p.drawPolygon(QPolygonF({c + QPointF(0, -1.3 * r), c + QPointF(1.2 * r, 0), c + QPointF(0, 1.3 * r), c + QPointF(-1.2 * r, 0)})); break;
    default: p.drawPolygon(QPolygonF({c + QPointF(0, 1.2 * r), c + QPointF(1.1 * r, -0.8 * r), c + QPointF(-1.1 * r, -0.8 * r)})); break;
  }
  p.setBrush(Qt::NoBrush);
}

struct LegendEntry {
  QString text;
  QColor colour;
  int shape = 0;       // marker shape, or -1 for a line
  Qt::PenStyle line = Qt::NoPen;
};

void draw_legend(QPainter& p, QPointF top_left, double fh, const std::vector<LegendEntry>& entries) {
  double width = 0;
  const QFontMetricsF fm(p.font());
  for (const auto& e : entries) width = std::max(width, fm.horizontalAdvance(e.text));
  const QRectF box(top_left, QSizeF(width + 3.2 * fh, entries.size() * 1.15 * fh + 0.5 * fh));
  p.setPen(QPen(QColor(160, 160, 160), 1));
  p.setBrush(QColor(255, 255, 255, 230));
  p.drawRect(box);
  p.setBrush(Qt::NoBrush);
  double y = box.top() + 0.25 * fh + 0.575 * fh;
  for (const auto& e : entries) {
    const QPointF swatch(box.left() + 1.2 * fh, y);
    if (e.line != Qt::NoPen) {
      p.setPen(QPen(e.colour, 2, e.line));
      p.drawLine(swatch - QPointF(0.8 * fh, 0), swatch + QPointF(0.8 * fh, 0));
    }
    if (e.shape >= 0) draw_marker(p, swatch, e.shape, 0.32 * fh, e.colour);
    p.setPen(Qt::black);
    p.drawText(QRectF(box.left() + 2.4 * fh, y - fh / 2, width + fh, fh), Qt::AlignLeft | Qt::AlignVCenter, e.text);
    y += 1.15 * fh;
  }
}

double font_height(QPainter& p, const QRectF& area) {
  QFont font("DejaVu Sans");
  font.setPixelSize(int(std::clamp(std::min(area.width(), area.height()) / 60.0, 9.0, 20.0)));
  p.setFont(font);
  return QFontMetricsF(font).height();
}

QString family_title(const std::string& f, const std::string& unit, const std::string& mechanism,
                     bool label_mechanism) {
  if (!label_mechanism) return method_family_title(f, unit);
  // Two mechanisms: four narrow columns, short titles.
  QString t;
  if (f == "ik") t = "IK: " + method_error_label(f, unit);
  else if (f == "leg-ik") t = "leg IK: " + method_error_label(f, unit);
  else if (f == "fk") t = "FK: " + (unit == "pose" ? QString("pose error") : method_error_label(f, unit));
  else if (f == "jacobian") t = "Jacobian: |J - J*| / |J*|";
  else if (f == "conditioning") t = "conditioning: |c - c*| / c*";
  else t = "fields: volume, extents";
  return QString::fromStdString(mechanism) + " " + t;
}

// (mechanism, family) panels in the order the rows first name them.
std::vector<std::pair<std::string, std::string>> panels_of(const std::vector<methods::MethodRow>& rows) {
  std::vector<std::pair<std::string, std::string>> out;
  for (const auto& r : rows)
    if (std::find(out.begin(), out.end(), std::make_pair(r.mechanism, r.family)) == out.end())
      out.emplace_back(r.mechanism, r.family);
  return out;
}

void draw_family(QPainter& p, const QRectF& cell, double fh, const std::vector<methods::MethodRow>& all,
                 const std::string& mechanism, const std::string& family, bool label_mechanism) {
  std::vector<std::size_t> idx;
  for (std::size_t i = 0; i < all.size(); ++i)
    if (all[i].family == family && all[i].mechanism == mechanism) idx.push_back(i);
  if (idx.empty()) return;
  double tmin = 1e300, tmax = 0, emin = 1e300, emax = 0;
  for (std::size_t i : idx) {
    const auto& r = all[i];
    tmin = std::min(tmin, r.seconds_per_evaluation);
    tmax = std::max(tmax, r.seconds_per_evaluation);
    for (double e : {r.error_median, r.error_p99})
      if (std::isfinite(e)) {
        emin = std::min(emin, std::max(e, kErrorFloor));
        emax = std::max(emax, std::max(e, kErrorFloor));
      }
  }
  const bool field = family == "field";
  // Methods in table order, one colour and marker each.
  std::map<std::string, int> colour_of;
  std::vector<LegendEntry> legend;
  for (std::size_t i : idx) {
    if (colour_of.count(all[i].method)) continue;
    const int k = int(colour_of.size());
    colour_of[all[i].method] = k;
    QString text = QString::fromStdString(all[i].method);
    if (!field && !all[i].parameter.empty()) text += " (" + QString::fromStdString(all[i].parameter) + ")";
    if (!field && all[i].failures > 0)
      text += QString(", %1 % not ok").arg(100.0 * all[i].failures / double(all[i].failures + all[i].samples), 0, 'f', 1);
    legend.push_back({text, kPalette[k % 8], k, field ? Qt::SolidLine : Qt::NoPen});
  }
  legend.push_back({"Pareto front (ringed)", QColor(60, 60, 60), -1, Qt::DashLine});
  if (!field) legend.push_back({"whisker: 99th percentile", QColor(90, 90, 90), -1, Qt::SolidLine});
  LogPanel panel;
  panel.plot = QRectF(cell.left() + 4.6 * fh, cell.top() + 1.8 * fh, cell.width() - 6.8 * fh, cell.height() - 4.8 * fh);
  panel.x0 = std::floor(std::log10(tmin) - 0.3);
  panel.x1 = std::ceil(std::log10(tmax) + 0.3);
  panel.y0 = std::floor(std::log10(emin) - 0.5);
  // Room above the data for the legend: it takes the top fraction f of the plot.
  const double f = std::min(0.6, (legend.size() * 1.15 * fh + 1.4 * fh) / panel.plot.height());
  const double top = std::log10(emax) + 0.3;
  panel.y1 = std::ceil((top - f * panel.y0) / (1 - f));
  const std::string& unit = all[idx.front()].error_unit;  // one unit a panel: one device's family
  panel.draw_axes(p, fh, family_title(family, unit, mechanism, label_mechanism),
                  field ? "time per field, all threads" : "time per evaluation, one thread",
                  method_error_label(family, unit),
                  time_label);
  p.save();
  p.setClipRect(panel.plot.adjusted(-fh, -fh, fh, fh));

  // Pareto front first, underneath the markers.
  const std::vector<std::size_t> front = methods::pareto_front(all, family, mechanism);
  if (front.size() >= 1) {
    QPainterPath stairs;
    for (std::size_t k = 0; k < front.size(); ++k) {
      const QPointF c = panel.at(all[front[k]].seconds_per_evaluation, std::max(all[front[k]].error_median, kErrorFloor));
      if (k == 0) stairs.moveTo(c);
      else stairs.lineTo(QPointF(c.x(), stairs.currentPosition().y())), stairs.lineTo(c);
    }
    stairs.lineTo(QPointF(panel.plot.right(), stairs.currentPosition().y()));
    p.setPen(QPen(QColor(60, 60, 60), 1.5, Qt::DashLine));
    p.drawPath(stairs);
  }
  const double r = 0.38 * fh;
  if (field) {
    for (const auto& [name, k] : colour_of) {
      QPolygonF line;
      for (std::size_t i : idx)
        if (all[i].method == name) line << panel.at(all[i].seconds_per_evaluation, std::max(all[i].error_median, kErrorFloor));
      p.setPen(QPen(kPalette[k % 8], 1.8));
      p.drawPolyline(line);
    }
  }
  for (std::size_t i : idx) {
    const auto& row = all[i];
    const int k = colour_of[row.method];
    const QPointF c = panel.at(row.seconds_per_evaluation, std::max(row.error_median, kErrorFloor));
    if (!field && std::isfinite(row.error_p99) && row.error_p99 > row.error_median) {
      const QPointF top = panel.at(row.seconds_per_evaluation, row.error_p99);
      p.setPen(QPen(kPalette[k % 8], 1.3));
      p.drawLine(c, top);
      p.drawLine(top - QPointF(0.3 * fh, 0), top + QPointF(0.3 * fh, 0));
    }
    draw_marker(p, c, k, r, kPalette[k % 8]);
    if (field) {
      p.setPen(QColor(70, 70, 70));
      p.drawText(QRectF(c.x() + 0.6 * fh, c.y() - 0.5 * fh, 4 * fh, fh), Qt::AlignLeft | Qt::AlignVCenter,
                 QString::fromStdString(row.parameter));
    }
  }
  for (std::size_t i : front) {
    const QPointF c = panel.at(all[i].seconds_per_evaluation, std::max(all[i].error_median, kErrorFloor));
    p.setPen(QPen(Qt::black, 1.4));
    p.drawEllipse(c, 2.0 * r, 2.0 * r);
  }
  p.restore();
  // Legend in the band kept free above the data.
  draw_legend(p, QPointF(panel.plot.left() + 0.4 * fh, panel.plot.top() + 0.4 * fh), fh, legend);
}

// White page, bold title and a one-line subtitle; returns the font height.
double draw_header(QPainter& p, const QRectF& area, const QString& title, const QString& subtitle) {
  p.fillRect(area, Qt::white);
  const double fh = font_height(p, area);
  QFont font = p.font();
  font.setBold(true);
  p.setFont(font);
  p.setPen(Qt::black);
  draw_fitting(p, QRectF(area.left() + 0.5 * fh, area.top() + 0.4 * fh, area.width() - fh, 1.2 * fh), title);
  font.setBold(false);
  p.setFont(font);
  draw_fitting(p, QRectF(area.left() + 0.5 * fh, area.top() + 1.6 * fh, area.width() - fh, 1.2 * fh), subtitle);
  return fh;
}

}  // namespace

QString method_family_title(const std::string& f, const std::string& unit) {
  if (f == "ik") return "Inverse kinematics: " + method_error_label(f, unit);
  if (f == "leg-ik") return "Leg IK: " + method_error_label(f, unit);
  if (f == "fk") return "Forward kinematics: " + (unit == "pose" ? QString("pose error") : method_error_label(f, unit));
  if (f == "jacobian") return "Jacobian: |J - J*| / |J*|";
  if (f == "conditioning") return "Condition numbers: |c - c*| / c*";
  return "Workspace fields: volume and extent errors";
}

QColor method_colour(int k) { return kPalette[k % 8]; }

QString method_error_label(const std::string& family, const std::string& unit) {
  const QString u = QString::fromStdString(unit);
  if (family == "ik" || family == "leg-ik") return "joint error (" + u + ")";
  if (family == "fk" && unit == "pose") return "max(|dp| / size, angle)";
  // The default harness: the actuator values FK's pose gives back (docs/methods.md).
  if (family == "fk" && unit != "relative") return "joint error of q back (" + u + ")";
  if (family == "fk") return "|dp| / size";
  return "relative error";
}

void draw_method_chart(QPainter& p, const QRectF& area, const std::vector<methods::MethodRow>& rows,
                       const QString& title) {
  p.save();
  const double fh = draw_header(p, area, title,
                                "error (log) against time (log): markers at the median error, lower-left is better");
  const QRectF body = area.adjusted(0.5 * fh, 3.2 * fh, -0.5 * fh, -0.3 * fh);
  const auto panels = panels_of(rows);
  bool several = false;
  for (const auto& pf : panels) several |= pf.first != panels.front().first;
  // Up to four panels 2 x 2; more (two mechanisms): four columns.
  const int columns = panels.size() <= 4 ? 2 : 4;
  const int lines = std::max<int>(1, int((panels.size() + columns - 1) / columns));
  QFont small = p.font();
  if (columns > 2) {
    small.setPixelSize(std::max(9, int(small.pixelSize() * 0.72)));
    p.setFont(small);
  }
  const double cell_fh = QFontMetricsF(p.font()).height();
  for (std::size_t k = 0; k < panels.size(); ++k) {
    const QRectF cell(body.left() + double(k % columns) * body.width() / columns,
                      body.top() + double(k / columns) * body.height() / lines, body.width() / columns,
                      body.height() / lines);
    draw_family(p, cell, cell_fh, rows, panels[k].first, panels[k].second, several);
  }
  p.restore();
}

void draw_sweep_chart(QPainter& p, const QRectF& area, const std::vector<stability::SweepRow>& rows,
                      const QString& title) {
  p.save();
  const double fh = draw_header(p, area, title,
                                "IK joint error (worst of the base points) against distance eps to each singular set; "
                                "crosses on the top band: not ok");
  const QRectF body = area.adjusted(0.5 * fh, 3.2 * fh, -0.5 * fh, -0.3 * fh);
  // Panels: (mechanism, path) in the order the rows name them.
  std::vector<std::pair<std::string, std::string>> panels;
  for (const auto& r : rows)
    if (std::find(panels.begin(), panels.end(), std::make_pair(r.mechanism, stability::path_label(r))) == panels.end())
      panels.emplace_back(r.mechanism, stability::path_label(r));
  const int columns = panels.size() <= 6 ? 3 : 4;
  const int lines = std::max<int>(1, int((panels.size() + columns - 1) / columns));
  if (columns > 3) {
    QFont small = p.font();
    small.setPixelSize(std::max(9, int(small.pixelSize() * 0.8)));
    p.setFont(small);
  }
  const double pfh = QFontMetricsF(p.font()).height();
  std::string legend_done;
  for (std::size_t panel_index = 0; panel_index < panels.size(); ++panel_index) {
    const auto& [mechanism, path] = panels[panel_index];
    const QRectF cell(body.left() + double(panel_index % columns) * body.width() / columns,
                      body.top() + double(panel_index / columns) * body.height() / lines, body.width() / columns,
                      body.height() / lines);
    auto in_panel = [&](const stability::SweepRow& r) {
      return r.mechanism == mechanism && stability::path_label(r) == path && (r.family == "ik" || r.family == "fk");
    };
    const stability::SweepRow& first = *std::find_if(rows.begin(), rows.end(), in_panel);
    std::vector<std::string> ik_methods;
    for (const auto& r : rows)
      if (in_panel(r) && std::find(ik_methods.begin(), ik_methods.end(), r.method) == ik_methods.end())
        ik_methods.push_back(r.method);
    const bool fk = std::any_of(rows.begin(), rows.end(), [&](const auto& r) { return in_panel(r) && r.family == "fk"; });
    LogPanel panel;
    panel.plot = QRectF(cell.left() + 4.6 * pfh, cell.top() + 1.8 * pfh, cell.width() - 6.2 * pfh,
                        cell.height() - 4.8 * pfh);
    panel.x0 = -12.3;
    panel.x1 = -0.7;
    panel.y0 = -18;
    panel.y1 = 0;
    // What eps means on this panel's path: an angle (joint paths), a
    // fraction of the way to the set (pose paths, FK rows), else a distance
    // relative to the device's size; devices' own sweeps give a residual.
    const bool own = !first.path_name.empty();
    const bool joint = !own && stability::is_joint_path(first.path);
    const bool pose = !own && fk;
    const QString name = QString::fromStdString(mechanism + " " + path);
    panel.draw_axes(p, pfh, name + (joint ? " (joint path)" : pose ? " (pose path)" : " (Cartesian path)"),
                    joint ? "eps: angle from the set (rad)" : pose ? "eps: s = s* (1 - eps)" : "eps: distance / size",
                    fk ? "FK pose error" : own ? "residual / size" : "joint error (rad)",
                    [](int k) { return decade_label(k); });
    // "not ok" band at the top.
    const double band = panel.plot.top() + 0.55 * pfh;
    p.setPen(QColor(120, 120, 120));
    p.drawText(QRectF(panel.plot.right() - 4.2 * pfh, panel.plot.top() + 1.0 * pfh, 4 * pfh, pfh), Qt::AlignRight,
               "not ok");
    p.setPen(QPen(QColor(200, 200, 200), 1, Qt::DotLine));
    p.drawLine(QPointF(panel.plot.left(), band + 0.6 * pfh), QPointF(panel.plot.right(), band + 0.6 * pfh));

    // Prediction, worst over base points per eps.
    std::map<double, double> predicted;
    for (const auto& r : rows)
      if (in_panel(r) && r.method == ik_methods.front() && std::isfinite(r.predicted) && r.status != Status::Singular)
        predicted[r.eps] = std::max(predicted[r.eps], r.predicted);
    QPolygonF pred_line;
    for (const auto& [eps, v] : predicted) pred_line << panel.at(eps, v);
    p.setPen(QPen(Qt::black, 1.6, Qt::DashLine));
    p.drawPolyline(pred_line);

    const double centre = 0.5 * double(ik_methods.size() - 1);
    for (std::size_t k = 0; k < ik_methods.size(); ++k) {
      std::map<double, std::pair<double, int>> worst;  // eps -> (worst ok error, not-ok count)
      for (const auto& r : rows) {
        if (!in_panel(r) || r.method != ik_methods[k]) continue;
        auto& w = worst[r.eps];
        if (r.status == Status::Ok && std::isfinite(r.error)) w.first = std::max(w.first, std::max(r.error, kErrorFloor));
        else ++w.second;
      }
      QPolygonF line;
      const QColor colour = kPalette[k % 8];
      const double jitter = (double(k) - centre) * 0.12 * pfh;  // keeps overlapping markers apart
      auto flush = [&] {
        p.setPen(QPen(colour, 1.6));
        p.drawPolyline(line);
        line.clear();
      };
      for (const auto& [eps, w] : worst) {
        if (w.first > 0) {
          line << panel.at(eps, w.first) + QPointF(jitter, 0);
        } else {
          flush();
        }
      }
      flush();
      for (const auto& [eps, w] : worst) {
        if (w.first > 0) draw_marker(p, panel.at(eps, w.first) + QPointF(jitter, 0), int(k), 0.26 * pfh, colour);
        if (w.second > 0) {
          const QPointF c(panel.at(eps, 1).x() + jitter, band + 0.2 * pfh * (double(k) - centre));
          p.setPen(QPen(colour, 1.6));
          p.drawLine(c + QPointF(-0.25 * pfh, -0.25 * pfh), c + QPointF(0.25 * pfh, 0.25 * pfh));
          p.drawLine(c + QPointF(-0.25 * pfh, 0.25 * pfh), c + QPointF(0.25 * pfh, -0.25 * pfh));
        }
      }
    }
    // One legend per mechanism and kind of method (IK or FK), in its first panel.
    const std::string legend_key = "|" + mechanism + (fk ? "/fk" : "/ik") + "|";
    if (legend_done.find(legend_key) == std::string::npos) {
      legend_done += legend_key;
      std::vector<LegendEntry> legend;
      for (std::size_t k = 0; k < ik_methods.size(); ++k) {
        const std::string& mname = ik_methods[k];
        const QString text = mname == "newton-near"    ? "newton, seed 1e-3 rad off"
                             : mname == "numeric-near" ? "numeric, seed 1e-3 off"
                             : mname == "numeric"      ? "numeric, home seed"
                                                       : QString::fromStdString(mname);
        legend.push_back({text, kPalette[k % 8], int(k), Qt::SolidLine});
      }
      legend.push_back({fk ? "prediction u B |J| (pose)" : "prediction u B / sigma_min", Qt::black, -1, Qt::DashLine});
      // Bottom left: near the actuator plane nothing is ok at small eps.
      const double height = legend.size() * 1.15 * pfh + 0.5 * pfh;
      draw_legend(p, QPointF(panel.plot.left() + 0.4 * pfh, panel.plot.bottom() - height - 0.4 * pfh), pfh, legend);
    }
  }
  p.restore();
}

void write_method_chart(const std::vector<methods::MethodRow>& rows, const QString& title,
                        const std::filesystem::path& path) {
  write_painted(path, QSize(1600, 1200), "Linkscape methods",
                [&](QPainter& p, const QRectF& area) { draw_method_chart(p, area, rows, title); });
}

void write_sweep_chart(const std::vector<stability::SweepRow>& rows, const QString& title,
                       const std::filesystem::path& path) {
  write_painted(path, QSize(1800, 1100), "Linkscape stability sweeps",
                [&](QPainter& p, const QRectF& area) { draw_sweep_chart(p, area, rows, title); });
}

}  // namespace linkscape::gui
