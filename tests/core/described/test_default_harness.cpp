// bench's accuracy table for devices without a harness of their own
// (core/generic_methods.cpp): every method is measured on branch 0, the
// branch it solves, against the drawn actuator values.
#include <gtest/gtest.h>

#include "core/method_harness.h"
#include "described_devices_support.h"

using namespace linkscape;
using namespace linkscape::described_test;

// Drawn actuator values on the five-bar's and the 3-RRR's other elbow
// branches had been compared with branch 0's solution and read errors up
// to pi rad; FK was compared with its own answer. Now each IK error is
// against the drawn q, FK's by the actuator values its pose gives back.
TEST(DefaultHarness, MeasuresEveryMethodOnTheBranchItSolves) {
  for (const char* file : {"five-bar.json", "three-rrr.json"}) {
    const auto m = load_device(file);
    methods::HarnessOptions o;
    o.samples = 200;
    o.repeats = 1;
    o.include_field = false;
    int rows = 0;
    for (const methods::MethodRow& row : m->measure_methods(o)) {
      ++rows;
      EXPECT_EQ(row.error_unit, "rad") << file << " " << row.method;
      EXPECT_EQ(row.failures, 0u) << file << " " << row.family << " " << row.method;
      EXPECT_LE(row.error_max, 1e-9) << file << " " << row.family << " " << row.method;
    }
    EXPECT_GE(rows, 4) << file;  // closed, closed-scalar and newton IK, newton FK
  }
}
