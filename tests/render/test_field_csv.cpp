// The field's files read back: every kinematic array of core/field_names.h
// under its file name in the .vti, and the CSV with units in its header and
// an empty cell (never "nan", never a stand-in) where a sample has no value.
#include <gtest/gtest.h>

#include <vtkDataArray.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkXMLImageDataReader.h>

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "core/csv.h"
#include "core/field_names.h"
#include "core/preset.h"
#include "render/field_vtk.h"

namespace linkscape {
namespace {

std::filesystem::path temp(const std::string& name) {
  return std::filesystem::temp_directory_path() / ("linkscape_field_csv_" + std::to_string(::getpid()) + "_" + name);
}

// A device's field over its whole box (reachable and unreachable samples),
// with a haptic-like array that is 0 where unreachable.
Field sampled(const std::string& device) {
  const auto m = make_mechanism(load_preset(device));
  const Grid grid = Grid::box(m->default_box().min(), m->default_box().max(), {7, 6, 5});
  Field f = *m->compute_field(grid, m->home_task(), {}, 1, {});
  Field::NamedArray force{"force_iso", "isotropic force", "N", "", {}};
  for (std::size_t s = 0; s < f.grid.size(); ++s) force.values.push_back(f.reachable[s] ? 0.5f + float(s) : 0.0f);
  f.extras.push_back(std::move(force));
  return f;
}

std::vector<std::vector<std::string>> read_cells(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::vector<std::vector<std::string>> rows;
  for (std::string line; std::getline(in, line);) rows.push_back(csv_cells(line));
  return rows;
}

TEST(FieldCsv, HeaderCarriesUnitsAndMissingValuesAreEmptyCells) {
  for (const char* device : {"delta", "pathos2"}) {
    const Field f = sampled(device);
    const auto path = temp(std::string(device) + ".csv");
    render::write_field_csv(f, path);
    const auto rows = read_cells(path);
    std::filesystem::remove(path);
    ASSERT_EQ(rows.size(), f.grid.size() + 1) << device;
    const std::string u = "_" + f.length_unit;
    std::vector<std::string> want = {"x" + u, "y" + u, "z" + u, "cond"};
    if (!f.cond_orientation.empty()) want.push_back("cond_orientation");
    for (std::string c : {"reach_margin" + u, "residual" + u, std::string("reachable"), std::string("iterations"),
                          std::string("status")})
      want.push_back(c);
    if (!f.method_used.empty()) want.push_back("method_used");
    for (const Field::NamedArray& e : f.extras) want.push_back(e.name + "_" + e.unit);  // the stops' arrays, then force_iso
    ASSERT_EQ(rows[0], want) << device;
    const auto col = [&](const std::string& name) { return std::size_t(std::find(want.begin(), want.end(), name) - want.begin()); };
    int unreachable = 0, reachable = 0;
    for (std::size_t s = 0; s < f.grid.size(); ++s) {
      const std::vector<std::string>& row = rows[s + 1];
      ASSERT_EQ(row.size(), want.size());
      for (const std::string& cell : row) ASSERT_NE(cell, "nan") << device << " sample " << s;
      // Always a value: where the sample is, its reach margin, status and iterations.
      EXPECT_EQ(float(*parse_number(row[col("reach_margin" + u)])), f.reach_margin[s]);
      EXPECT_EQ(*parse_number(row[col("status")]), f.status[s]);
      EXPECT_EQ(*parse_number(row[col("iterations")]), f.iterations[s]);
      EXPECT_EQ(*parse_number(row[col("reachable")]), f.reachable[s]);
      if (!f.reachable[s]) {
        ++unreachable;
        for (const char* none : {"cond", "force_iso_N"}) EXPECT_EQ(row[col(none)], "") << device << " " << none;
        EXPECT_EQ(row[col("residual" + u)], "");
        if (!f.method_used.empty()) EXPECT_EQ(row[col("method_used")], "");
        continue;
      }
      ++reachable;
      EXPECT_EQ(float(*parse_number(row[col("cond")])), f.cond[s]);  // "inf" only where truly singular
      EXPECT_EQ(float(*parse_number(row[col("force_iso_N")])), f.extra("force_iso")->values[s]);
      if (!f.method_used.empty()) {
        const std::string& m = row[col("method_used")];
        if (f.method_used[s] == Field::kNoMethod) EXPECT_EQ(m, "");
        else EXPECT_EQ(*parse_number(m), f.method_used[s]);
      }
    }
    EXPECT_GT(unreachable, 0) << device << ": the box should reach past the workspace";
    EXPECT_GT(reachable, 0) << device;
  }
}

// The .vti holds every kinematic array the field holds, by the table's file
// name, with the Field's values: a row added to the table is written.
TEST(FieldCsv, VtiHoldsEveryArrayOfTheTable) {
  const Field f = sampled("pathos2");
  const auto path = temp("pathos2.vti");
  render::write_vti(f, path);
  vtkNew<vtkXMLImageDataReader> reader;
  reader->SetFileName(path.c_str());
  reader->Update();
  std::filesystem::remove(path);
  vtkPointData* pd = reader->GetOutput()->GetPointData();
  int written = 0;
  for (const FieldArrayInfo& a : kFieldArrays) {
    vtkDataArray* array = pd->GetArray(std::string(a.file_name).c_str());
    if (!field_has(f, a)) {
      EXPECT_EQ(array, nullptr) << a.file_name;
      continue;
    }
    ASSERT_NE(array, nullptr) << a.file_name;
    ++written;
    for (vtkIdType i = 0; i < array->GetNumberOfTuples(); ++i) {
      // A real value that needs a solution is NaN where the device does not
      // reach the sample (a code array keeps its "no value" code).
      const bool none = a.needs_solution && array->IsA("vtkFloatArray") && !f.reachable[std::size_t(i)];
      const double want = none ? std::nan("") : field_value(f, a, std::size_t(i)), got = array->GetTuple1(i);
      ASSERT_TRUE(want == got || (std::isnan(want) && std::isnan(got))) << a.file_name << " sample " << i;
    }
  }
  EXPECT_EQ(written, int(kFieldArrays.size()));  // PATHOS-II holds them all
}

}  // namespace
}  // namespace linkscape
