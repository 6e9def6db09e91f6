#include "gui/window/field_panel.h"

#include <QCheckBox>
#include <QComboBox>
#include <QDoubleSpinBox>
#include <QFormLayout>
#include <QHBoxLayout>
#include <QLabel>
#include <QSignalBlocker>
#include <QSlider>
#include <cmath>

#include "core/haptics.h"
#include "gui/window/quantity_control.h"
#include "render/slice_image.h"

namespace linkscape::gui {

namespace {
constexpr int kPositionSteps = 400;  // either side of the sampling box's centre
}  // namespace

FieldPanel::FieldPanel(const Mechanism& device, QWidget* parent) : QWidget(parent) {
  const MechanismInfo& info = device.info();
  const FieldChoices choices = field_choices(info);
  plane_z_ = info.plane_z;
  has_methods_ = !choices.methods.empty();
  QWidget* w = this;
  auto* form = new QFormLayout(w);
  field_box_ = new QComboBox(w);
  field_box_->setObjectName("fieldBox");
  for (const auto& name : choices.fields) {
    QString text = qs(name);
    if (name == "cond") text = qs(info.measures.front().title);
    else if (info.measures.size() > 1 && name == info.measures[1].name) text = qs(info.measures[1].title);
    for (const haptics::FieldInfo& f : haptics::all_field_infos())
      if (f.name == name) text = qs(f.title + " (" + f.unit + ")");
    field_box_->addItem(text, qs(name));
  }
  field_box_->setToolTip(tr("method: which IK method served each sample (categorical colours)"));
  form->addRow(tr("Field"), field_box_);
  method_box_ = new QComboBox(w);
  method_box_->setObjectName("methodBox");
  for (const auto& m : info.ik_methods) {
    method_box_->addItem(qs(m.name));
    method_box_->setItemData(method_box_->count() - 1, qs(m.description), Qt::ToolTipRole);
  }
  if (choices.methods.empty()) method_box_->hide();
  else form->addRow(tr("IK method"), method_box_);
  method_box_->setToolTip(tr("The inverse kinematics method that solves each sample of the fields"));
  field_branch_box_ = new QComboBox(w);
  field_branch_box_->setObjectName("fieldBranchBox");
  for (const auto& b : info.branches) field_branch_box_->addItem(qs(b));
  field_branch_box_->setToolTip(tr("The branch the fields are sampled in; follows the device's branch."));
  if (info.branches.size() > 1) form->addRow(tr("Branch"), field_branch_box_);
  else field_branch_box_->hide();
  normal_box_ = new QComboBox(w);
  normal_box_->setObjectName("normalBox");
  normal_box_->addItems({"x", "y", "z"});
  // The device's own first plane (a planar device's is its plane of motion).
  normal_box_->setCurrentIndex(int(device.default_slice_plane(device.home_task()).first));
  normal_box_->setToolTip(tr("The axis the slice plane is normal to"));
  form->addRow(tr("Slice normal"), normal_box_);
  position_slider_ = new QSlider(Qt::Horizontal, w);
  position_slider_->setObjectName("positionSlider");
  position_slider_->setRange(-kPositionSteps, kPositionSteps);
  position_slider_->setValue(kPositionSteps / 8);
  position_label_ = new QLabel(w);
  position_label_->setObjectName("positionLabel");
  position_label_->setMinimumWidth(80);
  const QString position_tip = tr("Where the slice cuts the sampling box, and how far across it (0 %: its low side). "
                                  "The fraction stays when the design changes size.");
  position_slider_->setToolTip(position_tip);
  position_label_->setToolTip(position_tip);
  auto* row = new QHBoxLayout;
  row->addWidget(position_slider_, 1);
  row->addWidget(position_label_);
  form->addRow(tr("Position"), row);
  follow_box_ = new QCheckBox(tr("Through the driven point"), w);
  follow_box_->setObjectName("followBox");
  follow_box_->setToolTip(tr("The slice moves with the driven point (the position slider follows it)"));
  form->addRow(follow_box_);
  const QString main_measure = qs(info.measures.front().title);
  threshold_box_ = spin(w, 1.05, 100.0, 3.0, 2);
  threshold_box_->setObjectName("thresholdBox");
  threshold_box_->setToolTip(tr("%1 contour on the slice and the well-conditioned surface").arg(main_measure));
  form->addRow(tr("%1 threshold").arg(main_measure), threshold_box_);
  auto_range_box_ = new QCheckBox(tr("Automatic colour range"), w);
  auto_range_box_->setChecked(true);
  range_min_box_ = spin(w, -1e6, 1e6, 1.0, 3);
  range_max_box_ = spin(w, -1e6, 1e6, 10.0, 3);
  auto* range_row = new QHBoxLayout;
  range_row->addWidget(range_min_box_);
  range_row->addWidget(range_max_box_);
  form->addRow(auto_range_box_);
  form->addRow(tr("Colour range"), range_row);
  colour_map_box_ = new QComboBox(w);
  colour_map_box_->setObjectName("colourMapBox");
  for (const std::string& map : render::colour_maps()) colour_map_box_->addItem(qs(map));
  colour_map_box_->setToolTip(tr("viridis: perceptually uniform; cividis: also for colour vision deficiency; "
                                 "diverging: blue below, red above the middle (the range is symmetric about 0 "
                                 "for signed fields such as the reach margin)"));
  log_scale_box_ = new QCheckBox(tr("Logarithmic"), w);
  log_scale_box_->setObjectName("logScaleBox");
  log_scale_box_->setChecked(true);
  log_scale_box_->setToolTip(tr("A log10 colour scale for c(J), the residual and the haptic measures "
                                "(the other fields are always linear)"));
  auto* map_row = new QHBoxLayout;
  map_row->addWidget(colour_map_box_, 1);
  map_row->addWidget(log_scale_box_);
  form->addRow(tr("Colour map"), map_row);
  slice_resolution_box_ = new QComboBox(w);
  slice_resolution_box_->setObjectName("sliceResolutionBox");
  for (int n : choices.slice_resolutions) slice_resolution_box_->addItem(QString::number(n));
  slice_resolution_box_->setCurrentText(QString::number(choices.default_slice_resolution));
  volume_resolution_box_ = new QComboBox(w);
  volume_resolution_box_->setObjectName("volumeResolutionBox");
  for (int n : choices.volume_resolutions) volume_resolution_box_->addItem(QString::number(n));
  volume_resolution_box_->setCurrentText(QString::number(choices.default_volume_resolution));
  slice_resolution_box_->setToolTip(tr("Samples along each side of the slice"));
  volume_resolution_box_->setToolTip(tr("Samples along each side of the volume the workspace surfaces come from"));
  form->addRow(tr("Slice samples"), slice_resolution_box_);
  form->addRow(tr("Volume samples"), volume_resolution_box_);
  show_slice_box_ = new QCheckBox(tr("Slice"), w);
  show_slice_box_->setObjectName("showSliceBox");
  show_reach_box_ = new QCheckBox(tr("Reachable workspace"), w);
  show_reach_box_->setObjectName("showReachBox");
  show_well_box_ = new QCheckBox(tr("Well-conditioned workspace"), w);
  show_well_box_->setObjectName("showWellBox");
  reach_opacity_slider_ = new QSlider(Qt::Horizontal, w);
  well_opacity_slider_ = new QSlider(Qt::Horizontal, w);
  slice_opacity_slider_ = new QSlider(Qt::Horizontal, w);
  slice_opacity_slider_->setObjectName("sliceOpacitySlider");
  for (QSlider* s : {reach_opacity_slider_, well_opacity_slider_, slice_opacity_slider_}) s->setRange(0, 100);
  slice_opacity_slider_->setValue(100);
  reach_opacity_slider_->setValue(10);
  well_opacity_slider_->setValue(22);
  for (QCheckBox* c : {show_slice_box_, show_reach_box_, show_well_box_}) c->setChecked(true);
  show_slice_box_->setToolTip(tr("Show the slice (it is computed only while shown)"));
  show_reach_box_->setToolTip(tr("The boundary of the reachable set, translucent; the slider sets its opacity"));
  show_well_box_->setToolTip(tr("The region where the main measure is below the threshold; the slider sets its opacity"));
  reach_opacity_slider_->setToolTip(tr("Opacity of the reachable workspace"));
  slice_opacity_slider_->setToolTip(tr("Opacity of the slice: lower it to see the linkage through it"));
  well_opacity_slider_->setToolTip(tr("Opacity of the well-conditioned workspace"));
  form->addRow(show_slice_box_, slice_opacity_slider_);
  form->addRow(show_reach_box_, reach_opacity_slider_);
  form->addRow(show_well_box_, well_opacity_slider_);
  if (info.task.size() > 3)
    form->addRow(new QLabel(tr("Fields are sampled with the other task coordinates as they are now."), w));

  range_min_box_->setObjectName("rangeMinBox");
  range_min_box_->setToolTip(tr("Lower end of the colour range (the value's unit); shows the automatic one when that is on"));
  range_max_box_->setToolTip(tr("Upper end of the colour range (the value's unit); shows the automatic one when that is on"));
  range_max_box_->setObjectName("rangeMaxBox");
  auto_range_box_->setObjectName("autoRangeBox");
  auto_range_box_->setToolTip(tr("Colour range from the slice's data (the boxes show it); off: type the range"));
  // What each control changes: the slice, the volume, both, or only the slice's look.
  for (QComboBox* box : {normal_box_, slice_resolution_box_})
    connect(box, &QComboBox::currentIndexChanged, this, &FieldPanel::sliceChanged);
  connect(follow_box_, &QCheckBox::toggled, this, &FieldPanel::sliceChanged);
  connect(position_slider_, &QSlider::valueChanged, this, [this] {
    if (!follow_box_->isChecked()) emit sliceChanged();
  });
  for (QComboBox* box : {method_box_, field_branch_box_})
    connect(box, &QComboBox::currentIndexChanged, this, &FieldPanel::fieldsChanged);
  connect(volume_resolution_box_, &QComboBox::currentIndexChanged, this, &FieldPanel::volumeChanged);
  connect(threshold_box_, &QDoubleSpinBox::valueChanged, this, [this] {
    emit styleChanged();
    emit volumeChanged();
  });
  connect(field_box_, &QComboBox::currentIndexChanged, this, &FieldPanel::fieldChosen);
  connect(colour_map_box_, &QComboBox::currentIndexChanged, this, &FieldPanel::styleChanged);
  for (QCheckBox* box : {auto_range_box_, log_scale_box_}) connect(box, &QCheckBox::toggled, this, &FieldPanel::styleChanged);
  for (QDoubleSpinBox* box : {range_min_box_, range_max_box_})
    connect(box, &QDoubleSpinBox::valueChanged, this, &FieldPanel::styleChanged);
  // Fields are computed only while shown.
  connect(show_slice_box_, &QCheckBox::toggled, this, [this] {
    emit visibilityChanged();
    emit sliceChanged();
  });
  for (QCheckBox* c : {show_reach_box_, show_well_box_})
    connect(c, &QCheckBox::toggled, this, [this] {
      emit visibilityChanged();
      emit volumeChanged();
    });
  for (QSlider* s : {reach_opacity_slider_, well_opacity_slider_, slice_opacity_slider_})
    connect(s, &QSlider::valueChanged, this, &FieldPanel::visibilityChanged);
}

double FieldPanel::sliceOpacity() const { return slice_opacity_slider_->value() / 100.0; }

bool FieldPanel::sliceInPlane() const { return plane_z_ && normal() == Axis::Z; }

FieldSettings FieldPanel::settings(const Mechanism& device, const Eigen::VectorXd& x) const {
  FieldSettings f;
  f.field = field_box_->currentData().toString().toStdString();
  if (has_methods_) f.method = method_box_->currentText().toStdString();
  f.normal = normal_box_->currentText().toStdString();
  const int n = normal_box_->currentIndex();
  const Eigen::AlignedBox3d box = device.default_box();
  const double slid = box.center()(n) + 0.5 * box.sizes()(n) * position_slider_->value() / kPositionSteps;
  f.position = sliceInPlane() ? *plane_z_ : follow_box_->isChecked() ? x(n) : slid;
  f.follow_endpoint = follow_box_->isChecked() && !sliceInPlane();
  f.threshold = threshold_box_->value();
  if (!auto_range_box_->isChecked()) {
    f.range_min = range_min_box_->value();
    f.range_max = range_max_box_->value();
  }
  f.colour_map = colour_map_box_->currentText().toStdString();
  f.log_scale = log_scale_box_->isChecked();
  f.slice_resolution = slice_resolution_box_->currentText().toInt();
  f.volume_resolution = volume_resolution_box_->currentText().toInt();
  f.show_slice = show_slice_box_->isChecked();
  f.show_reach = show_reach_box_->isChecked();
  f.show_well_conditioned = show_well_box_->isChecked();
  f.reach_opacity = reach_opacity_slider_->value() / 100.0;
  f.well_conditioned_opacity = well_opacity_slider_->value() / 100.0;
  f.slice_opacity = sliceOpacity();
  return f;
}

void FieldPanel::apply(const FieldSettings& f, const Mechanism& device) {
  const QSignalBlocker b1(field_box_), b2(normal_box_), b3(position_slider_), b4(follow_box_), b5(threshold_box_),
      b6(auto_range_box_), b7(slice_resolution_box_), b8(volume_resolution_box_), b9(show_slice_box_),
      b10(show_reach_box_), b11(show_well_box_), b12(reach_opacity_slider_), b13(well_opacity_slider_),
      b14(method_box_), b15(range_min_box_), b16(range_max_box_), b17(colour_map_box_), b18(log_scale_box_),
      b19(slice_opacity_slider_);
  auto choose = [](QComboBox* box, int index) {
    if (index >= 0) box->setCurrentIndex(index);
  };
  choose(field_box_, field_box_->findData(qs(f.field)));
  choose(method_box_, method_box_->findText(qs(f.method)));
  choose(normal_box_, normal_box_->findText(qs(f.normal)));
  choose(slice_resolution_box_, slice_resolution_box_->findText(QString::number(f.slice_resolution)));
  choose(volume_resolution_box_, volume_resolution_box_->findText(QString::number(f.volume_resolution)));
  follow_box_->setChecked(f.follow_endpoint);
  threshold_box_->setValue(f.threshold);
  choose(colour_map_box_, colour_map_box_->findText(qs(f.colour_map)));
  log_scale_box_->setChecked(f.log_scale);
  auto_range_box_->setChecked(!(f.range_min && f.range_max));
  if (f.range_min) range_min_box_->setValue(*f.range_min);
  if (f.range_max) range_max_box_->setValue(*f.range_max);
  show_slice_box_->setChecked(f.show_slice);
  show_reach_box_->setChecked(f.show_reach);
  show_well_box_->setChecked(f.show_well_conditioned);
  reach_opacity_slider_->setValue(int(std::lround(f.reach_opacity * 100)));
  well_opacity_slider_->setValue(int(std::lround(f.well_conditioned_opacity * 100)));
  slice_opacity_slider_->setValue(int(std::lround(f.slice_opacity * 100)));
  const Eigen::AlignedBox3d box = device.default_box();
  const int n = normal_box_->currentIndex();
  const double half = 0.5 * (box.max()(n) - box.min()(n));
  position_slider_->setValue(int(std::lround((f.position - box.center()(n)) / half * kPositionSteps)));
}

int FieldPanel::fieldBranch() const { return field_branch_box_->currentIndex(); }

void FieldPanel::showFieldBranch(int branch) {
  const QSignalBlocker block(field_branch_box_);
  field_branch_box_->setCurrentIndex(branch);
}

Axis FieldPanel::normal() const { return parse_axis(normal_box_->currentText().toStdString()); }

void FieldPanel::showPosition(double position, const Mechanism& device) {
  const Eigen::AlignedBox3d box = device.default_box();
  const Eigen::Vector3d lo = box.min(), hi = box.max();
  const int n = normal_box_->currentIndex();
  const bool in_plane = sliceInPlane();
  if (follow_box_->isChecked() && !in_plane) {
    const QSignalBlocker block(position_slider_);
    position_slider_->setValue(
        int(std::lround((position - 0.5 * (lo(n) + hi(n))) / (0.5 * (hi(n) - lo(n))) * kPositionSteps)));
  }
  position_slider_->setEnabled(!in_plane);
  follow_box_->setEnabled(!in_plane);
  const QString where = QString("%1 = %2 %3").arg(normal_box_->currentText(), fixed(position, 2), qs(device.info().length_unit));
  position_label_->setText(in_plane ? tr("%1, the plane").arg(where)
                                    : QString("%1 (%2 %)").arg(where).arg(std::lround(100.0 * (position - lo(n)) / (hi(n) - lo(n)))));
}

void FieldPanel::showColourRange(double lo, double hi) {
  const QSignalBlocker b1(range_min_box_), b2(range_max_box_);
  range_min_box_->setValue(lo);
  range_max_box_->setValue(hi);
}

void FieldPanel::enableColourRange(bool typed) {
  range_min_box_->setEnabled(typed);
  range_max_box_->setEnabled(typed);
}

}  // namespace linkscape::gui
