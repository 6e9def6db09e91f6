// The Field panel: which field the slice shows (and by which IK method, in
// which branch), the slice plane, the colour scale, the samples, and which
// of the slice and the workspace surfaces are shown. Built from the
// device's description; its state reads and writes as FieldSettings.
#pragma once

#include <Eigen/Core>
#include <QWidget>
#include <optional>

#include "core/field.h"
#include "core/mechanism.h"
#include "gui/window/session.h"

class QCheckBox;
class QComboBox;
class QDoubleSpinBox;
class QLabel;
class QSlider;

namespace linkscape::gui {

class FieldPanel : public QWidget {
  Q_OBJECT

 public:
  explicit FieldPanel(const Mechanism& device, QWidget* parent = nullptr);

  // The panel's settings; the slice position is where it cuts `device`'s
  // sampling box, or the driven point of the task x while it follows it.
  FieldSettings settings(const Mechanism& device, const Eigen::VectorXd& x) const;
  // Takes the settings the panel offers (quietly); the others stay.
  void apply(const FieldSettings& settings, const Mechanism& device);
  int fieldBranch() const;
  void showFieldBranch(int branch);  // quietly
  Axis normal() const;
  // The slice's position shown (the slider moved there while it follows the driven point).
  void showPosition(double position, const Mechanism& device);
  // The colour range in use shown in the range boxes (quietly).
  void showColourRange(double lo, double hi);
  void enableColourRange(bool typed);
  // The slice's opacity, 0..1 (FieldSettings::slice_opacity).
  double sliceOpacity() const;
  // A planar device's slice in its plane: normal z, which no position changes.
  bool sliceInPlane() const;

 signals:
  void sliceChanged();       // the slice must be sampled again
  void volumeChanged();      // the volume (the surfaces) must be sampled again
  void fieldsChanged();      // both
  void fieldChosen();        // the field shown
  void styleChanged();       // the slice's colours or contour
  void visibilityChanged();  // what is shown, and how opaque

 private:
  QComboBox *field_box_ = nullptr, *method_box_ = nullptr, *normal_box_ = nullptr, *slice_resolution_box_ = nullptr,
            *volume_resolution_box_ = nullptr, *field_branch_box_ = nullptr, *colour_map_box_ = nullptr;
  QSlider* position_slider_ = nullptr;
  QLabel* position_label_ = nullptr;
  QCheckBox *log_scale_box_ = nullptr, *follow_box_ = nullptr, *auto_range_box_ = nullptr, *show_slice_box_ = nullptr,
            *show_reach_box_ = nullptr, *show_well_box_ = nullptr;
  QDoubleSpinBox *threshold_box_ = nullptr, *range_min_box_ = nullptr, *range_max_box_ = nullptr;
  std::optional<double> plane_z_;  // a planar device's plane: its field is the same at every height
  QSlider *reach_opacity_slider_ = nullptr, *well_opacity_slider_ = nullptr, *slice_opacity_slider_ = nullptr;
  bool has_methods_ = false;
};

}  // namespace linkscape::gui
