#include "api/client_address.h"

#include <algorithm>
#include <string_view>

namespace spheremap::api {
namespace {

bool is_trusted(const ApiSettings& settings, std::string_view address) {
  return std::find(settings.trusted_proxies.begin(), settings.trusted_proxies.end(), address) !=
         settings.trusted_proxies.end();
}

bool looks_like_address(std::string_view text) {
  return !text.empty() && text.size() <= 45 &&
         text.find_first_not_of("0123456789abcdefABCDEF.:") == std::string_view::npos;
}

std::string_view trimmed(std::string_view text) {
  const size_t begin = text.find_first_not_of(' ');
  if (begin == std::string_view::npos) return {};
  return text.substr(begin, text.find_last_not_of(' ') - begin + 1);
}

}  // namespace

std::string client_address(const ApiSettings& settings, const httplib::Request& request) {
  if (!is_trusted(settings, request.remote_addr) || !request.has_header("X-Forwarded-For"))
    return request.remote_addr;
  const std::string forwarded = request.get_header_value("X-Forwarded-For");
  std::string_view rest = forwarded;
  std::string_view client;
  // From the right: skip our own proxies; the first other entry is the client.
  while (!rest.empty()) {
    const size_t comma = rest.rfind(',');
    const std::string_view entry =
        trimmed(comma == std::string_view::npos ? rest : rest.substr(comma + 1));
    rest = comma == std::string_view::npos ? std::string_view() : rest.substr(0, comma);
    if (!looks_like_address(entry)) break;  // forged or mangled: believe no further
    client = entry;
    if (!is_trusted(settings, entry)) break;
  }
  return client.empty() ? request.remote_addr : std::string(client);
}

}  // namespace spheremap::api
