// The task volume's failing samples: a colour pair told apart with any
// colour vision, and a failing sample on the far side still in view.
#include <gtest/gtest.h>

#include <cmath>

#include <vtkActor2D.h>
#include <vtkCamera.h>
#include <vtkNew.h>
#include <vtkPolyData.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>

#include "core/task.h"
#include "render/task_scene.h"
#include "tests/render/offscreen_view.h"

namespace linkscape::render {
namespace {

TEST(TaskScene, AFailingSampleOnTheFarSideShows) {
  task::TaskVolume sphere;
  sphere.shape = task::Shape::Sphere;
  sphere.size = Eigen::Vector3d::Constant(2);  // radius 1
  vtkSmartPointer<vtkPolyData> surface = task_surface(sphere, Eigen::Vector3d::Zero(), 12);
  // The vertex farthest from a camera on +y fails; every other one meets the criteria.
  vtkIdType far = 0;
  for (vtkIdType i = 0; i < surface->GetNumberOfPoints(); ++i)
    if (surface->GetPoint(i)[1] < surface->GetPoint(far)[1]) far = i;
  std::vector<std::uint8_t> meets(std::size_t(surface->GetNumberOfPoints()), 1);
  meets[std::size_t(far)] = 0;

  TaskScene scene;
  vtkNew<vtkRenderer> renderer;
  renderer->SetBackground(1, 1, 1);
  vtkNew<vtkRenderWindow> window;
  offscreen_view::set_up(window, renderer, {0, 10, 0}, {0, 0, 1}, 1.5);
  renderer->GetActiveCamera()->SetClippingRange(1, 20);
  scene.add_to(renderer);
  scene.set_task(surface, meets);
  scene.set_visible(true);
  EXPECT_EQ(scene.failing_points(), 1u);
  ASSERT_TRUE(scene.failing_actor()->GetVisibility());

  const double* p = surface->GetPoint(far);
  // Seen from +y with z up, screen right is -x.
  const offscreen_view::Rgb seen = offscreen_view::at(offscreen_view::grab(window), -p[0], p[2]);
  const offscreen_view::Rgb fails = {kFailsColour[0], kFailsColour[1], kFailsColour[2]};
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(seen[c], fails[c], 12) << "channel " << c;

  // All met: no dots. Most failing: a region the surface's colours show, no dots over it.
  scene.set_task(surface, std::vector<std::uint8_t>(meets.size(), 1));
  EXPECT_FALSE(scene.failing_actor()->GetVisibility());
  std::vector<std::uint8_t> most(meets.size(), 0);
  most[0] = 1;
  scene.set_task(surface, most);
  EXPECT_FALSE(scene.failing_actor()->GetVisibility());
}

// Colour vision deficiency simulated with Machado, Oliveira & Fernandes
// (2009) at full severity, applied to the 0..255 values (an approximation:
// the paper works in linear RGB; it is enough to rank colour pairs).
double simulated_distance(const unsigned char* a, const unsigned char* b, const double m[3][3]) {
  double d2 = 0;
  for (int r = 0; r < 3; ++r) {
    double da = 0, db = 0;
    for (int c = 0; c < 3; ++c) {
      da += m[r][c] * a[c];
      db += m[r][c] * b[c];
    }
    d2 += (da - db) * (da - db);
  }
  return std::sqrt(d2);
}

TEST(TaskScene, PassAndFailStayApartForEveryColourVision) {
  const double protan[3][3] = {{0.152286, 1.052583, -0.204868}, {0.114503, 0.786281, 0.099216}, {-0.003882, -0.048116, 1.051998}};
  const double deutan[3][3] = {{0.367322, 0.860646, -0.227968}, {0.280085, 0.672501, 0.047413}, {-0.011820, 0.042940, 0.968881}};
  const double tritan[3][3] = {{1.255528, -0.076749, -0.178779}, {-0.078411, 0.930809, 0.147602}, {0.004733, 0.691367, 0.303900}};
  for (const auto* m : {&protan, &deutan, &tritan}) EXPECT_GT(simulated_distance(kMeetsColour, kFailsColour, *m), 150);
  // The green and red this replaces come within half that for deuteranopia.
  const unsigned char green[3] = {60, 170, 90}, red[3] = {220, 50, 40};
  EXPECT_LT(simulated_distance(green, red, deutan), 100);
}

}  // namespace
}  // namespace linkscape::render
