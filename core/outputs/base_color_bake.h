// The input's base colour resampled onto the octahedral square: what a remesh (whose
// TEXCOORD_0 is the square) needs to look like the textured original.
#pragma once

#include <functional>
#include <map>
#include <optional>
#include <span>
#include <string>

#include "core/io/gltf_appearance.h"
#include "core/io/image_reader.h"
#include "core/io/jpeg_scans.h"
#include "core/map/pipeline.h"
#include "core/outputs/octahedral.h"
#include "core/outputs/original_surface.h"
#include "core/outputs/sphere_locator.h"

namespace spheremap {

// The base-colour images of one look decoded once for several bakes (the parts of an
// asset), keyed by their image_data entry; `pixels` counts what was decoded against
// kMaxBaseColorPixels. Pass the same one to every bake of that look.
struct DecodedImages {
  std::map<size_t, RgbaImage> images;
  size_t pixels = 0;
};

struct BakedBaseColor {
  std::string png;  // size x size, 8-bit RGB
  int size = 0;
  size_t unlocated_texels = 0;  // texels whose sphere point no triangle held (grey)
  size_t images_decoded = 0;    // base-colour images read (PNG, JPEG)
  // No image and no vertex colour to sample: the texture holds materials' factors only.
  bool factors_only = false;
};

// Each texel's point of the square goes to the sphere, is located in the map, and takes
// the colour of the surface there: baseColorFactor x baseColorTexture (at the face's
// interpolated TEXCOORD_n, with its sampler's wrap) x COLOR_0. Nothing when the input has
// no material and no vertex colour. Preconditions: mapped.map.check.bijective; `look`
// and `input` from one read_gltf() call, `mapped` prepared from `input`; `oriented` the
// welded mesh's oriented_triangles() (the remesh has them already).
// `should_stop` (may be null) is asked before each image decode and before each row of
// texels (from every thread); once it says true, the bake throws InputError("stopped")
// instead of going on: a bake of a large texture keeps to a job's time limit.
// `input_faces` (may be null): the input face of each welded face, as welded_input_faces
// gives (a part's own list, so an asset of many parts is not scanned whole per part).
// `frame`: the remesh's (OctahedralRemesh::frame), so texel and sample share a sphere point.
// The most pixels bake_base_color decodes in all (4 bytes each); over it, it throws
// InputError("too_large").
inline constexpr size_t kMaxBaseColorPixels = size_t{1} << 26;

// The pixels of each distinct image a drawn material takes its base colour from, read
// from the images' headers (nothing decoded): what bake_base_color would decode.
size_t base_color_pixels(const GltfAppearance& look);
// The most scans of a JPEG among those images (counted from their markers, up to
// kMaxJpegScans + 1): over kMaxJpegScans, bake_base_color would refuse it.
size_t base_color_jpeg_scans(const GltfAppearance& look);

std::optional<BakedBaseColor> bake_base_color(
    const PolygonMesh& input, const GltfAppearance& look, const MappedMesh& mapped,
    std::span<const Triangle> oriented, int size, int threads,
    const std::function<bool()>* should_stop = nullptr, DecodedImages* images = nullptr,
    const std::vector<uint32_t>* input_faces = nullptr, const OctahedralFrame& frame = {},
    const SphereLocator* locator = nullptr);

// The same for the map of an envelope (prepare wrap, or auto wrapping the whole or a part)
// that stands for `original`: each texel's sphere point is located on the envelope, and
// the envelope's point there takes the colour of the closest point of the original's
// triangles (its face's material, TEXCOORD_n and COLOR_0 as above). Nothing when the
// original's look has no material and no vertex colour. `oriented`: the envelope's
// oriented_triangles(). `locator` (both bakes; may be null: one is built): a SphereLocator
// of the map's sphere and `oriented`, e.g. the one the remesh was sampled with.
std::optional<BakedBaseColor> bake_base_color_closest(
    const OriginalSurface& original, const MappedMesh& mapped, std::span<const Triangle> oriented,
    int size, int threads, const std::function<bool()>* should_stop,
    DecodedImages* images = nullptr, const OctahedralFrame& frame = {},
    const SphereLocator* locator = nullptr);

// The same colour per point (COLOR_0 of a wrapped sphere or UV mesh): the original's base
// colour, linear RGB clamped to [0, 1], at the closest point of its triangles to each of
// `points` (an envelope's vertices). Nothing when the original's look has no material and
// no vertex colour. `should_stop` (may be null) is asked every 4096 points and before
// each image decode; true throws InputError("stopped").
std::optional<std::vector<std::array<float, 3>>> colors_closest(
    const OriginalSurface& original, std::span<const Vec3> points, int threads,
    const std::function<bool()>* should_stop, DecodedImages* images = nullptr);

}  // namespace spheremap
