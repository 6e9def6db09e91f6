// The view's overlays as props (render/capsule_scene.h,
// render/force_ellipsoid_scene.h): each capsule's drawn surface round its
// link's segment at its radius, the closest pair, its gap and label; the
// ellipsoid's drawn surface where the rated-torque fractions have norm 1
// and its axes at the semi-axes; props reused across poses. No rendering:
// no display needed.
#include <gtest/gtest.h>
#include <vtkActor.h>
#include <vtkActor2D.h>
#include <vtkCamera.h>
#include <vtkCommand.h>
#include <vtkCoordinate.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkTextActor.h>
#include <vtkTextProperty.h>
#include <vtkAlgorithm.h>
#include <vtkLineSource.h>
#include <vtkMapper.h>
#include <vtkMapper2D.h>
#include <vtkMatrix4x4.h>
#include <vtkPolyData.h>
#include <vtkProperty.h>

#include <cmath>

#include "core/force_ellipsoid.h"
#include "core/mechanism.h"
#include "core/preset.h"
#include "render/capsule_scene.h"
#include "render/force_ellipsoid_scene.h"
#include "tests/render/offscreen_view.h"

namespace linkscape::render {
namespace {

using Eigen::Vector3d;
using interference::LinkCapsules;

// The actor's drawn points in the base frame.
std::vector<Vector3d> drawn_points(vtkActor* actor) {
  vtkAlgorithm* source = actor->GetMapper()->GetInputAlgorithm();
  source->Update();
  vtkPolyData* poly = vtkPolyData::SafeDownCast(source->GetOutputDataObject(0));
  vtkMatrix4x4* m = actor->GetMatrix();
  std::vector<Vector3d> out;
  for (vtkIdType i = 0; i < poly->GetNumberOfPoints(); ++i) {
    double p[4] = {0, 0, 0, 1}, w[4];
    poly->GetPoint(i, p);
    m->MultiplyPoint(p, w);
    out.push_back(Vector3d(w[0], w[1], w[2]));
  }
  return out;
}

double to_segment(const Vector3d& p, const Vector3d& a, const Vector3d& b) {
  const Vector3d d = b - a;
  const double t = d.squaredNorm() > 0 ? std::clamp((p - a).dot(d) / d.squaredNorm(), 0.0, 1.0) : 0.0;
  return (p - (a + t * d)).norm();
}

LinkCapsules three_links(double gap) {
  LinkCapsules c;
  c.links = {{{Vector3d(0, 0, 0), Vector3d(3, 1, 2), 0.5}, "leg 1 thigh", 0, true},
             {{Vector3d(0, 2 + gap, 0), Vector3d(0, 2 + gap, 4), 0.5}, "leg 2 shin", 1, true},
             {{Vector3d(-5, -5, -5), Vector3d(-5, -5, -1), 1.0}, "leg 3 shin", 2, true}};
  // The first two the closest pair, their axes sqrt(0.9) (2 + gap) apart (radii 0.5 each).
  interference::set_closest(c, 0, 1);
  return c;
}

// Each capsule is drawn round its link: every drawn point is its radius
// from the segment, and the drawing reaches round both ends.
TEST(CapsuleScene, EachCapsuleIsDrawnRoundItsLink) {
  CapsuleScene scene;
  const LinkCapsules c = three_links(1.0);
  scene.set_links(c, "mm");
  ASSERT_EQ(scene.link_count(), 3);
  for (int i = 0; i < 3; ++i) {
    const interference::Capsule& k = c.links[std::size_t(i)].capsule;
    const Vector3d u = (k.b - k.a).normalized();
    double lo = INFINITY, hi = -INFINITY;
    for (const Vector3d& p : drawn_points(scene.link_actor(i))) {
      EXPECT_NEAR(to_segment(p, k.a, k.b), k.radius, 1e-6 * k.radius) << "link " << i;
      lo = std::min(lo, (p - k.a).dot(u));
      hi = std::max(hi, (p - k.a).dot(u));
    }
    // The caps' tessellation has no vertex at the poles: within a tenth of the radius of them.
    EXPECT_LT(lo, -0.9 * k.radius);
    EXPECT_GT(hi, (k.b - k.a).norm() + 0.9 * k.radius);
  }
}

TEST(CapsuleScene, TheClosestPairIsHighlightedWithItsGap) {
  CapsuleScene scene;
  LinkCapsules c = three_links(1.0);
  scene.set_links(c, "mm");
  EXPECT_EQ(scene.gap(), CapsuleScene::Gap::Apart);
  double pair[3], other[3];
  scene.link_actor(0)->GetProperty()->GetColor(pair);
  scene.link_actor(2)->GetProperty()->GetColor(other);
  EXPECT_GT(std::abs(pair[0] - other[0]) + std::abs(pair[2] - other[2]), 0.5);
  EXPECT_GT(scene.link_actor(1)->GetProperty()->GetOpacity(), scene.link_actor(2)->GetProperty()->GetOpacity());
  // The line spans the gap between the surfaces.
  auto* line = vtkLineSource::SafeDownCast(scene.gap_line()->GetMapper()->GetInputAlgorithm());
  const auto ends = c.gap();
  EXPECT_LT((Vector3d(line->GetPoint1()) - ends[0]).norm(), 1e-12);
  EXPECT_LT((Vector3d(line->GetPoint2()) - ends[1]).norm(), 1e-12);
  EXPECT_TRUE(scene.gap_line()->GetVisibility());
  char expected[32];
  std::snprintf(expected, sizeof expected, "clearance %.3g mm", c.clearance);
  EXPECT_NE(scene.label_text().find(expected), std::string::npos) << scene.label_text();
  EXPECT_NE(scene.label_text().find("leg 1 thigh to leg 2 shin"), std::string::npos);
  // Closer than the thinner link's radius, then overlapping: the pair turns
  // vermillion and the label says so.
  scene.set_links(three_links(-0.8), "mm");
  EXPECT_EQ(scene.gap(), CapsuleScene::Gap::Close);
  EXPECT_EQ(scene.label_text().rfind("close", 0), 0u) << scene.label_text();
  scene.set_links(three_links(-1.5), "mm");
  EXPECT_EQ(scene.gap(), CapsuleScene::Gap::Overlap);
  EXPECT_EQ(scene.label_text().rfind("overlap", 0), 0u) << scene.label_text();
  double close[3];
  scene.link_actor(0)->GetProperty()->GetColor(close);
  EXPECT_GT(std::abs(close[1] - pair[1]), 0.15);  // orange to vermillion
}

// The label stands beside the gap on the screen, on the side away from the
// links' centre, so that it does not cover the linkage's joints and labels.
TEST(CapsuleScene, TheLabelStandsOffTheGapAwayFromTheLinks) {
  vtkNew<vtkRenderer> renderer;
  vtkNew<vtkRenderWindow> window;
  offscreen_view::set_up(window, renderer, {0, 0, 50}, {0, 1, 0}, 10);  // looking down z, x to the right
  CapsuleScene scene;
  scene.add_to(renderer);
  for (const double shift : {-20.0, 20.0}) {  // the pair left of the third link, then right of it
    LinkCapsules c = three_links(1.0);
    c.links[2].capsule.a.x() -= shift;
    c.links[2].capsule.b.x() -= shift;
    scene.set_links(c, "mm");
    const auto ends = c.gap();
    vtkNew<vtkCoordinate> at;
    at->SetCoordinateSystemToWorld();
    const Vector3d middle = 0.5 * (ends[0] + ends[1]);
    at->SetValue(middle.data());
    const double gap_x = at->GetComputedDoubleDisplayValue(renderer)[0];
    const double label_x = scene.label()->GetPositionCoordinate()->GetComputedDoubleDisplayValue(renderer)[0];
    // The third link's centre lies on the side `shift` points away from.
    EXPECT_GT(shift > 0 ? label_x - gap_x : gap_x - label_x, 10) << "shift " << shift;
    // Seen from below (x now to the left on the screen), the next frame puts it on the other side.
    renderer->GetActiveCamera()->SetPosition(0, 0, -50);
    renderer->InvokeEvent(vtkCommand::StartEvent);  // what a frame starts with
    const double turned_gap_x = at->GetComputedDoubleDisplayValue(renderer)[0];
    const double turned_x = scene.label()->GetPositionCoordinate()->GetComputedDoubleDisplayValue(renderer)[0];
    EXPECT_GT(shift > 0 ? turned_gap_x - turned_x : turned_x - turned_gap_x, 10) << "shift " << shift;
    renderer->GetActiveCamera()->SetPosition(0, 0, 50);
  }
}

TEST(CapsuleScene, PosesReuseTheActors) {
  CapsuleScene scene;
  scene.set_links(three_links(1.0), "mm");
  vtkActor* first = scene.link_actor(2);
  scene.set_links(three_links(2.0), "mm");
  EXPECT_EQ(scene.link_actor(2), first);
  // Fewer links: the rest hidden; none: no pair drawn.
  LinkCapsules two = three_links(1.0);
  two.links.pop_back();
  scene.set_links(two, "mm");
  EXPECT_EQ(scene.link_count(), 2);
  EXPECT_FALSE(first->GetVisibility());
  scene.set_links(LinkCapsules{}, "mm");
  EXPECT_EQ(scene.gap(), CapsuleScene::Gap::None);
  EXPECT_FALSE(scene.gap_line()->GetVisibility());
  scene.set_links(three_links(1.0), "mm");
  scene.set_visible(false);
  EXPECT_FALSE(scene.link_actor(0)->GetVisibility());
  EXPECT_FALSE(scene.gap_line()->GetVisibility());
  LinkCapsules bad = three_links(1.0);
  bad.links[1].capsule.a.x() = NAN;
  EXPECT_THROW(scene.set_links(bad, "mm"), std::invalid_argument);
}

// The Falcon at home: the drawn capsules round the links the device states.
TEST(CapsuleScene, FalconsLinksAreDrawnWhereTheDevicePutsThem) {
  const auto falcon = make_mechanism(load_preset("falcon"));
  const auto links = falcon->link_capsules(falcon->home_actuators(), falcon->home_task());
  ASSERT_TRUE(links && links->has_pair());
  CapsuleScene scene;
  scene.set_links(*links, "mm");
  ASSERT_EQ(scene.link_count(), int(links->links.size()));
  for (int i = 0; i < scene.link_count(); ++i) {
    const interference::Capsule& k = links->links[std::size_t(i)].capsule;
    for (const Vector3d& p : drawn_points(scene.link_actor(i))) ASSERT_NEAR(to_segment(p, k.a, k.b), k.radius, 1e-6);
  }
}

haptics::DeviceData falcon_data(const Mechanism& m) { return haptics::device_data(load_preset("falcon"), m.info()); }

// |W^-1 J_p^T F| for F in N, J in the device's unit per radian.
double torque_fraction(const Eigen::MatrixXd& J, const haptics::DeviceData& d, const Eigen::VectorXd& F) {
  Eigen::VectorXd tau = J.topRows(d.position_rows).transpose() * F;
  for (Eigen::Index i = 0; i < tau.size(); ++i)
    tau(i) *= d.metres_per_motor_radian(std::size_t(i)) / d.actuators[std::size_t(i)].continuous_torque_Nm;
  return tau.norm();
}

TEST(ForceEllipsoidScene, TheDrawnSurfaceNeedsTheRatedTorquesExactly) {
  const auto falcon = make_mechanism(load_preset("falcon"));
  const haptics::DeviceData d = falcon_data(*falcon);
  const Eigen::MatrixXd J = falcon->jacobian(falcon->home_actuators(), falcon->home_task());
  const haptics::ForceEllipsoid e = haptics::force_ellipsoid(J, d, haptics::TorqueRating::Continuous);
  ForceEllipsoidScene scene;
  const Vector3d centre = falcon->home_task().head<3>();
  const double scale = length_per_newton(e.semi_axes_N(0), 50);
  scene.set_ellipsoid({centre, e, scale, 1.0, 2.0, "mm", "continuous"});
  ASSERT_TRUE(scene.shape_shown());
  // Every drawn point, read as a force, is on the unit sphere of torque fractions.
  for (const Vector3d& p : drawn_points(scene.shape_actor()))
    ASSERT_NEAR(torque_fraction(J, d, (p - centre) / scale), 1.0, 1e-9);
  for (int k = 0; k < 3; ++k)
    EXPECT_LT((scene.axis_tip(k) - centre - scale * e.semi_axes_N(k) * e.axes.col(k)).norm(), 1e-9);
  EXPECT_NE(scene.label_text().find("drawn at"), std::string::npos);
  scene.set_hidden(centre, "the pose is singular");
  EXPECT_FALSE(scene.shape_shown());
  EXPECT_FALSE(scene.shape_actor()->GetVisibility());
  EXPECT_NE(scene.label_text().find("the pose is singular"), std::string::npos);
  EXPECT_THROW(scene.axis_tip(0), std::out_of_range);
}

TEST(ForceEllipsoidScene, APlanarDevicesEllipseLiesInItsPlane) {
  const Preset preset = load_preset("five-bar");
  const auto m = make_mechanism(preset);
  const haptics::DeviceData d = haptics::device_data(preset, m->info());
  const Eigen::MatrixXd J = m->jacobian(m->home_actuators(), m->home_task());
  const haptics::ForceEllipsoid e = haptics::force_ellipsoid(J, d, haptics::TorqueRating::Continuous);
  ASSERT_EQ(e.semi_axes_N.size(), 2);
  ForceEllipsoidScene scene;
  const Vector3d centre = m->home_task().head<3>();
  scene.set_ellipsoid({centre, e, 0.1, 1, 2, "cm", "continuous"});
  double largest = 0;
  for (const Vector3d& p : drawn_points(scene.shape_actor())) {
    ASSERT_NEAR(p.z(), centre.z(), 1e-12);
    const double f = torque_fraction(J, d, ((p - centre) / 0.1).head<2>());
    ASSERT_LE(f, 1 + 1e-9);  // the disk's rim on the ellipse, its centre inside
    largest = std::max(largest, f);
  }
  EXPECT_NEAR(largest, 1.0, 1e-9);
  EXPECT_THROW(scene.axis_tip(2), std::out_of_range);
}

TEST(ForceEllipsoidScene, OnlyABoundedEllipsoidIsDrawn) {
  ForceEllipsoidScene scene;
  haptics::ForceEllipsoid e;
  e.semi_axes_N = Eigen::Vector3d(INFINITY, 2, 1);
  e.axes = Eigen::Matrix3d::Identity();
  e.status = Status::Singular;
  EXPECT_THROW(scene.set_ellipsoid({Vector3d::Zero(), e, 1, 1, 1, "mm", "continuous"}), std::invalid_argument);
  e.semi_axes_N(0) = 3;
  e.status = Status::Ok;
  EXPECT_THROW(scene.set_ellipsoid({Vector3d::Zero(), e, 0, 1, 1, "mm", "continuous"}), std::invalid_argument);
  EXPECT_FALSE(scene.shape_shown());
}

TEST(ForceEllipsoidScene, TheScaleIsOneTwoOrFiveTimesAPowerOfTen) {
  EXPECT_DOUBLE_EQ(length_per_newton(10, 50), 5);
  EXPECT_DOUBLE_EQ(length_per_newton(4, 50), 10);    // 12.5: nearer 10 than 20
  EXPECT_DOUBLE_EQ(length_per_newton(3, 0.5), 0.2);  // 0.167
  for (double f : {0.013, 0.7, 3.3, 81.0, 4e3}) {
    const double s = length_per_newton(f, 10);
    const double mantissa = s / std::pow(10.0, std::floor(std::log10(s) + 1e-12));
    EXPECT_TRUE(std::abs(mantissa - 1) < 1e-9 || std::abs(mantissa - 2) < 1e-9 || std::abs(mantissa - 5) < 1e-9) << s;
    EXPECT_LT(std::abs(std::log(s * f / 10)), std::log(2.5));
  }
  EXPECT_THROW(length_per_newton(0, 1), std::invalid_argument);
  EXPECT_THROW(length_per_newton(INFINITY, 1), std::invalid_argument);
}

}  // namespace
}  // namespace linkscape::render
