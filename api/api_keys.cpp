#include "api/api_keys.h"

#include <fstream>
#include <sstream>

#include <stdexcept>

namespace spheremap::api {
namespace {

// Equal strings, in time that depends only on their lengths' maximum.
bool same(std::string_view a, std::string_view b) {
  unsigned difference = a.size() == b.size() ? 0 : 1;
  const size_t length = std::max(a.size(), b.size());
  for (size_t i = 0; i < length; ++i) {
    const unsigned char x = i < a.size() ? static_cast<unsigned char>(a[i]) : 0;
    const unsigned char y = i < b.size() ? static_cast<unsigned char>(b[i]) : 0;
    difference |= static_cast<unsigned>(x ^ y);
  }
  return difference == 0;
}

}  // namespace

ApiKeys ApiKeys::load(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::invalid_argument("cannot read the API key file '" + path + "'");
  ApiKeys keys;
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    const std::string where = path + ":" + std::to_string(number);
    if (const size_t hash = line.find('#'); hash != std::string::npos) line.resize(hash);
    std::istringstream fields(line);
    std::string tenant, key, extra;
    if (!(fields >> tenant)) continue;  // blank or comment
    if (!(fields >> key) || (fields >> extra))
      throw std::invalid_argument(where + ": expected 'TENANT KEY'");
    if (key.size() < 16)
      throw std::invalid_argument(where + ": keys must have at least 16 characters");
    for (const Entry& e : keys.entries_)
      if (e.key == key)
        throw std::invalid_argument(where + ": this key is already given to " + e.tenant);
    keys.entries_.push_back({tenant, key});
  }
  if (keys.entries_.empty()) throw std::invalid_argument(path + ": no 'TENANT KEY' line");
  return keys;
}

std::optional<std::string> ApiKeys::tenant_for(std::string_view authorization) const {
  constexpr std::string_view kScheme = "Bearer ";
  if (authorization.size() <= kScheme.size() || authorization.substr(0, kScheme.size()) != kScheme)
    return std::nullopt;
  const std::string_view key = authorization.substr(kScheme.size());
  const Entry* found = nullptr;
  for (const Entry& e : entries_)  // no early exit: every key is compared
    if (same(key, e.key)) found = &e;
  if (!found) return std::nullopt;
  return found->tenant;
}

}  // namespace spheremap::api
