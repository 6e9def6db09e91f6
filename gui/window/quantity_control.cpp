#include "gui/window/quantity_control.h"

#include <QDoubleSpinBox>
#include <QFormLayout>
#include <QHBoxLayout>
#include <QLabel>
#include <QSignalBlocker>
#include <QSlider>
#include <QStringList>
#include <cmath>
#include <map>
#include <numbers>

namespace linkscape::gui {

namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180.0;
constexpr int kSliderSteps = 1000;

}  // namespace

QString qs(const std::string& s) { return QString::fromStdString(s); }
QString number(double v, int precision) { return QString::number(v, 'g', precision); }
// Fixed-point text; values that round to zero print as 0, never -0.
QString fixed(double v, int decimals) {
  if (std::abs(v) < 0.5 * std::pow(10.0, -decimals)) v = 0.0;
  return QString::number(v, 'f', decimals);
}

// Angles are shown in degrees; everything else in its own unit.
double display_scale(const Quantity& q) { return q.unit == "rad" ? 1.0 / kDeg : 1.0; }
QString display_suffix(const Quantity& q) {
  if (q.unit == "rad" || q.unit == "deg") return QString::fromUtf8(" °");
  return q.unit.empty() ? QString() : " " + qs(q.unit);
}
QString value_text(const Quantity& q, double v) {
  return QString("%1 = %2%3").arg(qs(q.name), fixed(v * display_scale(q), q.unit == "rad" || q.unit == "deg" ? 1 : 3),
                                  display_suffix(q));
}

QString determinant_unit(const std::vector<std::string>& row_units, const std::vector<std::string>& column_units) {
  std::map<std::string, int> power;  // by unit, in the order of the names
  for (const std::string& u : row_units)
    if (!u.empty()) ++power[u];
  for (const std::string& u : column_units)
    if (!u.empty()) --power[u];
  auto term = [](const std::string& unit, int p) {
    static const char* const kSuperscript[] = {"⁰", "¹", "²", "³", "⁴", "⁵", "⁶", "⁷", "⁸", "⁹"};
    QString text = qs(unit);
    if (p > 1) {
      const std::string digits = std::to_string(p);
      for (char d : digits) text += QString::fromUtf8(kSuperscript[d - '0']);
    }
    return text;
  };
  QStringList above, below;
  for (const auto& [unit, p] : power) {
    if (p > 0) above << term(unit, p);
    if (p < 0) below << term(unit, -p);
  }
  const QString dot = QString::fromUtf8("·");
  if (below.isEmpty()) return above.join(dot);
  const QString denominator = below.size() > 1 ? "(" + below.join(dot) + ")" : below.front();
  return (above.isEmpty() ? QString("1") : above.join(dot)) + "/" + denominator;
}

QString determinant_unit(const MechanismInfo& info, int rows, int cols) {
  std::vector<std::string> row_units, column_units;
  for (std::size_t k = 0; k < info.task.size() && int(row_units.size()) < rows; ++k)
    if (!(info.plane_z && k == 2)) row_units.push_back(info.task[k].unit);  // a planar device's J has no z row
  for (std::size_t k = 0; k < info.actuators.size() && int(column_units.size()) < cols; ++k)
    column_units.push_back(info.actuators[k].unit);
  return determinant_unit(row_units, column_units);
}

double QuantityControl::value() const { return box->value() / scale; }

int QuantityControl::step_of(double display) const {
  const double lo = box->minimum(), hi = box->maximum();
  return hi > lo ? int(std::lround((display - lo) / (hi - lo) * kSliderSteps)) : 0;
}

void QuantityControl::set(double v) {
  const QSignalBlocker b1(slider), b2(box);
  // Angles with a full turn of travel are shown in (-180, 180].
  if (quantity.unit == "rad" && quantity.range.hi - quantity.range.lo >= 2 * kPi - 1e-9) v = std::remainder(v, 2 * kPi);
  box->setValue(v * scale);
  slider->setValue(step_of(box->value()));
}

void QuantityControl::set_range(const Range& r) {
  const double v = value();
  quantity.range = r;
  {
    const QSignalBlocker b(box);
    box->setRange(r.lo * scale, r.hi * scale);
  }
  set(v);
}

void QuantityControl::set_enabled(bool on) {
  slider->setEnabled(on);
  box->setEnabled(on);
  form->setRowVisible(label, on);
}

std::unique_ptr<QuantityControl> make_control(QWidget* parent, QFormLayout* form, const Quantity& q,
                                              std::function<void()> changed) {
  auto c = std::make_unique<QuantityControl>();
  c->quantity = q;
  c->scale = display_scale(q);
  c->slider = new QSlider(Qt::Horizontal, parent);
  c->slider->setObjectName(qs(q.name) + "Slider");
  c->slider->setRange(0, kSliderSteps);
  c->box = new QDoubleSpinBox(parent);
  c->box->setObjectName(qs(q.name) + "Box");
  c->box->setDecimals(q.unit == "rad" || q.unit == "deg" ? 1 : 3);
  c->box->setRange(q.range.lo * c->scale, q.range.hi * c->scale);
  c->box->setSingleStep(q.unit == "rad" || q.unit == "deg" ? 1.0 : 0.1);
  c->box->setSuffix(display_suffix(q));
  c->box->setKeyboardTracking(false);
  c->box->setMinimumWidth(96);
  // What it is, and in which unit (the spin box shows the unit too).
  const std::string unit = q.unit == "rad" ? "degrees" : q.unit;
  const QString tip = qs((q.description.empty() ? q.name : q.description) + (unit.empty() ? "" : " (" + unit + ")"));
  c->slider->setToolTip(tip);
  c->box->setToolTip(tip);
  auto* row = new QHBoxLayout;
  row->addWidget(c->slider, 1);
  row->addWidget(c->box);
  c->form = form;
  c->label = new QLabel(qs(q.name), parent);
  c->label->setToolTip(tip);
  form->addRow(c->label, row);
  c->set(q.value);
  QuantityControl* raw = c.get();
  QObject::connect(c->slider, &QSlider::valueChanged, c->box, [raw](int v) {
    const double lo = raw->box->minimum(), hi = raw->box->maximum();
    raw->box->setValue(lo + (hi - lo) * v / kSliderSteps);
  });
  QObject::connect(c->box, &QDoubleSpinBox::valueChanged, c->slider, [raw, changed](double v) {
    {
      const QSignalBlocker block(raw->slider);
      raw->slider->setValue(raw->step_of(v));
    }
    changed();
  });
  return c;
}

QDoubleSpinBox* spin(QWidget* parent, double lo, double hi, double value, int decimals, const QString& suffix) {
  auto* s = new QDoubleSpinBox(parent);
  s->setRange(lo, hi);
  s->setDecimals(decimals);
  s->setValue(value);
  s->setSuffix(suffix);
  s->setKeyboardTracking(false);
  return s;
}

}  // namespace linkscape::gui
