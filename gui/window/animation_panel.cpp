#include "gui/window/animation_panel.h"

#include <QCheckBox>
#include <QComboBox>
#include <QDoubleSpinBox>
#include <QFormLayout>
#include <QLabel>
#include <QPushButton>
#include <QTimer>
#include <cmath>
#include <numbers>

#include "gui/window/quantity_control.h"

namespace linkscape::gui {

AnimationPanel::AnimationPanel(double size, const QString& length_unit, Hooks hooks, QWidget* parent)
    : QWidget(parent), hooks_(std::move(hooks)) {
  QWidget* w = this;
  auto* form = new QFormLayout(w);
  path_box_ = new QComboBox(w);
  path_box_->setObjectName("pathBox");
  path_box_->addItems({tr("Circle around the driven point (slice plane)"),
                       tr("Line through the driven point (slice's first axis)")});
  path_box_->setToolTip(tr("The path the driven point follows while playing"));
  form->addRow(tr("Path"), path_box_);
  amplitude_box_ = spin(w, 0.0, 1e4, 0.15 * size, 2, " " + length_unit);
  amplitude_box_->setObjectName("amplitudeBox");
  amplitude_box_->setToolTip(tr("Radius of the circle or half-length of the line"));
  form->addRow(tr("Size"), amplitude_box_);
  speed_box_ = spin(w, 0.01, 100.0, 0.5, 2, tr(" cycles/s"));
  speed_box_->setToolTip(tr("Turns of the circle, or back-and-forth sweeps of the line, per second"));
  form->addRow(tr("Speed"), speed_box_);
  loop_box_ = new QCheckBox(tr("Loop"), w);
  loop_box_->setToolTip(tr("Play again from the start at the end of the path"));
  loop_box_->setChecked(true);
  form->addRow(loop_box_);
  play_button_ = new QPushButton(tr("Play"), w);
  play_button_->setObjectName("playButton");
  play_button_->setToolTip(tr("Move the driven point along the path (again to stop)"));
  play_button_->setCheckable(true);
  form->addRow(play_button_);
  form->addRow(new QLabel(tr("The path is followed by inverse kinematics in the current branch;\n"
                             "points the device cannot reach are skipped."), w));
  connect(play_button_, &QPushButton::toggled, this, [this](bool on) {
    play_button_->setText(on ? tr("Pause") : tr("Play"));
    if (on) {
      if (phase_ == 0.0) centre_ = hooks_.endpoint();
      timer_->start();
    } else {
      timer_->stop();
    }
    emit playingChanged(on);
  });
  connect(path_box_, &QComboBox::currentIndexChanged, this, [this] { phase_ = 0.0; });
  timer_ = new QTimer(this);
  timer_->setInterval(33);
  connect(timer_, &QTimer::timeout, this, [this] { step(timer_->interval() / 1000.0); });
}

bool AnimationPanel::playing() const { return timer_->isActive(); }

void AnimationPanel::stop() { timer_->stop(); }

void AnimationPanel::step(double dt) {
  phase_ += speed_box_->value() * dt;
  if (phase_ >= 1.0) {
    if (!loop_box_->isChecked()) {
      play_button_->setChecked(false);
      phase_ = 0.0;
      return;
    }
    phase_ -= 1.0;
  }
  const double angle = 2 * std::numbers::pi * phase_;
  const auto [u, v] = Grid::slice_axes(hooks_.normal());
  Eigen::Vector3d offset = Eigen::Vector3d::Zero();
  const double a = amplitude_box_->value();
  if (path_box_->currentIndex() == 0) {
    offset(int(u)) = a * std::cos(angle) - a;  // starts at the driven point
    offset(int(v)) = a * std::sin(angle);
  } else {
    offset(int(u)) = a * std::sin(angle);
  }
  hooks_.move_to(centre_ + offset);  // an unreachable point is skipped, the panel says why
}

}  // namespace linkscape::gui
