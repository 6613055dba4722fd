// The options of a job, as a JSON object (the `options` part of a multipart request, or
// query parameters): mapping parameters within the server's caps, which outputs to make,
// Draco on or off. Unknown keys and out-of-range values are 400 problems naming the key.
#pragma once

#include <nlohmann/json.hpp>

#include "api/job.h"
#include "core/io/gltf_reader.h"

namespace spheremap::api {

// The service's default preparation is auto (every part served: exactly where it can be,
// as an envelope where it cannot); the library's PrepareOptions default stays parts.
inline PrepareOptions service_prepare_defaults() {
  PrepareOptions prepare;
  prepare.method = PrepareMethod::kAuto;
  return prepare;
}

struct JobOptions {
  PrepareOptions prepare = service_prepare_defaults();
  GltfReadOptions gltf;
  MapOptions map;
  SphereLayout layout = SphereLayout::kOriginal;
  int draco_position_bits = 0;
  std::vector<std::string> outputs = {"sphere"};
  int remesh_resolution = 256;
  bool normal_map = true;  // the remesh of an envelope bakes the original's shading
};

// Throws Problem(400, "invalid_options").
JobOptions parse_job_options(const nlohmann::json& options);

// Query parameters as option values: "true"/"false" and numbers as such, text otherwise.
nlohmann::json options_from_query(const std::multimap<std::string, std::string>& params);

// The outputs a job can ask for.
const std::vector<std::string>& available_outputs();

}  // namespace spheremap::api
