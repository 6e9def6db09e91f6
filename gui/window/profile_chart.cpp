#include "gui/window/profile_chart.h"

#include <QChart>
#include <QLineSeries>
#include <QValueAxis>

#include <algorithm>
#include <cmath>

namespace linkscape::gui {

namespace {
QString with_unit(const std::string& title, const std::string& unit) {
  return QString::fromStdString(unit.empty() ? title : title + " (" + unit + ")");
}
}  // namespace

ProfileChart::ProfileChart(QWidget* parent) : QChartView(new QChart, parent) {
  setRenderHint(QPainter::Antialiasing);
  setMinimumHeight(200);
  setMinimumWidth(160);  // the dock's width decides
  chart()->legend()->hide();
  chart()->setMargins(QMargins(4, 4, 4, 4));
  clearProfile();
}

void ProfileChart::clearProfile() {
  chart()->removeAllSeries();
  for (QAbstractAxis* axis : chart()->axes()) chart()->removeAxis(axis);
  chart()->setTitle(tr("Pick two points in Line probe mode"));
}

void ProfileChart::showProfile(const render::LineProfile& profile) {
  clearProfile();
  auto* x_axis = new QValueAxis;
  auto* y_axis = new QValueAxis;
  x_axis->setTitleText(with_unit("distance", profile.length_unit));
  y_axis->setTitleText(with_unit(profile.title, profile.unit));
  chart()->addAxis(x_axis, Qt::AlignBottom);
  chart()->addAxis(y_axis, Qt::AlignLeft);
  double lo = INFINITY, hi = -INFINITY;
  QLineSeries* run = nullptr;  // the stretch with values being drawn
  for (std::size_t k = 0; k < profile.values.size(); ++k) {
    const double v = profile.values[k];
    if (!std::isfinite(v)) {
      run = nullptr;  // a gap
      continue;
    }
    if (!run) {
      run = new QLineSeries;
      run->setPen(QPen(QColor(30, 90, 200), 2));
      chart()->addSeries(run);
      run->attachAxis(x_axis);
      run->attachAxis(y_axis);
    }
    run->append(profile.distance[k], v);
    lo = std::min(lo, v);
    hi = std::max(hi, v);
  }
  x_axis->setRange(0, std::max(profile.distance.empty() ? 0.0 : profile.distance.back(), 1e-12));
  if (lo <= hi) {
    const double pad = hi > lo ? 0.05 * (hi - lo) : std::max(std::abs(hi) * 0.05, 1e-9);
    y_axis->setRange(lo - pad, hi + pad);
  }
  // Ticks at round numbers (the range widened to them), not at fifths of the segment.
  x_axis->applyNiceNumbers();
  y_axis->applyNiceNumbers();
  chart()->setTitle(lo <= hi ? QString() : tr("No value along this segment"));
}

int ProfileChart::pointCount() const {
  int n = 0;
  for (QAbstractSeries* s : chart()->series())
    if (auto* line = qobject_cast<QLineSeries*>(s)) n += line->count();
  return n;
}

}  // namespace linkscape::gui
