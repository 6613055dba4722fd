// The parts of an input glTF that outputs copy, reduced to what glTF allows: a writer
// that copied a node's or a material's JSON verbatim wrote the input's mistakes (a
// `name` that is not a string, a rotation that is not a unit quaternion, a metallic
// factor of 7) into every output, and made each one an invalid glTF. Internal to the
// glTF reader.
#pragma once

#include <array>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace spheremap::gltf {

// A node's `rotation` (4 numbers, x y z w) as the reader applies and the writers write
// it: as given when unit to float precision, else normalized (as viewers do); nullopt
// (no rotation) for a zero or non-finite one.
std::optional<std::array<double, 4>> usable_rotation(std::span<const double> q);

// A node the reader has walked (its transform members already checked to be numbers of
// the right count): name (a string), children, camera (an index below `cameras`), and
// either `matrix` or translation, the usable rotation and scale (glTF forbids both).
nlohmann::json checked_node(const nlohmann::json& node, size_t cameras);

// A material with the members glTF defines, each only with a value of its type and
// range (factors within [0, 1], alphaMode one of three names, ...), its texture
// references' index and texCoord, and the extensions in `declared` (the input's
// extensionsUsed that material_extension() names: the output declares those).
nlohmann::json checked_material(const nlohmann::json& material,
                                const std::vector<std::string>& declared);

// A texture's sampler, source, string name and `declared` extensions (already checked to
// resolve).
nlohmann::json checked_texture(const nlohmann::json& texture,
                               const std::vector<std::string>& declared);

}  // namespace spheremap::gltf
