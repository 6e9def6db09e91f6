// The line probe's chart: one field along the probed segment (distance on
// the x axis in the length unit, the value with its unit on y). Stretches
// without a value (outside the field, unreachable) are gaps, not zeros.
#pragma once

#include <QChartView>

#include "render/field_probe.h"

namespace linkscape::gui {

class ProfileChart : public QChartView {
  Q_OBJECT

 public:
  explicit ProfileChart(QWidget* parent = nullptr);
  void showProfile(const render::LineProfile& profile);
  void clearProfile();
  // The points drawn (all series), for tests.
  int pointCount() const;
};

}  // namespace linkscape::gui
