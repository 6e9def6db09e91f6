// The field-name vocabulary (core/field_names.h): one list for the command
// line, the window, the renderer and the files.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>

#include "core/field_names.h"
#include "core/mechanism.h"
#include "core/preset.h"

namespace linkscape {
namespace {

TEST(FieldNames, EveryArrayHasOneUserNameAndOneFileName) {
  std::set<std::string_view> names, file_names;
  for (const FieldArrayInfo& a : kFieldArrays) {
    EXPECT_TRUE(names.insert(a.name).second) << a.name;
    EXPECT_TRUE(file_names.insert(a.file_name).second) << a.file_name;
    if (a.shown != FieldShown::Never) {
      EXPECT_EQ(field_array(a.name), a.array) << a.name;
    }
    EXPECT_EQ(field_array_info(a.array).name, a.name);
  }
  EXPECT_FALSE(field_array("force_iso"));  // a haptic array: named in core/haptics.h
  EXPECT_FALSE(field_array("reach_margin"));  // a file's name, not a user's
  EXPECT_FALSE(field_array("reachable"));     // written to files, not offered to show
  EXPECT_EQ(field_array_names(), "cond, cond_jo, reach, residual, iterations, status, method");
}

// The member each row names, read by a switch written here (the table's
// accessor must agree with it at every sample of a device's field).
std::size_t by_hand_size(const Field& f, FieldArray a) {
  switch (a) {
    case FieldArray::Cond: return f.cond.size();
    case FieldArray::CondOrientation: return f.cond_orientation.size();
    case FieldArray::Reach: return f.reach_margin.size();
    case FieldArray::Residual: return f.residual.size();
    case FieldArray::Reachable: return f.reachable.size();
    case FieldArray::Iterations: return f.iterations.size();
    case FieldArray::Status: return f.status.size();
    case FieldArray::Method: return f.method_used.size();
  }
  return 0;
}

double by_hand(const Field& f, FieldArray a, std::size_t s) {
  switch (a) {
    case FieldArray::Cond: return f.cond[s];
    case FieldArray::CondOrientation: return f.cond_orientation[s];
    case FieldArray::Reach: return f.reach_margin[s];
    case FieldArray::Residual: return f.residual[s];
    case FieldArray::Reachable: return f.reachable[s];
    case FieldArray::Iterations: return f.iterations[s];
    case FieldArray::Status: return f.status[s];
    case FieldArray::Method: return f.method_used[s];
  }
  return std::nan("");
}

TEST(FieldNames, EveryRowReadsItsOwnMemberOfTheField) {
  for (const char* device : {"pathos2", "delta"}) {  // with and without a second measure
    const auto m = make_mechanism(load_preset(device));
    const Grid grid = Grid::box(m->default_box().min(), m->default_box().max(), {6, 5, 4});
    const Field f = *m->compute_field(grid, m->home_task(), {}, 1, {});
    for (const FieldArrayInfo& a : kFieldArrays) {
      const bool held = by_hand_size(f, a.array) == f.grid.size();
      EXPECT_EQ(field_has(f, a), held) << device << " " << a.name;
      if (!held) {
        EXPECT_TRUE(a.may_be_empty) << device << " " << a.name;
        continue;
      }
      for (std::size_t s = 0; s < f.grid.size(); ++s) {
        const double want = by_hand(f, a.array, s), got = field_value(f, a, s);
        ASSERT_TRUE(want == got || (std::isnan(want) && std::isnan(got))) << device << " " << a.name << " at " << s;
      }
    }
  }
}

TEST(FieldNames, AnEmptyOptionalArrayIsNotHeld) {
  Field f;
  f.grid.dims = {2, 1, 1};
  f.cond.assign(2, 1.0f);
  EXPECT_TRUE(field_has(f, field_array_info(FieldArray::Cond)));
  EXPECT_FALSE(field_has(f, field_array_info(FieldArray::Method)));
  EXPECT_FALSE(field_has(f, field_array_info(FieldArray::CondOrientation)));
  EXPECT_EQ(field_array_info(FieldArray::Method).no_value, Field::kNoMethod);
  EXPECT_TRUE(field_array_info(FieldArray::Reach).length);
  EXPECT_FALSE(field_array_info(FieldArray::Cond).length);
}

TEST(FieldNames, EachDeviceListsItsOwnFields) {
  for (const std::string& device : registered_mechanisms()) {
    const auto m = make_mechanism(load_preset(device));
    const MechanismInfo& info = m->info();
    const std::vector<std::string> fields = device_fields(info);
    ASSERT_FALSE(fields.empty()) << device;
    EXPECT_EQ(fields.front(), "cond") << device;
    auto has = [&](const std::string& name) { return std::count(fields.begin(), fields.end(), name) == 1; };
    EXPECT_EQ(has("method"), info.ik_methods.size() > 1) << device;
    if (info.measures.size() > 1) EXPECT_EQ(fields[1], info.measures[1].name) << device;
    // The second measure goes by its own name (PATHOS-II's is cond_jo), never the renderer's.
    const bool named_cond_jo = info.measures.size() > 1 && info.measures[1].name == "cond_jo";
    EXPECT_EQ(has("cond_jo"), named_cond_jo) << device;
    for (const char* name : {"reach", "residual", "iterations", "status"}) EXPECT_TRUE(has(name)) << device << " " << name;
    const std::vector<std::string> plain = device_fields(info, false);
    EXPECT_EQ(plain.size() + 2, fields.size()) << device << ": without diagnostics, no residual or iterations";
    EXPECT_EQ(std::count(plain.begin(), plain.end(), "residual"), 0) << device;
  }
}

TEST(FieldNames, AMethodCodeIsNamedAsTheDeviceNamesItsMethods) {
  Field unnamed;
  EXPECT_EQ(method_code_name(unnamed, Field::kNoMethod), "none");
  EXPECT_EQ(method_code_name(unnamed, 3), "method code 3");  // a field that recorded no names
  for (const std::string& device : registered_mechanisms()) {
    const auto m = make_mechanism(load_preset(device));
    const MechanismInfo& info = m->info();
    if (info.ik_methods.size() < 2) continue;  // no method field offered (device_fields)
    std::set<std::string> known;
    for (const NamedItem& method : info.ik_methods) known.insert(method.name);
    const Eigen::VectorXd home = m->home_task();
    const Eigen::Vector3d centre(home(0), home(1), home(2));
    const Grid grid = Grid::box(centre.array() - 1.0, centre.array() + 1.0, {3, 3, 1});
    for (const NamedItem& method : info.ik_methods) {
      IkOptions options;
      options.method = method.name;
      const std::optional<Field> f = m->compute_field(grid, home, options, 1, {});
      ASSERT_TRUE(f) << device;
      ASSERT_EQ(f->method_used.size(), f->grid.size()) << device;
      int named = 0;
      for (std::size_t s = 0; s < f->grid.size(); ++s) {
        if (f->method_used[s] == Field::kNoMethod) continue;
        const std::string name = method_code_name(*f, f->method_used[s]);
        EXPECT_TRUE(known.count(name)) << device << ": " << name << " is not one of its IK methods";
        // A method that serves itself is named as asked (a fallback names the one that served).
        if (method.name != "fallback") EXPECT_EQ(name, method.name) << device;
        ++named;
      }
      EXPECT_GT(named, 0) << device << " " << method.name << ": no sample solved near home";
    }
  }
}

}  // namespace
}  // namespace linkscape
