// The mapping options every mapping subcommand shares, with their --help text.
#pragma once

#include <set>
#include <string>
#include <vector>

#include "cli/arguments.h"
#include "core/io/gltf_reader.h"
#include "core/map/pipeline.h"

namespace spheremap::cli {

extern const std::set<std::string> kMapValueOptions;
extern const std::set<std::string> kMapFlags;
extern const char* const kMapOptionsHelp;

// "exact" or "repair" (--prepare); UsageError otherwise.
PrepareMethod parse_prepare_method(const std::string& name);

void read_map_options(const Arguments& args, PrepareOptions& prepare, MapOptions& options);

// Progress lines on stderr once a run has taken a second, at most twice a second;
// `last_print` must outlive the returned control.
MapControl progress_printer(bool quiet, double& last_print);

// --mesh INDEX|NAME: which glTF mesh to read (default: the whole default scene).
GltfReadOptions gltf_options(const Arguments& args);

// The INPUT file (first positional argument) read with gltf_options and mapped. A mesh
// that cannot map is refused with the failed check and, for a glTF scene, the meshes it
// draws and the option that maps one (InputError).
struct MappedInput {
  PolygonMesh input;
  GltfAppearance look;  // a glTF input's materials, attributes and nodes (else empty)
  MappedMesh mapped;
  std::vector<std::string> input_warnings;  // read leniently (printed; in --metrics too)
};
MappedInput map_input(const Arguments& args, const PrepareOptions& prepare,
                      const MapOptions& options, const MapControl& control);

// Parts left out of a run that still exits 0 (the rest certified), said on stderr too and
// not only in the metrics: manifold's Generic_Twin_7081 left out 19,376 of its 19,728
// faces (its body, not float32-safe) with nothing said. One line, the largest 3 named.
void print_parts_left_out(const PreparedMesh& prepared);

// A fix as the command line spells it: "--largest-component maps only ...".
std::string fix_hint(const Fix& fix);

}  // namespace spheremap::cli
