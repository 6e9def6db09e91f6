#include "core/sweep.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <random>
#include <sstream>
#include <stdexcept>

#include "core/csv.h"
#include "core/pareto.h"
#include "core/field.h"
#include "core/atomic_file.h"

namespace linkscape::sweep {
namespace {

constexpr std::size_t kMaxDesigns = 1'000'000'000;
// What a sweep keeps per design until its table is written (the design, its
// row in the checkpoint's map and in the table, its cells while the Pareto
// front is marked, its fit row for the chart): about 920 bytes plus 78 a
// column, measured as peak memory over designs with /usr/bin/time -v
// (docs/sweeps.md), rounded up.
constexpr double kBytesPerDesign = 1024, kBytesPerCell = 96;


double number_of(const std::string& text) {
  if (text.empty()) return std::nan("");
  return parse_number(text).value_or(std::nan(""));
}

// An error message as one CSV cell on one line (the checkpoint is a journal
// of lines): line breaks become spaces, commas and quotes are quoted.
std::string error_cell(std::string text) {
  std::replace(text.begin(), text.end(), '\n', ' ');
  std::replace(text.begin(), text.end(), '\r', ' ');
  return csv_text(text);
}

bool free_centre(const Plan& plan) { return !plan.problem.task.centre; }

// The first criterion on a measure (the chart's and the Pareto front's y), or none.
std::optional<std::size_t> measured_criterion(const Plan& plan) {
  const auto& c = plan.problem.criteria;
  const auto it = std::find_if(c.begin(), c.end(), [](const task::Criterion& x) { return !x.reach(); });
  if (it == c.end()) return std::nullopt;
  return std::size_t(it - c.begin());
}

const char* kFieldColumns[] = {"reach_volume", "gci", "task_reach", "task_worst_cond", "task_mean_cond"};

struct FieldMeasures {
  double reach_volume = 0, gci = std::nan(""), task_reach = std::nan(""), task_worst = std::nan(""),
         task_mean = std::nan("");
};

// The measures over the device's default box sampled at the plan's
// resolution (see Plan::field_resolution). Summed in index order, so the
// values do not depend on the thread count.
FieldMeasures field_measures(const Plan& plan, const Mechanism& m, const Eigen::Vector3d& centre) {
  const Eigen::AlignedBox3d box = m.default_box();
  const Eigen::Vector3d extent = box.sizes();
  std::array<int, 3> dims{};
  for (int k = 0; k < 3; ++k)
    dims[std::size_t(k)] = std::max(2, int(std::lround(plan.field_resolution * extent(k) / extent.maxCoeff())));
  const Grid grid = Grid::box(box.min(), box.max(), dims);
  const Eigen::VectorXd fixed = plan.problem.pose.size() ? plan.problem.pose : m.home_task();
  const std::optional<Field> field = m.compute_field(grid, fixed, plan.problem.ik, plan.problem.threads, {});
  if (!field) throw std::runtime_error("field sampling was cancelled");
  const std::optional<double> plane = m.info().plane_z;
  FieldMeasures out;
  std::size_t reachable = 0, in_task = 0, in_task_reachable = 0, finite = 0;
  double inverse_sum = 0, task_sum = 0, task_worst = 0;
  for (int k = 0; k < dims[2]; ++k)
    for (int j = 0; j < dims[1]; ++j)
      for (int i = 0; i < dims[0]; ++i) {
        const std::size_t s = grid.index(i, j, k);
        const bool reached = field->reachable[s] != 0;
        const double c = field->cond[s];
        if (reached) {
          ++reachable;
          inverse_sum += std::isfinite(c) && c > 0 ? 1.0 / c : 0.0;
        }
        Eigen::Vector3d p = grid.point(i, j, k);
        if (plane) p.z() = centre.z();  // a planar device's task: its section by the plane
        if (!plan.problem.task.contains(p, centre)) continue;
        ++in_task;
        task_worst = std::max(task_worst, reached ? c : INFINITY);
        if (!reached) continue;
        ++in_task_reachable;
        if (std::isfinite(c)) ++finite, task_sum += c;
      }
  out.reach_volume = double(reachable) * grid.spacing.prod();
  if (reachable) out.gci = inverse_sum / double(reachable);
  if (in_task) {
    out.task_reach = double(in_task_reachable) / double(in_task);
    out.task_worst = task_worst;
  }
  if (finite) out.task_mean = task_sum / double(finite);
  return out;
}

std::size_t column_of(const std::vector<std::string>& header, const std::string& name) {
  return std::size_t(std::find(header.begin(), header.end(), name) - header.begin());
}

}  // namespace

std::size_t design_count(const Plan& plan) {
  const auto& vars = plan.problem.variables;
  fit::check_bounds(vars, "sweep");
  if (plan.sampling == Sampling::Random) {
    if (plan.count < 1 || plan.count > kMaxDesigns)
      throw std::invalid_argument("sweep: --random needs 1 to 10^9 designs, got " + std::to_string(plan.count));
    return plan.count;
  }
  if (plan.levels < 2) throw std::invalid_argument("sweep: --grid needs at least 2 values per parameter");
  double total = 1;
  for (std::size_t i = 0; i < vars.size(); ++i) total *= plan.levels;
  if (total > double(kMaxDesigns))
    throw std::invalid_argument("sweep: a grid of " + std::to_string(plan.levels) + "^" + std::to_string(vars.size()) +
                                " designs is more than 10^9");
  return std::size_t(total);
}

double table_bytes(const Plan& plan) {
  const double cells = double(csv_cells(header(plan)).size());
  return double(design_count(plan)) * (kBytesPerDesign + kBytesPerCell * cells);
}

std::vector<std::vector<double>> designs(const Plan& plan) {
  const auto& vars = plan.problem.variables;
  const std::size_t n = design_count(plan);
  // Refused before the designs take any memory.
  const double needed = table_bytes(plan);
  if (const std::optional<double> available = available_memory_bytes(); available && needed > *available) {
    std::ostringstream message;
    message << std::setprecision(3) << "sweep: " << n << " designs need about " << needed / (1 << 30)
            << " GiB for the table, over the " << *available / (1 << 30)
            << " GiB of memory available now; sweep fewer designs (a coarser --grid, a smaller --random) or split "
               "the bounds into several sweeps";
    throw std::invalid_argument(message.str());
  }
  std::vector<std::vector<double>> out;
  out.reserve(n);
  if (plan.sampling == Sampling::Grid) {
    for (std::size_t d = 0; d < n; ++d) {
      std::vector<double> values(vars.size());
      std::size_t rest = d;
      for (std::size_t i = vars.size(); i-- > 0;) {  // the last variable fastest
        const double t = double(rest % std::size_t(plan.levels)) / (plan.levels - 1);
        rest /= std::size_t(plan.levels);
        values[i] = t == 1 ? vars[i].hi : vars[i].lo + t * (vars[i].hi - vars[i].lo);
      }
      out.push_back(std::move(values));
    }
  } else {
    std::mt19937_64 random(plan.seed);
    for (std::size_t d = 0; d < n; ++d) {
      std::vector<double> values(vars.size());
      for (std::size_t i = 0; i < vars.size(); ++i) {
        // 53 random bits as a double in [0, 1): the same on every platform
        // (std::uniform_real_distribution is not specified bit for bit).
        const double u = double(random() >> 11) * 0x1.0p-53;
        values[i] = vars[i].lo + u * (vars[i].hi - vars[i].lo);
      }
      out.push_back(std::move(values));
    }
  }
  return out;
}

std::string header(const Plan& plan) {
  std::ostringstream s;
  s << "design";
  for (const std::string& c : plan.columns) s << "," << csv_text(c);
  s << "," << fit::score_header(plan.problem);
  if (plan.field_resolution > 0)
    for (const char* c : kFieldColumns) s << "," << c;
  s << ",pareto,error";
  return s.str();
}

std::string evaluate_row(const Plan& plan, std::size_t index, const std::vector<double>& values) {
  const Preset preset = fit::design_preset(plan.problem, values);
  std::map<std::string, double> parameters = preset.parameters;  // the whole design, once built
  std::optional<fit::Row> row;
  std::optional<FieldMeasures> field;
  std::string error;
  try {
    row = fit::evaluate(plan.problem, values);
    if (!row) throw std::runtime_error("evaluation was cancelled");
    if (!row->invalid.empty()) {
      error = "invalid design: " + row->invalid;
    } else {
      parameters = row->parameters;
      if (plan.field_resolution > 0) field = field_measures(plan, *make_mechanism(preset), row->centre);
    }
  } catch (const std::exception& e) {
    error = std::string("evaluation failed: ") + e.what();
  }
  const bool scored = error.empty();
  std::ostringstream s;
  s << index;
  for (const std::string& c : plan.columns) {
    const auto it = parameters.find(c);
    s << "," << (it == parameters.end() ? "" : csv_number(it->second));
  }
  if (!scored) {
    // Empty scores: every column but design, the parameters, pareto and error.
    const std::size_t score_cells = csv_cells(header(plan)).size() - plan.columns.size() - 3;
    for (std::size_t i = 0; i < score_cells; ++i) s << ",";
    s << ",0," << error_cell(error);
    return s.str();
  }
  s << "," << fit::score_cells(plan.problem, *row);
  if (field)
    s << "," << csv_number(field->reach_volume) << "," << csv_number(field->gci) << "," << csv_number(field->task_reach) << ","
      << csv_number(field->task_worst) << "," << csv_number(field->task_mean);
  s << ",0,";
  return s.str();
}

fit::Result as_fit_result(const Plan& plan, const std::map<std::size_t, std::string>& rows) {
  const std::vector<std::string> head = csv_cells(header(plan));
  const bool free = free_centre(plan);
  const std::size_t size_col = column_of(head, "size"), meets_col = column_of(head, "meets"),
                    fraction_col = column_of(head, "fraction"), error_col = column_of(head, "error"),
                    samples_col = column_of(head, "samples"), failing_col = column_of(head, "failing");
  const std::size_t fit_col = free ? fraction_col - 1 : fraction_col, ratio_col = column_of(head, "ratio");
  const task::TaskVolume& t = plan.problem.task;
  fit::Result r;
  for (const auto& [index, text] : rows) {
    const std::vector<std::string> row_cells = csv_cells(text);
    if (row_cells.size() != head.size() || !row_cells[error_col].empty()) continue;
    fit::Row row;
    for (std::size_t k = 0; k < plan.columns.size(); ++k) row.parameters[plan.columns[k]] = number_of(row_cells[k + 1]);
    row.size = number_of(row_cells[size_col]);
    row.meets = row_cells[meets_col] == "1";
    row.fit = number_of(row_cells[fit_col]);
    if (free && t.shape == task::Shape::Sphere) row.fit /= t.diameter();
    row.report.fraction = number_of(row_cells[fraction_col]);
    row.report.samples = int(number_of(row_cells[samples_col]));
    row.report.failing = int(number_of(row_cells[failing_col]));
    row.ratio = number_of(row_cells[ratio_col]);
    for (std::size_t c = 0; c < plan.problem.criteria.size(); ++c) {
      task::CriterionReport report;
      report.criterion = plan.problem.criteria[c];
      report.worst = number_of(row_cells[ratio_col + 1 + 3 * c]);
      report.failing = int(number_of(row_cells[ratio_col + 3 + 3 * c]));
      row.report.criteria.push_back(report);
    }
    if (row.meets && (!r.best || row.size < r.rows[*r.best].size)) r.best = r.rows.size();
    if (!r.closest || row.fit > r.rows[*r.closest].fit) r.closest = r.rows.size();
    r.rows.push_back(std::move(row));
  }
  if (r.best) r.closest.reset();
  return r;
}

std::string table(const Plan& plan, const std::map<std::size_t, std::string>& rows) {
  const std::vector<std::string> head = csv_cells(header(plan));
  const std::size_t size_col = column_of(head, "size"), pareto_col = column_of(head, "pareto"),
                    error_col = column_of(head, "error");
  const std::optional<std::size_t> measured = measured_criterion(plan);
  const std::size_t ratio_col = column_of(head, "ratio");
  const std::size_t y_col = measured ? ratio_col + 1 + 3 * *measured : ratio_col;
  const bool larger_is_better = !measured || plan.problem.criteria[*measured].above;
  std::vector<std::vector<std::string>> lines;
  std::vector<double> x, y;
  std::vector<std::size_t> candidates;
  std::size_t expected = 0;
  for (const auto& [index, text] : rows) {
    if (index != expected++) throw std::invalid_argument("sweep: the table misses design " + std::to_string(index - 1));
    lines.push_back(csv_cells(text));
    const auto& c = lines.back();
    if (c.size() != head.size())
      throw std::invalid_argument("sweep: design " + std::to_string(index) + " has " + std::to_string(c.size()) +
                                  " cells, the header " + std::to_string(head.size()));
    const double size = number_of(c[size_col]), value = number_of(c[y_col]);
    if (c[error_col].empty() && std::isfinite(size) && std::isfinite(value)) {
      x.push_back(size);
      y.push_back(value);
      candidates.push_back(lines.size() - 1);
    }
  }
  const std::vector<bool> front = non_dominated(x, y, larger_is_better);
  for (std::size_t k = 0; k < candidates.size(); ++k) lines[candidates[k]][pareto_col] = front[k] ? "1" : "0";
  std::string out = header(plan) + "\n";
  for (const auto& c : lines) {
    for (std::size_t k = 0; k < c.size(); ++k) {
      if (k) out += ',';
      out += csv_text(c[k]);
    }
    out += "\n";
  }
  return out;
}

std::string fingerprint(const Plan& plan) {
  const fit::Problem& p = plan.problem;
  std::ostringstream s;
  s << "linkscape sweep 2; " << p.preset.mechanism << ";";
  for (const auto& [name, value] : p.preset.parameters) s << " " << name << "=" << csv_number(value);
  s << ";";
  // A stop switched off changes every answer (named only then: older journals still resume).
  if (!p.preset.checks.joint_limits) s << " joint limits off;";
  if (!p.preset.checks.interference) s << " interference off;";
  for (const fit::Variable& v : p.variables) s << " " << v.name() << "=" << csv_number(v.lo) << ":" << csv_number(v.hi);
  s << "; task " << p.task.text << ";";
  for (const task::Criterion& c : p.criteria) s << " " << c.text;
  s << "; pose";
  for (Eigen::Index i = 0; i < p.pose.size(); ++i) s << " " << csv_number(p.pose(i));
  s << "; method " << p.ik.method << " branch " << p.ik.branch.value_or(0) << " torque " << int(p.torque) << "; inscribed "
    << p.inscribed.resolution << " " << p.inscribed.refinements << " " << p.inscribed.places << "; task resolution "
    << p.task_resolution << "; ";
  if (p.inscribed.centres) s << "centres " << task::to_text(*p.inscribed.centres) << "; ";
  if (plan.sampling == Sampling::Grid) s << "grid " << plan.levels;
  else s << "random " << plan.count << " seed " << plan.seed;
  s << "; field " << plan.field_resolution << "; " << header(plan);
  return s.str();
}

Checkpoint::Checkpoint(const std::filesystem::path& path, const Plan& plan, std::size_t designs, bool resume)
    : path_(path), file_(followed_links(path)) {
  const std::string first = "# " + fingerprint(plan);
  const std::size_t width = csv_cells(header(plan)).size();
  if (resume) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw std::invalid_argument("sweep: --resume finds no checkpoint '" + path.string() + "'");
    std::stringstream text;
    text << in.rdbuf();
    const std::string all = text.str();
    // Whole lines only: a run killed while writing leaves a partial last line.
    const std::size_t complete = all.rfind('\n') == std::string::npos ? 0 : all.rfind('\n') + 1;
    std::istringstream lines(all.substr(0, complete));
    std::string line;
    if (!std::getline(lines, line) || line != first)
      throw std::invalid_argument("sweep: the checkpoint '" + path.string() +
                                  "' is of another sweep (its first line differs from this command's plan); "
                                  "remove it (or give another --checkpoint) to start again");
    for (int number = 2; std::getline(lines, line); ++number) {
      const std::string where = path.string() + ":" + std::to_string(number);
      const std::optional<double> index = parse_number(line.substr(0, line.find(',')));
      if (!index || *index < 0 || *index >= double(designs) || *index != std::floor(*index))
        throw std::invalid_argument("sweep: " + where + ": a checkpoint row starts with a design index below " +
                                    std::to_string(designs));
      std::size_t count = 0;
      try {
        count = csv_cells(line).size();
      } catch (const std::invalid_argument& e) {
        throw std::invalid_argument("sweep: " + where + ": " + e.what());
      }
      if (count != width)
        throw std::invalid_argument("sweep: " + where + ": " + std::to_string(count) + " cells, expected " +
                                    std::to_string(width));
      rows_[std::size_t(*index)] = line;
    }
    std::filesystem::resize_file(path, complete);
    out_.open(path, std::ios::binary | std::ios::app);
  } else {
    // A journal left by a stopped run holds finished work: never replaced silently.
    if (std::filesystem::exists(path))
      throw std::invalid_argument("sweep: a stopped sweep's checkpoint '" + path.string() +
                                  "' exists: add --resume to finish it, or remove it to start again");
    out_.open(path, std::ios::binary | std::ios::trunc);
    out_ << first << "\n";
  }
  out_.flush();
  if (!out_) throw std::runtime_error("sweep: cannot write the checkpoint '" + path.string() + "'");
}

void Checkpoint::add(std::size_t index, const std::string& row) {
  rows_[index] = row;
  out_ << row << "\n";
}

void Checkpoint::flush() {
  out_.flush();
  if (!out_) throw std::runtime_error("sweep: cannot write the checkpoint '" + path_.string() + "'");
}

void Checkpoint::remove() {
  out_.close();
  std::filesystem::remove(file_);
}

}  // namespace linkscape::sweep
