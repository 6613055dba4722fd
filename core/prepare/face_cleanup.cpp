#include "core/prepare/face_cleanup.h"

#include <algorithm>
#include <numeric>

#include "core/mesh/weld.h"
#include "core/prepare/t_junctions.h"

namespace spheremap {
namespace {

// The faces still in play, in two numberings: the input's vertex ids (what is written
// back) and the welded ids (what decides), with the input face each came from.
struct WorkingFaces {
  PolygonMesh input_ids, welded_ids;
  std::vector<uint32_t> source;
};

// Step 1: corners welded onto the corner before them are merged (a run keeps its first);
// a face left with fewer than 3 corners is dropped. A pinched polygon (a vertex twice, not
// in a row) is kept as it is: the topology check names it.
WorkingFaces drop_collapsed(const PolygonMesh& input, const std::vector<uint32_t>& to_welded,
                            FaceCleanup& report, StopCheck& stop) {
  WorkingFaces out;
  out.input_ids.positions = input.positions;
  std::vector<uint32_t> corners, welded, sorted;
  for (uint32_t f = 0; f < input.face_count(); ++f) {
    stop.tick();
    const auto face = input.face(f);
    const size_t d = face.size();
    corners.clear(), welded.clear();
    for (size_t k = 0; k < d; ++k) {
      const uint32_t w = to_welded[face[k]], before = to_welded[face[(k + d - 1) % d]];
      if (w != before) corners.push_back(face[k]), welded.push_back(w);
    }
    if (corners.size() < 3) {
      ++report.collapsed_faces;
      continue;
    }
    sorted = welded;
    std::sort(sorted.begin(), sorted.end());
    const bool pinched = std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end();
    if (pinched || corners.size() == d) {
      corners.assign(face.begin(), face.end());
      welded.clear();
      for (uint32_t v : face) welded.push_back(to_welded[v]);
    } else {
      ++report.shortened_faces;
    }
    out.input_ids.add_face(corners);
    out.welded_ids.add_face(welded);
    out.source.push_back(f);
  }
  return out;
}

// Step 2: faces with the same welded corners as an earlier face (in either orientation:
// double-sided exports store every face twice) are marked; the first one stays.
std::vector<char> duplicate_faces(const PolygonMesh& welded, StopCheck& stop) {
  const size_t n = welded.face_count();
  std::vector<uint32_t> sorted_corners(welded.indices);
  for (size_t f = 0; f < n; ++f, stop.tick())
    std::sort(sorted_corners.begin() + welded.offsets[f],
              sorted_corners.begin() + welded.offsets[f + 1]);
  auto corners_of = [&](size_t f) {
    return std::span<const uint32_t>(sorted_corners.data() + welded.offsets[f],
                                     welded.face_size(f));
  };
  std::vector<uint64_t> hash(n);
  for (size_t f = 0; f < n; ++f) {
    uint64_t h = 1469598103934665603ull;
    for (uint32_t v : corners_of(f)) h = (h ^ v) * 1099511628211ull;
    hash[f] = h;
  }
  std::vector<uint32_t> order(n);
  std::iota(order.begin(), order.end(), 0u);
  stop.check();  // the sort is not ticked: asked before and after it
  std::sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) {
    if (hash[a] != hash[b]) return hash[a] < hash[b];
    const auto ca = corners_of(a), cb = corners_of(b);
    if (!std::equal(ca.begin(), ca.end(), cb.begin(), cb.end()))
      return std::lexicographical_compare(ca.begin(), ca.end(), cb.begin(), cb.end());
    return a < b;
  });
  std::vector<char> duplicate(n, 0);
  for (size_t k = 1; k < n; ++k) {
    const auto previous = corners_of(order[k - 1]), current = corners_of(order[k]);
    duplicate[order[k]] =
        hash[order[k]] == hash[order[k - 1]] &&
        std::equal(previous.begin(), previous.end(), current.begin(), current.end());
  }
  return duplicate;
}

WorkingFaces without(const WorkingFaces& faces, const std::vector<char>& drop) {
  WorkingFaces out;
  out.input_ids.positions = faces.input_ids.positions;
  for (size_t f = 0; f < faces.source.size(); ++f) {
    if (drop[f]) continue;
    out.input_ids.add_face(faces.input_ids.face(f));
    out.welded_ids.add_face(faces.welded_ids.face(f));
    out.source.push_back(faces.source[f]);
  }
  return out;
}

// Step 3: T-junction cracks zipped (t_junctions.h): each face with a boundary edge that
// vertices of the other side lie on is replaced, in its place, by the fan of its corners
// with those vertices inserted (an inserted corner takes an input vertex that welds there).
WorkingFaces zip_t_junctions(const WorkingFaces& faces, const std::vector<Vec3>& positions,
                             const std::vector<uint32_t>& to_welded, FaceCleanup& report,
                             StopCheck* stop) {
  const std::vector<EdgeSplit> splits = find_t_junctions(faces.welded_ids, positions, stop);
  if (splits.empty()) return faces;
  std::vector<uint32_t> input_of_welded(positions.size(), kUnreferenced);
  for (uint32_t v = static_cast<uint32_t>(to_welded.size()); v-- > 0;)
    if (to_welded[v] != kUnreferenced) input_of_welded[to_welded[v]] = v;
  WorkingFaces out;
  out.input_ids.positions = faces.input_ids.positions;
  std::vector<Triangle> welded, input;
  size_t next = 0;
  for (uint32_t f = 0; f < faces.source.size(); ++f) {
    size_t run = next;
    while (run < splits.size() && splits[run].face == f) ++run;
    welded.clear(), input.clear();
    const std::span<const EdgeSplit> of_face(splits.data() + next, run - next);
    if (run > next && split_face(faces.welded_ids.face(f), faces.input_ids.face(f), of_face,
                                 input_of_welded, welded, input)) {
      for (const EdgeSplit& s : of_face) report.t_junctions_zipped += s.inserted.size();
      ++report.faces_split;
      for (size_t t = 0; t < welded.size(); ++t) {
        out.welded_ids.add_face(welded[t]);
        out.input_ids.add_face(input[t]);
        out.source.push_back(faces.source[f]);
      }
    } else {
      out.welded_ids.add_face(faces.welded_ids.face(f));
      out.input_ids.add_face(faces.input_ids.face(f));
      out.source.push_back(faces.source[f]);
    }
    next = run;
  }
  return out;
}

// Step 4: per part (faces joined across edges that exactly two faces share), the faces to
// reverse so that every such edge is walked once each way. Parts already consistent, and
// parts that cannot be oriented, get none.
std::vector<char> faces_to_flip(const PolygonMesh& welded, const std::vector<Vec3>& positions,
                                FaceCleanup& report, StopCheck& stop) {
  const size_t n = welded.face_count();
  struct Side {
    uint64_t edge;
    uint32_t face;
    bool forward;  // walks the edge from its smaller vertex id to its larger
  };
  std::vector<Side> sides;
  sides.reserve(welded.indices.size());
  for (uint32_t f = 0; f < n; ++f) {
    const auto face = welded.face(f);
    for (size_t k = 0; k < face.size(); ++k) {
      const uint32_t a = face[k], b = face[(k + 1) % face.size()];
      sides.push_back({(uint64_t{std::min(a, b)} << 32) | std::max(a, b), f, a < b});
    }
  }
  stop.check();
  std::sort(sides.begin(), sides.end(), [](const Side& x, const Side& y) {
    return x.edge != y.edge ? x.edge < y.edge : x.face < y.face;
  });
  // Neighbours across two-face edges, as CSR; `disagree`: the two walk it the same way.
  struct Link {
    uint32_t face;
    bool disagree;
  };
  std::vector<uint32_t> link_offsets(n + 1, 0);
  std::vector<char> open_face(n, 0);
  for (size_t k = 0; k < sides.size();) {
    size_t run = k;
    while (run < sides.size() && sides[run].edge == sides[k].edge) ++run;
    if (run - k == 2) {
      ++link_offsets[sides[k].face + 1], ++link_offsets[sides[k + 1].face + 1];
    } else {
      for (size_t s = k; s < run; ++s) open_face[sides[s].face] = 1;
    }
    k = run;
  }
  for (size_t f = 0; f < n; ++f) link_offsets[f + 1] += link_offsets[f];
  std::vector<Link> links(link_offsets.back());
  std::vector<uint32_t> cursor(link_offsets.begin(), link_offsets.end() - 1);
  for (size_t k = 0; k < sides.size();) {
    size_t run = k;
    while (run < sides.size() && sides[run].edge == sides[k].edge) ++run;
    if (run - k == 2) {
      const Side &x = sides[k], &y = sides[k + 1];
      const bool disagree = x.forward == y.forward;
      links[cursor[x.face]++] = {y.face, disagree};
      links[cursor[y.face]++] = {x.face, disagree};
    }
    k = run;
  }

  std::vector<char> flip(n, 0);
  std::vector<int8_t> parity(n, -1);
  std::vector<uint32_t> part, queue;
  stop.check();
  for (uint32_t root = 0; root < n; ++root, stop.tick()) {
    if (parity[root] >= 0) continue;
    part.clear(), queue.assign(1, root);
    parity[root] = 0;
    bool orientable = true, consistent = true, closed = true;
    while (!queue.empty()) {
      const uint32_t f = queue.back();
      queue.pop_back();
      part.push_back(f);
      closed = closed && !open_face[f];
      for (uint32_t l = link_offsets[f]; l < link_offsets[f + 1]; ++l) {
        const Link link = links[l];
        consistent = consistent && !link.disagree;
        const int8_t want = static_cast<int8_t>(parity[f] ^ (link.disagree ? 1 : 0));
        if (parity[link.face] < 0) {
          parity[link.face] = want;
          queue.push_back(link.face);
        } else if (parity[link.face] != want) {
          orientable = false;
        }
      }
    }
    if (consistent || !orientable) continue;
    size_t odd = 0;
    for (uint32_t f : part) odd += parity[f];
    // Which of the two consistent orientations: outward for a closed part (the signed
    // volume of its fans, from one of its vertices so far-away parts lose no digits),
    // else the one that reverses fewer faces.
    bool flip_odd = 2 * odd <= part.size();
    if (closed) {
      const Vec3 origin = positions[welded.face(part.front())[0]];
      double six_volume = 0;
      for (uint32_t f : part) {
        const auto face = welded.face(f);
        const double sign = parity[f] ? -1.0 : 1.0;  // as if the odd faces were reversed
        for (size_t k = 1; k + 1 < face.size(); ++k)
          six_volume +=
              sign * dot(positions[face[0]] - origin,
                         cross(positions[face[k]] - origin, positions[face[k + 1]] - origin));
      }
      flip_odd = six_volume >= 0;
    }
    for (uint32_t f : part)
      if ((parity[f] == 1) == flip_odd) flip[f] = 1, ++report.flipped_faces;
    ++report.reoriented_parts;
  }
  return flip;
}

}  // namespace

FaceCleanup clean_faces(const PolygonMesh& input, double weld_tolerance, StopCheck* stop) {
  FaceCleanup report;
  StopCheck never(nullptr);
  StopCheck& check = stop ? *stop : never;
  const WeldResult welded = weld(input, weld_tolerance, &check);
  check.check();
  WorkingFaces faces = drop_collapsed(input, welded.input_to_welded, report, check);
  check.check();
  const std::vector<char> duplicate = duplicate_faces(faces.welded_ids, check);
  check.check();
  report.duplicate_faces = static_cast<size_t>(std::count(duplicate.begin(), duplicate.end(), 1));
  if (report.duplicate_faces) faces = without(faces, duplicate);
  faces = zip_t_junctions(faces, welded.mesh.positions, welded.input_to_welded, report, &check);
  const std::vector<char> flip =
      faces_to_flip(faces.welded_ids, welded.mesh.positions, report, check);
  report.mesh.positions = input.positions;
  std::vector<uint32_t> corners;
  for (size_t f = 0; f < faces.source.size(); ++f) {
    check.tick();
    const auto face = faces.input_ids.face(f);
    corners.assign(face.begin(), face.end());
    if (flip[f]) std::reverse(corners.begin() + 1, corners.end());  // keeps its first corner
    report.mesh.add_face(corners);
  }
  report.source_face = std::move(faces.source);
  return report;
}

}  // namespace spheremap
