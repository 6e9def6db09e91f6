#include <gtest/gtest.h>
#include <vtkActor.h>
#include <vtkMapper.h>
#include <vtkNew.h>
#include <vtkPNGReader.h>
#include <vtkImageData.h>
#include <vtkPointData.h>
#include <vtkDataArray.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkPropCollection.h>

#include <filesystem>
#include <set>

#include "render/image_io.h"
#include "render/linkage_scene.h"

using namespace linkscape;

namespace {

// Distinct RGB triples in a PNG: a blank render has one or two.
std::size_t distinct_colours(const std::filesystem::path& png) {
  vtkNew<vtkPNGReader> reader;
  reader->SetFileName(png.c_str());
  reader->Update();
  vtkDataArray* rgb = reader->GetOutput()->GetPointData()->GetScalars();
  std::set<long> colours;
  for (vtkIdType i = 0; i < rgb->GetNumberOfTuples(); i += 3)
    colours.insert(long(rgb->GetComponent(i, 0)) << 16 | long(rgb->GetComponent(i, 1)) << 8 |
                   long(rgb->GetComponent(i, 2)));
  return colours.size();
}

}  // namespace

TEST(LinkageScene, RendersOffscreenToANonBlankPng) {
  if (!std::getenv("DISPLAY")) GTEST_SKIP() << "VTK's OpenGL needs an X server (ctest runs it under tests/with-xvfb.sh)";
  render::LinkageScene scene;
  parallel12r::Model m;
  m.L1 = m.L2 = 15;
  scene.set_model(m);
  scene.set_pose({0.3, 1.1, 0.1});
  vtkNew<vtkRenderer> renderer;
  renderer->SetBackground(1, 1, 1);
  scene.add_to(renderer);
  scene.reset_camera(renderer);
  vtkNew<vtkRenderWindow> window;
  window->SetOffScreenRendering(1);
  window->SetSize(640, 480);
  window->AddRenderer(renderer);
  const auto png = std::filesystem::temp_directory_path() / "linkscape_scene_test.png";
  render::save_png(window, png);
  EXPECT_GT(distinct_colours(png), 40u);
  std::filesystem::remove(png);
}

TEST(LinkageScene, PoseChangesMoveTransformsNotGeometry) {
  render::LinkageScene scene;
  vtkNew<vtkRenderer> renderer;
  scene.add_to(renderer);
  // Geometry sources of every actor (view props, not GetActors(): that needs
  // a render window for the text labels).
  auto geometry_times = [&] {
    std::vector<vtkMTimeType> times;
    vtkPropCollection* props = renderer->GetViewProps();
    props->InitTraversal();
    while (vtkProp* p = props->GetNextProp()) {
      auto* a = vtkActor::SafeDownCast(p);
      if (a && a->GetMapper() && a->GetMapper()->GetInputAlgorithm())
        times.push_back(a->GetMapper()->GetInputAlgorithm()->GetMTime());
    }
    return times;
  };
  const std::vector<vtkMTimeType> before = geometry_times();
  ASSERT_GE(before.size(), 22u);  // 10 links + 12 joints at least
  scene.set_pose({-0.4, 0.2, 2.0});
  EXPECT_EQ(geometry_times(), before);
  EXPECT_EQ(scene.pose(), Eigen::Vector3d(-0.4, 0.2, 2.0));
}
