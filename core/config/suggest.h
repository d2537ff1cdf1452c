#pragma once
// "Did you mean": the closest known names to a misspelled one (options, topics, presets).
#include <algorithm>
#include <string>
#include <vector>

namespace enact::config {

// Levenshtein distance between a and b (insertions, deletions, substitutions)
inline std::size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = up;
    }
  }
  return row[b.size()];
}

// " (did you mean X?)", or " (did you mean X or Y?)" for ties, naming the candidates closest
// to `word` when they are close (at most a third of its letters off, at least 1); else ""
inline std::string did_you_mean(const std::string& word, const std::vector<std::string>& candidates, const std::string& prefix = "") {
  const std::size_t limit = std::max<std::size_t>(1, word.size() / 3);
  std::size_t best = limit + 1;
  std::vector<std::string> closest;
  for (const std::string& c : candidates) {
    const std::size_t d = edit_distance(word, c);
    if (d < best) closest.clear(), best = d;
    if (d == best) closest.push_back(c);
  }
  if (closest.empty()) return "";
  std::string out = " (did you mean ";
  for (std::size_t i = 0; i < closest.size(); ++i) out += (i == 0 ? "" : i + 1 == closest.size() ? " or " : ", ") + prefix + closest[i];
  return out + "?)";
}

}  // namespace enact::config
