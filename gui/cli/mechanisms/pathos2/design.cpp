// linkscape design: the PATHOS-II design studies of the paper — the Table 2
// grid search over l2, l3, lp and the initial Rz (cost G of Eq. 21) and the
// l0 sweep of Fig. 6 — written as CSV tables and one chart.

#include <memory>
#include <unistd.h>

#include <QFontMetricsF>
#include <QPainter>
#include <QPainterPath>
#include <algorithm>
#include <atomic>
#include <cmath>
#include <fstream>
#include <iostream>
#include <map>
#include <numbers>
#include <ostream>
#include <sstream>
#include <stdexcept>

#include "core/atomic_file.h"
#include "core/csv.h"
#include "core/mechanisms/pathos2/design.h"
#include "core/mechanisms/pathos2/mechanism.h"
#include "core/preset.h"
#include "gui/cli/command.h"
#include "gui/cli/sampling.h"
#include "gui/figures/painted_file.h"
#include "gui/figures/plot_axes.h"
#include "gui/cli/terminal.h"
#include "render/slice_image.h"

namespace linkscape::gui {
namespace {

using pathos2::DesignOutcome;
using pathos2::DesignRow;

struct DesignOptions {
  PresetChoice mechanism{"pathos2", {}};  // Table 1 values: l0 = 50 unless --param l0 says otherwise
  std::string table;   // Table 2 search as CSV (one row per design)
  std::string sweep;   // l0 sweep as CSV
  std::string chart;   // both as a chart (.png, .svg, .pdf)
  bool quick = false;  // a coarse grid (a smoke test, not the paper's Table 2)
  bool quiet = false;  // no progress on stderr
  StopSwitches stops;  // the preset's assumed stops, on unless switched off
};

const char* to_string(DesignOutcome o) {
  switch (o) {
    case DesignOutcome::Evaluated: return "evaluated";
    case DesignOutcome::Degenerate: return "degenerate";
    case DesignOutcome::StartInfeasible: return "start-infeasible";
    case DesignOutcome::Cancelled: return "cancelled";
  }
  return "?";
}

void write_text(const std::string& path, const std::string& text) {
  write_text_atomically(path, text);
}

// The design tables (docs/file-formats.md): lengths in cm, angles in deg or
// rad as their suffix says, G a ratio; a design or start pose that was not
// evaluated has no ranges and no G (empty cells; its outcome or status says why).
std::string table_csv(const pathos2::DesignSearchResult& r) {
  std::string s = "l2_cm,l3_cm,lp_cm,rz_deg,outcome,dLx_cm,dLy_cm,dLz_cm,G\n";
  for (const DesignRow& row : r.rows) {
    const bool evaluated = row.outcome == DesignOutcome::Evaluated;
    const auto value = [evaluated](double v) { return csv_number(evaluated ? v : std::nan("")); };
    s += csv_number(row.l2) + "," + csv_number(row.l3) + "," + csv_number(row.lp) + "," + csv_number(row.rz_deg) +
         "," + to_string(row.outcome) + "," + value(row.dLx) + "," + value(row.dLy) + "," + value(row.dLz) + "," +
         value(row.G) + "\n";
  }
  return s;
}

std::string sweep_csv(const std::vector<pathos2::L0Row>& rows) {
  std::string s = "l0_cm,status,dLx_cm,dLy_cm,dLz_cm,dRx_rad,dRy_rad,dRz_rad\n";
  for (const auto& r : rows) {
    const bool ok = r.ranges.start_status == Status::Ok;  // else no ranges were measured
    s += csv_number(r.l0) + "," + std::string(linkscape::to_string(r.ranges.start_status));
    for (int a = 0; a < 6; ++a) s += "," + csv_number(ok ? r.ranges.delta(a) : std::nan(""));
    s += "\n";
  }
  return s;
}

// ---- Chart ------------------------------------------------------------------------

// Left: movable ranges against l0 (Fig. 6). Right: the best G over lp and
// Rz for every (l2, l3) of the Table 2 grid, with the best design and the
// paper's (l2 = 14, l3 = 6) marked.
void draw_design_chart(QPainter& p, const QRectF& area, const pathos2::DesignGrid& grid,
                       const pathos2::DesignSearchResult& search, const std::vector<pathos2::L0Row>& sweep,
                       const QString& title) {
  QFont font = p.font();
  font.setPixelSize(int(area.height() / 48));
  p.setFont(font);
  const double fh = QFontMetricsF(p.font()).height();
  p.fillRect(area, Qt::white);
  QFont bold = font;
  bold.setBold(true);
  p.setFont(bold);
  p.drawText(QRectF(area.left(), area.top() + 0.5 * fh, area.width(), 1.5 * fh), Qt::AlignCenter, title);
  p.setFont(font);
  const double top = area.top() + 4 * fh, bottom = area.bottom() - 4 * fh, half = area.width() / 2;

  // (a) the l0 sweep.
  {
    double ymax = 1;
    for (const auto& r : sweep)
      for (int a = 0; a < 3; ++a) ymax = std::max(ymax, r.ranges.delta(a));
    ymax = std::ceil(ymax / 5) * 5;
    const double x0 = sweep.empty() ? 40 : sweep.front().l0, x1 = sweep.empty() ? 55 : sweep.back().l0;
    const PlotFrame f{QRectF(area.left() + 6 * fh, top, half - 9 * fh, bottom - top), x0, std::max(x1, x0 + 1), 0, ymax};
    draw_axes(p, f, "l0, distance between the base plates (cm)", "movable range from the home pose (cm)");
    const QColor colours[] = {QColor(31, 119, 180), QColor(214, 39, 40), QColor(44, 160, 44)};
    const char* names[] = {"dLx", "dLy", "dLz"};
    for (int a = 0; a < 3; ++a) {
      QPainterPath path;
      for (std::size_t i = 0; i < sweep.size(); ++i) {
        const QPointF q = f.at(sweep[i].l0, sweep[i].ranges.delta(a));
        if (i == 0) path.moveTo(q);
        else path.lineTo(q);
      }
      p.setPen(QPen(colours[a], 2.5));
      p.drawPath(path);
      for (const auto& r : sweep) p.drawEllipse(f.at(r.l0, r.ranges.delta(a)), 3, 3);
      const QPointF key(f.plot.right() - 6 * fh, f.plot.top() + (1 + 1.3 * a) * fh);
      p.drawLine(key, key + QPointF(2 * fh, 0));
      p.setPen(Qt::black);
      p.drawText(QRectF(key.x() + 2.4 * fh, key.y() - fh / 2, 4 * fh, fh), Qt::AlignLeft | Qt::AlignVCenter, names[a]);
    }
    p.drawText(QRectF(f.plot.left(), top - 1.8 * fh, f.plot.width(), fh), Qt::AlignCenter,
               "(a) workspace along the axes against l0 (paper Fig. 6)");
  }

  // (b) the Table 2 search: best G per (l2, l3).
  {
    std::map<std::pair<double, double>, double> best;
    double l2max = 1, l3max = 1, gmax = 0;
    for (const DesignRow& r : search.rows) {
      if (r.outcome != DesignOutcome::Evaluated) continue;
      double& g = best[{r.l2, r.l3}];
      g = std::max(g, r.G);
      l2max = std::max(l2max, r.l2), l3max = std::max(l3max, r.l3), gmax = std::max(gmax, r.G);
    }
    const double w = grid.l2.step, h = grid.l3.step;
    const PlotFrame f{QRectF(area.left() + half + 6 * fh, top, half - 13 * fh, bottom - top), grid.l2.lo - w / 2, l2max + w / 2,
                  grid.l3.lo - h / 2, l3max + h / 2};
    for (const auto& [key, g] : best) {
      const auto c = render::colour_of(gmax > 0 ? g / gmax : 0);
      const QPointF a = f.at(key.first - w / 2, key.second + h / 2), b = f.at(key.first + w / 2, key.second - h / 2);
      p.fillRect(QRectF(a, b), QColor::fromRgbF(c[0], c[1], c[2]));
    }
    draw_axes(p, f, "l2 (cm)", "l3 (cm)");
    auto mark = [&](double l2, double l3, const QColor& colour, const QString& label) {
      const QPointF c = f.at(l2, l3);
      p.setPen(QPen(colour, 3));
      p.setBrush(Qt::NoBrush);
      p.drawEllipse(c, 0.6 * fh, 0.6 * fh);
      // The label sits on the side of the marker with room for it.
      const bool left = c.x() > f.plot.center().x();
      p.drawText(QRectF(left ? c.x() - 12.8 * fh : c.x() + 0.8 * fh, c.y() - 1.6 * fh, 12 * fh, fh),
                 left ? Qt::AlignRight : Qt::AlignLeft, label);
      p.setPen(Qt::black);
    };
    mark(14, 6, QColor(220, 30, 30), "paper: l2 = 14, l3 = 6");
    if (search.best >= 0) {
      const DesignRow& b = search.rows[std::size_t(search.best)];
      mark(b.l2, b.l3, Qt::white, QString("best G = %1").arg(b.G, 0, 'f', 2));
    }
    // Colour bar.
    const QRectF bar(f.plot.right() + 1.5 * fh, f.plot.top(), 1.2 * fh, f.plot.height());
    for (int i = 0; i < 128; ++i) {
      const auto c = render::colour_of((i + 0.5) / 128);
      p.fillRect(QRectF(bar.left(), bar.bottom() - (i + 1) * bar.height() / 128, bar.width(), bar.height() / 128 + 0.5),
                 QColor::fromRgbF(c[0], c[1], c[2]));
    }
    p.drawRect(bar);
    for (int k = 0; k <= 4; ++k) {
      const double y = bar.bottom() - k / 4.0 * bar.height();
      p.drawText(QRectF(bar.right() + 0.4 * fh, y - fh / 2, 4 * fh, fh), Qt::AlignLeft | Qt::AlignVCenter,
                 QString::number(gmax * k / 4, 'f', 1));
    }
    p.drawText(QRectF(bar.left() - 2 * fh, bar.top() - 1.5 * fh, 6 * fh, fh), Qt::AlignCenter, "G");
    p.drawText(QRectF(f.plot.left(), top - 1.8 * fh, f.plot.width(), fh), Qt::AlignCenter,
               "(b) best cost G (Eq. 21) over lp and Rz for each l2, l3 (Table 2 grid)");
  }
}

// Runs the search and the sweep, writes what was asked for and prints a
// summary (best design, the paper's design and its rank) to `out`. Throws
// std::invalid_argument for bad options (nothing written).
void run_design(const DesignOptions& o, std::ostream& out) {
  if (o.table.empty() && o.sweep.empty() && o.chart.empty())
    throw std::invalid_argument("design: give at least one of --table FILE.csv, --sweep FILE.csv, --chart FILE.png");
  for (const std::string* csv : {&o.table, &o.sweep})
    if (!csv->empty() && std::filesystem::path(*csv).extension() != ".csv")
      throw std::invalid_argument("design: --table and --sweep must end in .csv, got '" + *csv + "'");
  if (!o.table.empty() && std::filesystem::path(o.table).lexically_normal() == std::filesystem::path(o.sweep).lexically_normal())
    throw std::invalid_argument("design: --table and --sweep name the same file '" + o.table + "' (one would overwrite the other)");
  if (!o.chart.empty()) {
    const std::string ext = std::filesystem::path(o.chart).extension().string();
    if (ext != ".png" && ext != ".svg" && ext != ".pdf")
      throw std::invalid_argument("design: --chart must end in .png, .svg or .pdf, got '" + o.chart + "'");
  }
  Preset preset = load_preset(o.mechanism.name_or_path);
  if (preset.mechanism != pathos2::kMechanismName)
    throw std::invalid_argument("design: the Table 2 study is for pathos2 (the compiled device), got '" +
                                o.mechanism.name_or_path + "' (" + preset.mechanism + ")");
  preset.parameters["l0"] = pathos2::table1_model().l0;  // Table 1 optimises at l0 = 50
  apply_overrides(preset, o.mechanism.params);
  apply_stop_switches(o.stops, preset, "design");
  const pathos2::Model base = make_pathos2(preset);
  for (const std::string* file : {&o.table, &o.sweep, &o.chart}) check_output(*file);  // before the search

  pathos2::DesignGrid grid;
  if (o.quick) grid = {{2, 20, 3}, {2, 20, 3}, {0, 8, 2}, {0, 120, 30}};
  ProgressLine line(o.quiet);
  line.step("Table 2 search");
  auto progress = [&](std::size_t done, std::size_t total) {
    line.report(double(done) / double(std::max<std::size_t>(total, 1)));
  };
  const pathos2::DesignSearchResult search = pathos2::design_search(base, grid, {}, progress);
  line.clear();
  const std::vector<pathos2::L0Row> sweep =
      pathos2::l0_sweep(base, 40.0, 55.0, o.quick ? 5.0 : 1.0);

  if (!o.table.empty()) write_text(o.table, table_csv(search));
  if (!o.sweep.empty()) write_text(o.sweep, sweep_csv(sweep));
  if (!o.chart.empty())
    write_painted(o.chart, QSize(1800, 900), "Linkscape PATHOS-II design", [&](QPainter& p, const QRectF& area) {
      draw_design_chart(p, area, grid, search, sweep,
                        QString("PATHOS-II design study (l0 = %1 cm for the search, lb = %2, l1 = %3 cm)%4")
                            .arg(base.l0).arg(base.lb).arg(base.l1).arg(o.quick ? "  [quick grid]" : ""));
    });

  out << "stops: globular cone " << base.cone_limit * 180 / std::numbers::pi << " deg (180: none), link radius " << base.link_radius << " cm, grip radius " << base.grip_radius << " cm (0: none)\n";
  out << "designs " << search.rows.size() << ", evaluated " << search.evaluated << "\n";
  if (search.best >= 0) {
    const DesignRow& b = search.rows[std::size_t(search.best)];
    out << "best G " << b.G << " at l2 = " << b.l2 << ", l3 = " << b.l3 << ", lp = " << b.lp << ", Rz = " << b.rz_deg
        << " deg (dLx " << b.dLx << ", dLy " << b.dLy << ", dLz " << b.dLz << " cm)\n";
  }
  // The paper's optimum and its rank among the evaluated designs.
  for (const DesignRow& r : search.rows)
    if (r.l2 == 14 && r.l3 == 6 && r.lp == 2 && r.rz_deg == 30) {
      std::size_t better = 0;
      for (const DesignRow& q : search.rows) better += q.outcome == DesignOutcome::Evaluated && q.G > r.G;
      out << "paper's design (l2 14, l3 6, lp 2, Rz 30): G " << r.G << ", rank " << better + 1 << " of "
          << search.evaluated << "\n";
    }
  for (const auto& r : sweep)
    out << "l0 " << r.l0 << ": dLx " << r.ranges.delta(0) << ", dLy " << r.ranges.delta(1) << ", dLz "
        << r.ranges.delta(2) << " cm\n";
}

Command add_design(CLI::App& program, const DeviceHelp&) {
  auto options = std::make_shared<DesignOptions>();
  CLI::App* cmd = program.add_subcommand(
      "design", "PATHOS-II design study: the Table 2 grid search (cost G of Eq. 21 over l2, l3, lp, Rz) and the "
                "l0 sweep of Fig. 6; writes CSV tables and a chart, prints the best design");
  add_mechanism_options(*cmd, options->mechanism);
  add_stop_options(*cmd, options->stops);
  cmd->add_option("--table", options->table, "The search, one row per design (.csv)");
  cmd->add_option("--sweep", options->sweep, "Movable ranges against l0 from 40 to 55 cm (.csv)");
  cmd->add_option("--chart", options->chart, "Both as a chart (.png, .svg, .pdf)");
  cmd->add_flag("--quick", options->quick, "A coarse grid (a smoke test, not the paper's Table 2)");
  cmd->add_flag("-q,--quiet", options->quiet, "No progress line on stderr");
  return {cmd, Runs::Painting,  // the chart draws with QPainter
          "linkscape design --table table2.csv --sweep l0.csv --chart l0.png    the Table 2 grid search and the l0 sweep",
          [options](std::istream&, std::ostream& out) {
            run_design(*options, out);
            return 0;
          }};
}

const RegisterCommand registered{70, add_design};

}  // namespace

}  // namespace linkscape::gui
