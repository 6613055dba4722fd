#include "cli/arguments.h"

#include <algorithm>
#include <charconv>
#include <sstream>
#include <vector>

namespace spheremap::cli {
namespace {

std::string shortest(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

// Levenshtein distance: how many one-character edits turn a into b.
size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<size_t> row(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    size_t diagonal = row[0];
    row[0] = i;
    for (size_t j = 1; j <= b.size(); ++j) {
      const size_t replaced = diagonal + (a[i - 1] == b[j - 1] ? 0 : 1);
      diagonal = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, replaced});
    }
  }
  return row[b.size()];
}

// " (did you mean --quality?)" for a name within a few edits of a known option, else "".
std::string did_you_mean(const std::string& name, const std::set<std::string>& value_options,
                         const std::set<std::string>& flags) {
  if (name.size() > 64) return "";  // a typo is short; bound the work on junk
  std::string best;
  size_t best_distance = std::max<size_t>(2, name.size() / 3) + 1;
  for (const auto* known : {&value_options, &flags})
    for (const std::string& option : *known) {
      const size_t d = edit_distance(name, option);
      if (d < best_distance) best_distance = d, best = option;
    }
  return best.empty() ? "" : " (did you mean --" + best + "?)";
}

}  // namespace

Arguments::Arguments(int argc, char** argv, int first, const std::set<std::string>& value_options,
                     const std::set<std::string>& flags) {
  for (int i = first; i < argc; ++i) {
    std::string arg = argv[i];
    if (arg == "-o") arg = "--output";
    if (arg == "-h") arg = "--help";
    if (arg.size() < 2 || arg.compare(0, 2, "--") != 0 || arg == "--") {
      positional_.push_back(arg);
      continue;
    }
    std::string name = arg.substr(2), value;
    const size_t eq = name.find('=');
    const bool inline_value = eq != std::string::npos;
    if (inline_value) value = name.substr(eq + 1), name = name.substr(0, eq);
    if (flags.count(name) && !inline_value) {
      flags_.insert(name);
    } else if (value_options.count(name)) {
      if (!inline_value) {
        if (i + 1 >= argc) throw UsageError("option --" + name + " needs a value");
        value = argv[++i];
      }
      values_[name] = value;
    } else {
      throw UsageError("unknown option --" + name + did_you_mean(name, value_options, flags));
    }
  }
}

std::string Arguments::text(const std::string& name, const std::string& fallback) const {
  auto it = values_.find(name);
  return it == values_.end() ? fallback : it->second;
}

double Arguments::number(const std::string& name, double fallback, double lo, double hi) const {
  auto it = values_.find(name);
  if (it == values_.end()) return fallback;
  const std::string& s = it->second;
  double v = 0;
  auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec != std::errc() || ptr != s.data() + s.size() || !(v >= lo && v <= hi))
    throw UsageError("--" + name + " must be a number in [" + shortest(lo) + ", " + shortest(hi) +
                     "], got '" + s + "'");
  return v;
}

long long Arguments::integer(const std::string& name, long long fallback, long long lo,
                             long long hi) const {
  auto it = values_.find(name);
  if (it == values_.end()) return fallback;
  const std::string& s = it->second;
  long long v = 0;
  auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec != std::errc() || ptr != s.data() + s.size() || v < lo || v > hi)
    throw UsageError("--" + name + " must be an integer in [" + std::to_string(lo) + ", " +
                     std::to_string(hi) + "], got '" + s + "'");
  return v;
}

}  // namespace spheremap::cli
