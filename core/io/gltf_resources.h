// The files a .gltf names by relative URI (its .bin buffers), looked up safely. A URI is
// only ever a relative path inside the .gltf's own folder: percent-decoded, then refused
// when it is absolute, has a scheme other than data:, a backslash, a NUL, or a ".."
// segment. Where the bytes come from is the caller's choice: a folder on disk (the CLI)
// or the parts of an upload (the service), never anything else.
#pragma once

#include <cstddef>
#include <map>
#include <optional>
#include <string>

namespace spheremap {

// The relative path a glTF URI names, percent-decoded and checked; throws
// InputError("gltf") saying why it is refused.
std::string checked_resource_path(const std::string& uri);

class GltfResources {
 public:
  virtual ~GltfResources() = default;
  // The bytes of the file at `path` (a checked_resource_path), or nothing when it is not
  // there. Throws InputError("too_large") when it holds more than `max_bytes`.
  virtual std::optional<std::string> fetch(const std::string& path, size_t max_bytes) const = 0;
  // How to supply what is missing, for the error that lists it.
  virtual std::string how_to_supply() const = 0;
};

// Files inside `folder` (the .gltf's own), symlinks followed only while they stay inside.
class FolderResources : public GltfResources {
 public:
  explicit FolderResources(std::string folder);
  std::optional<std::string> fetch(const std::string& path, size_t max_bytes) const override;
  std::string how_to_supply() const override;

 private:
  std::string folder_;
};

// Files given by name (the parts of a multipart upload).
class MemoryResources : public GltfResources {
 public:
  MemoryResources(std::map<std::string, std::string_view> files, std::string how_to_supply)
      : files_(std::move(files)), how_(std::move(how_to_supply)) {}
  std::optional<std::string> fetch(const std::string& path, size_t max_bytes) const override;
  std::string how_to_supply() const override { return how_; }

 private:
  std::map<std::string, std::string_view> files_;
  std::string how_;
};

}  // namespace spheremap
