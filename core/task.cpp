#include "core/task.h"

#include <cmath>
#include <stdexcept>

#include "core/csv.h"

namespace linkscape::task {

Criterion parse_criterion(const std::string& text) {
  Criterion c;
  c.text = text;
  if (text == "reach" || text == "reachable") {
    c.measure = "reach";
    return c;
  }
  const auto op = text.find_first_of("<>");
  if (op == std::string::npos || op == 0)
    throw std::invalid_argument("criterion '" + text +
                                "': expected reach or NAME<VALUE / NAME>VALUE, e.g. cond<3, force_iso>2, "
                                "resolution<0.5, inertia<0.2");
  c.measure = text.substr(0, op);
  c.above = text[op] == '>';
  std::size_t number = op + 1;
  if (number < text.size() && text[number] == '=') ++number;  // <= and >= read as < and >
  const std::optional<double> v = parse_number(text.substr(number));
  if (!v || !std::isfinite(*v))
    throw std::invalid_argument("criterion '" + text + "': the threshold must be a finite number");
  c.threshold = *v;
  const bool larger_is_better = c.measure == "force_iso" || c.measure == "force_max";
  if (c.above != larger_is_better)
    throw std::invalid_argument("criterion '" + text + "': " + c.measure + " is bounded " +
                                (larger_is_better ? "from below (" + c.measure + ">VALUE)"
                                                  : "from above (" + c.measure + "<VALUE)"));
  if (!haptics::is_haptic_field(c.measure) && !(c.threshold > 1))
    throw std::invalid_argument("criterion '" + text + "': no pose meets it (condition numbers are at least 1)");
  if (!(c.threshold > 0))
    throw std::invalid_argument("criterion '" + text + "': no pose meets it (the threshold must be positive)");
  return c;
}

void check_criterion(const Criterion& c, const MechanismInfo& info, const haptics::DeviceData* data) {
  if (c.measure == "reach" || c.measure == "cond") return;
  std::string known = "reach, cond";
  for (std::size_t k = 0; k < info.measures.size(); ++k) {
    if (info.measures[k].name == c.measure) return;
    if (info.measures[k].name != "cond") known += ", " + info.measures[k].name;
  }
  if (data)
    for (const haptics::FieldInfo& f : haptics::field_infos(*data)) {
      if (f.name == c.measure) return;
      known += ", " + f.name;
    }
  if (c.measure == "inertia" && data)
    throw std::invalid_argument("criterion '" + c.text + "': the preset gives no rotor_inertia_kgm2 for every actuator");
  throw std::invalid_argument("criterion '" + c.text + "': unknown measure '" + c.measure + "' for " + info.name +
                              " (known: " + known + ")");
}

}  // namespace linkscape::task
