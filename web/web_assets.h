// The web page the service serves at GET / and the modules it loads (three.js), built
// into the binary by web/CMakeLists.txt.
#pragma once

#include <string_view>
#include <vector>

namespace spheremap::web {

struct Asset {
  std::string_view path;  // URL path: "/index.html", "/web/app.js", ...
  std::string_view content_type;
  std::string_view bytes;
};

const std::vector<Asset>& assets();
// The asset at a URL path ("/" is "/index.html"), or nullptr.
const Asset* find_asset(std::string_view path);
// The base64 SHA-256 of index.html's inline import map, for its Content-Security-Policy.
std::string_view import_map_sha256();

}  // namespace spheremap::web
