// The one error type a user's input can cause. `check` names the failed check
// (stable, machine-readable: "boundary", "genus", "parse", ...); what() is one line
// for a person, with the counts.
#pragma once

#include <stdexcept>
#include <string>

namespace spheremap {

class InputError : public std::runtime_error {
 public:
  InputError(std::string check, const std::string& message)
      : std::runtime_error(message), check_(std::move(check)) {}
  const std::string& check() const { return check_; }

 private:
  std::string check_;
};

}  // namespace spheremap
