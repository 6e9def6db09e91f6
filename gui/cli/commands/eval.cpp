// linkscape eval: inverse or forward kinematics of each row of a CSV, written as CSV.
#include <Eigen/Core>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <optional>
#include <sstream>
#include <stdexcept>

#include "core/atomic_file.h"
#include "core/csv.h"
#include "core/mechanism.h"
#include "core/spelling.h"
#include "gui/cli/command.h"
#include "gui/cli/sampling.h"
#include "gui/cli/terminal.h"

namespace linkscape::gui {
namespace {

struct EvalOptions {
  PresetChoice mechanism;
  StopSwitches stops;
  std::string ik_file;  // CSV of task coordinates ("-" = stdin); exclusive with fk_file
  std::string fk_file;  // CSV of actuator values
  std::string method;   // empty: the device's first IK method
  std::optional<int> branch;
  std::string seed;     // actuator values, comma separated
  double tolerance = 1e-10;
  std::optional<int> max_iterations;  // default IkOptions' (100)
  std::string output = "-";  // file, or "-" for stdout
  bool quiet = false;        // no summary on stderr
};

Table read_input(const std::string& file, std::istream& stdin_stream) {
  if (file == "-") return read_csv(stdin_stream, "<stdin>");
  std::error_code ec;
  if (std::filesystem::is_directory(file, ec)) throw std::invalid_argument("input '" + file + "' is a folder, not a CSV file");
  std::ifstream in(file);
  if (!in) throw std::invalid_argument("cannot open input file '" + file + "'");
  return read_csv(in, file);
}

// Every value a command reads must be finite: the first that is not is an
// error naming its file, line and column.
void require_finite(const Table& table, const std::vector<std::size_t>& columns) {
  for (std::size_t r = 0; r < table.rows.size(); ++r)
    for (std::size_t c : columns)
      if (!std::isfinite(table.rows[r][c]))
        throw std::invalid_argument(table.where(r) + ": column '" + table.columns[c] + "': " +
                                    (std::isnan(table.rows[r][c]) ? std::string("no value (an empty cell or nan)")
                                                                  : format_number(table.rows[r][c])) +
                                    " is not a finite number");
}

// A column the command does not read is refused (a mistyped seed_x had left
// FK starting from home without a word), naming the columns it reads.
void refuse_unread(const Table& table, const std::vector<std::size_t>& used, const std::vector<std::string>& reads) {
  for (std::size_t c = 0; c < table.columns.size(); ++c) {
    if (std::count(used.begin(), used.end(), c)) continue;
    std::string list;
    for (const std::string& name : reads) list += (list.empty() ? "" : ",") + name;
    throw std::invalid_argument(table.origin + ":1: column '" + table.columns[c] + "' is not one this reads (" + list +
                                ")" + did_you_mean(table.columns[c], reads));
  }
}

// Runs `body` for each row; an invalid_argument thrown for a row is reported
// with the row's file and line.
template <typename Body>
void for_each_row(const Table& table, Body body) {
  for (std::size_t r = 0; r < table.rows.size(); ++r) {
    try {
      body(table.rows[r]);
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(table.where(r) + ": " + e.what());
    }
  }
}

std::string empties(std::size_t n) { return std::string(n, ','); }

// Inverse kinematics of each row of task coordinates: one output row per
// solution (branch), or one row that says why there is none. Columns as
// MechanismInfo::EvalColumns describes.
void write_ik(const Mechanism& m, const Table& table, const IkOptions& ik, std::ostream& out) {
  const MechanismInfo& info = m.info();
  const auto& c = info.eval_columns;
  std::vector<std::size_t> col;
  std::vector<std::string> reads;
  for (const Quantity& q : info.task) {
    col.push_back(table.column(q.name));
    reads.push_back(q.name);
  }
  refuse_unread(table, col, reads);
  require_finite(table, col);
  out << joined_names(info.task) << (c.ik_branch ? ",branch" : "") << ",status"
      << (c.ik_failing_part.empty() ? "" : "," + c.ik_failing_part) << "," << joined_names(info.actuators);
  for (const NamedItem& measure : info.measures) out << "," << measure.name;
  out << (c.ik_det ? ",det" : "") << (c.ik_diagnostics ? ",residual,iterations" : "") << "\n";
  const std::size_t after_status = info.actuators.size() + info.measures.size() + (c.ik_det ? 1 : 0) +
                                   (c.ik_diagnostics ? 2 : 0) + (c.ik_failing_part.empty() ? 0 : 1);
  for_each_row(table, [&](const std::vector<double>& row) {
    Eigen::VectorXd x(Eigen::Index(col.size()));
    std::string where;
    for (std::size_t k = 0; k < col.size(); ++k) {
      x(Eigen::Index(k)) = row[col[k]];
      where += csv_number(row[col[k]]) + ",";
    }
    check_read_coordinates(info, x, "");
    const IkResult r = m.inverse(x, ik);
    for (const IkSolution& s : r.solutions) {
      out << where;
      if (c.ik_branch) out << s.branch << ",";
      out << to_string(s.status);
      if (!c.ik_failing_part.empty()) out << "," << csv_text(s.failing_part);
      for (Eigen::Index k = 0; k < s.q.size(); ++k) out << "," << csv_number(s.q(k));
      // Measures only where the legs close (not where the solver stopped short or missed).
      const bool closes = s.status == Status::Ok || s.status == Status::OutOfLimits || s.status == Status::Singular;
      const Measures meas = closes ? m.measures(s.q, x) : Measures{};
      for (std::size_t k = 0; k < info.measures.size(); ++k)
        out << "," << (k < meas.values.size() ? csv_number(meas.values[k]) : "");
      if (c.ik_det) out << "," << (closes ? csv_number(meas.det) : "");
      if (c.ik_diagnostics) out << "," << csv_number(s.residual) << "," << s.iterations;
      out << "\n";
    }
    if (r.solutions.empty()) {
      const Status status = r.status == Status::Ok ? Status::NotConverged : r.status;
      out << where;
      if (c.ik_branch) out << (ik.branch ? std::to_string(*ik.branch) : "") << ",";
      out << csv_text(r.status_text.empty() ? std::string(to_string(status)) : r.status_text);
      if (!c.ik_failing_part.empty()) out << "," << csv_text(r.failing_part) << empties(after_status - 1) << "\n";
      else out << empties(after_status) << "\n";
    }
  });
}

// Forward kinematics of each row of actuator values (and the task
// coordinates the device reads as inputs), from the home pose or the row's
// seed_<coordinate> columns: a row's answer depends on that row alone.
void write_fk(const Mechanism& m, const Table& table, std::ostream& out) {
  const MechanismInfo& info = m.info();
  const auto& c = info.eval_columns;
  std::vector<std::size_t> q_col, input_col, used;
  for (const Quantity& q : info.actuators) used.push_back(q_col.emplace_back(table.column(q.name)));
  std::vector<int> input_index, result_index;  // into info.task
  for (std::size_t k = 0; k < info.task.size(); ++k) {
    const bool input = std::count(info.fk_inputs.begin(), info.fk_inputs.end(), info.task[k].name) > 0;
    (input ? input_index : result_index).push_back(int(k));
    if (input) used.push_back(input_col.emplace_back(table.column(info.task[k].name)));
  }
  // Seeds: all of seed_<result coordinate> or none.
  std::vector<std::size_t> seed_col;
  std::string seed_names;
  for (int k : result_index) {
    const std::string name = "seed_" + info.task[std::size_t(k)].name;
    seed_names += (seed_names.empty() ? "" : ",") + name;
    if (std::count(table.columns.begin(), table.columns.end(), name)) seed_col.push_back(table.column(name));
  }
  if (!seed_col.empty() && seed_col.size() != result_index.size())
    throw std::invalid_argument(table.origin + ": give all of the seed columns (" + seed_names + ") or none");
  used.insert(used.end(), seed_col.begin(), seed_col.end());
  std::vector<std::string> reads;
  for (const Quantity& q : info.actuators) reads.push_back(q.name);
  for (int k : input_index) reads.push_back(info.task[std::size_t(k)].name);
  for (int k : result_index) reads.push_back("seed_" + info.task[std::size_t(k)].name);
  refuse_unread(table, used, reads);
  require_finite(table, used);

  out << joined_names(info.actuators);
  for (int k : input_index) out << "," << info.task[std::size_t(k)].name;
  if (c.fk_status) out << ",status";
  for (int k : result_index) out << "," << info.task[std::size_t(k)].name;
  if (c.fk_measures) {
    for (const NamedItem& measure : info.measures) out << "," << measure.name;
    out << ",det";
  }
  out << (c.fk_diagnostics ? ",iterations,residual" : "") << "\n";
  const Eigen::VectorXd home = m.home_task();
  for_each_row(table, [&](const std::vector<double>& row) {
    Eigen::VectorXd q(Eigen::Index(q_col.size()));
    for (std::size_t k = 0; k < q_col.size(); ++k) q(Eigen::Index(k)) = row[q_col[k]];
    // A seed only where the row gives one (or the inputs it carries): a
    // closed form's default mode is the device's working one, not the one
    // nearer home.
    FkOptions fo;
    if (!seed_col.empty() || !input_col.empty()) fo.seed = home;
    for (std::size_t k = 0; k < input_index.size(); ++k) (*fo.seed)(input_index[k]) = row[input_col[k]];
    for (std::size_t k = 0; k < seed_col.size(); ++k) (*fo.seed)(result_index[k]) = row[seed_col[k]];
    if (fo.seed) check_read_coordinates(info, *fo.seed, "");
    for (std::size_t k = 0; k < q_col.size(); ++k) out << (k ? "," : "") << csv_number(row[q_col[k]]);
    for (std::size_t k = 0; k < input_col.size(); ++k) out << "," << csv_number(row[input_col[k]]);
    const FkResult r = m.forward(q, fo);
    // The pose and its measures wherever the device assembles there (out of
    // limits or singular too), as IK's rows give them.
    const bool ok = (r.status == Status::Ok || r.status == Status::OutOfLimits || r.status == Status::Singular) &&
                    r.x.size() == Eigen::Index(info.task.size()) && r.x.allFinite();
    if (c.fk_status) out << "," << (r.status_text.empty() ? std::string(to_string(r.status)) : r.status_text);
    for (int k : result_index) out << "," << (ok ? csv_number(r.x(k)) : "");
    if (c.fk_measures) {
      const Measures meas = ok ? m.measures(q, r.x) : Measures{};
      for (std::size_t k = 0; k < info.measures.size(); ++k)
        out << "," << (ok && k < meas.values.size() ? csv_number(meas.values[k]) : "");
      out << "," << (ok ? csv_number(meas.det) : "");
    }
    if (c.fk_diagnostics) {
      if (r.status_text.empty()) out << "," << r.iterations << "," << csv_number(r.residual);
      else out << ",,";
    }
    out << "\n";
  });
}

// Writes the evaluation as CSV. Throws std::invalid_argument for bad input.
void run_eval(const EvalOptions& o, std::istream& stdin_stream, std::ostream& stdout_stream) {
  if (o.ik_file.empty() == o.fk_file.empty())
    throw std::invalid_argument("eval: give exactly one of --ik FILE or --fk FILE");
  check_ik_tolerance(o.tolerance, "eval");
  // Forward kinematics has one answer a row, from the row's seed columns:
  // the options of IK would be quietly ignored.
  if (!o.fk_file.empty())
    for (const auto& [given, option] : {std::pair{!o.method.empty(), "--method"}, {o.branch.has_value(), "--branch"},
                                        {!o.seed.empty(), "--seed"}, {o.max_iterations.has_value(), "--max-iterations"}})
      if (given)
        throw std::invalid_argument(std::string("eval: ") + option + " applies to --ik; forward kinematics starts from "
                                    "the home pose or the row's seed_<coordinate> columns");
  if (o.max_iterations && *o.max_iterations < 1)
    throw std::invalid_argument("eval: --max-iterations must be at least 1, got " + std::to_string(*o.max_iterations));
  Preset preset = chosen_preset(o.mechanism);
  apply_stop_switches(o.stops, preset, "eval");
  const std::shared_ptr<const Mechanism> m = make_mechanism(preset);
  const MechanismInfo& info = m->info();
  IkOptions ik = checked_ik(info, o.method, o.branch, "eval");  // before reading input
  if (!o.seed.empty()) {
    const std::vector<double> seed =
        parse_numbers(o.seed, info.actuators.size(),
                      "eval: --seed expects " + joined_names(info.actuators) + " (" +
                          std::to_string(info.actuators.size()) + " finite values, comma separated) for " + info.name);
    ik.seed = Eigen::Map<const Eigen::VectorXd>(seed.data(), Eigen::Index(seed.size()));
    const std::string method = o.method.empty() ? info.ik_methods.front().name : o.method;
    const std::vector<std::string>& seeded = info.seeded_ik_methods;
    if (std::find(seeded.begin(), seeded.end(), method) == seeded.end())
      throw std::invalid_argument("eval: --seed: " + info.name + "'s IK method '" + method +
                                  "' does not start from a seed (" +
                                  (seeded.empty() ? "none of its methods does: each leg is solved from seeds of its own"
                                                  : "with --method " + seeded.front() + " it does") + ")");
  }
  ik.tolerance = o.tolerance;
  if (o.max_iterations) ik.max_iterations = *o.max_iterations;
  const auto start = std::chrono::steady_clock::now();
  Table table = read_input(o.ik_file.empty() ? o.fk_file : o.ik_file, stdin_stream);
  // A planar device's z is its plane's: its targets, and its FK seeds, may leave it out.
  const auto has = [&](const std::string& column) {
    return std::find(table.columns.begin(), table.columns.end(), column) != table.columns.end();
  };
  const std::string z = o.ik_file.empty() ? "seed_z" : "z";
  const bool fk_seeded = o.ik_file.empty() && std::any_of(table.columns.begin(), table.columns.end(), [](const auto& c) {
                           return c.rfind("seed_", 0) == 0;
                         });
  if (info.plane_z && !has(z) && (!o.ik_file.empty() || fk_seeded)) {
    table.columns.push_back(z);
    for (std::vector<double>& row : table.rows) row.push_back(*info.plane_z);
  }
  std::ostringstream result;
  if (!o.ik_file.empty()) write_ik(*m, table, ik, result);
  else write_fk(*m, table, result);

  if (o.output == "-") {
    stdout_stream << result.str();
  } else {
    write_text_atomically(o.output, result.str());
  }
  // Written to stdout, the rows themselves say it worked; a summary there would only get in a pipe's way.
  if (o.output != "-")
    summary(o.quiet, std::string("eval: ") + (o.ik_file.empty() ? "forward" : "inverse") + " kinematics of " +
                       std::to_string(table.rows.size()) + (table.rows.size() == 1 ? " row (" : " rows (") + info.name + ") written to " +
                       o.output + " in " + seconds_since(start));
}

Command add_eval(CLI::App& program, const DeviceHelp& help) {
  auto o = std::make_shared<EvalOptions>();
  CLI::App* cmd = program.add_subcommand("eval", "Evaluate kinematics for each CSV row; writes CSV (stdout by default)");
  add_mechanism_options(*cmd, o->mechanism);
  add_stop_options(*cmd, o->stops);
  auto* ik = cmd->add_option(
      "--ik", o->ik_file,
      "Inverse kinematics of the targets in a CSV whose header names the device's task coordinates (" +
          help.per_device([](const MechanismInfo& i) { return with_units(i.task); }) +
          "; a described device's: linkscape describe NAME; '-' = stdin). Writes one row per branch found: the "
          "target, branch, status, actuators, measures and diagnostics, as far as the device reports them");
  auto* fk = cmd->add_option(
      "--fk", o->fk_file,
      "Forward kinematics of a CSV whose header names the device's actuators and FK inputs (" +
          help.per_device([](const MechanismInfo& i) { return with_units(fk_columns(i)); }) +
          "; a described device's: linkscape describe NAME). Iterative FK starts from the home pose, or from the "
          "row's seed_<coordinate> columns when given, so each row's answer depends on that row alone; writes the "
          "actuators, the task coordinates, and the status, measures and diagnostics as far as the device reports them");
  ik->excludes(fk);
  cmd->add_option("--method", o->method,
                  "IK method, one of the device's (default: its first). " +
                      help.per_device([](const MechanismInfo& i) { return names(i.ik_methods, ", ", true); }))
      ->capture_default_str();
  cmd->add_option("--branch", o->branch, "Only this assembly branch, an index of the device's (" + branches_help(help) + ")");
  cmd->add_option("--seed", o->seed,
                  "Start for the IK methods that iterate from a seed (refused for the others: a closed form, a "
                  "described device's legs, solved from seeds of their own): the device's actuator values, "
                  "comma separated (default: each branch's home pose)");
  cmd->add_option("--tolerance", o->tolerance, "Accept a solution when residual <= tolerance * the device's size")
      ->capture_default_str();
  cmd->add_option("--max-iterations", o->max_iterations,
                  "Iteration limit of the compiled devices' newton/dls (a described device's numerical solver takes "
                  "up to 40 a seed, its seeds as docs/described-mechanisms.md says); default 100");
  cmd->add_option("-o,--output", o->output, "Output CSV file (written atomically); '-' = stdout")->capture_default_str();
  cmd->add_flag("-q,--quiet", o->quiet, "No summary on stderr (there is none when the rows go to stdout)");
  return {cmd, Runs::Headless,
          "linkscape eval --mechanism NAME --ik targets.csv     inverse kinematics of each row's task coordinates\n"
          "linkscape eval --mechanism NAME --fk actuators.csv   forward kinematics of each row's actuator values",
          [o](std::istream& in, std::ostream& out) {
            run_eval(*o, in, out);
            return 0;
          }};
}

const RegisterCommand registered{10, add_eval};

}  // namespace
}  // namespace linkscape::gui
