// The Animation panel: the driven point follows a circle or a line about
// where it was when Play was pressed, in the slice plane, at a size and
// speed, once or in a loop. The path's target each frame goes to `move_to`
// (inverse kinematics in the current branch; unreachable points are skipped).
#pragma once

#include <Eigen/Core>
#include <QWidget>
#include <functional>

#include "core/field.h"

class QCheckBox;
class QComboBox;
class QDoubleSpinBox;
class QPushButton;
class QTimer;

namespace linkscape::gui {

class AnimationPanel : public QWidget {
  Q_OBJECT

 public:
  struct Hooks {
    std::function<Eigen::Vector3d()> endpoint;  // where the driven point is
    std::function<Axis()> normal;               // the slice plane's normal
    std::function<void(const Eigen::Vector3d&)> move_to;
  };
  // `size`: the path's default radius is 15 % of it, in `length_unit`.
  AnimationPanel(double size, const QString& length_unit, Hooks hooks, QWidget* parent = nullptr);

  bool playing() const;
  void stop();
  // One frame of the path (the timer's step, `dt` seconds).
  void step(double dt);

 signals:
  void playingChanged(bool playing);

 private:
  Hooks hooks_;
  QComboBox* path_box_ = nullptr;
  QDoubleSpinBox *speed_box_ = nullptr, *amplitude_box_ = nullptr;
  QCheckBox* loop_box_ = nullptr;
  QPushButton* play_button_ = nullptr;
  QTimer* timer_ = nullptr;
  double phase_ = 0.0;
  Eigen::Vector3d centre_ = Eigen::Vector3d::Zero();
};

}  // namespace linkscape::gui
