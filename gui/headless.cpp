#include "gui/headless.h"

#include <fstream>
#include <iostream>
#include <sstream>
#include <stdexcept>

#include "core/atomic_file.h"
#include "core/csv.h"
#include "core/parallel12r.h"
#include "core/preset.h"

namespace linkscape::gui {
namespace {

using parallel12r::IkResult;
using parallel12r::IkSolution;

Table read_input(const std::string& file, std::istream& stdin_stream) {
  if (file == "-") return read_csv(stdin_stream, "<stdin>");
  std::ifstream in(file);
  if (!in) throw std::invalid_argument("cannot open input file '" + file + "'");
  return read_csv(in, file);
}

// CSV cells; missing values are empty cells, never NaN.
std::string cell(double v) { return std::isfinite(v) ? format_number(v) : (std::isinf(v) ? "inf" : ""); }

void write_ik(const parallel12r::Model& model, const Table& table, const EvalOptions& o, std::ostream& out) {
  const std::size_t cx = table.column("x"), cy = table.column("y"), cz = table.column("z");
  parallel12r::IkOptions ik;
  ik.seed = o.seed;
  ik.tolerance = o.tolerance;
  ik.max_iterations = o.max_iterations;
  const auto method = parallel12r::parse_ik_method(o.method);
  out << "x,y,z,branch,status,alpha,beta,gamma,cond,det,residual,iterations\n";
  for (const auto& row : table.rows) {
    const Eigen::Vector3d p(row[cx], row[cy], row[cz]);
    const std::string where = cell(p.x()) + "," + cell(p.y()) + "," + cell(p.z()) + ",";
    const IkResult r = parallel12r::inverse(model, p, method, ik);
    bool written = false;
    for (const IkSolution& s : r.solutions) {
      if (o.branch && s.branch != *o.branch) continue;
      const auto c = parallel12r::conditioning(model, s.q_actuated);
      out << where << s.branch << "," << to_string(s.status) << "," << cell(s.q_actuated.x()) << ","
          << cell(s.q_actuated.y()) << "," << cell(s.q_actuated.z()) << "," << cell(c.cond) << ","
          << cell(c.det) << "," << cell(s.residual) << "," << s.iterations << "\n";
      written = true;
    }
    if (!written) {
      // No solution (in the requested branch): one row that says why.
      const Status status = r.status == Status::Ok ? Status::NotConverged : r.status;
      out << where << (o.branch ? std::to_string(*o.branch) : "") << "," << to_string(status)
          << ",,,,,,,\n";
    }
  }
}

void write_fk(const parallel12r::Model& model, const Table& table, std::ostream& out) {
  const std::size_t ca = table.column("alpha"), cb = table.column("beta"), cg = table.column("gamma");
  out << "alpha,beta,gamma,x,y,z,cond,det\n";
  for (const auto& row : table.rows) {
    const Eigen::Vector3d q(row[ca], row[cb], row[cg]);
    const Eigen::Vector3d p = parallel12r::forward(model, q);
    const auto c = parallel12r::conditioning(model, q);
    out << cell(q.x()) << "," << cell(q.y()) << "," << cell(q.z()) << "," << cell(p.x()) << ","
        << cell(p.y()) << "," << cell(p.z()) << "," << cell(c.cond) << "," << cell(c.det) << "\n";
  }
}

}  // namespace

void run_eval(const EvalOptions& o, std::istream& stdin_stream, std::ostream& stdout_stream) {
  if (o.ik_file.empty() == o.fk_file.empty())
    throw std::invalid_argument("eval: give exactly one of --ik FILE or --fk FILE");
  if (o.branch && (*o.branch < 0 || *o.branch > 1))
    throw std::invalid_argument("eval: --branch must be 0 or 1, got " + std::to_string(*o.branch));
  if (!(o.tolerance > 0)) throw std::invalid_argument("eval: --tolerance must be positive");
  Preset preset = load_preset(o.mechanism.mechanism);
  apply_overrides(preset, o.mechanism.params);
  const parallel12r::Model model = make_parallel12r(preset);
  parallel12r::parse_ik_method(o.method);  // reject a bad name before reading input
  const Table table = read_input(o.ik_file.empty() ? o.fk_file : o.ik_file, stdin_stream);

  std::ostringstream result;
  if (!o.ik_file.empty()) write_ik(model, table, o, result);
  else write_fk(model, table, result);

  if (o.output == "-") {
    stdout_stream << result.str();
  } else {
    write_atomically(o.output, [&](const std::filesystem::path& tmp) {
      std::ofstream out(tmp);
      out << result.str();
      if (!out) throw std::runtime_error("cannot write '" + o.output + "'");
    });
  }
}

}  // namespace linkscape::gui
