// What a fit (core/fit.h) shows, the same on the command line (`linkscape
// fit`) and in the window's Fit tab: the report text, the CSV of every
// design evaluated and the chart of size (or, at a given size, the first
// free variable) against the worst measure.
#pragma once

#include <QRectF>
#include <QString>
#include <filesystem>
#include <string>
#include <vector>

#include "core/fit.h"

class QPainter;

namespace linkscape::gui {

// The parameters a table names: those the design panel shows and the free ones.
std::vector<std::string> design_columns(const MechanismInfo& info, const std::vector<fit::Variable>& variables);

// The chosen design (or the closest), its size, the verdict (task::verdict_text),
// its centre (also from the home point), its ratio, every criterion's worst
// value, margin and samples meeting it, where the task fails, the number of
// designs and the time.
std::string fit_report(const fit::Problem& problem, const fit::Result& result, const MechanismInfo& info);

// The parameters of the design panel and the free ones, then
// fit::score_header's columns; the chosen (or closest) design first,
// then every valid design by size.
std::string fit_csv(const fit::Problem& problem, const fit::Result& result, const MechanismInfo& info);

// Every valid design: size (at a given size, the first free variable)
// against the worst value of the first criterion on a measure (the ratio
// where there is none), meeting ones filled, the non-dominated ones joined,
// the chosen one ringed, the bound dashed.
void draw_fit_chart(QPainter& p, const QRectF& area, const fit::Problem& problem, const fit::Result& result,
                    const MechanismInfo& info);
// The chart as PNG, SVG or PDF by the extension (gui/figures/painted_file.h).
void write_fit_chart(const std::filesystem::path& path, const fit::Problem& problem, const fit::Result& result,
                     const MechanismInfo& info);
// The CSV, written atomically. Throws std::runtime_error if it cannot be written.
void write_fit_csv(const std::filesystem::path& path, const fit::Problem& problem, const fit::Result& result,
                   const MechanismInfo& info);

}  // namespace linkscape::gui
