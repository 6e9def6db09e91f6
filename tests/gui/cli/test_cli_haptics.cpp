// The haptic fields through the real binary: slice, field and mesh of every
// device, and the bad inputs that must be refused with exit code 2.
#include <gtest/gtest.h>

#include <fstream>

#include "tests/gui/cli/cli_runner.h"

namespace {

const fs::path kOut = fs::temp_directory_path() / "linkscape_cli_haptics";

std::string out(const std::string& name) {
  fs::create_directories(kOut);
  return (kOut / name).string();
}

}  // namespace

TEST(CliHaptics, EveryDeviceSlicesEachHapticField) {
  for (const std::string device : {"parallel-12r", "pathos2", "delta"})
    for (const std::string field : {"force_iso", "force_max", "resolution", "inertia"}) {
      const std::string png = out(device + "_" + field + ".png");
      fs::remove(png);
      const CommandResult r = run_linkscape("slice -m " + device + " --field " + field + " --size 64x64 -q -o " + png);
      EXPECT_EQ(r.exit_code, 0) << device << " " << field << ": " << r.out;
      EXPECT_TRUE(fs::exists(png)) << png;
    }
}

// A slice CSV carries the array; its values agree with the continuous and
// the peak torque (the ratio of the shipped defaults, 1.0 / 0.18 N m).
TEST(CliHaptics, PeakTorqueScalesTheForces) {
  const std::string continuous = out("iso_cont.csv"), peak = out("iso_peak.csv");
  ASSERT_EQ(run_linkscape("slice --field force_iso --size 24x24 -q -o " + continuous).exit_code, 0);
  ASSERT_EQ(run_linkscape("slice --field force_iso --torque peak --size 24x24 -q -o " + peak).exit_code, 0);
  std::ifstream a(continuous), b(peak);
  const linkscape::Table ta = linkscape::read_csv(a, continuous), tb = linkscape::read_csv(b, peak);
  const std::size_t col = ta.column("force_iso_N"), reach = ta.column("reachable");
  int compared = 0;
  for (std::size_t r = 0; r < ta.rows.size(); ++r) {
    if (ta.rows[r][reach] != 1) continue;
    EXPECT_NEAR(tb.rows[r][col] / ta.rows[r][col], 1.0 / 0.18, 1e-5);
    ++compared;
  }
  EXPECT_GT(compared, 100);
}

TEST(CliHaptics, FieldWritesTheRequestedArraysAndMeshBoundsACriterion) {
  const std::string csv = out("volume.csv");
  const CommandResult r = run_linkscape("field -m delta --resolution 8 --field force_iso,resolution -q -o " + csv);
  ASSERT_EQ(r.exit_code, 0) << r.out;
  std::ifstream in(csv);
  std::string header;
  std::getline(in, header);
  EXPECT_NE(header.find(",force_iso_N,resolution_mm"), std::string::npos) << header;
  EXPECT_EQ(header.find("force_max"), std::string::npos) << header;

  const CommandResult mesh = run_linkscape("mesh --surface 'force_iso>1' --resolution 32 -q -o " + out("iso.stl"));
  EXPECT_EQ(mesh.exit_code, 0) << mesh.out;
  EXPECT_NE(mesh.out.find("watertight"), std::string::npos) << mesh.out;
}

TEST(CliHaptics, BadHapticInputsExitWithTwo) {
  const std::string no_inertia =
      temp_file("no_inertia.json",
                R"({"mechanism": "parallel-12r", "length_unit": "cm", "parameters": {"L1": 15, "L2": 15},
                    "actuator_data": {"all": {"peak_torque_Nm": 1, "continuous_torque_Nm": 0.2,
                                              "encoder_counts_per_rev": 1000}}})")
          .string();
  const std::string bad_unit =
      temp_file("bad_unit.json",
                R"({"mechanism": "parallel-12r", "length_unit": "unit", "parameters": {"L1": 1, "L2": 1}})")
          .string();
  for (const auto& [args, expected] : std::vector<std::pair<std::string, std::string>>{
           {"slice -m " + no_inertia + " --field inertia -o " + out("x.png"), "rotor_inertia_kgm2"},
           {"field -m " + no_inertia + " --field inertia -o " + out("x.csv"), "rotor_inertia_kgm2"},
           {"slice -m " + bad_unit + " --field force_iso -o " + out("x.png"), "length_unit"},
           {"slice --field force_iso --torque stall -o " + out("x.png"), "continuous or peak"},
           {"field --field cond -o " + out("x.csv"), "--field adds"},
           {"mesh --surface 'force_iso<2' -o " + out("x.stl"), "--surface"},
           {"mesh --surface 'resolution>2' -o " + out("x.stl"), "--surface"},
           {"mesh --surface 'force_iso>0' -o " + out("x.stl"), "--surface"},
       }) {
    const CommandResult r = run_linkscape(args);
    EXPECT_EQ(r.exit_code, 2) << args << "\n" << r.out;
    EXPECT_NE(r.out.find(expected), std::string::npos) << args << "\n" << r.out;
  }
}
