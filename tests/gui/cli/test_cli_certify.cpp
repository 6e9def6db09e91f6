// Certified verdicts, model export and motor ratings through the real binary:
// `verify`'s verdicts and exit statuses (0 proved, 3 disproved, 2 bad input),
// its JSON, `fit --certify`'s bracket, `export-model` (a described device, a
// compiled one through its described twin, refusals) and motor ratings given
// as parameters. The proofs' soundness is tested in tests/core/verify, the
// MJCF in MuJoCo in tests/core/model_export.
#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>

#include "tests/gui/cli/cli_runner.h"

namespace {

const fs::path kOut = fs::temp_directory_path() / "linkscape_cli_certify";

std::string out(const std::string& name) {
  fs::create_directories(kOut);
  fs::remove(kOut / name);
  return (kOut / name).string();
}

// The 12R with L1 = L2 = L and seed 001's 15 cm sphere where fit places it
// for L = 12.4 cm (docs/task-volumes.md, "Certified verdicts").
std::string twelve_r(double L) {
  return " -m parallel-12r --param L1=" + std::to_string(L) + " --param L2=" + std::to_string(L) +
         " --task sphere:diameter=15,centre=0.7092,-12.96,-8.385 --criterion 'cond<3'";
}

TEST(CliVerify, ProvesExitsZeroAndDisprovesExitsThreeWithTheCounterexample) {
  const CommandResult proved = run_linkscape("verify" + twelve_r(12.4));
  EXPECT_EQ(proved.exit_code, 0) << proved.out;
  EXPECT_NE(proved.out.find("proved"), std::string::npos) << proved.out;
  const CommandResult disproved = run_linkscape("verify" + twelve_r(11.5));
  EXPECT_EQ(disproved.exit_code, 3) << disproved.out;
  EXPECT_NE(disproved.out.find("disproved"), std::string::npos) << disproved.out;
  EXPECT_NE(disproved.out.find("c(J)"), std::string::npos) << disproved.out;
}

// The Omnid's Delta arm (docs/mechanisms/omnid-delta.md): its firmware's
// 200 x 200 mm section is within the arms' travel, with c(J) < 3, at every
// point of a 103 mm block and not of a 103.5 mm one; the firmware's whole
// box is not.
TEST(CliVerify, TheOmnidArmsBlockIsProvedAndTheFirmwaresBoxIsNot) {
  const std::string omnid = "verify -m omnid-delta --criterion reach,'cond<3' --task box:size=200,200,";
  const CommandResult block = run_linkscape(omnid + "103,centre=0,0,369.7");
  EXPECT_EQ(block.exit_code, 0) << block.out;
  for (const std::string& box : {std::string("103.5,centre=0,0,369.75"), std::string("250,centre=0,0,325")}) {
    const CommandResult r = run_linkscape(omnid + box);
    EXPECT_EQ(r.exit_code, 3) << box << "\n" << r.out;
    EXPECT_NE(r.out.find("outside the travel"), std::string::npos) << r.out;
  }
}

TEST(CliVerify, JsonCarriesTheVerdictAndTheCounterexample) {
  const CommandResult r = run_linkscape("verify" + twelve_r(11.5) + " --json", "", "2>/dev/null");
  ASSERT_EQ(r.exit_code, 3) << r.out;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j.at("verdict"), "disproved");
  EXPECT_TRUE(j.contains("counterexample")) << r.out;
}

TEST(CliVerify, BadInputAndWhatCannotBeCertifiedExitTwo) {
  for (const std::string& args :
       {std::string("verify -m parallel-12r --task sphere:diameter=15 --criterion 'cond<3'"),  // no centre
        std::string("verify -m parallel-12r --task sphere:diameter=15,centre=0,-13,-8"),      // no criterion
        std::string("verify -m pathos2 --task sphere:diameter=2,centre=0,0,22 --criterion 'cond<3'"),
        std::string("verify -m parallel-12r --task sphere:diameter=15,centre=0,-13,-8 --criterion 'cond<3' "
                    "--depth 0")}) {
    const CommandResult r = run_linkscape(args);
    EXPECT_EQ(r.exit_code, 2) << args << "\n" << r.out;
    EXPECT_NE(r.out.find("error"), std::string::npos) << r.out;
  }
}

// A described device whose legs are closed forms: each verdict with its exit
// status, the stops it does not cover named, and the devices it cannot
// certify refused naming their legs.
TEST(CliVerify, DescribedDevicesWithClosedFormLegsHaveTheThreeVerdicts) {
  const std::string delta = "verify -m delta-described --task sphere:diameter=5,centre=0,0,-20 --criterion ";
  const CommandResult proved = run_linkscape(delta + "'cond<5'");
  EXPECT_EQ(proved.exit_code, 0) << proved.out;
  EXPECT_NE(proved.out.find("proved: every point"), std::string::npos) << proved.out;
  EXPECT_NE(proved.out.find("not covered: its passive-joint limits"), std::string::npos) << proved.out;
  const CommandResult disproved = run_linkscape(delta + "'cond<1.5'");
  EXPECT_EQ(disproved.exit_code, 3) << disproved.out;
  EXPECT_NE(disproved.out.find("c(J) >="), std::string::npos) << disproved.out;
  const CommandResult undecided = run_linkscape(delta + "'cond<3' --depth 2");
  EXPECT_EQ(undecided.exit_code, 4) << undecided.out;
  EXPECT_NE(undecided.out.find("undecided"), std::string::npos) << undecided.out;
  const CommandResult hexapod = run_linkscape(
      "verify -m hexapod-rus --task sphere:diameter=1,centre=0,0,11.1 --criterion 'cond<5' --json", "", "2>/dev/null");
  ASSERT_EQ(hexapod.exit_code, 0) << hexapod.out;
  const nlohmann::json j = nlohmann::json::parse(hexapod.out);
  EXPECT_EQ(j.at("verdict"), "proved");
  EXPECT_EQ(j.at("mechanism"), "hexapod-rus");
  EXPECT_FALSE(j.contains("not_covered"));
  for (const auto& [args, words] : {std::pair<std::string, std::string>{"-m pathos2-described --task "
                                                                        "sphere:diameter=2,centre=0,0,22",
                                                                        "leg 1 (three-revolute)"},
                                    {"-m five-bar --task sphere:diameter=2,centre=0,10,0", "planar"}}) {
    const CommandResult r = run_linkscape("verify " + args + " --criterion 'cond<3'");
    EXPECT_EQ(r.exit_code, 2) << r.out;
    EXPECT_NE(r.out.find(words), std::string::npos) << r.out;
  }
}

TEST(CliFitCertify, BracketsSeed001sAnswerBetweenAProofAndACounterexample) {
  const CommandResult r = run_linkscape(
      "fit -m parallel-12r --task sphere:diameter=15 --criterion 'cond<3' --equal L1,L2 --bounds L1=11:14 "
      "--certify --bracket 0.1 -q");
  EXPECT_EQ(r.exit_code, 0) << r.out;
  EXPECT_NE(r.out.find("proved at"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("disproved at"), std::string::npos) << r.out;
  const CommandResult two = run_linkscape(
      "fit -m parallel-12r --task sphere:diameter=15 --criterion 'cond<3' --certify -q");  // L1 and L2 both free
  EXPECT_EQ(two.exit_code, 2) << two.out;
  EXPECT_NE(two.out.find("one variable"), std::string::npos) << two.out;
}

TEST(CliExportModel, WritesMjcfOfADescribedDeviceAndOfACompiledOneThroughItsTwin) {
  for (const std::string& device : {"falcon", "delta"}) {
    const std::string file = out(device + ".xml");
    const CommandResult r = run_linkscape("export-model -m " + device + " -o " + file);
    ASSERT_EQ(r.exit_code, 0) << r.out;
    std::ifstream in(file);
    const std::string text{std::istreambuf_iterator<char>(in), {}};
    EXPECT_NE(text.find("<mujoco model="), std::string::npos);
    EXPECT_NE(text.find("<weld body1=\"leg_1_end\""), std::string::npos) << text.substr(0, 400);
    EXPECT_NE(text.find("<motor name=\"q1\""), std::string::npos);
  }
  // The Delta's La = 9 cm becomes 0.09 m in the twin's thigh.
  const std::string longer = out("delta-long.xml");
  ASSERT_EQ(run_linkscape("export-model -m delta --param La=9 -o " + longer).exit_code, 0);
  std::ifstream in(longer);
  const std::string text{std::istreambuf_iterator<char>(in), {}};
  EXPECT_NE(text.find("0.089999999999999997 0 0"), std::string::npos);
}

TEST(CliExportModel, RefusesWhatItCannotWriteWithoutWriting) {
  const std::string file = out("no.xml");
  for (const std::string& args : {"export-model -m parallel-12r -o " + file, "export-model -m falcon -o " + out("x.txt"),
                                  "export-model -m pathos2 --param h0=8 -o " + file}) {
    const CommandResult r = run_linkscape(args);
    EXPECT_EQ(r.exit_code, 2) << args << "\n" << r.out;
  }
  EXPECT_FALSE(fs::exists(file));
}

TEST(CliMotorRatings, AParameterRatingScalesTheForces) {
  auto force_at_home = [](const std::string& params) {
    const std::string file = out("force" + std::to_string(params.size()) + ".csv");
    const CommandResult r = run_linkscape("slice -m delta --field force_iso --size 9x9 --quiet -o " + file + params);
    EXPECT_EQ(r.exit_code, 0) << r.out;
    std::ifstream in(file);
    std::stringstream text;
    text << in.rdbuf();
    double largest = 0;
    for (const auto& row : parse_cells(text.str()))
      if (row.count("force_iso_N") && !row.at("force_iso_N").empty()) largest = std::max(largest, std::stod(row.at("force_iso_N")));
    return largest;
  };
  const double base = force_at_home(" --param continuous_torque_Nm=0.1");
  const double geared = force_at_home(" --param continuous_torque_Nm=0.1 --param gear_ratio=3");
  ASSERT_GT(base, 0);
  EXPECT_NEAR(geared, 3 * base, 1e-6 * geared);
  const CommandResult bad = run_linkscape("slice -m delta --size 4x4 -o " + out("bad.csv") + " --param gear_ratio=0");
  EXPECT_EQ(bad.exit_code, 2) << bad.out;
}

}  // namespace
