// The main window: the 3-D view of the linkage and the panels that drive it.
#pragma once

#include <QMainWindow>
#include <QString>
#include <array>
#include <memory>
#include <string>

#include <Eigen/Core>

#include "core/parallel12r.h"
#include "core/preset.h"
#include "gui/headless.h"

class QDoubleSpinBox;
class QLabel;
class QSlider;
class vtkRenderer;

namespace linkscape::render {
class LinkageScene;
}

namespace linkscape::gui {

class VtkWidget;

struct WindowOptions {
  MechanismChoice mechanism;
  std::string screenshot;      // save a PNG of the window and exit
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
  VtkWidget* view() const { return view_; }

 public slots:
  // Moves the linkage to q = (alpha, beta, gamma) in rad; sliders follow.
  void setPose(const Eigen::Vector3d& q_actuated);
  // New link lengths; the pose is kept.
  void setLinkLengths(double L1, double L2);

 signals:
  void poseChanged();

 private:
  QWidget* buildActuatorPanel();
  QWidget* buildMechanismPanel();
  void updateReadouts();

  Preset preset_;
  std::unique_ptr<render::LinkageScene> scene_;
  vtkRenderer* renderer_ = nullptr;  // owned by the view's render window
  VtkWidget* view_ = nullptr;
  Eigen::Vector3d q_;
  std::array<QSlider*, 3> sliders_{};
  std::array<QDoubleSpinBox*, 3> angle_boxes_{};
  std::array<QDoubleSpinBox*, 2> length_boxes_{};
  QLabel* endpoint_label_ = nullptr;
  QLabel* cond_label_ = nullptr;
  QLabel* det_label_ = nullptr;
  QLabel* singular_label_ = nullptr;
  QLabel* branch_label_ = nullptr;
};

}  // namespace linkscape::gui
