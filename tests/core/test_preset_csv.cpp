#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>

#include "core/csv.h"
#include "core/mechanisms/parallel12r/mechanism.h"
#include "core/preset.h"
#include "core/spelling.h"

using namespace linkscape;
namespace fs = std::filesystem;

// parse_preset refuses the text, its message containing `words`.
void refused(const std::string& text, const std::string& words) {
  try {
    parse_preset(text, "t");
    ADD_FAILURE() << "accepted: " << text;
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
  }
}

TEST(Preset, ShippedParallel12rIsThePapersDesign) {
  const Preset p = load_preset("parallel-12r");
  EXPECT_EQ(p.mechanism, "parallel-12r");
  EXPECT_EQ(p.length_unit, "cm");
  const auto m = make_parallel12r(p);
  EXPECT_DOUBLE_EQ(m.L1, 15.0);
  EXPECT_DOUBLE_EQ(m.L2, 15.0);
  EXPECT_NEAR(m.alpha_limits.hi, std::numbers::pi / 2, 1e-15);
}

TEST(Preset, OverridesAndTheirErrors) {
  Preset p = load_preset("parallel-12r");
  apply_overrides(p, {"L1=1", "L2=2.5"});
  EXPECT_DOUBLE_EQ(make_parallel12r(p).L2, 2.5);
  EXPECT_THROW(apply_overrides(p, {"L3=1"}), std::invalid_argument);
  EXPECT_THROW(apply_overrides(p, {"L1"}), std::invalid_argument);
  EXPECT_THROW(apply_overrides(p, {"L1=abc"}), std::invalid_argument);
  EXPECT_THROW(apply_overrides(p, {"L1=1x"}), std::invalid_argument);
  EXPECT_THROW(apply_overrides(p, {"L1=-2"}), std::invalid_argument);
  EXPECT_THROW(apply_overrides(p, {"L1=0"}), std::invalid_argument);
}

TEST(Preset, MalformedFileNamesTheFileAndTheProblem) {
  const auto dir = std::filesystem::temp_directory_path();
  const auto file = dir / "linkscape_bad_preset.json";
  {
    std::ofstream out(file);
    out << "{ \"mechanism\": \"parallel-12r\", \"parameters\": { \"L1\": 1, }";
  }
  try {
    load_preset(file.string());
    FAIL() << "expected an exception";
  } catch (const std::invalid_argument& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find(file.string()), std::string::npos) << msg;
    EXPECT_NE(msg.find("parse error"), std::string::npos) << msg;
  }
  EXPECT_THROW(load_preset("no-such-mechanism"), std::invalid_argument);
  refused(R"({"mechanism":"parallel-12r","length_unit":"cm","parameters":{"L1":"x","L2":1}})", "parameters.L1");
  refused(R"({"mechanism":"other","length_unit":"cm","parameters":{}})", "other");
  std::filesystem::remove(file);
}

// A preset states its unit (one the program converts) and every parameter
// of a compiled device's design: nothing is taken from a default unseen.
TEST(Preset, StatesItsUnitAndItsDesign) {
  refused(R"({"mechanism":"delta","parameters":{"R":9.5,"r":5.4,"La":8,"Lb":17}})", "missing key 'length_unit'");
  refused(R"({"mechanism":"delta","length_unit":"furlong","parameters":{"R":9.5,"r":5.4,"La":8,"Lb":17}})",
          "length_unit must be one of mm, cm, m, in, got 'furlong'");
  refused(R"({"mechanism":"delta","length_unit":"cm","parameters":{"R":9.5,"La":8}})", "lack r, Lb");
  refused(R"({"mechanism":"parallel-12r","length_unit":"cm","parameters":{}})", "lack L1, L2");
  refused(R"({"mechanism":"pathos2","length_unit":"cm","parameters":{"l0":45}})", "lack lb, l1, l2, l3, lp, h0, theta_t");
  // PATHOS-II's offsets and limits follow from the rest where not given.
  EXPECT_NO_THROW(parse_preset(
      R"({"mechanism":"pathos2","length_unit":"cm",
          "parameters":{"l0":45,"lb":10,"l1":7,"l2":14,"l3":6,"lp":2,"h0":7,"theta_t":30}})",
      "t"));
}

TEST(Csv, ReadsHeaderAndRowsAndReportsLineOfBadField) {
  std::istringstream good("# comment\nx, y ,z\n1,2,3\n\n4.5,-6,7e-3\n");
  const Table t = read_csv(good, "good.csv");
  ASSERT_EQ(t.rows.size(), 2u);
  EXPECT_EQ(t.column("y"), 1u);
  EXPECT_DOUBLE_EQ(t.rows[1][2], 7e-3);
  EXPECT_THROW(t.column("w"), std::invalid_argument);

  std::istringstream bad("x,y,z\n1,2,3\n1,two,3\n");
  try {
    read_csv(bad, "bad.csv");
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("bad.csv:3"), std::string::npos) << e.what();
  }
  std::istringstream short_row("x,y,z\n1,2\n");
  EXPECT_THROW(read_csv(short_row, "s.csv"), std::invalid_argument);
  std::istringstream empty("");
  EXPECT_THROW(read_csv(empty, "e.csv"), std::invalid_argument);
}

TEST(Csv, NumbersRoundTrip) {
  for (double v : {0.1, 1.0 / 3.0, -2.5e-300, 15.0}) EXPECT_EQ(std::stod(format_number(v)), v);
}

TEST(Csv, AcceptsAByteOrderMarkAndAPlusSignAndKeepsLineNumbers) {
  std::istringstream in("\xEF\xBB\xBFx,y,z\n# comment\n+1,2,+3e0\n\n-4,5,6\n");
  const Table t = read_csv(in, "bom.csv");
  ASSERT_EQ(t.columns.front(), "x");  // the mark is not part of the first name
  ASSERT_EQ(t.rows.size(), 2u);
  EXPECT_DOUBLE_EQ(t.rows[0][0], 1.0);
  EXPECT_DOUBLE_EQ(t.rows[0][2], 3.0);
  EXPECT_EQ(t.where(0), "bom.csv:3");
  EXPECT_EQ(t.where(1), "bom.csv:5");
  for (const char* not_numbers : {"++1", "+-1", "+", "-", "1e", "0x10", "1,0"})
    EXPECT_FALSE(parse_number(not_numbers).has_value()) << not_numbers;
}

// Cells in double quotes, as spreadsheets save them (RFC 4180): the quotes
// are not part of the value, a quoted name may hold a comma, "" is a quote.
TEST(Csv, ReadsQuotedCells) {
  std::istringstream in("\"x\", \"a, b\" ,z\n\"0\", \"15\" ,+1.5\n\"\",2,3\n");
  const Table t = read_csv(in, "quoted.csv");
  ASSERT_EQ(t.columns, (std::vector<std::string>{"x", "a, b", "z"}));
  ASSERT_EQ(t.rows.size(), 2u);
  EXPECT_EQ(t.rows[0][0], 0.0);
  EXPECT_EQ(t.rows[0][1], 15.0);  // spaces outside the quotes are not the cell's
  EXPECT_EQ(t.rows[0][2], 1.5);
  EXPECT_TRUE(std::isnan(t.rows[1][0]));  // "": no value, as an empty cell
  std::istringstream space_inside("x\n\" 15\"\n");  // inside quotes a space is the cell's: not a number
  EXPECT_THROW(read_csv(space_inside, "q.csv"), std::invalid_argument);
  std::istringstream open_quote("x,y\n\"1,2\n");  // an unclosed quote takes the rest of the line
  EXPECT_THROW(read_csv(open_quote, "q.csv"), std::invalid_argument);
}

// A name the file system refuses (longer than NAME_MAX) is an unknown preset,
// not a std::filesystem::filesystem_error (found by fuzzing sessions).
TEST(Preset, AnOverlongNameIsAnUnknownPreset) {
  const std::string name(5000, 'a');
  EXPECT_THROW(load_preset(name), std::invalid_argument);
  EXPECT_THROW(load_preset(name + ".json"), std::invalid_argument);
  EXPECT_THROW(load_preset("dir/" + name), std::invalid_argument);
}

TEST(Csv, RefusesAByteOrderMarkAnywhereButTheStart) {
  // A second mark would become an invisible column name (or part of one) that
  // no header written back can reproduce.
  for (const char* text : {"\xEF\xBB\xBF\xEF\xBB\xBF\n", "x,\xEF\xBB\xBFy\n1,2\n", "x\n\xEF\xBB\xBF" "1\n"}) {
    std::istringstream in(text);
    try {
      read_csv(in, "marks.csv");
      FAIL() << "accepted a byte-order mark inside the text";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("marks.csv:"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("byte-order mark"), std::string::npos) << e.what();
    }
  }
}

TEST(Csv, RefusesRepeatedAndUnnamedColumns) {
  std::istringstream repeated("x,y,x\n1,2,3\n");
  try {
    read_csv(repeated, "dup.csv");
    FAIL() << "a repeated column was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("dup.csv:1: column 'x' appears twice"), std::string::npos) << e.what();
  }
  std::istringstream unnamed("x,,z\n1,2,3\n");
  EXPECT_THROW(read_csv(unnamed, "u.csv"), std::invalid_argument);
}

// numpy's savetxt writes the header as a comment, which is skipped: the
// first row of numbers is then named as the header's mistake; a file whose
// lines end in a lone CR (one line to getline) is named as such.
TEST(Csv, AHeaderOfNumbersOrLoneCarriageReturnsAreNamed) {
  const auto message = [](const std::string& text) {
    std::istringstream in(text);
    try {
      read_csv(in, "in.csv");
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_NE(message("# x,y,z\n0,0,-16.5\n1,2,3\n").find("in.csv:2: the header holds numbers ('0,0,-16.5')"),
            std::string::npos);
  EXPECT_NE(message("x,y,z\r0,0,-16.5\r").find("in.csv:1: lines end in a lone carriage return"), std::string::npos);
  EXPECT_EQ(message("x,y,z\r\n0,0,-16.5\r\n"), "accepted");  // CR LF, as spreadsheets save
  EXPECT_EQ(message("# a comment\nx,y,z\n0,0,-16.5\n"), "accepted");
}

TEST(Csv, SaysOutOfRangeRatherThanNotANumber) {
  bool out_of_range = false;
  EXPECT_FALSE(parse_number("1e400", &out_of_range).has_value());
  EXPECT_TRUE(out_of_range);
  try {
    parse_number_or_throw("1e400", "parameter L1");
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("out of the range"), std::string::npos) << e.what();
  }
  EXPECT_THROW(parse_number_or_throw("inf", "x"), std::invalid_argument);
  EXPECT_TRUE(std::isinf(parse_number_or_throw("inf", "x", true)));
  // Small but representable values are numbers, whatever a model then says of them.
  EXPECT_DOUBLE_EQ(parse_number_or_throw("1e-300", "x"), 1e-300);
}

TEST(Preset, ParamOverridesUseTheStrictNumberRules) {
  Preset p = load_preset("parallel-12r");
  try {
    apply_overrides(p, {"L1=1e400"});
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("out of the range"), std::string::npos) << e.what();
  }
  EXPECT_THROW(apply_overrides(p, {"L1=inf"}), std::invalid_argument);
  EXPECT_THROW(apply_overrides(p, {"L1=nan"}), std::invalid_argument);
  apply_overrides(p, {"L1=+12"});
  EXPECT_DOUBLE_EQ(make_parallel12r(p).L1, 12.0);
}

TEST(Preset, RefusesWhatItWouldIgnore) {
  // PATHOS-II's joint limits are parameters; a limits block would be ignored.
  refused(R"({"mechanism":"pathos2","length_unit":"cm","parameters":{"l0":45,"lb":10,"l1":7,"l2":14,"l3":6,"lp":2,
              "h0":7,"theta_t":30},"actuator_limits_deg":{"q1":[-90,90]}})",
          "pathos2 takes no actuator_limits_deg");
  // A misspelt key would be ignored too.
  try {
    parse_preset(R"({"mechanism":"parallel-12r","length_unit":"cm","parameters":{"L1":1,"L2":1},"actuator_limit_deg":{}})",
                 "p.json");
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("actuator_limit_deg"), std::string::npos) << e.what();
  }
  refused(R"({"mechanism":"parallel-12r","length_unit":"cm","parameters":{"L1":1,"L2":1},"actuator_limits_deg":{"delta":[0,1]}})",
          "delta");
}

TEST(Preset, ReferenceIsTheNameForShippedPresetsAndThePathOtherwise) {
  const Preset shipped = load_preset("parallel-12r");
  EXPECT_EQ(preset_reference(shipped), "parallel-12r");
  const auto file = std::filesystem::temp_directory_path() / "linkscape_own_preset.json";
  std::filesystem::copy_file(shipped.source, file, std::filesystem::copy_options::overwrite_existing);
  const Preset own = load_preset(file.string());
  EXPECT_EQ(preset_reference(own), std::filesystem::absolute(file).string());
  std::filesystem::remove(file);
}

// One number cell for every table (one writer used to put "inf" for -inf).
TEST(Csv, NumberCellsRoundTripWithSignedInfinitiesAndEmptyForNaN) {
  for (double v : {0.1, -2.5e-300, 1e308, 3.0}) EXPECT_EQ(parse_number(csv_number(v)), v);
  EXPECT_EQ(csv_number(std::numeric_limits<double>::infinity()), "inf");
  EXPECT_EQ(csv_number(-std::numeric_limits<double>::infinity()), "-inf");
  EXPECT_EQ(csv_number(std::nan("")), "");
}

// The fast writers' cells: the same text as csv_number for doubles, a
// float's own shortest text (that reads back to the same float), integers
// as they are, and nothing for NaN.
TEST(Csv, AppendedCellsMatchCsvNumberAndKeepFloatsShort) {
  const auto cell = [](auto v) {
    std::string out;
    append_csv_number(out, v);
    return out;
  };
  for (double v : {0.1, -2.5e-300, 1e308, 3.0, std::numeric_limits<double>::infinity(),
                   -std::numeric_limits<double>::infinity(), std::nan("")})
    EXPECT_EQ(cell(v), csv_number(v)) << v;
  EXPECT_EQ(cell(0.1f), "0.1");
  EXPECT_EQ(cell(std::numeric_limits<float>::quiet_NaN()), "");
  EXPECT_EQ(cell(-std::numeric_limits<float>::infinity()), "-inf");
  for (float v : {1e-30f, 3.4e38f, 0.3f, -7.123457f}) EXPECT_EQ(float(*parse_number(cell(v))), v) << v;
  EXPECT_EQ(cell(std::uint8_t(255)), "255");
  EXPECT_EQ(cell(std::uint16_t(50)), "50");
}

// What the writers leave empty reads back as no value.
TEST(Csv, AnEmptyCellReadsAsNoValue) {
  std::istringstream in("x,cond,status\n1,,0\n2,inf,2\n");
  const Table t = read_csv(in, "t.csv");
  ASSERT_EQ(t.rows.size(), 2u);
  EXPECT_TRUE(std::isnan(t.rows[0][1]));
  EXPECT_EQ(t.rows[0][2], 0.0);
  EXPECT_TRUE(std::isinf(t.rows[1][1]));
}

TEST(Csv, ColumnsCarryTheirUnitAsASuffix) {
  EXPECT_EQ(csv_column("reach_margin", "cm"), "reach_margin_cm");
  EXPECT_EQ(csv_column("force_iso", "N"), "force_iso_N");
  EXPECT_EQ(csv_column("cond", ""), "cond");  // a ratio: no unit
}

TEST(Csv, TextCellsAreQuotedWhereRfc4180NeedsIt) {
  EXPECT_EQ(csv_text("leg 3"), "leg 3");
  EXPECT_EQ(csv_text(""), "");
  EXPECT_EQ(csv_text("leg 3, left"), "\"leg 3, left\"");
  EXPECT_EQ(csv_text("the \"long\" leg"), "\"the \"\"long\"\" leg\"");
  EXPECT_EQ(csv_text("two\nlines"), "\"two\nlines\"");
  EXPECT_EQ(csv_text(" padded"), "\" padded\"");
}

// A folder or a pipe named as a preset is not "missing": the message says
// what it is, and a pipe is never opened (its read would block).
TEST(Preset, AFolderOrPipeNamedAsAPresetSaysWhatItIs) {
  const fs::path dir = fs::temp_directory_path() / ("linkscape_preset_kinds" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir / "folder.json");
  ASSERT_EQ(::mkfifo((dir / "pipe.json").c_str(), 0600), 0);
  for (const auto& [name, expected] : std::vector<std::pair<std::string, std::string>>{
           {"folder.json", "is a folder, not a file"}, {"pipe.json", "is not a regular file"}, {"none.json", "does not exist"}}) {
    try {
      load_preset((dir / name).string());
      FAIL() << name;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
    }
  }
  fs::remove_all(dir);
}

TEST(Spelling, AMistypedWordGetsTheNearestName) {
  const std::vector<std::string> commands = {"eval", "slice", "field", "mesh", "fit", "sweep"};
  EXPECT_EQ(closest_name("evl", commands), "eval");
  EXPECT_EQ(closest_name("silce", commands), "slice");  // two letters swapped: one step
  EXPECT_EQ(closest_name("--plnae", {"--plane", "--pose"}), "--plane");
  EXPECT_FALSE(closest_name("frobnicate", commands));
  // Ties are all offered; the same name in another case is what was meant.
  const std::vector<std::string> presets = {"three-rpr", "three-rrr", "delta"};
  EXPECT_EQ(did_you_mean("three-rr", presets), "; did you mean 'three-rpr' or 'three-rrr'?");
  EXPECT_EQ(did_you_mean("delat", presets), "; did you mean 'delta'?");
  EXPECT_EQ(did_you_mean("A", {"a", "b", "d"}), "; did you mean 'a'?");
  EXPECT_EQ(did_you_mean("x", {"a", "b", "d"}), "; did you mean 'a', 'b' or 'd'?");
  EXPECT_EQ(did_you_mean("frobnicate", presets), "");
}

TEST(Preset, AMistypedPresetNameGetsASuggestion) {
  try {
    load_preset("delat");
    FAIL() << "expected an error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("did you mean 'delta'?"), std::string::npos) << e.what();
  }
  try {
    load_preset("frobnicate");
    FAIL() << "expected an error";
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(std::string(e.what()).find("did you mean"), std::string::npos) << e.what();
  }
}

// The JSON library's error codes stay out of what the user reads.
TEST(Preset, AMalformedFileSaysWhereWithoutTheLibrarysCode) {
  const fs::path file = fs::temp_directory_path() / ("linkscape_malformed" + std::to_string(::getpid()) + ".json");
  std::ofstream(file) << "{\"mechanism\": \"delta\", \"parameters\": {";
  try {
    load_preset(file.string());
    FAIL() << "expected an error";
  } catch (const std::invalid_argument& e) {
    const std::string what = e.what();
    EXPECT_EQ(what.find("json.exception"), std::string::npos) << what;
    EXPECT_NE(what.find("line 1, column"), std::string::npos) << what;
  }
  fs::remove(file);
}
