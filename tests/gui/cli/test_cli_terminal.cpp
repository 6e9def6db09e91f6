// What the command line says: one error style, suggestions for mistyped
// words, a summary on success (silenced by --quiet), progress with the time
// left on a terminal, and a file argument as the desktop entry passes it.
#include <gtest/gtest.h>

#include <fstream>

#include "tests/gui/cli/cli_runner.h"

using namespace cli_runner;

namespace {

const fs::path kDir = fs::temp_directory_path() / "linkscape_cli_terminal";
const std::string kNoDisplay = "env -u DISPLAY -u WAYLAND_DISPLAY -u QT_QPA_PLATFORM";

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

}  // namespace

TEST(CliTerminal, AMistypedCommandGetsASuggestionAndExitTwo) {
  const CommandResult r = run_linkscape("evl --fk x.csv", kNoDisplay);
  EXPECT_EQ(r.exit_code, 2) << r.out;
  EXPECT_EQ(r.out.rfind("linkscape: error: ", 0), 0u) << r.out;
  EXPECT_TRUE(contains(r.out, "mean 'linkscape eval'?")) << r.out;
}

TEST(CliTerminal, AMistypedOptionGetsASuggestion) {
  const CommandResult r = run_linkscape("slice --plnae x=0.25 -o a.png", kNoDisplay);
  EXPECT_EQ(r.exit_code, 2) << r.out;
  EXPECT_EQ(r.out.rfind("linkscape: error: ", 0), 0u) << r.out;
  EXPECT_TRUE(contains(r.out, "Did you mean '--plane'?")) << r.out;
  EXPECT_TRUE(contains(r.out, "Run 'linkscape slice --help'")) << r.out;
  // Nothing close: no suggestion, still the help pointer.
  const CommandResult far = run_linkscape("--frobnicate", kNoDisplay);
  EXPECT_EQ(far.exit_code, 2);
  EXPECT_FALSE(contains(far.out, "Did you mean")) << far.out;
  EXPECT_TRUE(contains(far.out, "Run 'linkscape --help'")) << far.out;
}

TEST(CliTerminal, InputErrorsOfEveryKindShareOneStyle) {
  for (const std::string& args : {std::string("slice --plane x=0.25 -o out.txt"), std::string("field --resolution 1 -o f.vti"),
                                  std::string("mesh --surface 'cond<0.5' -o m.stl"), std::string("eval --fk missing.csv")}) {
    const CommandResult r = run_linkscape(args, kNoDisplay);
    EXPECT_EQ(r.exit_code, 2) << args << "\n" << r.out;
    EXPECT_EQ(r.out.rfind("linkscape: error: ", 0), 0u) << args << "\n" << r.out;
  }
}

TEST(CliTerminal, EveryCommandSaysWhatItWroteUnlessQuiet) {
  fs::create_directories(kDir);
  const fs::path angles = temp_file("terminal_angles.csv", "alpha,beta,gamma\n0,0,1.5707963267948966\n");
  struct Case {
    std::string args, summary;
  };
  const std::vector<Case> cases = {
      {"slice --plane x=0.25 --size 40x30 -o " + (kDir / "s.png").string(), "linkscape: slice: wrote "},
      {"field --resolution 12 -o " + (kDir / "f.vti").string(), "linkscape: field: wrote "},
      {"eval --fk " + angles.string() + " -o " + (kDir / "fk.csv").string(),
       "linkscape: eval: forward kinematics of 1 row (parallel-12r) written to "},
  };
  for (const Case& c : cases) {
    const CommandResult loud = run_linkscape(c.args, kNoDisplay);
    EXPECT_EQ(loud.exit_code, 0) << c.args << "\n" << loud.out;
    EXPECT_TRUE(contains(loud.out, c.summary)) << c.args << "\n" << loud.out;
    EXPECT_TRUE(contains(loud.out, " s\n")) << "the summary ends with the time taken: " << loud.out;
    const CommandResult quiet = run_linkscape(c.args + " --quiet", kNoDisplay);
    EXPECT_EQ(quiet.exit_code, 0) << quiet.out;
    EXPECT_EQ(quiet.out, "") << c.args;
  }
}

TEST(CliTerminal, ProgressIsShownOnATerminalOnly) {
  // script(1) gives the command a terminal. The time left itself is checked
  // without timing in TerminalProgress.* (it needs a step longer than 0.5 s).
  fs::create_directories(kDir);
  const std::string field = std::string(LINKSCAPE_BINARY) + " field --mechanism pathos2 --resolution 120 -o " +
                            (kDir / "p.vti").string();
  const CommandResult tty = run_linkscape("", "script -qec '" + field + "' /dev/null; true ||");
  EXPECT_TRUE(contains(tty.out, "sampling")) << tty.out;
  EXPECT_TRUE(contains(tty.out, "writing " + (kDir / "p.vti").string())) << tty.out;
  EXPECT_TRUE(contains(tty.out, "\r")) << "the line is redrawn in place";
  const CommandResult pipe = run_linkscape("field --mechanism pathos2 --resolution 40 -o " + (kDir / "p.vti").string());
  EXPECT_EQ(pipe.exit_code, 0) << pipe.out;
  EXPECT_FALSE(contains(pipe.out, "\r")) << "no progress line when stderr is not a terminal";
}

TEST(CliTerminal, AFileArgumentOpensASessionOrAMechanism) {
  SKIP_WITHOUT_WINDOW();
  fs::create_directories(kDir);
  // A preset file is opened as the mechanism: its error names it.
  const fs::path preset = temp_file("terminal_bad_preset.json", R"({"mechanism": "parallel-12r", "length_unit": "cm", "parameters": {"L1": -1, "L2": 15}})");
  const CommandResult bad_preset = run_linkscape(preset.string() + " --screenshot " + (kDir / "w.png").string());
  EXPECT_EQ(bad_preset.exit_code, 2) << bad_preset.out;
  EXPECT_TRUE(contains(bad_preset.out, "L1")) << bad_preset.out;
  // A session file is opened as a session: its checks apply.
  const fs::path session = temp_file("terminal_bad_session.json",
                                     R"({"format": "linkscape-session", "version": 1, "mechanism": "no-such-device"})");
  const CommandResult bad_session = run_linkscape(session.string() + " --screenshot " + (kDir / "w.png").string());
  EXPECT_EQ(bad_session.exit_code, 2) << bad_session.out;
  EXPECT_TRUE(contains(bad_session.out, "no-such-device")) << bad_session.out;
  // A file and --mechanism: ambiguous, refused.
  const CommandResult both = run_linkscape(session.string() + " --mechanism pathos2");
  EXPECT_EQ(both.exit_code, 2) << both.out;
  if (!std::getenv("DISPLAY")) GTEST_SKIP() << "opening a good session needs an X server";
  const fs::path good = temp_file("terminal_session.json",
                                  R"({"format": "linkscape-session", "version": 1, "mechanism": "parallel-12r",
                                      "parameters": {"L1": 13, "L2": 16}, "pose_rad": [0.1, 1.2, 0.3]})");
  const fs::path png = kDir / "session.png";
  fs::remove(png);
  const CommandResult opened = run_linkscape(good.string() + " --screenshot " + png.string() + " --size 900x600");
  EXPECT_EQ(opened.exit_code, 0) << opened.out;
  EXPECT_TRUE(fs::exists(png));
}

TEST(CliTerminal, TheViewAloneIsDrawnAtTheAskedSize) {
  SKIP_WITHOUT_WINDOW();
  fs::create_directories(kDir);
  const CommandResult bad_size = run_linkscape("--view-image v.png --view-size 10x10");
  EXPECT_EQ(bad_size.exit_code, 2) << bad_size.out;
  const CommandResult bad_type = run_linkscape("--view-image v.jpg");
  EXPECT_EQ(bad_type.exit_code, 2) << bad_type.out;
  if (!std::getenv("DISPLAY")) GTEST_SKIP() << "drawing the view needs an X server";
  const fs::path png = kDir / "view.png";
  fs::remove(png);
  const CommandResult r = run_linkscape("--view-image " + png.string() + " --view-size 1500x400 --size 900x600");
  ASSERT_EQ(r.exit_code, 0) << r.out;
  // Width and height from the PNG header: the asked size, larger than the window itself.
  std::ifstream in(png, std::ios::binary);
  unsigned char h[24] = {};
  in.read(reinterpret_cast<char*>(h), 24);
  auto be32 = [&](int o) { return (h[o] << 24) | (h[o + 1] << 16) | (h[o + 2] << 8) | h[o + 3]; };
  EXPECT_EQ(be32(16), 1500);
  EXPECT_EQ(be32(20), 400);
}

// Help fits the terminal: 80 columns in a pipe (and so in the man page made
// from it); the width of $COLUMNS where it is set.
TEST(CliTerminal, HelpIsWrappedToTheTerminal) {
  for (const std::string command : {"", "eval", "slice", "field", "mesh", "fit", "sweep", "bench", "design"}) {
    for (const auto& [columns, width] : std::vector<std::pair<std::string, std::size_t>>{{"-u COLUMNS", 80}, {"COLUMNS=100", 100}}) {
      const auto r = run_linkscape(command + " --help", "env " + columns);
      ASSERT_EQ(r.exit_code, 0) << command << ": " << r.out;
      std::istringstream lines(r.out);
      std::size_t longest = 0, count = 0;
      for (std::string line; std::getline(lines, line); ++count) longest = std::max(longest, line.size());
      EXPECT_LE(longest, width) << "linkscape " << command << " --help with " << columns;
      EXPECT_GT(count, 10u) << command;
    }
  }
}
