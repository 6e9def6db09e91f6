// linkscape sweep through the real binary, on one process and under mpirun
// (1, 2 and 4 ranks, oversubscribed on this machine) and on 1 or 2 threads:
// the same table byte for byte, a design that cannot be built reported in its row, a rank killed
// mid-run reported as a failed run whose checkpoint --resume completes to the
// same table, and the bad inputs that exit with 2.
#include <gtest/gtest.h>

#include <signal.h>

#include <chrono>
#include <fstream>
#include <thread>
#include <tuple>

#include "tests/gui/cli/cli_runner.h"

namespace {

const fs::path kOut = fs::temp_directory_path() / "linkscape_cli_sweep";
// mpirun refuses to start as root (CI) without these.
const std::string kMpiEnvironment = "OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1";
// A small sweep with one design that cannot be built (L1 = -5).
const std::string kSmall =
    "sweep --task sphere:diameter=15 --criterion 'cond<3' --bounds L1=-5:20 --bounds L2=10:20 --grid 4 "
    "--resolution 16 --refinements 1 --places 1 --task-resolution 6 --field-resolution 16 --chunk 2 -q";

// A fresh output path: no table or checkpoint of an earlier run.
std::string out(const std::string& name) {
  fs::create_directories(kOut);
  fs::remove(kOut / name);
  fs::remove(kOut / (name + ".checkpoint"));
  return (kOut / name).string();
}

std::string read(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

CommandResult mpirun(int ranks, const std::string& args) {
  return run_shell(kMpiEnvironment + " mpirun --oversubscribe -np " + std::to_string(ranks) + " " + LINKSCAPE_BINARY +
                   " " + args + " 2>&1");
}

// The process whose command line holds `marker` and whose environment says
// it is MPI rank `rank`; 0 if none.
pid_t find_rank(const std::string& marker, int rank) {
  for (const auto& entry : fs::directory_iterator("/proc")) {
    const std::string name = entry.path().filename();
    if (name.find_first_not_of("0123456789") != std::string::npos) continue;
    std::string cmdline = read(entry.path() / "cmdline"), environ = read(entry.path() / "environ");
    std::replace(cmdline.begin(), cmdline.end(), '\0', ' ');
    std::replace(environ.begin(), environ.end(), '\0', '\n');
    if (cmdline.rfind(LINKSCAPE_BINARY, 0) == 0 && cmdline.find(marker) != std::string::npos &&
        ("\n" + environ).find("\nOMPI_COMM_WORLD_RANK=" + std::to_string(rank) + "\n") != std::string::npos)
      return pid_t(std::stoi(name));
  }
  return 0;
}

}  // namespace

TEST(CliSweep, OneTwoAndFourRanksWriteTheSingleProcessTableByteForByte) {
  const std::string single = out("single.csv");
  const std::string vti = out("single.vti");
  const CommandResult r = run_linkscape(kSmall + " --threads 1 -o " + single + " --vti " + vti);
  ASSERT_EQ(r.exit_code, 0) << r.out;
  EXPECT_NE(r.out.find("16 designs (4 with an error) on 1 process x 1 thread"), std::string::npos) << r.out;
  const std::string table = read(single);
  ASSERT_EQ(std::count(table.begin(), table.end(), '\n'), 17);
  EXPECT_FALSE(fs::exists(single + ".checkpoint"));  // removed once the table is written
  // The design that cannot be built is a row with its reason.
  const auto rows = parse_cells(table);
  EXPECT_EQ(rows[0].at("L1"), "-5");
  EXPECT_NE(rows[0].at("error").find("invalid design: parallel-12r: L1 must be"), std::string::npos);
  EXPECT_EQ(rows[0].at("size"), "");
  EXPECT_EQ(rows[15].at("error"), "");
  EXPECT_NE(rows[15].at("gci"), "");
  // The grid as image data: 4 x 4 points, an array per score.
  const std::string image = read(vti);
  EXPECT_NE(image.find("WholeExtent=\"0 3 0 3 0 0\""), std::string::npos) << image.substr(0, 400);
  EXPECT_NE(image.find("Origin=\"-5 10 0\""), std::string::npos) << image.substr(0, 400);
  for (const char* name : {"Name=\"size\"", "Name=\"worst_cond\"", "Name=\"gci\"", "Name=\"pareto\"", "Name=\"axis_x\""})
    EXPECT_NE(image.find(name), std::string::npos) << name;
  int on_front = 0;
  for (const auto& row : rows) on_front += row.at("pareto") == "1";
  EXPECT_GT(on_front, 0);
  // Two threads, each evaluating whole designs: the same bytes.
  const std::string threads = out("threads.csv");
  ASSERT_EQ(run_linkscape(kSmall + " --threads 2 -o " + threads).exit_code, 0);
  EXPECT_EQ(read(threads), table);
  for (int ranks : {1, 2, 4}) {
    const std::string file = out("ranks" + std::to_string(ranks) + ".csv");
    const CommandResult m = mpirun(ranks, kSmall + " --threads " + (ranks == 2 ? "2" : "1") + " -o " + file);
    ASSERT_EQ(m.exit_code, 0) << m.out;
    EXPECT_NE(m.out.find("on " + std::string(ranks == 1 ? "1 process" : std::to_string(ranks) + " ranks") + " x " +
                         (ranks == 2 ? "2 threads" : "1 thread")),
              std::string::npos)
        << m.out;
    EXPECT_EQ(std::count(m.out.begin(), m.out.end(), '\n'), 1) << "one summary, from rank 0 only:\n" << m.out;
    EXPECT_EQ(read(file), table) << ranks << " ranks";
  }
}

TEST(CliSweep, AKilledRankFailsTheRunAndResumeCompletesTheSameTable) {
  // About 0.04 s per design on one thread: long enough to kill a rank mid-run.
  const std::string sweep =
      "sweep --task sphere:diameter=15 --criterion 'cond<3' --bounds L1=5:20 --bounds L2=10:20 --grid 10 "
      "--resolution 48 --refinements 1 --places 1 --task-resolution 8 --field-resolution 96 --threads 1 --chunk 1 -q";
  const std::string straight = out("straight.csv");
  ASSERT_EQ(run_linkscape(sweep + " -o " + straight).exit_code, 0);

  const std::string killed = out("killed.csv");
  const fs::path checkpoint = killed + ".checkpoint", log = kOut / "killed.log", rc = kOut / "killed.rc";
  fs::remove(rc);
  const std::string command = "(" + kMpiEnvironment + " mpirun --oversubscribe -np 2 " + LINKSCAPE_BINARY + " " +
                              sweep + " -o " + killed + "; echo $? > " + rc.string() + ") > " + log.string() +
                              " 2>&1 &";
  ASSERT_EQ(std::system(command.c_str()), 0);
  // Once a few rows are in the checkpoint, rank 1 is killed.
  pid_t rank1 = 0;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (std::chrono::steady_clock::now() < deadline) {
    const std::string journal = read(checkpoint);
    if (std::count(journal.begin(), journal.end(), '\n') >= 4 && (rank1 = find_rank(killed, 1))) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  ASSERT_NE(rank1, 0) << read(log);
  ASSERT_EQ(::kill(rank1, SIGKILL), 0);
  while (!fs::exists(rc) && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  std::this_thread::sleep_for(std::chrono::milliseconds(100));  // the exit code written through
  const std::string report = read(log);
  ASSERT_TRUE(fs::exists(rc)) << report;
  EXPECT_NE(std::stoi(read(rc)), 0) << report;
  EXPECT_FALSE(fs::exists(killed)) << "no table from a failed run";
  // mpirun names the rank that died; rank 0 says where the finished designs are.
  EXPECT_NE(report.find("rank 1"), std::string::npos) << report;
  EXPECT_NE(report.find("run the same command with --resume"), std::string::npos) << report;
  const std::string journal = read(checkpoint);
  const long done = std::count(journal.begin(), journal.end(), '\n') - 1;
  EXPECT_LT(done, 100) << "the run was stopped before its end";

  const CommandResult resumed = run_linkscape(sweep + " -o " + killed + " --resume");
  ASSERT_EQ(resumed.exit_code, 0) << resumed.out;
  EXPECT_NE(resumed.out.find(std::to_string(done) + " from the checkpoint"), std::string::npos) << resumed.out;
  EXPECT_EQ(read(killed), read(straight));
  EXPECT_FALSE(fs::exists(checkpoint));
}

TEST(CliSweep, BadInputsExitWithTwoAndWriteNothing) {
  const std::string file = out("bad.csv");
  const std::string base = "sweep --task sphere:diameter=15 -o " + file;
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"sweep --task sphere:diameter=15 -o " + file, "either --grid N"},
      {base + " --grid 3 --random 5", "either --grid N"},
      {base + " --grid 1", "at least 2 values"},
      {base + " --grid 0", "at least 2 values"},
      {"sweep --task sphere:diameter=15 --grid 3 -o " + (kOut / "bad.txt").string(), "--output must end in .csv"},
      {base + " --grid 3 --chart c.bmp", "--chart must end in"},
      {base + " --grid 3 --field-resolution 2", "--field-resolution"},
      {base + " --grid 3 --bounds L1=5", "NAME=lo:hi"},
      {base + " --grid 3 --criterion 'speed<3'", "speed"},
      {base + " --grid 3 --resume", "--resume finds no checkpoint"},
      {base + " --random 5 --vti " + (kOut / "bad.vti").string(), "--vti needs --grid"},
      {base + " --grid 3 --threads 100000", "--threads must be 0 (OpenMP's default) to 256"},
      {base + " --random 5 --seed -1", "--seed expects a whole number from 0 to 18446744073709551615"},
      {base + " --random 5 --seed 18446744073709551616", "--seed expects a whole number"},
      {base + " --grid 3 --bounds L1=5:30 --bounds L1=6:20", "--bounds given twice for L1"},
      {base + " --grid 3 --bounds L1=1:1e31", "must lie within -1e+06 to 1e+06"},
      {base + " --grid 3 --task-resolution 300", "--task-resolution 2 to 256"},
      {base + " --grid 3 --refinements 11", "--refinements 0 to 10"},
      {base + " --random 1000000000", "GiB of memory available now"},
  };
  for (const auto& [args, expected] : cases) {
    const CommandResult r = run_linkscape(args);
    EXPECT_EQ(r.exit_code, 2) << args << "\n" << r.out;
    EXPECT_NE(r.out.find(expected), std::string::npos) << args << "\n" << r.out;
    EXPECT_FALSE(fs::exists(file)) << args;
  }
  // A stopped sweep's checkpoint is neither replaced by a new run nor
  // resumed by another sweep.
  std::ofstream(file + ".checkpoint") << "# linkscape sweep 1; another plan\n";
  const CommandResult fresh = run_linkscape(kSmall + " -o " + file);
  EXPECT_EQ(fresh.exit_code, 2) << fresh.out;
  EXPECT_NE(fresh.out.find("add --resume to finish it"), std::string::npos) << fresh.out;
  fs::remove(file + ".checkpoint");
  ASSERT_EQ(run_linkscape(kSmall + " -o " + file).exit_code, 0);
  fs::remove(file);
  std::ofstream(file + ".checkpoint") << "# linkscape sweep 1; another plan\n";
  const CommandResult other = run_linkscape(kSmall + " -o " + file + " --resume");
  EXPECT_EQ(other.exit_code, 2) << other.out;
  EXPECT_NE(other.out.find("is of another sweep"), std::string::npos) << other.out;
  EXPECT_NE(other.out.find("remove it (or give another --checkpoint) to start again"), std::string::npos) << other.out;
  fs::remove(file + ".checkpoint");
}

TEST(CliSweep, HelpExplainsEveryOptionWithAnExample) {
  const CommandResult r = run_linkscape("sweep --help", "COLUMNS=250");  // unwrapped: phrases on one line
  ASSERT_EQ(r.exit_code, 0) << r.out;
  for (const char* option : {"--grid", "--random", "--seed", "--field-resolution", "--threads", "--chunk", "--output",
                             "--checkpoint", "--resume", "--chart", "--vti", "mpirun -np 4 linkscape sweep"})
    EXPECT_NE(r.out.find(option), std::string::npos) << option;
}

// Outputs that cannot be written stop the sweep before any design is
// evaluated: no table, no checkpoint (they used to be written, the chart
// failing after all the work).
TEST(CliSweep, OutputsThatCannotBeWrittenStopBeforeAnyWork) {
  const std::string file = out("unwritten.csv");
  fs::remove_all(kOut / "no_such_folder");
  const std::string folder = out("a_folder.vti");
  fs::create_directories(folder);
  for (const auto& [args, code, expected] : std::vector<std::tuple<std::string, int, std::string>>{
           {" --chart " + (kOut / "no_such_folder" / "c.png").string(), 1, "no_such_folder' does not exist"},
           {" --vti " + folder, 2, "it is a folder"},
           {" --checkpoint " + (kOut / "no_such_folder" / "journal").string(), 1, "no_such_folder' does not exist"},
       }) {
    const CommandResult r = run_linkscape(kSmall + " -o " + file + args);
    EXPECT_EQ(r.exit_code, code) << args << "\n" << r.out;
    EXPECT_NE(r.out.find(expected), std::string::npos) << args << "\n" << r.out;
    EXPECT_FALSE(fs::exists(file)) << args;
    EXPECT_FALSE(fs::exists(file + ".checkpoint")) << args;
  }
  fs::remove(folder);
}

// Text in the table is quoted as RFC 4180 quotes it: a reason with a comma
// reads back whole, and every line has the header's cells.
TEST(CliSweep, ReasonsWithCommasAreQuotedCells) {
  const std::string file = out("quoted.csv");
  const CommandResult r = run_linkscape(
      "sweep --task sphere:diameter=15 --bounds L1=-5:20 --bounds L2=10:20 --grid 2 --resolution 16 --refinements 0 "
      "--places 1 --task-resolution 4 --threads 1 -q -o " + file);
  ASSERT_EQ(r.exit_code, 0) << r.out;
  std::istringstream lines(read(file));
  std::string line;
  std::getline(lines, line);
  const std::vector<std::string> header = linkscape::csv_cells(line);
  const std::size_t error = std::size_t(std::find(header.begin(), header.end(), "error") - header.begin());
  ASSERT_LT(error, header.size());
  std::getline(lines, line);
  const std::vector<std::string> first = linkscape::csv_cells(line);
  ASSERT_EQ(first.size(), header.size()) << line;
  EXPECT_NE(first[error].find("must be a length in ["), std::string::npos) << first[error];
  EXPECT_NE(first[error].find(", got -5"), std::string::npos) << first[error];
  while (std::getline(lines, line)) EXPECT_EQ(linkscape::csv_cells(line).size(), header.size()) << line;
}
