// The topology report of a polygon mesh (ALGORITHM §0.2) and the checks a mesh must
// pass before it can be mapped: closed, manifold (edges and vertex fans), consistently
// oriented, one component, genus 0.
#pragma once

#include <cstddef>
#include <map>
#include <string>
#include <vector>

#include "core/mesh/input_error.h"
#include "core/mesh/mesh.h"
#include "core/mesh/stop_check.h"

namespace spheremap {

struct TopologyReport {
  size_t vertices = 0, edges = 0, faces = 0;
  std::map<size_t, size_t> face_sizes;  // corners -> number of faces
  size_t non_finite_vertices = 0;
  size_t faces_with_repeated_vertices = 0;
  size_t zero_area_faces = 0;
  size_t boundary_edges = 0, boundary_loops = 0;
  size_t non_manifold_edges = 0;           // edges with more than 2 faces
  size_t non_manifold_vertices = 0;        // vertices whose faces form more than one fan
  size_t inconsistent_edges = 0;           // two faces traversing the edge the same way
  std::vector<size_t> component_vertices;  // per component, largest first
  std::vector<size_t> component_faces;     // in the same order
  long long euler_characteristic = 0;
  // In the units of the mesh scaled by a power of two to coordinates of about 1: its sign
  // is what counts (< 0: consistently oriented inward).
  double signed_volume = 0;
  // Faces inward by the map's own rule (runs_inward, mesh.h): a surface enclosing no
  // volume counts as facing out, whatever the sign of its rounding noise.
  bool inward = false;

  bool closed() const { return boundary_edges == 0; }
  bool manifold() const {
    return non_manifold_edges == 0 && non_manifold_vertices == 0 &&
           faces_with_repeated_vertices == 0;
  }
  // Genus of a closed, orientable, connected surface; -1 when that does not apply.
  long long genus() const;
};

// `stop` (optional) is asked between its passes (each well under a second at the
// service's caps): it may end the analysis with InputError("stopped").
TopologyReport analyze_topology(const PolygonMesh& mesh, const StopCheck* stop = nullptr);

struct ValidationFailure {
  ValidationFailure(std::string check_name, std::string text, Fix option = {})
      : check(std::move(check_name)), message(std::move(text)), fix(std::move(option)) {}
  std::string check;    // stable name: "non_finite", "boundary", "genus", ...
  std::string message;  // one sentence with the counts
  Fix fix;              // the option that gets past it, when one does
};

// Every failed check, most fundamental first; empty when the mesh can be mapped.
std::vector<ValidationFailure> mapping_failures(const TopologyReport& report);

// Throws InputError naming the first failed check, with all failures in its message and
// the first fix any of them has.
void require_mappable(const TopologyReport& report);
// The same for a list of failures already made (and perhaps given fixes).
void require_none(const std::vector<ValidationFailure>& failures);

}  // namespace spheremap
