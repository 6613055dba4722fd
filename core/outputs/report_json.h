// JSON forms of the reports, as the command-line tool and the service print them.
#pragma once

#include <nlohmann/json.hpp>

#include "core/io/gltf_reader.h"
#include "core/map/pipeline.h"

namespace spheremap {

// The checks a prepared mesh fails, each with the option that would get past it (a glTF
// scene that draws one mesh several times is told to map that mesh alone).
std::vector<ValidationFailure> input_failures(const PreparedMesh& prepared,
                                              const GltfReadStats* gltf = nullptr);
// What preparation did (and holes_filled, faces_added, holes_left, largest_fill,
// handles_closed, handles_left, largest_handle_cycle, farthest_handle_fill; under prepare=wrap also
// the envelope's report: voxel_size, offset, handles_cut, handles_filled, voxels_changed,
// envelope_hausdorff, envelope_rms, ... as docs/http-api.md lists):
// {"method", "input_faces", "collapsed_faces_dropped",
// "faces_shortened", "duplicate_faces_dropped", "faces_flipped", "parts_reoriented"}.
nlohmann::json preparation_json(const PreparationReport& preparation);
// {"option", "value", "effect"} of a fix, the value as JSON.
nlohmann::json fix_json(const Fix& fix);

// The topology report with "mappable" and "failures" (each with its "fix" when one exists),
// and "warnings" when the glTF was read leniently (GltfReadStats::warnings).
nlohmann::json topology_json(const PreparedMesh& prepared, const GltfReadStats* gltf = nullptr);
// The map's metrics, and for an asset of several parts "parts" (parts_json), "parts_mapped"
// and "parts_left_out".
nlohmann::json metrics_json(const MappedMesh& mapped, const MapOptions& options);
// metrics_json without the parts.
nlohmann::json map_metrics_json(const MappedMesh& mapped, const MapOptions& options);
// Per part of the asset (prepared.parts, largest first): {"part", "vertices", "faces",
// "mapped"}, with "check" and "reason" for a part left out, and its map's verdict, stretch,
// area distortion and sphere placement when `mapped` has it.
nlohmann::json parts_json(const PreparedMesh& prepared, const MappedMesh* mapped);

// The metrics without their "seconds" (at any depth), for the extras of a GLB: the same
// input and options then give byte-identical files; metrics.json keeps the timings.
nlohmann::json without_timings(nlohmann::json metrics);

}  // namespace spheremap
