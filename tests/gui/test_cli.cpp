// The headless commands, run as a user runs them: the real binary, its
// output and its exit code.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <sstream>

#include "core/csv.h"
#include "core/parallel12r.h"
#include "core/reference_12r.h"

namespace fs = std::filesystem;
using linkscape::testing::ConfigurationSampler;
using linkscape::testing::paper_forward;

namespace {

struct CommandResult {
  int exit_code = -1;
  std::string out;  // stdout and stderr
};

// Runs the binary with `args`; `environment` is prefixed as in a shell.
CommandResult run_linkscape(const std::string& args, const std::string& environment = "") {
  CommandResult r;
  const std::string command = environment + " " + std::string(LINKSCAPE_BINARY) + " " + args + " 2>&1";
  FILE* pipe = popen(command.c_str(), "r");
  char buffer[4096];
  while (std::size_t n = fread(buffer, 1, sizeof buffer, pipe)) r.out.append(buffer, n);
  const int status = pclose(pipe);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

fs::path temp_file(const std::string& name, const std::string& content) {
  const fs::path dir = fs::temp_directory_path() / "linkscape_cli_tests";
  fs::create_directories(dir);
  const fs::path p = dir / name;
  std::ofstream(p) << content;
  return p;
}

linkscape::Table parse(const std::string& csv) {
  std::istringstream in(csv);
  return linkscape::read_csv(in, "output");
}

}  // namespace

TEST(Cli, EvalInverseAgreesWithIndependentForwardForEveryMethod) {
  // Targets from random configurations of L1 = 1, L2 = 1.3 plus two points
  // outside the reach; every solution written must reproduce its target
  // through the printed Eqs. 11-13 to 1e-9 relative.
  ConfigurationSampler sample(81, 0.2);
  std::ostringstream csv;
  csv << "x,y,z\n";
  const int n = 300;
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector3d q = sample();
    const Eigen::Vector3d p = paper_forward(1.0, 1.3, q.x(), q.y(), q.z());
    csv << linkscape::format_number(p.x()) << "," << linkscape::format_number(p.y()) << ","
        << linkscape::format_number(p.z()) << "\n";
  }
  csv << "3,3,3\n0.05,0.1,0.0\n";
  const fs::path input = temp_file("targets.csv", csv.str());
  for (const char* method : {"paper", "planar", "newton", "dls"}) {
    const CommandResult r = run_linkscape("eval --mechanism parallel-12r --param L1=1 --param L2=1.3 --method " +
                      std::string(method) + " --ik " + input.string());
    ASSERT_EQ(r.exit_code, 0) << r.out;
    EXPECT_EQ(r.out.substr(0, r.out.find('\n')),
              "x,y,z,branch,status,alpha,beta,gamma,cond,det,residual,iterations");
    int solved = 0, unreachable = 0;
    // The status column is text, so the rows are split here by hand.
    std::istringstream lines(r.out);
    std::string line;
    std::getline(lines, line);
    while (std::getline(lines, line)) {
      std::vector<std::string> f;
      std::stringstream ss(line);
      std::string field;
      while (std::getline(ss, field, ',')) f.push_back(field);
      f.resize(12);
      if (f[4] == "unreachable") {
        ++unreachable;
        continue;
      }
      if (f[4] != "ok") continue;
      ++solved;
      const Eigen::Vector3d target(std::stod(f[0]), std::stod(f[1]), std::stod(f[2]));
      const Eigen::Vector3d back = paper_forward(1.0, 1.3, std::stod(f[5]), std::stod(f[6]), std::stod(f[7]));
      EXPECT_LT((back - target).norm(), 1e-9 * target.norm()) << method << ": " << line;
    }
    EXPECT_EQ(unreachable, 2) << method;
    // Closed forms find both branches of every target; the iterative methods
    // from their default seeds find at least one for nearly every target.
    const bool closed = std::string(method) == "paper" || std::string(method) == "planar";
    EXPECT_GE(solved, closed ? 2 * n : n * 9 / 10) << method;
  }
}

TEST(Cli, EvalInverseSingleBranch) {
  const fs::path input = temp_file("one.csv", "x,y,z\n0,1,1\n");
  const CommandResult r = run_linkscape("eval --param L1=1 --param L2=1 --branch 1 --ik " + input.string());
  ASSERT_EQ(r.exit_code, 0) << r.out;
  // One row: branch 1 of the Fig. 5 optimum is (0, 0, pi/2) with c(J) = 1.
  ASSERT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 2) << r.out;
  std::string row = r.out.substr(r.out.find('\n') + 1);
  EXPECT_EQ(row.substr(0, 13), "0,1,1,1,ok,-0") << row;
  row.replace(row.find("ok"), 2, "0");
  const linkscape::Table t = parse("x,y,z,branch,status,alpha,beta,gamma,cond,det,residual,iterations\n" + row);
  EXPECT_NEAR(t.rows[0][5], 0.0, 1e-15);
  EXPECT_NEAR(t.rows[0][6], 0.0, 1e-15);
  EXPECT_NEAR(t.rows[0][7], std::numbers::pi / 2, 1e-15);
  EXPECT_NEAR(t.rows[0][8], 1.0, 1e-12);
}

TEST(Cli, EvalForwardMatchesEquations) {
  const fs::path input = temp_file("angles.csv", "alpha,beta,gamma\n0,0,1.5707963267948966\n0.3,-0.4,2.1\n");
  const CommandResult r = run_linkscape("eval -m parallel-12r --fk " + input.string());
  ASSERT_EQ(r.exit_code, 0) << r.out;
  const linkscape::Table t = parse(r.out);
  ASSERT_EQ(t.rows.size(), 2u);
  const auto& row = t.rows[1];
  const Eigen::Vector3d expected = paper_forward(15, 15, 0.3, -0.4, 2.1);
  EXPECT_NEAR(row[t.column("x")], expected.x(), 1e-12);
  EXPECT_NEAR(row[t.column("y")], expected.y(), 1e-12);
  EXPECT_NEAR(row[t.column("z")], expected.z(), 1e-12);
  EXPECT_NEAR(t.rows[0][t.column("cond")], 1.0, 1e-12);  // the Fig. 5 optimum
}

TEST(Cli, OutputFileIsWrittenWhole) {
  const fs::path input = temp_file("angles2.csv", "alpha,beta,gamma\n0.1,0.2,0.3\n");
  const fs::path output = fs::temp_directory_path() / "linkscape_cli_tests" / "fk_out.csv";
  fs::remove(output);
  const CommandResult r = run_linkscape("eval --fk " + input.string() + " --output " + output.string());
  ASSERT_EQ(r.exit_code, 0) << r.out;
  std::ifstream in(output);
  EXPECT_EQ(linkscape::read_csv(in, "fk_out").rows.size(), 1u);
  for (const auto& e : fs::directory_iterator(output.parent_path()))
    EXPECT_EQ(e.path().filename().string().find(".tmp"), std::string::npos) << e.path();
}

TEST(Cli, BadArgumentsAndInputExitWithTwo) {
  const fs::path good = temp_file("good.csv", "x,y,z\n0,1,1\n");
  const fs::path bad_number = temp_file("bad_number.csv", "x,y,z\n0,one,1\n");
  const fs::path bad_header = temp_file("bad_header.csv", "a,b,c\n0,1,1\n");
  const fs::path bad_preset = temp_file("bad_preset.json", "{ \"mechanism\": \"parallel-12r\", ");
  const std::pair<std::string, std::string> cases[] = {
      {"eval --ik " + good.string() + " --mechanism nonsense", "unknown mechanism"},
      {"eval --ik " + good.string() + " --param L3=2", "unknown parameter"},
      {"eval --ik " + good.string() + " --param L1=-1", "positive"},
      {"eval --ik " + good.string() + " --param L1", "key=value"},
      {"eval --ik /no/such/file.csv", "cannot open"},
      {"eval --ik " + bad_number.string(), ":2:"},
      {"eval --ik " + bad_header.string(), "missing column 'x'"},
      {"eval --ik " + good.string() + " --method magic", "unknown IK method"},
      {"eval --ik " + good.string() + " --branch 3", "--branch"},
      {"eval --ik " + good.string() + " --fk " + good.string(), "excludes"},
      {"eval", "exactly one of"},
      {"eval --ik " + good.string() + " --mechanism " + bad_preset.string(), bad_preset.string()},
      {"eval --ik " + good.string() + " --seed 1,2", "--seed"},
      {"frobnicate", ""},
  };
  for (const auto& [args, message] : cases) {
    const CommandResult r = run_linkscape(args);
    EXPECT_EQ(r.exit_code, 2) << args << "\n" << r.out;
    EXPECT_NE(r.out.find(message), std::string::npos) << args << "\n" << r.out;
  }
}

TEST(Cli, HelpExplainsEveryOption) {
  const CommandResult top = run_linkscape("--help");
  EXPECT_EQ(top.exit_code, 0);
  for (const char* word : {"--mechanism", "--param", "--screenshot", "eval"})
    EXPECT_NE(top.out.find(word), std::string::npos) << word;
  const CommandResult eval = run_linkscape("eval --help");
  EXPECT_EQ(eval.exit_code, 0);
  for (const char* word : {"--ik", "--fk", "--method", "--branch", "--seed", "--output", "paper", "dls"})
    EXPECT_NE(eval.out.find(word), std::string::npos) << word;
}

TEST(Cli, ScreenshotShowsTheLinkage) {
  if (!std::getenv("DISPLAY")) GTEST_SKIP() << "needs an X server (ctest runs this under xvfb-run)";
  const fs::path png = fs::temp_directory_path() / "linkscape_cli_tests" / "window.png";
  fs::remove(png);
  const CommandResult r = run_linkscape("--screenshot " + png.string() + " --size 1000x700");
  ASSERT_EQ(r.exit_code, 0) << r.out;
  ASSERT_TRUE(fs::exists(png));
  EXPECT_GT(fs::file_size(png), 20000u);  // a blank window compresses to a few KiB
}

TEST(Cli, WindowWithoutDisplaySaysSoAndShowsHeadlessCommands) {
  const CommandResult r = run_linkscape("", "env -u DISPLAY -u WAYLAND_DISPLAY -u QT_QPA_PLATFORM");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.out.find("no display"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("linkscape eval"), std::string::npos) << r.out;
}
