// A count with its noun in the right number, for messages: counted(1, "byte") is "1 byte",
// counted(3, "byte") "3 bytes", counted(2, "vertex", "vertices") "2 vertices".
#pragma once

#include <cstdint>
#include <string>

namespace spheremap {

inline std::string counted(uint64_t n, const std::string& singular, const std::string& plural) {
  std::string text = std::to_string(n);
  text += ' ';
  text += n == 1 ? singular : plural;
  return text;
}

inline std::string counted(uint64_t n, const std::string& singular) {
  return counted(n, singular, singular + "s");
}

}  // namespace spheremap
