// The main window: the 3-D view of the linkage and its fields, and the
// docked panels that drive them. It wires panels to core and render; field
// work runs on FieldJobRunner threads, never on the GUI thread.
#pragma once

#include <QMainWindow>
#include <QString>
#include <array>
#include <memory>
#include <string>

#include <Eigen/Core>
#include <vtkSmartPointer.h>

#include "core/parallel12r.h"
#include "core/preset.h"
#include "gui/field_job.h"
#include "gui/headless.h"
#include "gui/session.h"

class QCheckBox;
class QComboBox;
class QDoubleSpinBox;
class QLabel;
class QMenu;
class QProgressBar;
class QPushButton;
class QSlider;
class QTimer;
class vtkCallbackCommand;
class vtkHandleWidget;
class vtkPointHandleRepresentation3D;
class vtkRenderer;

namespace linkscape::render {
class FieldScene;
class LinkageScene;
}  // namespace linkscape::render

namespace linkscape::gui {

class MethodsPanel;
class VtkWidget;

struct WindowOptions {
  MechanismChoice mechanism;
  std::string session;         // open this session file at start
  std::string screenshot;      // save a PNG of the window and exit
  bool latency = false;        // measure interaction latencies, print them and exit
  std::string size = "1280x800";
};

// Opens the window (QApplication lives here). Returns the exit code.
int run_window(const WindowOptions& options, int argc, char** argv);

class MainWindow : public QMainWindow {
  Q_OBJECT

 public:
  explicit MainWindow(const Preset& preset, QWidget* parent = nullptr);
  ~MainWindow() override;

  const parallel12r::Model& model() const;
  Eigen::Vector3d pose() const { return q_; }
  int branch() const { return parallel12r::branch_of(q_); }
  VtkWidget* view() const { return view_; }
  const render::FieldScene& fieldScene() const { return *field_scene_; }
  // True once the latest field request has been answered at full resolution.
  bool fieldsSettled() const { return slice_settled_ && surfaces_settled_; }
  QString endpointMessage() const;
  Session session() const;

 public slots:
  // Moves the linkage to q = (alpha, beta, gamma) in rad; sliders follow.
  void setPose(const Eigen::Vector3d& q_actuated);
  // New link lengths; the pose is kept; fields are recomputed.
  void setLinkLengths(double L1, double L2);
  // New actuator ranges (alpha, beta, gamma; degrees): sliders follow, the
  // pose is clamped into them, fields are recomputed. An empty or inverted
  // range is refused with a message and the ranges stay as they were.
  void setActuatorRanges(const std::array<parallel12r::Interval, 3>& ranges_deg);
  // Inverse kinematics to `target`. Without `branch` (drags, animation) the
  // current branch is tracked and a target that would make the linkage jump
  // is refused; with it (typed targets) any pose of that branch is taken.
  // Leaves the pose unchanged and says why when the target is refused.
  bool moveEndpointTo(const Eigen::Vector3d& target, int branch = -1);
  void applySession(const Session& session);
  bool openSession(const QString& path);
  bool saveSession(const QString& path);

 signals:
  void poseChanged();
  void fieldsUpdated(bool fine);
  // The slice or the isosurfaces were replaced (coarse or full resolution).
  void sliceUpdated(bool fine);
  void surfacesUpdated(bool fine);

 protected:
  void closeEvent(QCloseEvent* event) override;

 private:
  QWidget* buildMechanismPanel();
  QWidget* buildActuatorPanel();
  QWidget* buildEndpointPanel();
  QWidget* buildFieldPanel();
  QWidget* buildAnimationPanel();
  void buildMenus();
  void updateReadouts();
  void requestFields(bool slice, bool volume);
  void restyleSlice();
  void applyFieldVisibility();
  void onSlice(const SliceResult& result);
  void onSurfaces(const SurfaceResult& result);
  void animationStep();
  void addRecent(const QString& path);
  void rebuildRecentMenu();
  void exportSliceImage();
  FieldSettings fieldSettingsFromPanel() const;
  void placeHandle();
  void syncRangeBoxes();

  Preset preset_;
  std::unique_ptr<render::LinkageScene> scene_;
  std::unique_ptr<render::FieldScene> field_scene_;
  vtkRenderer* renderer_ = nullptr;  // owned by the view's render window
  VtkWidget* view_ = nullptr;
  Eigen::Vector3d q_;
  FieldJobRunner slice_runner_, volume_runner_;
  std::shared_ptr<const Field> slice_field_, volume_field_;
  vtkSmartPointer<vtkPolyData> reach_mesh_, well_mesh_;
  bool slice_settled_ = false, surfaces_settled_ = false;

  // Endpoint dragging in the view.
  vtkSmartPointer<vtkHandleWidget> handle_;
  vtkSmartPointer<vtkPointHandleRepresentation3D> handle_rep_;
  vtkSmartPointer<vtkCallbackCommand> handle_callback_;

  // Panels.
  std::array<QDoubleSpinBox*, 2> length_boxes_{};
  std::array<std::array<QDoubleSpinBox*, 2>, 3> limit_boxes_{};  // [actuator][min, max], degrees
  std::array<QSlider*, 2> length_sliders_{};
  std::array<QSlider*, 3> sliders_{};
  std::array<QDoubleSpinBox*, 3> angle_boxes_{};
  QLabel *endpoint_label_ = nullptr, *cond_label_ = nullptr, *det_label_ = nullptr, *singular_label_ = nullptr,
         *branch_label_ = nullptr;
  std::array<QDoubleSpinBox*, 3> target_boxes_{};
  QComboBox* branch_box_ = nullptr;
  QLabel* endpoint_status_ = nullptr;
  QComboBox *field_box_ = nullptr, *normal_box_ = nullptr, *slice_resolution_box_ = nullptr,
            *volume_resolution_box_ = nullptr, *method_box_ = nullptr;
  QSlider* position_slider_ = nullptr;
  QLabel* position_label_ = nullptr;
  QCheckBox *follow_box_ = nullptr, *auto_range_box_ = nullptr, *show_slice_box_ = nullptr, *show_reach_box_ = nullptr,
            *show_well_box_ = nullptr;
  QDoubleSpinBox *threshold_box_ = nullptr, *range_min_box_ = nullptr, *range_max_box_ = nullptr;
  QSlider *reach_opacity_slider_ = nullptr, *well_opacity_slider_ = nullptr;
  QComboBox* path_box_ = nullptr;
  QDoubleSpinBox *speed_box_ = nullptr, *amplitude_box_ = nullptr;
  QCheckBox* loop_box_ = nullptr;
  QPushButton* play_button_ = nullptr;
  QTimer* animation_timer_ = nullptr;
  double animation_phase_ = 0.0;
  Eigen::Vector3d animation_centre_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d animation_pose_ = Eigen::Vector3d::Zero();
  QMenu* recent_menu_ = nullptr;
  QLabel* compute_label_ = nullptr;  // in the status bar (window_parts.h)
  QString endpoint_message_;
  MethodsPanel* methods_ = nullptr;
};

}  // namespace linkscape::gui
