#include "core/io/gltf_resources.h"

#include <algorithm>
#include <filesystem>
#include <fstream>

#include "core/mesh/input_error.h"

namespace spheremap {
namespace {

namespace fs = std::filesystem;

// At most 80 characters of a client's URI in a message.
std::string shown(const std::string& uri) {
  std::string out = "'";
  out.append(uri, 0, std::min<size_t>(uri.size(), 77));
  if (uri.size() > 77) out += "...";
  return out += "'";
}

[[noreturn]] void refuse(const std::string& uri, const std::string& why) {
  throw InputError("gltf", "the URI " + shown(uri) + " is refused: " + why +
                               "; only files in the .gltf's own folder can be named");
}

int hex_value(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}

}  // namespace

std::string checked_resource_path(const std::string& uri) {
  // A scheme is letters, digits, '+', '-', '.' before the first ':' (RFC 3986); data:
  // URIs never get here.
  const size_t colon = uri.find(':');
  if (colon != std::string::npos &&
      uri.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789+-.") >=
          colon)
    refuse(uri, "it has a scheme");
  std::string path;
  for (size_t i = 0; i < uri.size(); ++i) {
    if (uri[i] != '%') {
      path += uri[i];
      continue;
    }
    const int high = i + 2 < uri.size() ? hex_value(uri[i + 1]) : -1;
    const int low = high >= 0 ? hex_value(uri[i + 2]) : -1;
    if (low < 0) refuse(uri, "a '%' is not followed by two hex digits");
    path += static_cast<char>(high * 16 + low);
    i += 2;
  }
  if (path.empty()) refuse(uri, "it is empty");
  if (path.find('\0') != std::string::npos) refuse(uri, "it holds a NUL byte");
  if (path.find('\\') != std::string::npos) refuse(uri, "it holds a backslash");
  if (path.front() == '/') refuse(uri, "it is an absolute path");
  for (size_t start = 0; start <= path.size();) {
    size_t end = path.find('/', start);
    if (end == std::string::npos) end = path.size();
    if (path.compare(start, end - start, "..") == 0) refuse(uri, "it has a '..' segment");
    start = end + 1;
  }
  return path;
}

FolderResources::FolderResources(std::string folder)
    : folder_(folder.empty() ? std::string(".") : std::move(folder)) {}

std::optional<std::string> FolderResources::fetch(const std::string& path, size_t max_bytes) const {
  std::error_code error;
  const fs::path root = fs::canonical(folder_, error);
  if (error) return std::nullopt;
  const fs::path file = fs::canonical(root / path, error);
  if (error) return std::nullopt;
  // canonical() resolved every symlink: what it names must still be inside the folder.
  const auto [root_end, unused] = std::mismatch(root.begin(), root.end(), file.begin(), file.end());
  if (root_end != root.end())
    throw InputError("gltf", "the URI " + shown(path) +
                                 " leads out of the .gltf's folder through a symbolic link");
  if (!fs::is_regular_file(file, error)) return std::nullopt;
  const uintmax_t size = fs::file_size(file, error);
  if (error) return std::nullopt;
  if (size > max_bytes)
    throw InputError("too_large", "the file " + shown(path) + " holds " + std::to_string(size) +
                                      " bytes, over the limit of " + std::to_string(max_bytes));
  std::ifstream in(file, std::ios::binary);
  std::string bytes(static_cast<size_t>(size), '\0');
  if (!in.read(bytes.data(), static_cast<std::streamsize>(size)))
    throw InputError("io", "cannot read " + shown(path));
  return bytes;
}

std::string FolderResources::how_to_supply() const {
  return "they must be in " + shown(folder_) +
         ", the .gltf's folder, under the names its URIs give";
}

std::optional<std::string> MemoryResources::fetch(const std::string& path, size_t max_bytes) const {
  const auto it = files_.find(path);
  if (it == files_.end()) return std::nullopt;
  if (it->second.size() > max_bytes)
    throw InputError("too_large", "the file " + shown(path) + " holds " +
                                      std::to_string(it->second.size()) +
                                      " bytes, over the limit of " + std::to_string(max_bytes));
  return std::string(it->second);
}

}  // namespace spheremap
