// A small command-line parser: "--name value", "--name=value" and flags, with positional
// arguments collected in order. Unknown options are errors (no silent typos).
#pragma once

#include <map>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

namespace spheremap::cli {

struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

class Arguments {
 public:
  // value_options take a value, flags do not; "-o" is an alias of "--output".
  Arguments(int argc, char** argv, int first, const std::set<std::string>& value_options,
            const std::set<std::string>& flags);

  bool flag(const std::string& name) const { return flags_.count(name) > 0; }
  bool has(const std::string& name) const { return values_.count(name) > 0; }
  std::string text(const std::string& name, const std::string& fallback) const;
  double number(const std::string& name, double fallback, double lo, double hi) const;
  long long integer(const std::string& name, long long fallback, long long lo, long long hi) const;
  const std::vector<std::string>& positional() const { return positional_; }

 private:
  std::map<std::string, std::string> values_;
  std::set<std::string> flags_;
  std::vector<std::string> positional_;
};

}  // namespace spheremap::cli
