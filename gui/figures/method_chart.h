// Charts of the method harness and the stability sweeps, drawn with QPainter
// into any rectangle (the window's panel, or a PNG/SVG/PDF page headless).
//
// Method chart: one log-log panel per family (IK, Jacobian, condition
// number, workspace fields), error against time per evaluation, one marker
// per method (whisker up to the 99th percentile; fields: one curve per
// measure over grid resolutions), Pareto front as a dashed staircase with
// ringed members.
// Sweep chart: one panel per singular-set path, IK joint error against eps
// (worst over the base points), the condition-number prediction u B /
// sigma_min dashed, non-ok results as crosses on the "not ok" band.
#pragma once

#include <QColor>
#include <QRectF>
#include <QString>
#include <filesystem>
#include <string>
#include <vector>

#include "core/method_harness.h"
#include "core/stability.h"

class QPainter;

namespace linkscape::gui {

// Exact results (error 0) are drawn on this floor of the log error axis, by
// the painted chart and the window's interactive one alike.
inline constexpr double kExactErrorFloor = 1e-18;

// A family's panel title ("Inverse kinematics: joint error (rad)") and the
// label of its error axis ("joint error (rad)"), shared by both charts, for
// its rows' error_unit ("rad", "cm", "pose", "relative").
QString method_family_title(const std::string& family, const std::string& unit);
QString method_error_label(const std::string& family, const std::string& unit);
// The label of the decade 10^k: "10⁻⁶".
QString decade_label(int k);
// The colour of the k-th method of a family (Tableau 10: distinct under
// common colour-vision deficiencies).
QColor method_colour(int k);

void draw_method_chart(QPainter& painter, const QRectF& area, const std::vector<methods::MethodRow>& rows,
                       const QString& title);
void draw_sweep_chart(QPainter& painter, const QRectF& area, const std::vector<stability::SweepRow>& rows,
                      const QString& title);

// Write the chart as PNG, SVG or PDF by the extension of `path`, atomically.
// Throws std::invalid_argument for another extension, std::runtime_error if
// the file cannot be written. Needs a QGuiApplication (any platform).
void write_method_chart(const std::vector<methods::MethodRow>& rows, const QString& title,
                        const std::filesystem::path& path);
void write_sweep_chart(const std::vector<stability::SweepRow>& rows, const QString& title,
                       const std::filesystem::path& path);

}  // namespace linkscape::gui
