#include "core/error.h"

#include <algorithm>

namespace colony {

std::string Diagnostic::ToString() const {
  std::string out;
  if (!file.empty()) {
    out.append(file);
    if (line > 0) out.append(":").append(std::to_string(line));
    out.append(": ");
  }
  if (!element.empty()) out.append("<").append(element).append(">");
  if (!attribute.empty()) {
    if (!element.empty()) out.append(" ");
    out.append("attribute '").append(attribute).append("'");
  }
  if (!element.empty() || !attribute.empty()) out.append(": ");
  out.append(message);
  return out;
}

static std::string JoinDiagnostics(const std::vector<Diagnostic>& ds) {
  std::string out;
  for (size_t i = 0; i < ds.size(); ++i) {
    if (i) out += "\n";
    out += ds[i].ToString();
  }
  return out;
}

ConfigError::ConfigError(std::vector<Diagnostic> diagnostics)
    : std::runtime_error(JoinDiagnostics(diagnostics)), diagnostics_(std::move(diagnostics)) {}

ConfigError::ConfigError(const std::string& message)
    : std::runtime_error(message), diagnostics_{Diagnostic{"", 0, "", "", "", message}} {}

void Diagnostics::ThrowIfAny() {
  if (items_.empty()) return;
  std::vector<Diagnostic> items;
  items.swap(items_);
  throw ConfigError(std::move(items));
}

// Optimal string alignment distance: an insertion, a deletion, a
// substitution or a swap of neighbours ("lenght") each count 1.
static size_t EditDistance(const std::string& a, const std::string& b) {
  std::vector<size_t> before(b.size() + 1), prev(b.size() + 1), cur(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) prev[j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    cur[0] = i;
    for (size_t j = 1; j <= b.size(); ++j) {
      const size_t subst = prev[j - 1] + (a[i - 1] == b[j - 1] ? 0 : 1);
      cur[j] = std::min({prev[j] + 1, cur[j - 1] + 1, subst});
      if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1]) {
        cur[j] = std::min(cur[j], before[j - 2] + 1);
      }
    }
    before.swap(prev);
    prev.swap(cur);
  }
  return prev[b.size()];
}

std::string DidYouMean(const std::string& word, const std::vector<std::string>& candidates) {
  std::string best;
  size_t best_distance = std::max<size_t>(2, word.size() / 3) + 1;
  for (const auto& c : candidates) {
    const size_t d = EditDistance(word, c);
    // Replacing every character is no typo ("b" is not a misspelt "a").
    if (d >= std::max(word.size(), c.size())) continue;
    if (d < best_distance) {
      best_distance = d;
      best = c;
    }
  }
  return best;
}

}  // namespace colony
