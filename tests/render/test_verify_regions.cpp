// A certified verdict's regions as meshes (render/verify_regions.h): each box
// is six outward faces on its bounds; the props show what the result holds
// and clear. No rendering: no display needed.
#include <gtest/gtest.h>
#include <vtkPolyData.h>
#include <vtkPolygon.h>

#include "render/verify_regions.h"

using namespace linkscape;

TEST(VerifyRegions, EachBoxIsSixOutwardFacesOnItsBounds) {
  const std::vector<verify::Box> boxes = {{{0, 0, 0}, {1, 2, 3}}, {{-1, 5, 2}, {0, 6, 2.5}}};
  const auto mesh = render::boxes_mesh(boxes);
  ASSERT_EQ(mesh->GetNumberOfPolys(), 12);
  ASSERT_EQ(mesh->GetNumberOfPoints(), 48);
  double b[6];
  mesh->GetBounds(b);
  EXPECT_EQ(b[0], -1);
  EXPECT_EQ(b[1], 1);
  EXPECT_EQ(b[2], 0);
  EXPECT_EQ(b[3], 6);
  EXPECT_EQ(b[4], 0);
  EXPECT_EQ(b[5], 3);
  // The first box's faces: their areas add up to its surface, and each
  // normal points away from its centre, along an axis, to the face's plane.
  const Eigen::Vector3d centre(0.5, 1, 1.5);
  double total_area = 0;
  for (vtkIdType f = 0; f < 6; ++f) {
    vtkCell* cell = mesh->GetCell(f);
    ASSERT_EQ(cell->GetNumberOfPoints(), 4);
    double n[3], p[3], face_centre[3] = {0, 0, 0};
    vtkPolygon::ComputeNormal(cell->GetPoints(), n);
    Eigen::Vector3d corner[4];
    for (int k = 0; k < 4; ++k) {
      cell->GetPoints()->GetPoint(k, p);
      corner[k] = Eigen::Vector3d(p[0], p[1], p[2]);
      for (int a = 0; a < 3; ++a) face_centre[a] += p[a] / 4;
    }
    const Eigen::Vector3d normal(n[0], n[1], n[2]),
        out = Eigen::Vector3d(face_centre[0], face_centre[1], face_centre[2]) - centre;
    EXPECT_NEAR(normal.dot(out.normalized()), 1, 1e-12) << "face " << f;
    total_area += 0.5 * (corner[2] - corner[0]).cross(corner[3] - corner[1]).norm();  // a planar quadrilateral's area
  }
  EXPECT_NEAR(total_area, 2 * (1 * 2 + 2 * 3 + 1 * 3), 1e-12);
  EXPECT_EQ(render::boxes_mesh({})->GetNumberOfPolys(), 0);
}

TEST(VerifyRegions, ShowWhatTheResultHoldsAndClear) {
  render::VerifyRegions regions;
  verify::Result r;
  r.proved_boxes = {{{0, 0, 0}, {1, 1, 1}}, {{1, 0, 0}, {2, 1, 1}}};
  r.undecided_boxes = {{{2, 0, 0}, {3, 1, 1}}};
  regions.show(r, 0.1);
  EXPECT_EQ(regions.proved(), 2u);
  EXPECT_EQ(regions.undecided(), 1u);
  EXPECT_FALSE(regions.counterexample());
  r.counterexample = verify::Counterexample{};
  regions.show(r, 0.1);
  EXPECT_TRUE(regions.counterexample());
  EXPECT_THROW(regions.show(r, 0), std::invalid_argument);
  EXPECT_THROW(regions.add_to(nullptr), std::invalid_argument);
  regions.clear();
  EXPECT_EQ(regions.proved() + regions.undecided(), 0u);
  EXPECT_FALSE(regions.counterexample());
}
