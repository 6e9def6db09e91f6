// Hostile command lines: every input that cannot be honoured is an error
// naming what is wrong, and no output is ever silently lost.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <set>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include "cli_runner.h"
#include "full_disk.h"

namespace {

const char* kTargets = "x,y,z\n0,15,15\n10,20,5\n";

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

}  // namespace

TEST(CliHardening, OutputLostToAFullDeviceOrAClosedStdoutIsAnError) {
  const fs::path in = temp_file("hard_targets.csv", kTargets);
  for (const std::string redirect : {">/dev/full", ">&-"}) {
    const auto r = run_linkscape("eval --ik " + in.string(), "", redirect);
    EXPECT_EQ(r.exit_code, 1) << redirect << ": " << r.out;
    EXPECT_TRUE(contains(r.out, "cannot write to standard output")) << r.out;
  }
  const auto ok = run_linkscape("eval --ik " + in.string(), "", ">/dev/null");
  EXPECT_EQ(ok.exit_code, 0) << ok.out;
}

// On a nearly full disk every format of every writing command fails with
// exit 1 and the reason, and the file that was there stays whole (PDF/SVG
// figures and PLY/OBJ/OFF meshes used to come out cut at the room left, with
// exit 0 and "wrote").
TEST(CliHardening, AFullDiskFailsEveryFormatAndKeepsThePreviousFile) {
  FullDisk disk("cli");
  if (!disk.why_not().empty()) GTEST_SKIP() << disk.why_not();
  std::string targets = "x,y,z\n";
  for (int k = 0; k < 300; ++k) targets += std::to_string(k % 20 - 10) + ",15," + std::to_string(k % 7) + "\n";
  const fs::path in = temp_file("hard_many_targets.csv", targets);
  // Every output is larger than the 16 KiB left.
  const std::vector<std::pair<std::string, std::string>> commands = {
      {"slice --size 96x96 --figure -o ", "figure.pdf"},  {"slice --size 96x96 --figure -o ", "figure.svg"},
      {"slice --size 96x96 --figure -o ", "figure.png"},  {"slice --size 192x192 -o ", "slice.png"},
      {"slice --size 96x96 -o ", "slice.csv"},            {"field --resolution 24 -o ", "field.vti"},
      {"mesh --resolution 24 -o ", "mesh.ply"},            {"mesh --resolution 24 -o ", "mesh.obj"},
      {"mesh --resolution 24 -o ", "mesh.off"},            {"mesh --resolution 24 -o ", "mesh.stl"},
      {"mesh --resolution 24 -o ", "mesh.vtp"},            {"eval --ik " + in.string() + " -o ", "eval.csv"}};
  std::set<std::string> names = {"filler"};
  for (const auto& [command, name] : commands) {
    std::ofstream(disk.folder() / name) << "old " << name;
    names.insert(name);
  }
  for (const auto& [command, name] : commands) {
    disk.fill(16 * 1024);
    const fs::path out = disk.folder() / name;
    const auto r = run_linkscape(command + out.string());
    EXPECT_EQ(r.exit_code, 1) << command << name << ": " << r.out;
    EXPECT_TRUE(contains(r.out, "cannot write '" + out.string() + "': No space left on device")) << r.out;
    EXPECT_FALSE(contains(r.out, "wrote")) << r.out;
    std::ifstream old(out);
    std::string text;
    std::getline(old, text);
    EXPECT_EQ(text, "old " + name);
  }
  for (const auto& e : fs::directory_iterator(disk.folder()))
    EXPECT_TRUE(names.count(e.path().filename().string())) << "left behind: " << e.path();
}

// A pipe is written through without a temporary file: a full TMPDIR does not
// cut what goes down it.
TEST(CliHardening, APipeGetsTheWholeOutputWhenTheTemporaryFolderIsFull) {
  FullDisk disk("cli_tmpdir");
  if (!disk.why_not().empty()) GTEST_SKIP() << disk.why_not();
  disk.fill();
  const fs::path dir = fs::temp_directory_path() / "linkscape_cli_tests";
  fs::create_directories(dir);
  const fs::path fifo = dir / "figure-pipe.pdf", received = dir / "figure-received.pdf";
  fs::remove(fifo);
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  // (the reader gives up after a while, should the command fail before it opens the pipe)
  const auto r = run_shell("timeout 60 cat " + fifo.string() + " > " + received.string() + " & TMPDIR=" + disk.folder().string() +
                           " " + LINKSCAPE_BINARY + " slice --size 96x96 --figure -o " + fifo.string() + " 2>&1; wait");
  EXPECT_EQ(r.exit_code, 0) << r.out;
  std::ifstream pdf(received, std::ios::binary);
  const std::string text((std::istreambuf_iterator<char>(pdf)), std::istreambuf_iterator<char>());
  EXPECT_EQ(text.rfind("%PDF", 0), 0u);
  EXPECT_NE(text.find("%%EOF", text.size() > 16 ? text.size() - 16 : 0), std::string::npos) << "the PDF was cut";
  fs::remove(fifo);
}

// A pipe named as a session is refused at once (reading it used to block),
// and window images are PNG by name, refused before any window opens.
TEST(CliHardening, WindowFilesOfTheWrongKindAreRefusedBeforeAnyWindow) {
  SKIP_WITHOUT_WINDOW();
  const fs::path dir = fs::temp_directory_path() / "linkscape_cli_tests";
  fs::create_directories(dir);
  const fs::path fifo = dir / "session-pipe.json";
  fs::remove(fifo);
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  const auto pipe = run_linkscape("--session " + fifo.string(), "timeout 20");
  EXPECT_EQ(pipe.exit_code, 2) << pipe.out;
  EXPECT_TRUE(contains(pipe.out, "is not a regular file")) << pipe.out;
  fs::remove(fifo);
  for (const std::string option : {"--screenshot", "--view-image"}) {
    const auto r = run_linkscape(option + " " + (dir / "window.jpg").string());
    EXPECT_EQ(r.exit_code, 2) << r.out;
    EXPECT_TRUE(contains(r.out, option + " writes PNG")) << r.out;
    EXPECT_FALSE(fs::exists(dir / "window.jpg"));
  }
}

// `mesh --surface cond>3` unquoted: the shell writes to a file "3" and the
// program sees "cond"; the error says to quote.
TEST(CliHardening, AComparisonTheShellTookAsARedirectionIsExplained) {
  const fs::path dir = fs::temp_directory_path() / "linkscape_cli_tests";
  fs::create_directories(dir);
  // What the shell leaves (with or without the other required options), a
  // bare name among several criteria, and a force's bound from below.
  for (const auto& [args, quoted] : std::vector<std::pair<std::string, std::string>>{
           {"mesh --resolution 8 --surface cond -o " + (dir / "m.stl").string(), "'cond<3'"},
           {"mesh --surface cond", "'cond<3'"},
           {"fit --task sphere:diameter=15 --criterion cond", "'cond<3'"},
           {"fit --criterion cond", "'cond<3'"},
           {"fit --task sphere:diameter=15 --criterion 'cond<3, force_iso'", "'force_iso>1'"},
           {"verify --task sphere:diameter=15,centre=0,15,15 --criterion cond", "'cond<3'"}}) {
    const auto r = run_linkscape(args);
    EXPECT_EQ(r.exit_code, 2) << r.out;
    EXPECT_TRUE(contains(r.out, "quote the criterion: " + quoted)) << args << ": " << r.out;
  }
  // The help shows criteria quoted.
  for (const std::string command : {"fit", "sweep", "verify", "mesh"}) {
    const auto help = run_linkscape(command + " --help");
    EXPECT_TRUE(contains(help.out, "'cond<T'")) << command << ": " << help.out;
  }
}

TEST(CliHardening, OptionsBeforeTheCommandAreRefusedNotIgnored) {
  const fs::path in = temp_file("hard_targets.csv", kTargets);
  for (const std::string& before : std::vector<std::string>{"--param L1=12", "--mechanism pathos2", "--mechanism foo"}) {
    const auto r = run_linkscape(before + " eval --ik " + in.string());
    EXPECT_EQ(r.exit_code, 2) << before << ": " << r.out;
    EXPECT_TRUE(contains(r.out, "belongs after the command")) << r.out;
  }
  // An option of the window alone is not sent after a command that lacks it.
  for (const std::string& before : std::vector<std::string>{"--size 800x600", "--task sphere:diameter=3"}) {
    const auto r = run_linkscape(before + " eval --ik " + in.string());
    EXPECT_EQ(r.exit_code, 2) << before << ": " << r.out;
    EXPECT_TRUE(contains(r.out, "is the window's, and eval has no such option")) << r.out;
  }
  const auto file = run_linkscape("delta.json eval --ik " + in.string());
  EXPECT_EQ(file.exit_code, 2) << file.out;
  EXPECT_TRUE(contains(file.out, "give the device after it: linkscape eval -m FILE")) << file.out;
  // After the command the same option is honoured.
  const auto after = run_linkscape("eval --param L1=12 --ik " + in.string());
  ASSERT_EQ(after.exit_code, 0) << after.out;
  const auto fifteen = run_linkscape("eval --ik " + in.string());
  EXPECT_NE(after.out, fifteen.out);
}

TEST(CliHardening, BadRowsNameTheirFileLineAndColumn) {
  const fs::path nan12r = temp_file("hard_nan.csv", "x,y,z\n0,15,15\n\n0,nan,3\n");
  const auto a = run_linkscape("eval --ik " + nan12r.string());
  EXPECT_EQ(a.exit_code, 2) << a.out;
  EXPECT_TRUE(contains(a.out, "hard_nan.csv:4: column 'y'")) << a.out;

  const fs::path fk = temp_file("hard_inf.csv", "alpha,beta,gamma\n0,1,inf\n");
  const auto b = run_linkscape("eval --fk " + fk.string());
  EXPECT_EQ(b.exit_code, 2) << b.out;
  EXPECT_TRUE(contains(b.out, "hard_inf.csv:2: column 'gamma'")) << b.out;

  for (const std::string& bad : std::vector<std::string>{"nan", "inf", "-inf"}) {
    const fs::path poses = temp_file("hard_pose.csv", "x,y,z,rx,ry,rz,h0\n0,0,22.5,0,0,0.5,7\n0,0,22.5,0,0,0.5," + bad + "\n");
    const auto c = run_linkscape("eval -m pathos2 --ik " + poses.string());
    EXPECT_EQ(c.exit_code, 2) << bad << ": " << c.out;
    EXPECT_TRUE(contains(c.out, "hard_pose.csv:3: column 'h0'")) << c.out;
  }
}

TEST(CliHardening, NonFiniteAndOutOfRangeOptionValuesAreRefused) {
  const fs::path in = temp_file("hard_targets.csv", kTargets);
  for (const std::string& args : std::vector<std::string>{"eval --tolerance inf --ik " + in.string(), "eval --tolerance nan --ik " + in.string(),
        "eval --tolerance 1e-17 --ik " + in.string(), "slice --tolerance 1e-16 -o x.png",
        "eval --max-iterations 0 --ik " + in.string(), "slice --param L1=1e400 -o x.png",
        "mesh --decimate inf -o x.stl", "slice --plane x=nan -o x.png", "mesh --surface 'cond<inf' -o x.stl"}) {
    const auto r = run_linkscape(args);
    EXPECT_EQ(r.exit_code, 2) << args << ": " << r.out;
  }
  const auto big = run_linkscape("slice --param L1=1e400 -o x.png");
  EXPECT_TRUE(contains(big.out, "out of the range")) << big.out;
}

// Values that would be quietly ignored, taken twice or read past their
// meaning are refused, naming the option (and the preset a --param broke).
TEST(CliHardening, OptionsThatWouldBeIgnoredOrMeaninglessAreRefused) {
  const fs::path in = temp_file("hard_round.csv", kTargets);
  const fs::path q = temp_file("hard_round_q.csv", "q1,q2,q3\n0.1,0.2,0.3\n");
  const fs::path grip = temp_file("hard_grip.csv", "x,y,z,rx,ry,rz,h0\n0,0,22.5,0,0,0.5236,7\n0,0,22.5,0,0,0.5236,20\n");
  const fs::path grip_q = temp_file("hard_grip_q.csv", "q1,q2,q3,q4,q5,q6,h0\n2.66,2.66,2.66,-2.66,-2.66,-2.66,7\n"
                                                       "2.66,2.66,2.66,-2.66,-2.66,-2.66,0\n");
  const fs::path typo = temp_file("hard_typo_q.csv", "q1,q2,q3,sed_x,sed_y,sed_z\n0.1,0.2,0.3,0,0,-20\n");
  const fs::path extra = temp_file("hard_extra.csv", "x,y,z,rz\n0,0,-20,0.1\n");
  const std::vector<std::pair<std::string, std::string>> refused{
      // Columns it does not read (a mistyped seed had left FK starting from home).
      {"eval -m delta --fk " + typo.string(), ":1: column 'sed_x' is not one this reads (q1,q2,q3,seed_x,seed_y,seed_z); "
                                                "did you mean 'seed_x'?"},
      {"eval -m delta --ik " + extra.string(), ":1: column 'rz' is not one this reads (x,y,z)"},
      {"eval -m delta --fk " + q.string() + " --branch 5", "--branch applies to --ik"},
      {"eval -m delta --fk " + q.string() + " --method newton", "--method applies to --ik"},
      {"eval -m delta --fk " + q.string() + " --seed 1,2,3", "--seed applies to --ik"},
      {"eval -m delta --fk " + q.string() + " --max-iterations 3", "--max-iterations applies to --ik"},
      {"eval --ik " + in.string() + " --param L1=12 --param L1=13", "--param L1 is given twice"},
      {"eval --ik " + in.string() + " --method newton --tolerance 1e300", "--tolerance must lie between"},
      {"slice --tolerance 0.01 -o x.png", "--tolerance must lie between"},
      {"eval -m delta --ik " + in.string() + " --method newton --seed 0.4,0.4,0.4,", "--seed expects q1,q2,q3"},
      // A seed for a method that takes none (it had been ignored).
      {"eval -m delta --ik " + in.string() + " --seed 0.4,0.4,0.4", "'closed' does not start from a seed (with --method newton"},
      {"eval -m delta-described --ik " + in.string() + " --method newton --seed 0.4,0.4,0.4",
       "none of its methods does: each leg is solved from seeds of its own"},
      {"slice --size 32x32 --contour nan --figure -o x.png", "--contour levels are condition numbers"},
      {"slice --size 32x32 --contour -5 -o x.png", "--contour levels are condition numbers"},
      {"slice --size 32x32 --range 5,1 -o x.png", "--range expects min,max"},
      {"slice --size 32x32 --field status --linear -o x.png", "--linear sets a colour scale; --field status"},
      {"slice --size 32x32 --field status --range 0,3 -o x.png", "--range sets a colour scale"},
      {"slice --size 32x32 --extent -1e308,1e308,0,2 -o x.png", "--extent expects"},
      {"eval -m five-bar --param d=50 --ik " + in.string(), "five-bar with --param d=50: description.legs"},
      {"sweep --task sphere:diameter=4 --bounds L1=5:5 --grid 3 -o x.csv", "holds it at one value"},
      {"sweep --task sphere:diameter=4 --bounds L1=20:10 --grid 3 -o x.csv", "with lo <= hi, got 20:10"},
      {"eval -m five-bar --param A=10 --ik " + in.string(), "unknown parameter 'A' for five-bar; did you mean 'a'?"},
      {"verify --task sphere:diameter=5 --criterion 'cond<3' --time-limit inf", "seconds from 0 to 1e9"},
      {"describe", "which device?"},
      {"slice -m pathos2-described --pose 0,0,22.5,0,0,0.5236,-7 -o x.png", "outside pathos2-described's range"},
      // So is a target row's grip (it had been solved as if the grip could open that far).
      {"eval -m pathos2 --ik " + grip.string(), ":3: h0 = 20 is outside pathos2's range 2.1 to 10.5 cm"},
      {"eval -m pathos2-described --ik " + grip.string(), ":3: h0 = 20 is outside pathos2-described's range"},
      {"eval -m pathos2 --fk " + grip_q.string(), ":3: h0 = 0 is outside pathos2's range"},
      {"eval -m delta --param continuous_torque_Nm=5 --ik " + in.string(), "continuous_torque_Nm of q1 exceeds its peak"},
      {"mesh --box 0,1,0,1,0,nan --resolution 12 -o x.stl", "--box expects"},
      {"mesh --box 0,1,0,1,0,1e8 --resolution 12 -o x.stl", "wide against the device's size"},
      {"fit --task sphere:diameter=15 --pose 0,1,2", "--pose holds the task coordinates after x, y, z"},
      // The window's: refused before any window opens (no display needed).
      {"--screenshot ''", "--screenshot is empty"},
      {"--screenshot a.png --latency", "each ask for a run of their own"},
      {"--shortcuts --view-image v.png", "each ask for a run of their own"},
      {"--screenshot a.png --criterion 'cond<3'", "--criterion sets the criteria of --task"},
      {"--session s.json -m delta", "a session brings its own mechanism and design"}};
  for (const auto& [args, why] : refused) {
    const auto r = run_linkscape(args);
    EXPECT_EQ(r.exit_code, 2) << args << ": " << r.out;
    EXPECT_TRUE(contains(r.out, why)) << args << ": " << r.out;
  }
  // Found in every command, not only where they are read: a preset's motor
  // ratings for an actuator the device lacks; a plane's axis, named by its
  // option; the window's sizes, with a display or without.
  const fs::path ratings = temp_file(
      "hard_ratings.json", R"({"mechanism": "delta", "length_unit": "cm", "parameters": {"R": 9.5, "r": 5.445, "La": 8, "Lb": 17},
      "actuator_data": {"all": {"peak_torque_Nm": 1, "continuous_torque_Nm": 0.18}, "q9": {"peak_torque_Nm": 1}}})");
  const std::vector<std::tuple<std::string, std::string, std::string>> found{
      {"slice --size 32x32 -q -m " + ratings.string() + " -o x.png", "", "'q9' is not an actuator of delta"},
      {"slice --size 32x32 --plane q=1 -o x.png", "", "--plane: axis must be x, y or z, got 'q'"},
      {"--size 100000x100000 --screenshot a.png", "env -u DISPLAY -u WAYLAND_DISPLAY -u QT_QPA_PLATFORM",
       "--size expects WIDTHxHEIGHT"},
      {"--view-size 9x9 --view-image v.png", "env -u DISPLAY -u WAYLAND_DISPLAY -u QT_QPA_PLATFORM",
       "--view-size expects WIDTHxHEIGHT"}};
  for (const auto& [args, env, why] : found) {
    const auto r = run_linkscape(args, env);
    EXPECT_EQ(r.exit_code, 2) << args << ": " << r.out;
    EXPECT_TRUE(contains(r.out, why)) << args << ": " << r.out;
  }
  // Out of limits, the pose exists: FK gives it, as IK gives such a row's actuators.
  const fs::path beyond = temp_file("hard_round_beyond.csv", "q1,q2,q3\n1.5,1.5,1.5\n");
  const auto out = run_linkscape("eval -m delta --fk " + beyond.string());
  EXPECT_EQ(out.exit_code, 0) << out.out;
  EXPECT_TRUE(contains(out.out, "1.5,1.5,1.5,out-of-limits,")) << out.out;
  EXPECT_FALSE(contains(out.out, "out-of-limits,,")) << out.out;
  // A planar device's FK seed may leave z out, as its targets may.
  const fs::path planar = temp_file("hard_planar_fk.csv", "q1,q2,seed_x,seed_y\n1.8,1.2,-3,10\n");
  const auto fk = run_linkscape("eval -m five-bar --fk " + planar.string());
  EXPECT_EQ(fk.exit_code, 0) << fk.out;
  EXPECT_TRUE(contains(fk.out, "1.8,1.2,ok,")) << fk.out;
}

// A solver stopped short is a row's status, not the batch's end; its
// measures stay empty (its legs do not close, so there are none).
TEST(CliHardening, ARowTheSolverLeavesOpenIsNotConvergedWithNoMeasures) {
  const fs::path in = temp_file("hard_delta.csv", "x,y,z\n0,0,-20\n5,5,-15\n");
  for (const char* device : {"delta", "parallel-12r"}) {
    const auto r = run_linkscape(std::string("eval -m ") + device + " --method newton --max-iterations 1 --ik " + in.string());
    EXPECT_EQ(r.exit_code, 0) << device << ": " << r.out;
    // x,y,z,branch,status,q1,q2,q3,cond,det,residual,iterations: cond and det empty.
    std::istringstream lines(r.out);
    int checked = 0;
    for (std::string line; std::getline(lines, line);) {
      if (!contains(line, "not-converged")) continue;
      std::vector<std::string> cells;
      std::istringstream row(line);
      for (std::string cell; std::getline(row, cell, ',');) cells.push_back(cell);
      ASSERT_EQ(cells.size(), 12u) << line;
      EXPECT_EQ(cells[8], "") << device << ": " << line;
      EXPECT_EQ(cells[9], "") << device << ": " << line;
      ++checked;
    }
    EXPECT_GE(checked, 2) << device << ": " << r.out;
  }
  // A target so far that its squared distances overflow: refused, not infinite leg lengths.
  const fs::path far = temp_file("hard_far.csv", "x,y,z,rx,ry,rz\n0,0,1e9,0,0,0\n0,0,1e200,0,0,0\n");
  const auto beyond = run_linkscape("eval -m stewart --ik " + far.string());
  EXPECT_EQ(beyond.exit_code, 2) << beyond.out;
  EXPECT_TRUE(contains(beyond.out, "hard_far.csv:3: described: x (0, 0, 1e+200) cm is beyond 1e9 times")) << beyond.out;
  // A bound on the threads, not a crash.
  const auto threads = run_linkscape("verify --task sphere:diameter=15,centre=0.7,-13,-8.4 --criterion 'cond<3' --threads 100000");
  EXPECT_EQ(threads.exit_code, 2) << threads.out;
  EXPECT_TRUE(contains(threads.out, "--threads")) << threads.out;
}

// bench measures for minutes: what it would fail on afterwards is refused first.
TEST(CliHardening, BenchRefusesBadDevicesAndOutputsBeforeMeasuring) {
  // Exit 2 for bad input, 1 for an output that cannot be written (README).
  const std::tuple<std::string, std::string, int> cases[] = {
      {"bench --quick --compare bogus", "unknown mechanism 'bogus'", 2},
      {"bench --quick --csv no-such-folder/b.csv", "folder 'no-such-folder' does not exist", 1},
      {"bench --quick --csv b.txt", "--csv must end in .csv", 2},
  };
  for (const auto& [args, message, code] : cases) {
    const auto r = run_linkscape(args);
    EXPECT_EQ(r.exit_code, code) << args << ": " << r.out;
    EXPECT_TRUE(contains(r.out, message)) << args << ": " << r.out;
    EXPECT_FALSE(contains(r.out, "peak resident memory")) << "measured first: " << r.out;
  }
}

TEST(CliHardening, WindowSizeIsBoundedBeforeAnyWindowOpens) {
  SKIP_WITHOUT_WINDOW();
  // A size the OpenGL driver cannot allocate used to crash it.
  for (const std::string& size : std::vector<std::string>{"100000x100000", "9000x600", "800x600junk", "100x100"}) {
    const auto r = run_linkscape("--size " + size + " --screenshot never.png", "DISPLAY=:0");
    EXPECT_EQ(r.exit_code, 2) << size << ": " << r.out;
    EXPECT_TRUE(contains(r.out, "--size")) << r.out;
  }
}

TEST(CliHardening, OutputPathsThatCannotBeWrittenGiveOneLineWithTheReason) {
  const fs::path in = temp_file("hard_targets.csv", kTargets);
  const auto empty = run_linkscape("eval --ik " + in.string() + " -o ''");
  EXPECT_EQ(empty.exit_code, 2) << empty.out;
  EXPECT_TRUE(contains(empty.out, "output path is empty")) << empty.out;
  for (const std::string& cmd : std::vector<std::string>{"slice --size 16x16 -o /proc/linkscape.png", "field --resolution 8 -o /proc/l.vti",
                                 "mesh --resolution 16 -o /proc/l.stl"}) {
    const auto r = run_linkscape(cmd);
    EXPECT_EQ(r.exit_code, 1) << cmd << ": " << r.out;
    EXPECT_TRUE(contains(r.out, "cannot write '/proc/l")) << r.out;
    EXPECT_LE(std::count(r.out.begin(), r.out.end(), '\n'), 1) << "expected one line, got:\n" << r.out;
  }
  const fs::path folder = fs::temp_directory_path() / "linkscape_cli_tests" / "a_folder";
  fs::create_directories(folder);
  const auto dir = run_linkscape("eval --ik " + in.string() + " -o " + folder.string());
  EXPECT_EQ(dir.exit_code, 2) << dir.out;
  EXPECT_TRUE(contains(dir.out, "it is a folder")) << dir.out;
}

TEST(CliHardening, MemoryGuardCountsTheWholeCommand) {
  // 1400^3 samples: the arrays alone (~44 GiB) exceed any limit here, and the
  // message names the estimated peak.
  const auto r = run_linkscape("field --resolution 1400 -o big.vti -q");
  EXPECT_EQ(r.exit_code, 2) << r.out;
  EXPECT_TRUE(contains(r.out, "GiB at peak")) << r.out;
  EXPECT_FALSE(fs::exists("big.vti"));
  // A .vti export needs more than a CSV of the same grid: at a size where the
  // arrays fit but the export's copy does not, only the .vti is refused.
  const auto csv = run_linkscape("field --resolution 8 -o " +
                                 (fs::temp_directory_path() / "linkscape_cli_tests" / "small.csv").string() + " -q");
  EXPECT_EQ(csv.exit_code, 0) << csv.out;
}

TEST(CliHardening, Pathos2ForwardKinematicsOfARowDependsOnTheRowAlone) {
  // Row B evaluated after row A, and alone, must give the same answer. The
  // preset's assumed stops off: row B tilts beyond its globular cone.
  const std::string stops_off = " --joint-limits off --interference off";
  const std::string header = "q1,q2,q3,q4,q5,q6,h0\n";
  const fs::path ik_in = temp_file("hard_p2_ik.csv",
                                   "x,y,z,rx,ry,rz,h0\n0,0,22.5,0,0,0.5235987755982988,7\n"
                                   "3,-2,21,0.1,-0.05,0.6,7\n");
  const auto ik = run_linkscape("eval -m pathos2 --ik " + ik_in.string() + stops_off);
  ASSERT_EQ(ik.exit_code, 0) << ik.out;
  const auto poses = parse_cells(ik.out);
  ASSERT_EQ(poses.size(), 2u);
  auto q_row = [&](const std::map<std::string, std::string>& p) {
    return p.at("q1") + "," + p.at("q2") + "," + p.at("q3") + "," + p.at("q4") + "," + p.at("q5") + "," +
           p.at("q6") + "," + p.at("h0") + "\n";
  };
  const fs::path both = temp_file("hard_p2_both.csv", header + q_row(poses[1]) + q_row(poses[0]));
  const fs::path alone = temp_file("hard_p2_alone.csv", header + q_row(poses[0]));
  const auto r_both = run_linkscape("eval -m pathos2 --fk " + both.string() + stops_off);
  const auto r_alone = run_linkscape("eval -m pathos2 --fk " + alone.string() + stops_off);
  ASSERT_EQ(r_both.exit_code, 0) << r_both.out;
  ASSERT_EQ(r_alone.exit_code, 0) << r_alone.out;
  const auto rows_both = parse_cells(r_both.out), rows_alone = parse_cells(r_alone.out);
  ASSERT_EQ(rows_both.size(), 2u);
  ASSERT_EQ(rows_alone.size(), 1u);
  EXPECT_EQ(rows_both[1], rows_alone[0]);
  EXPECT_EQ(rows_alone[0].at("status"), "ok");

  // Seed columns: all six or none.
  const fs::path partial = temp_file("hard_p2_seed.csv", "q1,q2,q3,q4,q5,q6,h0,seed_x\n" +
                                                             q_row(poses[0]).substr(0, q_row(poses[0]).size() - 1) +
                                                             ",0\n");
  const auto r_partial = run_linkscape("eval -m pathos2 --fk " + partial.string());
  EXPECT_EQ(r_partial.exit_code, 2) << r_partial.out;
  // A seed at the answer converges to it.
  const auto& p = poses[1];
  const fs::path seeded = temp_file(
      "hard_p2_seeded.csv", "q1,q2,q3,q4,q5,q6,h0,seed_x,seed_y,seed_z,seed_rx,seed_ry,seed_rz\n" +
                                q_row(p).substr(0, q_row(p).size() - 1) + ",3,-2,21,0.1,-0.05,0.6\n");
  const auto r_seeded = run_linkscape("eval -m pathos2 --fk " + seeded.string() + stops_off);
  ASSERT_EQ(r_seeded.exit_code, 0) << r_seeded.out;
  const auto row = parse_cells(r_seeded.out).at(0);
  EXPECT_EQ(row.at("status"), "ok");
  EXPECT_NEAR(std::stod(row.at("x")), 3.0, 1e-9);
  EXPECT_NEAR(std::stod(row.at("rz")), 0.6, 1e-9);
}
