// JSON forms of the reports, as the command-line tool and the service print them.
#pragma once

#include <nlohmann/json.hpp>

#include "core/map/pipeline.h"

namespace spheremap {

nlohmann::json topology_json(const PreparedMesh& prepared);
nlohmann::json metrics_json(const MappedMesh& mapped, const MapOptions& options);

}  // namespace spheremap
