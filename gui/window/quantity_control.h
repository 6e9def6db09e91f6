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

// The unit of det J for a J whose rows are in `row_units` and columns in
// `column_units`: every term of the determinant takes one entry of each
// row and each column, so its unit is the product of the rows' units over
// the product of the columns', with common units cancelled ("cm³/rad³" for
// three lengths over three angles); empty where everything cancels.
QString determinant_unit(const std::vector<std::string>& row_units, const std::vector<std::string>& column_units);
// The same for a device's J = dx/dq of `rows` x `cols` (core/mechanism.h):
// rows the task coordinates it drives (a planar device's without z), columns
// its actuators.
QString determinant_unit(const MechanismInfo& info, int rows, int cols);

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
