#include "gui/figures/fit_report.h"

#include <QFontMetricsF>
#include <QPainter>
#include <QPainterPath>
#include <algorithm>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "core/atomic_file.h"
#include "core/csv.h"
#include "core/pareto.h"
#include "core/sweep.h"
#include "gui/figures/painted_file.h"
#include "render/slice_image.h"

namespace linkscape::gui {
namespace {



// 3 significant digits for the report.
std::string short_number(double v) {
  if (!std::isfinite(v)) return std::isinf(v) ? (v > 0 ? "inf" : "-inf") : "?";
  std::ostringstream s;
  s << std::setprecision(4) << v + 0.0;  // + 0.0: no "-0"
  return s.str();
}

// A point as evaluated (shortest round-trip numbers): typed back, the same point.
std::string exact_point_text(const Eigen::Vector3d& p, const std::string& unit) {
  std::string s = "(";
  s += format_number(p.x() + 0.0) + ", " + format_number(p.y() + 0.0) + ", " + format_number(p.z() + 0.0) + ") " + unit;
  return s;
}

std::string point_text(const Eigen::Vector3d& p, const std::string& unit) {
  std::string s = "(";  // appended: GCC 12 warns (-Wrestrict) on "literal" + temporary here, wrongly
  s += short_number(p.x()) + ", " + short_number(p.y()) + ", " + short_number(p.z()) + ") " + unit;
  return s;
}


// The best or closest row first, then every valid design by size.
std::vector<std::size_t> csv_order(const fit::Result& r) {
  std::vector<std::size_t> rest;
  const std::optional<std::size_t> first = r.best ? r.best : r.closest;
  for (std::size_t i = 0; i < r.rows.size(); ++i)
    if (r.rows[i].invalid.empty() && i != first) rest.push_back(i);
  std::stable_sort(rest.begin(), rest.end(), [&](std::size_t a, std::size_t b) { return r.rows[a].size < r.rows[b].size; });
  if (first) rest.insert(rest.begin(), *first);
  return rest;
}

std::string rows_csv(const fit::Problem& p, const fit::Result& r, const std::vector<std::string>& columns) {
  std::ostringstream s;
  for (const std::string& c : columns) s << csv_text(c) << ",";
  s << fit::score_header(p) << "\n";
  for (std::size_t i : csv_order(r)) {
    const fit::Row& row = r.rows[i];
    for (const std::string& c : columns) s << csv_number(row.parameters.at(c)) << ",";
    s << fit::score_cells(p, row) << "\n";
  }
  return s.str();
}

// ---- The Pareto chart ----------------------------------------------------------------

// Size against the worst value of the first criterion on a measure (the
// fit where there is none): every design, meeting ones filled, the
// non-dominated ones joined, the chosen one ringed, the bound dashed.
void draw_pareto(QPainter& p, const QRectF& area, const fit::Problem& problem, const fit::Result& r,
                 const std::string& length_unit, const std::string& size_description, const QString& title) {
  // At a given size every design has it: the first free variable tells them apart.
  const bool at_size = problem.size.has_value();
  auto x_of = [&](const fit::Row& row) { return at_size ? row.values[0] : row.size; };
  const auto measured = std::find_if(problem.criteria.begin(), problem.criteria.end(),
                                     [](const task::Criterion& c) { return !c.reach(); });
  const std::size_t ci = std::size_t(measured - problem.criteria.begin());
  // At a given size the search maximises the ratio: it is what is drawn.
  const bool use_fit = at_size || measured == problem.criteria.end();
  const bool above = use_fit || measured->above;  // larger is better
  const bool log = !use_fit && !measured->above;  // conditioning, resolution, inertia span decades
  auto y_of = [&](const fit::Row& row) { return use_fit ? row.ratio : row.report.criteria[ci].worst; };
  struct Point {
    double x, y;
    bool meets;
    std::size_t row;
  };
  std::vector<Point> pts;
  for (std::size_t i = 0; i < r.rows.size(); ++i) {
    const fit::Row& row = r.rows[i];
    if (!row.invalid.empty()) continue;  // a design that could not be built has no criteria
    const double y = y_of(row);
    if (std::isfinite(y) && (!log || y > 0)) pts.push_back({x_of(row), y, row.meets, i});
  }
  QFont font("DejaVu Sans");
  font.setPixelSize(std::max(10, int(area.height() / 45)));  // readable in a dock too
  p.setFont(font);
  const double fh = QFontMetricsF(font).height();
  p.fillRect(area, Qt::white);
  QFont bold = font;
  bold.setBold(true);
  p.setFont(bold);
  p.drawText(QRectF(area.left(), area.top() + 0.5 * fh, area.width(), 1.4 * fh), Qt::AlignCenter,
             QFontMetricsF(bold).elidedText(title, Qt::ElideRight, area.width() - 2 * fh));  // a dock may be narrow
  p.setFont(font);
  const QRectF plot(area.left() + 8.5 * fh, area.top() + 3.5 * fh, area.width() - 11.5 * fh, area.height() - 8 * fh);
  double x0 = INFINITY, x1 = -INFINITY, y0 = INFINITY, y1 = -INFINITY;
  for (const Point& q : pts) x0 = std::min(x0, q.x), x1 = std::max(x1, q.x), y0 = std::min(y0, q.y), y1 = std::max(y1, q.y);
  const double bound = use_fit ? 1.0 : measured->threshold;  // a ratio of 1 is on the bound
  y0 = std::min(y0, bound), y1 = std::max(y1, bound);
  if (pts.empty()) x0 = 0, x1 = 1, y0 = log ? 1 : 0, y1 = log ? 10 : 1;
  if (x1 <= x0) x0 -= 1, x1 += 1;
  auto ty = [&](double y) { return log ? std::log10(y) : y; };
  double ly0 = ty(y0), ly1 = ty(y1);
  if (ly1 <= ly0) ly0 -= 0.5, ly1 += 0.5;
  const double pad_x = 0.05 * (x1 - x0), pad_y = 0.08 * (ly1 - ly0);
  x0 -= pad_x, x1 += pad_x, ly0 -= pad_y, ly1 += pad_y;
  auto at = [&](double x, double y) {
    return QPointF(plot.left() + (x - x0) / (x1 - x0) * plot.width(), plot.bottom() - (ty(y) - ly0) / (ly1 - ly0) * plot.height());
  };
  p.setPen(QPen(Qt::black, 1));
  p.drawRect(plot);
  // Ticks at round numbers (render::nice_ticks); on a log axis the decades'
  // 1, 2, 5 (or every digit over less than a decade).
  for (double x : render::nice_ticks(x0, x1, 5)) {
    const QPointF a(plot.left() + (x - x0) / (x1 - x0) * plot.width(), plot.bottom());
    p.drawLine(a, a + QPointF(0, 0.3 * fh));
    p.drawText(QRectF(a.x() - 3 * fh, a.y() + 0.4 * fh, 6 * fh, fh), Qt::AlignCenter, QString::fromStdString(short_number(x)));
  }
  std::vector<double> yticks;
  if (log) {
    const bool digits = ly1 - ly0 < 1.2;
    for (int d = int(std::floor(ly0)); d <= int(std::ceil(ly1)); ++d)
      for (double m = 1; m < 10; ++m)
        if (const double v = m * std::pow(10.0, d); (digits || m == 1 || m == 2 || m == 5) && ty(v) >= ly0 && ty(v) <= ly1)
          yticks.push_back(v);
  } else {
    yticks = render::nice_ticks(ly0, ly1, 5);
  }
  for (double v : yticks) {
    const QPointF a = at(x0, v);
    p.drawLine(a, a - QPointF(0.3 * fh, 0));
    p.drawText(QRectF(a.x() - 6.4 * fh, a.y() - fh / 2, 6 * fh, fh), Qt::AlignRight | Qt::AlignVCenter,
               QString::fromStdString(short_number(v)));
  }
  p.drawText(QRectF(plot.left(), plot.bottom() + 1.6 * fh, plot.width(), fh), Qt::AlignCenter,
             QString::fromStdString(at_size ? problem.variables[0].name() + " (" + length_unit + "), designs of size " +
                                                  size_description + " = " + short_number(*problem.size)
                                            : "size " + size_description + " (" + length_unit + ")"));
  p.save();
  p.translate(area.left() + 1.2 * fh, plot.center().y());
  p.rotate(-90);
  const std::string ylabel = use_fit ? std::string(problem.task.centre ? "ratio (bound / worst)"
                                                                       : "ratio (largest shape / task)")
                                     : "worst " + measured->measure + " over the task" +
                                           (task::criterion_unit(*measured, length_unit).empty() ? "" : " (" + task::criterion_unit(*measured, length_unit) + ")");
  p.drawText(QRectF(-plot.height() / 2, -fh / 2, plot.height(), fh), Qt::AlignCenter, QString::fromStdString(ylabel));
  p.restore();
  p.setClipRect(plot);
  // The bound.
  p.setPen(QPen(QColor(200, 60, 60), 1.5, Qt::DashLine));
  p.drawLine(at(x0, bound), at(x1, bound));
  // The non-dominated designs: none both smaller and better.
  std::vector<Point> front;
  if (!at_size) {
    std::vector<double> xs, ys;
    for (const Point& q : pts) xs.push_back(q.x), ys.push_back(q.y);
    const std::vector<bool> on_front = non_dominated(xs, ys, above);
    for (std::size_t i = 0; i < pts.size(); ++i)
      if (on_front[i]) front.push_back(pts[i]);
  }
  std::sort(front.begin(), front.end(), [](const Point& a, const Point& b) { return a.x < b.x; });
  if (front.size() > 1) {
    QPainterPath path(at(front.front().x, front.front().y));
    for (std::size_t i = 1; i < front.size(); ++i) {
      path.lineTo(at(front[i].x, front[i - 1].y));
      path.lineTo(at(front[i].x, front[i].y));
    }
    p.setPen(QPen(QColor(90, 90, 90), 1.2, Qt::DashLine));
    p.setBrush(Qt::NoBrush);
    p.drawPath(path);
  }
  const QColor meets(44, 160, 44), fails(150, 150, 150);
  for (const Point& q : pts) {
    p.setPen(QPen(q.meets ? meets.darker() : fails, 1.2));
    p.setBrush(q.meets ? QBrush(meets) : Qt::NoBrush);
    p.drawEllipse(at(q.x, q.y), 0.25 * fh, 0.25 * fh);
  }
  const std::optional<std::size_t> chosen = r.best ? r.best : r.closest;
  for (const Point& q : pts)
    if (chosen && q.row == *chosen) {
      p.setPen(QPen(QColor(214, 39, 40), 2.5));
      p.setBrush(Qt::NoBrush);
      p.drawEllipse(at(q.x, q.y), 0.6 * fh, 0.6 * fh);
    }
  p.setClipping(false);
  // Legend: in the plot's corner that covers the fewest designs, on a light backing.
  const int entries = at_size ? 4 : 5;
  const QSizeF legend_size(15.8 * fh, (entries * 1.3 + 0.1) * fh);
  QRectF legend;
  int covered = std::numeric_limits<int>::max();
  for (const QPointF& corner : {QPointF(plot.right() - 0.1 * fh - legend_size.width(), plot.top() + 0.1 * fh),
                                QPointF(plot.left() + 0.1 * fh, plot.top() + 0.1 * fh),
                                QPointF(plot.right() - 0.1 * fh - legend_size.width(), plot.bottom() - 0.1 * fh - legend_size.height()),
                                QPointF(plot.left() + 0.1 * fh, plot.bottom() - 0.1 * fh - legend_size.height())}) {
    const QRectF box(corner, legend_size);
    const int n = int(std::count_if(pts.begin(), pts.end(), [&](const Point& q) { return box.contains(at(q.x, q.y)); }));
    if (n < covered) covered = n, legend = box;
  }
  p.fillRect(legend, QColor(255, 255, 255, 215));
  double ly = legend.top() + 0.7 * fh;
  const double lx = legend.left() + 0.9 * fh;
  auto key = [&](const QColor& pen, const QBrush& brush, double radius, const QString& text) {
    p.setPen(QPen(pen, radius > 0.5 * fh ? 2.5 : 1.2));
    p.setBrush(brush);
    p.drawEllipse(QPointF(lx, ly), radius, radius);
    p.setPen(Qt::black);
    p.drawText(QRectF(lx + fh, ly - fh / 2, 14 * fh, fh), Qt::AlignLeft | Qt::AlignVCenter, text);
    ly += 1.3 * fh;
  };
  key(meets.darker(), QBrush(meets), 0.25 * fh, "design meeting the task");
  key(fails, Qt::NoBrush, 0.25 * fh, "design failing it");
  key(QColor(214, 39, 40), Qt::NoBrush, 0.6 * fh, r.best ? (at_size ? "largest ratio" : "smallest meeting design") : "closest design");
  if (!at_size) {
    p.setPen(QPen(QColor(90, 90, 90), 1.2, Qt::DashLine));
    p.drawLine(QPointF(lx - 0.6 * fh, ly), QPointF(lx + 0.6 * fh, ly));
    p.setPen(Qt::black);
    p.drawText(QRectF(lx + fh, ly - fh / 2, 14 * fh, fh), Qt::AlignLeft | Qt::AlignVCenter, "non-dominated designs");
  } else {
    ly -= 1.3 * fh;
  }
  ly += 1.3 * fh;
  p.setPen(QPen(QColor(200, 60, 60), 1.5, Qt::DashLine));
  p.drawLine(QPointF(lx - 0.6 * fh, ly), QPointF(lx + 0.6 * fh, ly));
  p.setPen(Qt::black);
  p.drawText(QRectF(lx + fh, ly - fh / 2, 14 * fh, fh), Qt::AlignLeft | Qt::AlignVCenter,
             QString::fromStdString(use_fit ? "ratio 1" : "bound " + measured->text));
}

std::string design_text(const fit::Row& row, const std::vector<std::string>& columns) {
  std::string s;
  // As evaluated: typed back, the same design.
  for (const std::string& c : columns) s += (s.empty() ? "" : ", ") + c + " = " + format_number(row.parameters.at(c));
  return s;
}



}  // namespace

std::vector<std::string> design_columns(const MechanismInfo& info, const std::vector<fit::Variable>& variables) {
  std::vector<std::string> out;
  for (const Quantity& q : info.parameters)
    if (q.in_panel) out.push_back(q.name);
  for (const fit::Variable& v : variables)
    for (const std::string& p : v.parameters)
      if (std::find(out.begin(), out.end(), p) == out.end()) out.push_back(p);
  return out;
}


std::string fit_report(const fit::Problem& problem, const fit::Result& r, const MechanismInfo& info) {
  const std::vector<std::string> columns = design_columns(info, problem.variables);
  std::string criteria_text;
  for (const task::Criterion& c : problem.criteria) criteria_text += (criteria_text.empty() ? "" : ", ") + c.text;
  std::string free_text;
  for (const fit::Variable& v : problem.variables)
    free_text += (free_text.empty() ? "" : "; ") + v.name() + " in [" + short_number(v.lo) + ", " + short_number(v.hi) + "]";
  const std::string& unit = info.length_unit;
  std::ostringstream out;
  out << "fit " << info.name << ": " << problem.task.text << " (" << (problem.task.centre                ? "centre fixed"
                                                                            : problem.inscribed.centres
                                                                                ? "centre free within " + task::to_text(*problem.inscribed.centres)
                                                                                : std::string("centre free"))
      << ") meeting " << criteria_text << "\n"
      << "free: " << free_text << "; size = " << info.size_description << " (" << unit << ")";
  if (problem.size) out << " held at " << short_number(*problem.size) << " " << unit;
  out << "\n";
  // A stop the device states but the designer switched off changes every verdict: say so.
  const StopChecks stated = stated_stops(problem.preset), on = problem.preset.checks;
  std::string off;
  if (stated.joint_limits && !on.joint_limits) off = "passive-joint limits";
  if (stated.interference && !on.interference) off += (off.empty() ? "" : ", ") + std::string("link interference");
  if (!off.empty()) out << "stops off: " << off << " (the device states them; the verdict ignores them)\n";
  const std::optional<std::size_t> shown = r.best ? r.best : r.closest;
  const bool ratings = !problem.variables.empty() && motor_parameter(problem.variables.front().parameters.front());
  if (r.best)
    out << (problem.size ? "largest ratio at that size: " : ratings ? "smallest ratings meeting it: " : "smallest design meeting it: ");
  else if (problem.task.centre && !problem.size &&
           std::any_of(problem.variables.begin(), problem.variables.end(), [](const fit::Variable& v) { return v.lo < v.hi; }))
    // The search takes a larger design to hold more, true of a task placed
    // at each design, not of one whose centre is fixed.
    out << "no design evaluated meets it (with the centre fixed a larger design need not hold more, so one between "
           "those evaluated may: narrow --bounds about the closest, or let the centre free); closest: ";
  else out << "no design in the bounds meets it; closest: ";
  if (shown) {
    const fit::Row& row = r.rows[*shown];
    out << design_text(row, columns) << " (size " << format_number(row.size) << " " << unit << ")\n"
        << "  verdict: " << task::verdict_text(row.report) << "\n"
        << "  centre " << exact_point_text(row.centre, unit) << ", "
        << point_text((row.centre - row.home).unaryExpr([&](double v) { return std::abs(v) < 1e-12 * row.size ? 0.0 : v; }), unit)
        << " from the home point " << point_text(row.home, unit) << "\n"
        << "  ratio " << short_number(row.ratio);
    if (problem.task.centre)
      out << ": the smallest bound / worst over the criteria";
    else
      out << (problem.task.shape == task::Shape::Sphere
                  ? ": the largest " + std::string(info.plane_z ? "disc" : "sphere") + " the placement found there is " +
                        short_number(row.fit * problem.task.diameter()) + " " + unit + " across (the task's " +
                        short_number(problem.task.diameter()) + ")"
                  : ": the largest box the placement found there is " + short_number(row.fit) + " times the task's");
    out << "\n  per criterion: the worst value, its margin to the bound (the measure's unit; < 0: past it), the "
           "samples meeting it\n";
    for (const task::CriterionReport& c : row.report.criteria) {
      const std::string u = task::criterion_unit(c.criterion, unit);
      out << "  " << c.criterion.text << ": worst " << short_number(c.worst) << (u.empty() ? "" : " " + u) << " at "
          << point_text(c.worst_point, unit) << ", margin " << short_number(c.margin()) << (u.empty() ? "" : " " + u)
          << ", " << task::samples_text(row.report.samples - c.failing, row.report.samples) << "\n";
    }
    if (row.report.failing > 0)
      out << "  fails at " << row.report.failing << " of " << row.report.samples << " samples, around "
          << point_text(row.report.failing_centroid, unit) << "\n";
  } else {
    out << "none could be evaluated\n";
  }
  if (r.at_lower_bounds) out << "the design sits on a lower bound: lower it (--bounds) to look for smaller ones\n";
  std::size_t invalid = 0;
  const fit::Row* first_invalid = nullptr;
  for (const fit::Row& row : r.rows)
    if (!row.invalid.empty() && invalid++ == 0) first_invalid = &row;
  out << "evaluated " << r.rows.size() << (r.rows.size() == 1 ? " design" : " designs");
  if (invalid) out << " (" << invalid << " could not be built)";
  out << " in " << short_number(r.seconds) << " s\n";
  // Designs that cannot be built bound the search as the bounds do: a
  // smaller design that meets the task may lie among them (a description's
  // home every design must reach, say).
  if (first_invalid)
    out << "  the first not built: " << first_invalid->invalid << "\n";
  return out.str();
}

std::string fit_csv(const fit::Problem& problem, const fit::Result& result, const MechanismInfo& info) {
  return rows_csv(problem, result, design_columns(info, problem.variables));
}

void draw_fit_chart(QPainter& p, const QRectF& area, const fit::Problem& problem, const fit::Result& result,
                    const MechanismInfo& info) {
  std::string criteria_text;
  for (const task::Criterion& c : problem.criteria) criteria_text += (criteria_text.empty() ? "" : ", ") + c.text;
  draw_pareto(p, area, problem, result, info.length_unit, info.size_description,
              QString::fromStdString(info.name + ": " + problem.task.text + " meeting " + criteria_text +
                                     (problem.size ? " at " + info.size_description + " = " + short_number(*problem.size) : "")));
}

void write_fit_chart(const std::filesystem::path& path, const fit::Problem& problem, const fit::Result& result,
                     const MechanismInfo& info) {
  write_painted(path, QSize(1200, 800), "Linkscape fit",
                [&](QPainter& p, const QRectF& area) { draw_fit_chart(p, area, problem, result, info); });
}

void write_fit_csv(const std::filesystem::path& path, const fit::Problem& problem, const fit::Result& result,
                   const MechanismInfo& info) {
  write_text_atomically(path, fit_csv(problem, result, info));
}

}  // namespace linkscape::gui
