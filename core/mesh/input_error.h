// The one error type a user's input can cause. `check` names the failed check
// (stable, machine-readable: "boundary", "genus", "parse", ...); what() is one line
// for a person, with the counts. `fix` names the option that would get past the check,
// when one would, so that each front end can say it in its own words (a CLI flag, a
// job option).
#pragma once

#include <stdexcept>
#include <string>

namespace spheremap {

// An option that gets past a failed check: `option` is the job option's key
// ("largest_component"; the CLI flag is the same with dashes), `value` its value as
// JSON text ("true", "0"), `effect` what it then does, as a phrase.
struct Fix {
  std::string option, value, effect;
  bool empty() const { return option.empty(); }
  // The value as a command line or a query string spells it: a JSON string unquoted.
  std::string plain_value() const {
    return value.size() >= 2 && value.front() == '"' && value.back() == '"'
               ? value.substr(1, value.size() - 2)
               : value;
  }
};

class InputError : public std::runtime_error {
 public:
  InputError(std::string check, const std::string& message, Fix fix = {})
      : std::runtime_error(message), check_(std::move(check)), fix_(std::move(fix)) {}
  const std::string& check() const { return check_; }
  const Fix& fix() const { return fix_; }

 private:
  std::string check_;
  Fix fix_;
};

}  // namespace spheremap
