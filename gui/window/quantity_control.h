// The controls the panels are made of: a slider with a spin box for one
// named quantity of the device's description (angles shown in degrees),
// and the texts that show quantities.
#pragma once

#include <QString>
#include <functional>
#include <memory>
#include <string>

#include "core/mechanism.h"

class QDoubleSpinBox;
class QFormLayout;
class QLabel;
class QSlider;
class QWidget;

namespace linkscape::gui {

QString qs(const std::string& s);
// As %.{precision}g.
QString number(double v, int precision = 4);
// Fixed-point text; values that round to zero print as 0, never -0.
QString fixed(double v, int decimals = 2);
// Angles are shown in degrees; everything else in its own unit.
double display_scale(const Quantity& q);
QString display_suffix(const Quantity& q);
// "name = value unit", in display units.
QString value_text(const Quantity& q, double v);

// A slider and a spin box showing one quantity (the spin box carries the
// unit; angles in degrees); `changed` runs when the user moves either.
struct QuantityControl {
  Quantity quantity;
  double scale = 1.0;  // display units per model unit
  QSlider* slider = nullptr;
  QDoubleSpinBox* box = nullptr;
  QLabel* label = nullptr;
  QFormLayout* form = nullptr;  // its row

  double value() const;  // in the model's unit
  int step_of(double display) const;
  void set(double v);  // quietly: `changed` does not run
  void set_range(const Range& r);
  void set_enabled(bool on);  // and its row shown
};


// A row of `form` for `q`, its object names "<name>Slider" and "<name>Box".
std::unique_ptr<QuantityControl> make_control(QWidget* parent, QFormLayout* form, const Quantity& q,
                                              std::function<void()> changed);

// A spin box that reports only finished edits.
QDoubleSpinBox* spin(QWidget* parent, double lo, double hi, double value, int decimals, const QString& suffix = {});

}  // namespace linkscape::gui
