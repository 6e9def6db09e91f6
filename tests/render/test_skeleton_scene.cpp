// SkeletonScene: prop bookkeeping, geometry built once per model, pose as
// matrices only, and offscreen renders (tests/with-xvfb.sh in ctest) checked
// pixel by pixel against where the bodies must appear.
#include <gtest/gtest.h>
#include <vtkActor.h>
#include <vtkBillboardTextActor3D.h>
#include <vtkCamera.h>
#include <vtkDataArray.h>
#include <vtkImageData.h>
#include <vtkMatrix4x4.h>
#include <vtkNew.h>
#include <vtkPNGReader.h>
#include <vtkPlaneSource.h>
#include <vtkPointData.h>
#include <vtkProperty.h>
#include <vtkPolyData.h>
#include <vtkPolyDataMapper.h>
#include <vtkPropCollection.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkTextActor.h>
#include <vtkTubeFilter.h>
#include <vtkWindowToImageFilter.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <numbers>
#include <set>
#include <stdexcept>
#include <utility>

#include "offscreen_view.h"
#include "render/image_io.h"
#include "render/skeleton_scene.h"

using namespace linkscape;
using render::SkeletonScene;

namespace {

constexpr double kScale = 3.0;

// A ground body (a bar along x at y = -1.35 and a square plate at the upper
// right) and one moving link from its frame's origin to (1, 0, 0), hinged at
// the origin about z (actuated, labelled) with a ball joint at its tip.
SkeletonModel two_bodies(double scale = kScale) {
  SkeletonModel m;
  m.scale = scale;
  Body ground;
  ground.name = "base";
  ground.ground = true;
  ground.polylines = {{{-1.5, -1.35, 0}, {1.5, -1.35, 0}}};
  ground.faces = {{{0.9, 0.6, -0.1}, {1.4, 0.6, -0.1}, {1.4, 1.1, -0.1}, {0.9, 1.1, -0.1}}};
  Body link;
  link.name = "link";
  link.polylines = {{{0, 0, 0}, {1, 0, 0}}};
  m.bodies = {ground, link};
  Joint hinge;
  hinge.name = "hinge";
  hinge.type = JointType::Revolute;
  hinge.body = 1;
  hinge.axis_body_joint = Eigen::Vector3d::UnitZ();
  hinge.actuated = true;
  hinge.label = "q1";
  Joint tip;
  tip.name = "tip";
  tip.type = JointType::Spherical;
  tip.body = 1;
  tip.p_body_joint = {1, 0, 0};
  m.joints = {hinge, tip};
  return m;
}

// The link turned by `angle` about z; the endpoint at its tip.
SkeletonPose link_at(double angle, BodyState link_state = BodyState::Normal) {
  SkeletonPose p;
  p.X_world_body = {Eigen::Isometry3d::Identity(), Eigen::Isometry3d(Eigen::AngleAxisd(angle, Eigen::Vector3d::UnitZ()))};
  p.states = {BodyState::Normal, link_state};
  p.p_world_endpoint = p.X_world_body[1] * Eigen::Vector3d(1, 0, 0);
  return p;
}

int view_prop_count(vtkRenderer* renderer) { return renderer->GetViewProps()->GetNumberOfItems(); }

bool has_view_prop(vtkRenderer* renderer, vtkProp* prop) { return renderer->GetViewProps()->IsItemPresent(prop) != 0; }

Eigen::Matrix4d to_eigen(vtkMatrix4x4* m) {
  Eigen::Matrix4d out;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) out(r, c) = m->GetElement(r, c);
  return out;
}

vtkTubeFilter* tube_of(vtkActor* actor) { return vtkTubeFilter::SafeDownCast(actor->GetMapper()->GetInputAlgorithm()); }

std::array<double, 6> bounds_of(vtkActor* actor) {
  std::array<double, 6> b;
  actor->GetBounds(b.data());
  return b;
}

bool have_display() { return std::getenv("DISPLAY") != nullptr; }

using offscreen_view::Rgb;

// An offscreen 400 x 300 view looking down -z at the origin with parallel
// projection: 100 pixels per length unit, world (0, 0) at pixel (200, 150),
// x to the right, y up.
struct TopView {
  vtkNew<vtkRenderer> renderer;
  vtkNew<vtkRenderWindow> window;

  TopView() {
    renderer->SetBackground(1, 1, 1);
    window->SetOffScreenRendering(1);
    window->SetSize(400, 300);
    window->SetMultiSamples(0);
    window->AddRenderer(renderer);
    vtkCamera* camera = renderer->GetActiveCamera();
    camera->ParallelProjectionOn();
    camera->SetFocalPoint(0, 0, 0);
    camera->SetPosition(0, 0, 10);
    camera->SetViewUp(0, 1, 0);
    camera->SetParallelScale(1.5);
    camera->SetClippingRange(1, 20);
  }
  vtkSmartPointer<vtkImageData> grab() { return offscreen_view::grab(window); }
  static Rgb pixel(vtkImageData* image, int x, int y) { return offscreen_view::pixel(image, x, y); }
  static Rgb at(vtkImageData* image, double a, double b) { return offscreen_view::at(image, a, b); }
};

bool is_background(const Rgb& c) { return c[0] == 255 && c[1] == 255 && c[2] == 255; }
bool is_red(const Rgb& c) { return c[0] > 150 && c[0] > 2 * c[1] && c[0] > 2 * c[2]; }

// Red pixels in the square of half-width `half` pixels around world (x, y).
int red_pixels_around(vtkImageData* image, double x, double y, int half) {
  const int cx = int(std::floor(200 + 100 * x)), cy = int(std::floor(150 + 100 * y));
  int n = 0;
  for (int j = cy - half; j <= cy + half; ++j)
    for (int i = cx - half; i <= cx + half; ++i) n += is_red(TopView::pixel(image, i, j)) ? 1 : 0;
  return n;
}

}  // namespace

TEST(SkeletonScene, OnePropPerBodyPartJointLabelEndpointAndAxes) {
  SkeletonScene scene;
  scene.set_model(two_bodies());
  vtkNew<vtkRenderer> renderer;
  scene.add_to(renderer);
  scene.add_to(renderer);  // idempotent
  // ground tube + ground plate + link tube + 2 knuckles + 1 label (and its
  // overlay twin) + endpoint + axes
  EXPECT_EQ(view_prop_count(renderer), 9);
  EXPECT_NE(scene.body_tube_actor(0), nullptr);
  EXPECT_NE(scene.body_face_actor(0), nullptr);
  EXPECT_NE(scene.body_tube_actor(1), nullptr);
  EXPECT_EQ(scene.body_face_actor(1), nullptr);  // the link has no faces
  EXPECT_NE(scene.joint_label(0), nullptr);
  EXPECT_EQ(scene.joint_label(1), nullptr);  // empty label
  EXPECT_STREQ(scene.joint_label(0)->GetInput(), "q1");
  // What a pick lands on is named: the base's tube and plate, the link, both joints, the driven point.
  std::vector<std::string> parts;
  for (const SkeletonScene::Part& p : scene.pickable_parts()) parts.push_back(p.what);
  EXPECT_EQ(parts, (std::vector<std::string>{"link base", "link base", "link link", "joint hinge", "joint tip",
                                             "driven point"}));
  EXPECT_EQ(scene.pickable_parts()[3].actor, scene.joint_actor(0));
  EXPECT_THROW(scene.add_to(nullptr), std::invalid_argument);
  EXPECT_THROW(scene.body_tube_actor(2), std::out_of_range);
  EXPECT_THROW(scene.joint_actor(-1), std::out_of_range);

  // Every knuckle draws one of two shared sources; the hinge a cylinder, the ball a sphere.
  vtkAlgorithm* hinge_source = scene.joint_actor(0)->GetMapper()->GetInputAlgorithm();
  vtkAlgorithm* ball_source = scene.joint_actor(1)->GetMapper()->GetInputAlgorithm();
  EXPECT_STREQ(hinge_source->GetClassName(), "vtkCylinderSource");
  EXPECT_STREQ(ball_source->GetClassName(), "vtkSphereSource");

  // A new model with more bodies and joints: the renderer's props follow,
  // the old ones leave it.
  vtkActor* old_link = scene.body_tube_actor(1);
  SkeletonModel three = two_bodies();
  three.bodies.push_back(three.bodies[1]);
  Joint second = three.joints[0];
  second.body = 2;
  second.label = "q2";
  three.joints.push_back(second);
  scene.set_model(three);
  EXPECT_EQ(view_prop_count(renderer), 9 + 1 + 1 + 2);  // tube, knuckle, label and its overlay
  EXPECT_FALSE(has_view_prop(renderer, old_link));
  EXPECT_TRUE(has_view_prop(renderer, scene.body_tube_actor(2)));
  EXPECT_EQ(scene.joint_actor(2)->GetMapper()->GetInputAlgorithm(), hinge_source);  // still shared

  // An empty model leaves the endpoint and the axes.
  scene.set_model(SkeletonModel{});
  EXPECT_EQ(view_prop_count(renderer), 2);
}

TEST(SkeletonScene, DestroyedSceneLeavesTheRendererEmpty) {
  vtkNew<vtkRenderer> renderer;
  {
    SkeletonScene scene;
    scene.set_model(two_bodies());
    scene.add_to(renderer);
    ASSERT_EQ(view_prop_count(renderer), 9);
  }
  EXPECT_EQ(view_prop_count(renderer), 0);
  // And a renderer destroyed before the scene is forgotten.
  SkeletonScene scene;
  {
    vtkNew<vtkRenderer> short_lived;
    scene.add_to(short_lived);
  }
  EXPECT_NO_THROW(scene.set_model(two_bodies()));
}

TEST(SkeletonScene, PoseSetsMatricesOnlyAndPlacesGeometryInTheBodyFrame) {
  SkeletonScene scene;
  scene.set_model(two_bodies());
  vtkActor* link = scene.body_tube_actor(1);
  vtkActor* ground = scene.body_tube_actor(0);
  vtkTubeFilter* link_tube = tube_of(link);
  ASSERT_NE(link_tube, nullptr);
  vtkPolyData* link_lines = vtkPolyData::SafeDownCast(link_tube->GetInput());
  vtkPolyData* plate_faces = vtkPolyData::SafeDownCast(scene.body_face_actor(0)->GetMapper()->GetInput());
  ASSERT_NE(link_lines, nullptr);
  ASSERT_NE(plate_faces, nullptr);
  link_tube->Update();
  vtkPolyData* tubes_out = link_tube->GetOutput();
  vtkAlgorithm* hinge_source = scene.joint_actor(0)->GetMapper()->GetInputAlgorithm();
  hinge_source->Update();

  const vtkMTimeType lines_time = link_lines->GetMTime(), faces_time = plate_faces->GetMTime();
  const vtkMTimeType tubes_time = tubes_out->GetMTime(), source_time = hinge_source->GetMTime();
  const vtkMTimeType source_output_time = vtkPolyData::SafeDownCast(hinge_source->GetOutputDataObject(0))->GetMTime();

  const double angle = 0.5 * std::numbers::pi;
  const SkeletonPose pose = link_at(angle);
  for (int n = 0; n < 20; ++n) scene.set_pose(link_at(0.05 * n));
  scene.set_pose(pose);
  link_tube->Update();
  hinge_source->Update();

  // Same data objects, not modified, and the tube filter did not re-run.
  EXPECT_EQ(vtkPolyData::SafeDownCast(link_tube->GetInput()), link_lines);
  EXPECT_EQ(link_tube->GetOutput(), tubes_out);
  EXPECT_EQ(link_lines->GetMTime(), lines_time);
  EXPECT_EQ(plate_faces->GetMTime(), faces_time);
  EXPECT_EQ(tubes_out->GetMTime(), tubes_time);
  EXPECT_EQ(hinge_source->GetMTime(), source_time);
  EXPECT_EQ(vtkPolyData::SafeDownCast(hinge_source->GetOutputDataObject(0))->GetMTime(), source_output_time);

  // The matrices are the body frames.
  EXPECT_TRUE(to_eigen(link->GetUserMatrix()).isApprox(pose.X_world_body[1].matrix(), 1e-12));
  EXPECT_TRUE(to_eigen(ground->GetUserMatrix()).isApprox(Eigen::Matrix4d::Identity(), 1e-12));
  // The ball knuckle sits at the link's tip in the base frame: (0, 1, 0).
  const Eigen::Vector3d ball = to_eigen(scene.joint_actor(1)->GetUserMatrix()).block<3, 1>(0, 3);
  EXPECT_LT((ball - Eigen::Vector3d(0, 1, 0)).norm(), 1e-12);
  double endpoint[3];
  scene.endpoint_actor()->GetPosition(endpoint);
  EXPECT_NEAR(endpoint[0], 0.0, 1e-12);
  EXPECT_NEAR(endpoint[1], 1.0, 1e-12);

  // Bounds of the turned link: x within the tube radius of 0, y from 0 to 1
  // (flat caps); about as wide across as it is thick (a 12-sided tube).
  const auto b = bounds_of(link);
  const double radius = 0.5 * (b[5] - b[4]);
  EXPECT_GT(radius, 0.0);
  EXPECT_NEAR(b[1] - b[0], 2 * radius, 0.04 * 2 * radius);
  EXPECT_NEAR(0.5 * (b[0] + b[1]), 0.0, 1e-9);
  EXPECT_NEAR(b[2], 0.0, 1.01 * radius);
  EXPECT_NEAR(b[3], 1.0, 1.01 * radius);
  EXPECT_LT(b[2], 1e-9);
  EXPECT_GT(b[3], 1.0 - 1e-9);

  // The label stays beside its joint, which does not move (the hinge at the origin).
  double label[3];
  scene.joint_label(0)->GetPosition(label);
  EXPECT_NEAR(label[0], 0.0, 1e-12);
  EXPECT_NEAR(label[1], 0.0, 1e-12);
  EXPECT_GT(label[2], 0.0);  // on the base z axis: straight up
}

TEST(SkeletonScene, LabelsInFrontShowThroughWhatCoversThem) {
  if (!have_display()) GTEST_SKIP() << "needs a display";
  TopView view;
  SkeletonScene scene;
  scene.set_model(two_bodies());
  scene.set_pose(link_at(0.0));
  scene.add_to(view.renderer);
  // An opaque red sheet between the camera and the hinge's label (above
  // the whole device).
  double label[3];
  scene.joint_label(0)->GetPosition(label);
  vtkNew<vtkPlaneSource> sheet;
  const double z = 5.0;
  ASSERT_GT(z, label[2]);
  sheet->SetOrigin(-1, -1, z);
  sheet->SetPoint1(1, -1, z);
  sheet->SetPoint2(-1, 1, z);
  vtkNew<vtkPolyDataMapper> mapper;
  mapper->SetInputConnection(sheet->GetOutputPort());
  vtkNew<vtkActor> cover;
  cover->SetMapper(mapper);
  cover->GetProperty()->SetColor(1, 0, 0);
  cover->GetProperty()->LightingOff();
  view.renderer->AddActor(cover);
  constexpr int kHalf = 10, kSquare = (2 * kHalf + 1) * (2 * kHalf + 1);
  // Hidden (but for the axes' own overlay captions at the origin).
  const int hidden = red_pixels_around(view.grab(), label[0], label[1], kHalf);
  EXPECT_GT(hidden, 0.9 * kSquare);
  scene.set_labels_in_front(true);
  EXPECT_FALSE(scene.joint_label(0)->GetVisibility());
  EXPECT_TRUE(scene.joint_front_label(0)->GetVisibility());
  const int shown = red_pixels_around(view.grab(), label[0], label[1], kHalf);
  EXPECT_LT(shown, hidden - kSquare / 4);  // on its plate, over the sheet
}

TEST(SkeletonScene, SizesScaleWithTheModelScale) {
  // Thickness of the link tube, the hinge knuckle's extents and the ball's
  // diameter, at scale 1 and scale 3 (the geometry itself unchanged).
  auto sizes = [](double scale) {
    SkeletonScene scene;
    scene.set_model(two_bodies(scale));
    const auto tube = bounds_of(scene.body_tube_actor(1));
    const auto hinge = bounds_of(scene.joint_actor(0));
    const auto ball = bounds_of(scene.joint_actor(1));
    return std::array<double, 4>{tube[5] - tube[4], hinge[1] - hinge[0], hinge[5] - hinge[4], ball[1] - ball[0]};
  };
  const auto one = sizes(1.0), three = sizes(3.0);
  for (int k = 0; k < 4; ++k) {
    EXPECT_GT(one[k], 0.0);
    EXPECT_NEAR(three[k] / one[k], 3.0, 1e-6) << k;  // VTK points are float
  }
  // The hinge (axis z) is longer along its axis than across it.
  EXPECT_GT(one[2], one[1]);
}

TEST(SkeletonScene, KnucklesLieAlongTheirAxesInTheBodyFrame) {
  // A prismatic joint along the body's y axis, on a body turned by 90 deg
  // about z: in the base frame it lies along -x.
  SkeletonModel m = two_bodies(1.0);
  m.joints[0].type = JointType::Prismatic;
  m.joints[0].axis_body_joint = {0, 2, 0};  // not unit: only the direction counts
  m.joints[0].p_body_joint = {0.5, 0, 0};
  SkeletonScene scene;
  scene.set_model(m);
  scene.set_pose(link_at(0.5 * std::numbers::pi));
  const auto b = bounds_of(scene.joint_actor(0));
  const double along = b[1] - b[0], across_y = b[3] - b[2], across_z = b[5] - b[4];
  EXPECT_GT(along, 2 * across_y);
  EXPECT_NEAR(across_y, across_z, 0.02 * across_z);  // a 20-sided cylinder
  // Centred at the turned point (0, 0.5, 0).
  EXPECT_NEAR(0.5 * (b[0] + b[1]), 0.0, 1e-9);
  EXPECT_NEAR(0.5 * (b[2] + b[3]), 0.5, 1e-9);
  EXPECT_NEAR(0.5 * (b[4] + b[5]), 0.0, 1e-9);
}

TEST(SkeletonScene, BadPosesThrowAndLeaveTheSceneUnchanged) {
  SkeletonScene scene;
  scene.set_model(two_bodies());
  const SkeletonPose good = link_at(0.3);
  scene.set_pose(good);
  const Eigen::Matrix4d before = to_eigen(scene.body_tube_actor(1)->GetUserMatrix());

  SkeletonPose few_frames = link_at(1.0);
  few_frames.X_world_body.pop_back();
  SkeletonPose many_frames = link_at(1.0);
  many_frames.X_world_body.push_back(Eigen::Isometry3d::Identity());
  SkeletonPose few_states = link_at(1.0);
  few_states.states.pop_back();
  SkeletonPose nan_frame = link_at(1.0);
  nan_frame.X_world_body[1].translation().x() = std::nan("");
  SkeletonPose nan_endpoint = link_at(1.0);
  nan_endpoint.p_world_endpoint.z() = std::nan("");
  for (const SkeletonPose* bad : {&few_frames, &many_frames, &few_states, &nan_frame, &nan_endpoint}) {
    EXPECT_THROW(scene.set_pose(*bad), std::invalid_argument);
    EXPECT_TRUE(scene.pose().X_world_body[1].isApprox(good.X_world_body[1]));
    EXPECT_EQ(to_eigen(scene.body_tube_actor(1)->GetUserMatrix()), before);
  }
}

TEST(SkeletonScene, BadModelsThrowAndLeaveTheSceneUnchanged) {
  SkeletonScene scene;
  scene.set_model(two_bodies());
  vtkNew<vtkRenderer> renderer;
  scene.add_to(renderer);
  vtkActor* link = scene.body_tube_actor(1);

  std::vector<SkeletonModel> bad(8, two_bodies());
  bad[0].joints[1].body = 2;
  bad[1].joints[1].body = -1;
  bad[2].joints[0].axis_body_joint.setZero();
  bad[3].bodies[1].polylines[0].resize(1);
  bad[4].bodies[0].faces[0].resize(2);
  bad[5].scale = 0.0;
  bad[6].scale = std::nan("");
  bad[7].bodies[1].polylines[0][1].y() = std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k < bad.size(); ++k) {
    EXPECT_THROW(scene.set_model(bad[k]), std::invalid_argument) << k;
    EXPECT_EQ(scene.model().scale, kScale) << k;
    EXPECT_EQ(scene.body_tube_actor(1), link) << k;
    EXPECT_EQ(view_prop_count(renderer), 9) << k;
  }
  // A zero axis means nothing for a ball joint.
  SkeletonModel ball_without_axis = two_bodies();
  ball_without_axis.joints[1].axis_body_joint.setZero();
  EXPECT_NO_THROW(scene.set_model(ball_without_axis));
}

TEST(SkeletonScene, NewModelKeepsAPoseThatFits) {
  SkeletonScene scene;
  scene.set_model(two_bodies());
  const SkeletonPose pose = link_at(0.7);
  scene.set_pose(pose);
  scene.set_model(two_bodies(2.0));  // same bodies: pose kept
  EXPECT_TRUE(to_eigen(scene.body_tube_actor(1)->GetUserMatrix()).isApprox(pose.X_world_body[1].matrix(), 1e-12));
  SkeletonModel three = two_bodies();
  three.bodies.push_back(three.bodies[1]);
  scene.set_model(three);  // does not fit: every body at the base frame
  ASSERT_EQ(scene.pose().X_world_body.size(), 3u);
  for (int b = 0; b < 3; ++b)
    EXPECT_TRUE(to_eigen(scene.body_tube_actor(b)->GetUserMatrix()).isApprox(Eigen::Matrix4d::Identity(), 1e-15));
  EXPECT_NO_THROW(scene.set_pose({{Eigen::Isometry3d::Identity(), Eigen::Isometry3d::Identity(),
                                   Eigen::Isometry3d::Identity()},
                                  {BodyState::Normal, BodyState::Normal, BodyState::Failing},
                                  Eigen::Vector3d::Zero()}));
}

// The base axes run along +x, +y and +z from the origin (the x axis red):
// the pixel tests keep the link in the -x, -y quadrant, clear of them.
constexpr double kLeft = std::numbers::pi, kDown = 1.5 * std::numbers::pi;

TEST(SkeletonScene, TheRenderChangesWhereTheLinkMovedAndNowhereElse) {
  if (!have_display()) GTEST_SKIP() << "VTK's OpenGL needs an X server (ctest runs it under tests/with-xvfb.sh)";
  SkeletonScene scene;
  scene.set_model(two_bodies());
  TopView view;
  scene.add_to(view.renderer);
  scene.set_pose(link_at(kLeft));
  const auto left = view.grab();
  scene.set_pose(link_at(kDown));
  const auto down = view.grab();

  // The link's middle: (-0.5, 0) before, (0, -0.5) after. Blue there, background where it left.
  const Rgb before = TopView::at(left, -0.5, 0.0), after = TopView::at(down, 0.0, -0.5);
  EXPECT_GT(before[2], before[0] + 50) << "the link is blue";
  EXPECT_GT(after[2], after[0] + 50);
  EXPECT_TRUE(is_background(TopView::at(left, 0.0, -0.5)));
  EXPECT_TRUE(is_background(TopView::at(down, -0.5, 0.0)));
  // The ground bar (y = -1.35) and plate (upper right) are drawn in both.
  for (const auto& image : {left, down}) {
    EXPECT_FALSE(is_background(TopView::at(image, -0.6, -1.35)));
    EXPECT_FALSE(is_background(TopView::at(image, 1.15, 0.85)));
  }

  // Every changed pixel lies within reach of the link (length 1, plus the
  // endpoint marker's radius and a few pixels); something changed.
  int changed = 0;
  for (int y = 0; y < 300; ++y)
    for (int x = 0; x < 400; ++x) {
      if (TopView::pixel(left, x, y) == TopView::pixel(down, x, y)) continue;
      ++changed;
      const double wx = (x + 0.5 - 200) / 100, wy = (y + 0.5 - 150) / 100;
      EXPECT_LT(std::hypot(wx, wy), 1.0 + 0.05 * kScale + 0.05) << "pixel " << x << ", " << y;
    }
  EXPECT_GT(changed, 2 * 100 * 5);  // the link's width (> 5 px) over its length, twice
}

TEST(SkeletonScene, AFailingBodyIsDrawnRed) {
  if (!have_display()) GTEST_SKIP() << "VTK's OpenGL needs an X server (ctest runs it under tests/with-xvfb.sh)";
  SkeletonScene scene;
  scene.set_model(two_bodies());
  TopView view;
  scene.add_to(view.renderer);
  scene.set_pose(link_at(kLeft));
  const auto normal = view.grab();
  scene.set_pose(link_at(kLeft, BodyState::Failing));
  const auto failing = view.grab();
  scene.set_pose(link_at(kLeft));
  const auto normal_again = view.grab();

  // Around the link's middle: no red while normal, the tube's width in red
  // over the window's length while failing.
  EXPECT_EQ(red_pixels_around(normal, -0.5, 0.0, 20), 0);
  EXPECT_GT(red_pixels_around(failing, -0.5, 0.0, 20), 5 * 41);
  EXPECT_EQ(red_pixels_around(normal_again, -0.5, 0.0, 20), 0);
  // The ground is never red.
  EXPECT_EQ(red_pixels_around(failing, -0.6, -1.35, 10), 0);
}

namespace {

// A delta-like device: a ground plate, three motor arms, three parallelogram
// forearms (drawn as two rods each, with ball joints) and a platform.
// Lengths in cm; not solved kinematics, a plausible drawing.
std::pair<SkeletonModel, SkeletonPose> delta_like() {
  const double base_radius = 10, arm = 12, platform_radius = 4, rod_gap = 2.5;
  const Eigen::Vector3d platform(1.5, -1.0, -24);
  SkeletonModel m;
  m.scale = 10;
  SkeletonPose pose;
  Body base;
  base.name = "base";
  base.ground = true;
  std::vector<Eigen::Vector3d> rim;
  for (int k = 0; k <= 6; ++k) {
    const double a = k * std::numbers::pi / 3 + std::numbers::pi / 6;
    rim.push_back({1.35 * base_radius * std::cos(a), 1.35 * base_radius * std::sin(a), 1.0});
  }
  base.polylines = {rim};
  base.faces = {{rim.begin(), rim.end() - 1}};
  m.bodies.push_back(base);
  pose.X_world_body.push_back(Eigen::Isometry3d::Identity());
  pose.states.push_back(BodyState::Normal);

  Body plate;
  plate.name = "platform";
  for (int i = 0; i < 3; ++i) {
    const double phi = 2 * std::numbers::pi * i / 3;
    const Eigen::Vector3d radial(std::cos(phi), std::sin(phi), 0), tangent(-std::sin(phi), std::cos(phi), 0);
    // Arm frame: x along the arm (radial, tilted down), y along the motor axis (tangent).
    const double tilt = 0.35 + 0.15 * i;
    Eigen::Isometry3d arm_frame = Eigen::Isometry3d::Identity();
    arm_frame.translate(base_radius * radial);
    arm_frame.rotate(Eigen::AngleAxisd(phi, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(tilt, Eigen::Vector3d::UnitY()));
    Body upper;
    upper.name = "arm " + std::to_string(i + 1);
    upper.polylines = {{{0, 0, 0}, {arm, 0, 0}}, {{arm, -rod_gap, 0}, {arm, rod_gap, 0}}};
    m.bodies.push_back(upper);
    pose.X_world_body.push_back(arm_frame);
    pose.states.push_back(i == 2 ? BodyState::Failing : BodyState::Normal);
    Joint motor;
    motor.name = "motor " + std::to_string(i + 1);
    motor.body = int(m.bodies.size()) - 1;
    motor.axis_body_joint = Eigen::Vector3d::UnitY();
    motor.actuated = true;
    motor.label = "q" + std::to_string(i + 1);
    m.joints.push_back(motor);

    // Forearm frame at the elbow, x towards the platform attachment.
    const Eigen::Vector3d elbow = arm_frame * Eigen::Vector3d(arm, 0, 0);
    const Eigen::Vector3d wrist = platform + platform_radius * radial;
    const Eigen::Vector3d d = wrist - elbow;
    Eigen::Isometry3d fore_frame = Eigen::Isometry3d::Identity();
    fore_frame.translate(elbow);
    fore_frame.rotate(Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitX(), d.normalized()));
    const Eigen::Vector3d side = fore_frame.linear().transpose() * tangent * rod_gap;
    Body fore;
    fore.name = "forearm " + std::to_string(i + 1);
    const Eigen::Vector3d end(d.norm(), 0, 0);
    fore.polylines = {{side, end + side}, {-side, end - side}};
    m.bodies.push_back(fore);
    pose.X_world_body.push_back(fore_frame);
    pose.states.push_back(BodyState::Normal);
    for (const Eigen::Vector3d& p : {Eigen::Vector3d(side), Eigen::Vector3d(-side), Eigen::Vector3d(end + side),
                                     Eigen::Vector3d(end - side)}) {
      Joint ball;
      ball.name = "ball";
      ball.type = JointType::Spherical;
      ball.body = int(m.bodies.size()) - 1;
      ball.p_body_joint = p;
      m.joints.push_back(ball);
    }
    plate.faces.resize(1);
    plate.faces[0].push_back(platform_radius * radial + rod_gap * tangent);
    plate.faces[0].push_back(platform_radius * radial - rod_gap * tangent);
  }
  // Close the platform outline as a tube too.
  plate.polylines = {plate.faces[0]};
  plate.polylines[0].push_back(plate.faces[0].front());
  m.bodies.push_back(plate);
  pose.X_world_body.push_back(Eigen::Isometry3d(Eigen::Translation3d(platform)));
  pose.states.push_back(BodyState::Normal);
  pose.p_world_endpoint = platform;
  return {m, pose};
}

// Distinct RGB triples in a PNG: a blank render has one or two.
std::size_t distinct_colours(const std::filesystem::path& png) {
  vtkNew<vtkPNGReader> reader;
  reader->SetFileName(png.c_str());
  reader->Update();
  vtkDataArray* rgb = reader->GetOutput()->GetPointData()->GetScalars();
  std::set<long> colours;
  for (vtkIdType i = 0; i < rgb->GetNumberOfTuples(); ++i)
    colours.insert(long(rgb->GetComponent(i, 0)) << 16 | long(rgb->GetComponent(i, 1)) << 8 |
                   long(rgb->GetComponent(i, 2)));
  return colours.size();
}

}  // namespace

TEST(SkeletonScene, DrawsADeviceFramedByResetCamera) {
  if (!have_display()) GTEST_SKIP() << "VTK's OpenGL needs an X server (ctest runs it under tests/with-xvfb.sh)";
  const auto [model, pose] = delta_like();
  SkeletonScene scene;
  scene.set_model(model);
  scene.set_pose(pose);
  vtkNew<vtkRenderer> renderer;
  renderer->SetBackground(1, 1, 1);
  scene.add_to(renderer);
  const Eigen::AlignedBox3d workspace(Eigen::Vector3d(-12, -12, -32), Eigen::Vector3d(12, 12, -14));
  vtkNew<vtkRenderWindow> window;
  window->SetOffScreenRendering(1);
  window->SetSize(640, 480);
  window->AddRenderer(renderer);
  scene.reset_camera(renderer, workspace);
  EXPECT_THROW(scene.reset_camera(nullptr, workspace), std::invalid_argument);
  EXPECT_THROW(scene.reset_camera(renderer, Eigen::AlignedBox3d()), std::invalid_argument);
  const auto png = std::filesystem::temp_directory_path() / "linkscape_skeleton_scene_test.png";
  render::save_png(window, png);
  EXPECT_GT(distinct_colours(png), 40u);
  std::filesystem::remove(png);

  // Every corner of the workspace box lies inside the view, and the box fills
  // most of it (fitted, not merely visible).
  double widest = 0.0;
  for (int k = 0; k < 8; ++k) {
    const Eigen::Vector3d c = workspace.corner(Eigen::AlignedBox3d::CornerType(k));
    renderer->SetWorldPoint(c.x(), c.y(), c.z(), 1.0);
    renderer->WorldToView();
    double v[3];
    renderer->GetViewPoint(v);
    EXPECT_LT(std::abs(v[0]), 1.0) << "corner " << k;
    EXPECT_LT(std::abs(v[1]), 1.0) << "corner " << k;
    widest = std::max({widest, std::abs(v[0]), std::abs(v[1])});
  }
  EXPECT_GT(widest, 0.6);
}
