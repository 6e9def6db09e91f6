// A described preset without what bounds it beyond its actuators' travel:
// its passive joints' limits and its links' radii removed, for comparisons
// with devices that do not model them (the compiled Delta).
#pragma once

#include <nlohmann/json.hpp>

#include "core/preset.h"

namespace linkscape::testing_support {

inline void strip_stops(nlohmann::json& steps) {
  for (nlohmann::json& step : steps) {
    for (const char* key : {"cone", "ranges_deg", "radius", "link"}) step.erase(key);
    if (!step.value("actuated", false)) step.erase("range_deg");
  }
}

inline Preset without_stops(Preset p) {
  nlohmann::json d = nlohmann::json::parse(p.description);
  for (nlohmann::json& leg : d["legs"])
    for (const char* list : {"base", "chain", "anchor"})
      if (leg.contains(list)) strip_stops(leg[list]);
  p.description = d.dump();
  return p;
}

}  // namespace linkscape::testing_support
