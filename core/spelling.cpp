#include "core/spelling.h"

#include <algorithm>
#include <cctype>

namespace linkscape {
namespace {

// Optimal string alignment distance: insertions, deletions, substitutions
// and swaps of neighbours each cost 1 ("--plnae" is one step from "--plane").
std::size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::vector<std::size_t>> d(a.size() + 1, std::vector<std::size_t>(b.size() + 1));
  for (std::size_t i = 0; i <= a.size(); ++i) d[i][0] = i;
  for (std::size_t j = 0; j <= b.size(); ++j) d[0][j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i)
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t cost = a[i - 1] == b[j - 1] ? 0 : 1;
      d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + cost});
      if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1]) d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
    }
  return d[a.size()][b.size()];
}

// Every candidate at the least distance from `word` within the limit
// (a third of its length, at least 1), in the candidates' order.
std::vector<std::string> closest_names(const std::string& word, const std::vector<std::string>& candidates) {
  // The same name in another case is what was meant ("A" for "a", not "b").
  const auto lower = [](std::string t) {
    std::transform(t.begin(), t.end(), t.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return t;
  };
  for (const std::string& c : candidates)
    if (lower(c) == lower(word)) return {c};
  const std::size_t limit = std::max<std::size_t>(1, word.size() / 3);
  std::vector<std::string> best;
  std::size_t best_distance = limit;
  for (const std::string& c : candidates) {
    const std::size_t d = edit_distance(word, c);
    if (d > limit) continue;
    if (d < best_distance) best.clear(), best_distance = d;
    if (d == best_distance) best.push_back(c);
  }
  return best;
}

}  // namespace

std::optional<std::string> closest_name(const std::string& word, const std::vector<std::string>& candidates) {
  const std::vector<std::string> best = closest_names(word, candidates);
  if (best.empty()) return std::nullopt;
  return best.front();
}

std::string did_you_mean(const std::string& word, const std::vector<std::string>& candidates) {
  const std::vector<std::string> best = closest_names(word, candidates);
  std::string out;
  for (std::size_t i = 0; i < best.size(); ++i)
    out += std::string(i == 0 ? "" : i + 1 == best.size() ? " or " : ", ") + "'" + best[i] + "'";
  return best.empty() ? "" : "; did you mean " + out + "?";
}

}  // namespace linkscape
