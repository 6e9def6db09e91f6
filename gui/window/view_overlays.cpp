#include "gui/window/view_overlays.h"

#include <algorithm>

#include <QAction>
#include <QMenu>

#include <stdexcept>

#include "core/force_ellipsoid.h"
#include "gui/window/device_state.h"
#include "gui/window/vtk_widget.h"
#include "render/capsule_scene.h"
#include "render/force_ellipsoid_scene.h"

namespace linkscape::gui {

namespace {
// The ellipsoid's largest semi-axis, where the scale is chosen, as a fraction of the device's size.
constexpr double kEllipsoidSize = 0.25;
constexpr haptics::TorqueRating kRating = haptics::TorqueRating::Continuous;  // as the Drive tab's forces
}  // namespace

ViewOverlays::ViewOverlays(const DeviceState& state, vtkRenderer* renderer, VtkWidget* view, QObject* parent)
    : QObject(parent),
      state_(state),
      view_(view),
      capsules_(std::make_unique<render::CapsuleScene>()),
      ellipsoid_(std::make_unique<render::ForceEllipsoidScene>()) {
  capsules_->add_to(renderer);
  ellipsoid_->add_to(renderer);
  capsules_->set_visible(false);
  ellipsoid_->set_visible(false);
}

ViewOverlays::~ViewOverlays() = default;

std::pair<QAction*, QAction*> ViewOverlays::addActions(QMenu* menu) {
  QAction* capsules = menu->addAction(tr("Show link &capsules"));
  capsules->setObjectName("showLinkCapsules");
  capsules->setCheckable(true);  // its status tip follows the device (followDevice)
  QAction* ellipsoid = menu->addAction(tr("Show force &ellipsoid"));
  ellipsoid->setObjectName("showForceEllipsoid");
  ellipsoid->setCheckable(true);
  ellipsoid->setStatusTip(tr("At the driven point, the forces the motors exert within their continuous torques "
                             "(sum of squared torque fractions at most 1), with its semi-axes"));
  return {capsules, ellipsoid};
}

void ViewOverlays::connectActions(QAction* capsules, QAction* ellipsoid) {
  capsules_action_ = capsules;
  followDevice();
  connect(capsules, &QAction::toggled, this, [this](bool on) {
    show_capsules_ = on;
    update();
  });
  connect(ellipsoid, &QAction::toggled, this, [this](bool on) {
    show_ellipsoid_ = on;
    update();
  });
  // Checked on every device (disabled where it states no link radii): a
  // window hands its toggles to the next one (sessions, another device),
  // and a device that states link radii then keeps its default.
  capsules->setChecked(true);
  ellipsoid->setChecked(false);
}

// The capsules are offered while the device checks link radii (its
// clearance field): a design switched to --interference off and back takes
// the toggle with it.
void ViewOverlays::followDevice() {
  const std::vector<NamedItem>& extras = state_.mechanism().info().extra_fields;
  const bool has_links =
      std::any_of(extras.begin(), extras.end(), [](const NamedItem& f) { return f.name == "clearance"; });
  capsules_action_->setEnabled(has_links);
  capsules_action_->setStatusTip(has_links ? tr("The links as the capsules interference is checked with, the closest "
                                                "pair highlighted with its clearance")
                                           : tr("This device states no link radii"));
}

void ViewOverlays::update() {
  if (capsules_action_) followDevice();
  capsules_->set_visible(show_capsules_);
  ellipsoid_->set_visible(show_ellipsoid_);
  if (show_capsules_) drawCapsules();
  if (show_ellipsoid_) drawEllipsoid();
  view_->requestRender();
}

void ViewOverlays::drawCapsules() {
  try {
    const auto links = state_.mechanism().link_capsules(state_.actuators(), state_.task());
    if (links) capsules_->set_links(*links, state_.mechanism().info().length_unit);
    else capsules_->set_visible(false);
  } catch (const std::invalid_argument&) {
    capsules_->set_visible(false);  // a pose that does not assemble: the skeleton says why
  }
}

void ViewOverlays::drawEllipsoid() {
  const Mechanism& m = state_.mechanism();
  const Eigen::Vector3d centre = state_.endpoint();
  try {
    const haptics::DeviceData data = haptics::device_data(state_.preset(), m.info());
    const Eigen::MatrixXd J = m.jacobian(state_.actuators(), state_.task());
    const haptics::ForceEllipsoid e = haptics::force_ellipsoid(J, data, kRating);
    if (e.status != Status::Ok || m.measures(state_.actuators(), state_.task()).status == Status::Singular) {
      ellipsoid_->set_hidden(centre, tr("the pose is singular").toStdString());
      return;
    }
    if (scaled_for_.lock() != state_.shared_mechanism()) {
      length_per_N_ = render::length_per_newton(e.semi_axes_N(0), kEllipsoidSize * m.size());
      scaled_for_ = state_.shared_mechanism();
    }
    const haptics::Measures h = haptics::measures(J, data, kRating);
    ellipsoid_->set_ellipsoid(
        {centre, e, length_per_N_, h.force_iso_N, h.force_max_N, m.info().length_unit, haptics::to_string(kRating)});
  } catch (const std::invalid_argument& error) {  // no ratings, or a length unit forces cannot use
    ellipsoid_->set_hidden(centre, error.what());
  }
}

}  // namespace linkscape::gui
