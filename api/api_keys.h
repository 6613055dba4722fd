// API keys: who a request is. A file of `TENANT KEY` lines (blank lines and `#` comments
// allowed) maps keys to tenants; a request names its key as `Authorization: Bearer KEY`.
// Keys are compared in constant time against every configured key, so the time an
// answer takes says nothing about how close a guess was.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace spheremap::api {

class ApiKeys {
 public:
  ApiKeys() = default;  // none: every request is anonymous, tenants are client addresses
  // Throws std::invalid_argument naming the file and line for a malformed file, a key shorter than
  // 16 characters, or a key given twice.
  static ApiKeys load(const std::string& path);

  bool enabled() const { return !entries_.empty(); }
  size_t size() const { return entries_.size(); }
  // The tenant whose key the Authorization header value carries ("Bearer KEY"), if any.
  std::optional<std::string> tenant_for(std::string_view authorization) const;

 private:
  struct Entry {
    std::string tenant, key;
  };
  std::vector<Entry> entries_;
};

}  // namespace spheremap::api
