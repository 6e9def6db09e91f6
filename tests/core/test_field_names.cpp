// The field-name vocabulary (core/field_names.h): one list for the command
// line, the window, the renderer and the files.
#include <gtest/gtest.h>

#include <algorithm>
#include <set>

#include "core/field_names.h"
#include "core/preset.h"

namespace linkscape {
namespace {

TEST(FieldNames, EveryArrayHasOneUserNameAndOneFileName) {
  std::set<std::string_view> names, file_names;
  for (const FieldArrayName& a : kFieldArrays) {
    EXPECT_TRUE(names.insert(a.name).second) << a.name;
    EXPECT_TRUE(file_names.insert(a.file_name).second) << a.file_name;
    EXPECT_EQ(field_array(a.name), a.array) << a.name;
    EXPECT_EQ(field_array_name(a.array).name, a.name);
  }
  EXPECT_FALSE(field_array("force_iso"));  // a haptic array: named in core/haptics.h
  EXPECT_FALSE(field_array("reach_margin"));  // a file's name, not a user's
  EXPECT_EQ(field_array_names(), "cond, cond_jo, reach, residual, iterations, status, method");
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

}  // namespace
}  // namespace linkscape
