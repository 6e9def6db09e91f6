// Suggestions for mistyped names (commands, options, presets, fields).
#pragma once

#include <optional>
#include <string>
#include <vector>

namespace linkscape {

// The candidate `word` was most likely meant to be (edit distance with
// transpositions at most a third of its length, at least 1), if any.
std::optional<std::string> closest_name(const std::string& word, const std::vector<std::string>& candidates);

// "; did you mean 'a'?" (or "'a' or 'b'?" where candidates tie at the
// closest distance), empty where none is close enough.
std::string did_you_mean(const std::string& word, const std::vector<std::string>& candidates);

}  // namespace linkscape
