#include "core/outputs/base_color_bake.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>
#include <set>

#include "core/io/image_reader.h"
#include "core/io/jpeg_scans.h"
#include "core/io/png_writer.h"
#include "core/mesh/barycentric.h"
#include "core/mesh/input_error.h"
#include "core/mesh/parallel.h"
#include "core/mesh/parallel_stop.h"
#include "core/mesh/stop_check.h"
#include "core/mesh/triangle_tree.h"
#include "core/outputs/octahedral.h"
#include "core/outputs/sphere_asset.h"
#include "core/outputs/sphere_locator.h"

namespace spheremap {
namespace {

constexpr size_t kMaxImagePixels = size_t{1} << 24;  // 4096 x 4096
constexpr int kRepeat = 10497, kClamp = 33071, kMirror = 33648;

using Rgba = std::array<double, 4>;  // linear colour

double srgb_to_linear(double c) {
  return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
}
// An 8-bit sRGB channel's linear value: the same numbers as srgb_to_linear(byte / 255),
// looked up (a bilinear sample takes twelve; std::pow was a quarter of a remesh of 3,000
// baked parts).
double srgb_byte_to_linear(uint8_t byte) {
  static const std::array<double, 256> table = [] {
    std::array<double, 256> t{};
    for (int b = 0; b < 256; ++b) t[static_cast<size_t>(b)] = srgb_to_linear(b / 255.0);
    return t;
  }();
  return table[byte];
}
double linear_to_srgb(double c) {
  c = std::clamp(c, 0.0, 1.0);
  return c <= 0.0031308 ? c * 12.92 : 1.055 * std::pow(c, 1 / 2.4) - 0.055;
}

// A material's base colour: factor x texture (as its sampler wraps it).
struct BaseColor {
  Rgba factor{1, 1, 1, 1};
  const RgbaImage* image = nullptr;
  std::string texcoord = "TEXCOORD_0";
  int wrap_s = kRepeat, wrap_t = kRepeat;
};

int wrapped(long long x, int n, int mode) {
  if (mode == kClamp) return static_cast<int>(std::clamp<long long>(x, 0, n - 1));
  if (mode == kMirror) {
    const long long m = ((x % (2LL * n)) + 2LL * n) % (2LL * n);
    return static_cast<int>(m < n ? m : 2LL * n - 1 - m);
  }
  return static_cast<int>(((x % n) + n) % n);
}

// Bilinear sample, linear colour (glTF base colour textures are sRGB-encoded).
Rgba sample(const BaseColor& c, double u, double v) {
  const RgbaImage& im = *c.image;
  if (!std::isfinite(u) || !std::isfinite(v)) u = v = 0;
  const double x = std::clamp(u, -1e6, 1e6) * im.width - 0.5;
  const double y = std::clamp(v, -1e6, 1e6) * im.height - 0.5;
  const long long x0 = static_cast<long long>(std::floor(x)),
                  y0 = static_cast<long long>(std::floor(y));
  const double fx = x - static_cast<double>(x0), fy = y - static_cast<double>(y0);
  Rgba out{};
  for (int dy = 0; dy < 2; ++dy)
    for (int dx = 0; dx < 2; ++dx) {
      const int px = wrapped(x0 + dx, im.width, c.wrap_s);
      const int py = wrapped(y0 + dy, im.height, c.wrap_t);
      const double w = (dx ? fx : 1 - fx) * (dy ? fy : 1 - fy);
      const uint8_t* p = &im.rgba[(static_cast<size_t>(py) * im.width + px) * 4];
      for (int k = 0; k < 3; ++k) out[k] += w * srgb_byte_to_linear(p[k]);
      out[3] += w * p[3] / 255.0;
    }
  return out;
}

// An unsigned member of a JSON object, or `fallback` when absent or of another type (the
// look is the input's JSON: nothing in it is trusted to have the right type).
size_t unsigned_or(const nlohmann::json& object, const char* key, size_t fallback) {
  const auto it = object.find(key);
  return it != object.end() && it->is_number_unsigned() ? it->get<size_t>() : fallback;
}

// Per material, whether a primitive draws with it.
std::vector<char> drawn_materials(const GltfAppearance& look) {
  std::vector<char> drawn(look.materials.size(), 0);
  for (const auto& p : look.primitives)
    if (p.material >= 0 && static_cast<size_t>(p.material) < drawn.size())
      drawn[static_cast<size_t>(p.material)] = 1;
  return drawn;
}

// The image material `m` takes its base colour from, or SIZE_MAX for none.
size_t base_color_image(const GltfAppearance& look, size_t m) {
  const auto pbr = look.materials[m].find("pbrMetallicRoughness");
  if (pbr == look.materials[m].end() || !pbr->is_object()) return SIZE_MAX;
  const auto info = pbr->find("baseColorTexture");
  if (info == pbr->end() || !info->is_object()) return SIZE_MAX;
  const nlohmann::json& t = look.textures.at(unsigned_or(*info, "index", 0));  // checked
  return t.contains("source") && t["source"].is_number_unsigned() ? t["source"].get<size_t>()
                                                                  : SIZE_MAX;
}

// The base colour of every material drawn, decoding each distinct image it uses once,
// at most kMaxBaseColorPixels in all.
std::vector<BaseColor> base_colors(const GltfAppearance& look, DecodedImages& cache,
                                   size_t& decoded, const StopCheck& stop) {
  std::map<size_t, RgbaImage>& images = cache.images;
  size_t& pixels = cache.pixels;
  std::vector<BaseColor> out(look.materials.size());
  const std::vector<char> drawn = drawn_materials(look);
  for (size_t m = 0; m < look.materials.size(); ++m) {
    if (!drawn[m]) continue;  // its image is never sampled: not decoded
    const nlohmann::json pbr = look.materials[m].contains("pbrMetallicRoughness")
                                   ? look.materials[m]["pbrMetallicRoughness"]
                                   : nlohmann::json::object();
    if (!pbr.is_object()) continue;
    if (const auto f = pbr.find("baseColorFactor");
        f != pbr.end() && f->is_array() && f->size() == 4)
      for (size_t k = 0; k < 4; ++k)
        if ((*f)[k].is_number()) out[m].factor[k] = (*f)[k].get<double>();
    const auto info = pbr.find("baseColorTexture");
    if (info == pbr.end() || !info->is_object()) continue;
    const size_t texture = unsigned_or(*info, "index", 0);
    const size_t set = unsigned_or(*info, "texCoord", 0);
    out[m].texcoord = "TEXCOORD_" + std::to_string(std::min<size_t>(set, 9));
    const nlohmann::json& t = look.textures.at(texture);  // checked when the look was read
    if (!t.contains("source") || !t["source"].is_number_unsigned()) continue;
    const size_t source = t["source"].get<size_t>();
    if (t.contains("sampler") && t["sampler"].is_number_unsigned()) {
      const nlohmann::json& s = look.samplers.at(t["sampler"].get<size_t>());
      out[m].wrap_s = static_cast<int>(unsigned_or(s, "wrapS", kRepeat));
      out[m].wrap_t = static_cast<int>(unsigned_or(s, "wrapT", kRepeat));
    }
    // Keyed by the image's bytes, not the image: images sharing bytes decode once.
    const std::string* bytes = look.image_bytes(source);
    if (!bytes) continue;
    const size_t data = look.image_source[source];
    if (!images.count(data)) {
      stop.check();  // a decode takes up to seconds
      pixels += std::min(image_pixels(*bytes), kMaxImagePixels + 1);
      if (pixels > kMaxBaseColorPixels)
        throw InputError("too_large", "the base-colour images the remesh samples hold over " +
                                          std::to_string(kMaxBaseColorPixels) +
                                          " pixels in all, the limit of the colour bake");
      if (auto image = decode_image(*bytes, kMaxImagePixels)) {
        images.emplace(data, std::move(*image));
        ++decoded;
      }
    }
    if (const auto it = images.find(data); it != images.end()) out[m].image = &it->second;
  }
  return out;
}

// Calls `visit` with the bytes of each distinct image a drawn material takes its base
// colour from: the images bake_base_color would decode.
template <typename Visit>
void for_each_base_color_image(const GltfAppearance& look, Visit visit) {
  const std::vector<char> drawn = drawn_materials(look);
  std::set<size_t> seen;  // image_data entries
  for (size_t m = 0; m < look.materials.size(); ++m) {
    const size_t image = drawn[m] ? base_color_image(look, m) : SIZE_MAX;
    const std::string* bytes = image == SIZE_MAX ? nullptr : look.image_bytes(image);
    if (bytes && seen.insert(look.image_source[image]).second) visit(*bytes);
  }
}

}  // namespace

size_t base_color_pixels(const GltfAppearance& look) {
  size_t pixels = 0;
  for_each_base_color_image(look, [&](const std::string& bytes) {
    pixels += std::min(image_pixels(bytes), kMaxImagePixels + 1);
  });
  return pixels;
}

size_t base_color_jpeg_scans(const GltfAppearance& look) {
  size_t most = 0;
  for_each_base_color_image(look, [&](const std::string& bytes) {
    if (image_type(bytes) == "image/jpeg") most = std::max(most, jpeg_scan_count(bytes));
  });
  return most;
}

namespace {

// The colour of the input's surface at a point of one of its faces: baseColorFactor x
// baseColorTexture (at the face's interpolated TEXCOORD_n, with its sampler's wrap) x
// COLOR_0, from the corners `vertex` (input vertices of the face) and their weights.
class FaceColors {
 public:
  // O(primitives log primitives): a part's bake need not touch every face of the input.
  FaceColors(const GltfAppearance& look, const std::vector<BaseColor>& colors)
      : look_(look), colors_(colors), by_first_face_(look.primitives.size()) {
    std::iota(by_first_face_.begin(), by_first_face_.end(), 0u);
    std::stable_sort(by_first_face_.begin(), by_first_face_.end(), [&](uint32_t a, uint32_t b) {
      return look.primitives[a].first_face < look.primitives[b].first_face;
    });
  }

  Rgba at(uint32_t face, const std::array<uint32_t, 3>& vertex,
          const std::array<double, 3>& weight) const {
    const GltfAppearance::Primitive& p = look_.primitives[primitive_of(face)];
    auto interpolate = [&](const GltfAppearance::Attribute& a, int component) {
      double x = 0;
      for (int k = 0; k < 3; ++k)
        x += weight[k] * a.values[vertex[k] * static_cast<size_t>(a.components) + component];
      return x;
    };
    Rgba color{1, 1, 1, 1};
    if (p.material >= 0 && static_cast<size_t>(p.material) < colors_.size()) {
      const BaseColor& c = colors_[static_cast<size_t>(p.material)];
      color = c.factor;
      const GltfAppearance::Attribute* uv =
          p.has(c.texcoord) ? look_.attribute(c.texcoord) : nullptr;
      if (c.image && uv) {
        const Rgba t = sample(c, interpolate(*uv, 0), interpolate(*uv, 1));
        for (int k = 0; k < 4; ++k) color[k] *= t[k];
      }
    }
    if (const auto* vc = p.has("COLOR_0") ? look_.attribute("COLOR_0") : nullptr)
      for (int k = 0; k < 3; ++k) color[k] *= interpolate(*vc, k);
    return color;
  }

 private:
  // The primitive whose face range holds `face` (ranges are disjoint: reading order), or
  // the first primitive when none does. Precondition: the look has a primitive.
  uint32_t primitive_of(uint32_t face) const {
    const auto after = std::upper_bound(
        by_first_face_.begin(), by_first_face_.end(), face,
        [&](uint32_t f, uint32_t p) { return f < look_.primitives[p].first_face; });
    if (after == by_first_face_.begin()) return 0;
    const GltfAppearance::Primitive& p = look_.primitives[*(after - 1)];
    return face - p.first_face < p.face_count ? *(after - 1) : 0;
  }

  const GltfAppearance& look_;
  const std::vector<BaseColor>& colors_;
  std::vector<uint32_t> by_first_face_;  // primitive indices by first_face
};

// Whether `look` gives a surface a colour of its own (a material or vertex colours).
bool coloured(const GltfAppearance& look) {
  return !look.empty() && std::any_of(look.primitives.begin(), look.primitives.end(),
                                      [](auto& p) { return p.material >= 0 || p.has("COLOR_0"); });
}

// The square's texels, each located on the map's sphere and coloured by `color_of(hit)`
// (false: no colour, grey); a miss of the locator is counted as unlocated.
template <typename ColorOf>
void bake_texels(BakedBaseColor& baked, const SphereLocator& locator, const OctahedralFrame& frame,
                 int size, int threads, const std::function<bool()>* should_stop,
                 ColorOf color_of) {
  std::vector<uint16_t> rgb(static_cast<size_t>(size) * size * 3, 128);
  std::vector<char> missed(static_cast<size_t>(size) * size, 0);
  // Over texels, not rows (a few thousand rows stay under parallel_for's threshold, so a
  // 2048 square ran on one thread); the stop asked once a row (milliseconds).
  ParallelStop row_stop(should_stop, static_cast<size_t>(size));
  parallel_for(rgb.size() / 3, resolve_threads(threads), [&](size_t texel) {
    if (row_stop.skip(texel)) return;
    const size_t row = texel / static_cast<size_t>(size);
    const size_t column = texel % static_cast<size_t>(size);
    const double u = (column + 0.5) / size, v = (row + 0.5) / size;
    const SphereHit hit = locator.locate(octahedral_decode({2 * u - 1, 1 - 2 * v}, frame));
    Rgba color;
    if (hit.triangle == UINT32_MAX || !color_of(hit, color)) {
      missed[texel] = hit.triangle == UINT32_MAX;
      return;
    }
    for (int k = 0; k < 3; ++k)
      rgb[texel * 3 + k] = static_cast<uint16_t>(std::lround(255 * linear_to_srgb(color[k])));
  });
  row_stop.throw_if_stopped();
  baked.unlocated_texels = static_cast<size_t>(std::count(missed.begin(), missed.end(), 1));
  baked.size = size;
  baked.png = encode_png(size, size, 8, rgb);
}

}  // namespace

std::optional<BakedBaseColor> bake_base_color(const PolygonMesh& input, const GltfAppearance& look,
                                              const MappedMesh& mapped,
                                              std::span<const Triangle> oriented, int size,
                                              int threads, const std::function<bool()>* should_stop,
                                              DecodedImages* images,
                                              const std::vector<uint32_t>* input_faces,
                                              const OctahedralFrame& frame,
                                              const SphereLocator* shared_locator) {
  const StopCheck stop(should_stop);
  if (!coloured(look) || size <= 0) return std::nullopt;
  BakedBaseColor baked;
  DecodedImages own;
  const std::vector<BaseColor> colors =
      base_colors(look, images ? *images : own, baked.images_decoded, stop);

  // Welded faces are the input's faces in order, less dropped components: face t of the
  // map is input face input_face[t], its corners matched by welded vertex.
  const PolygonMesh& welded = mapped.prepared.welded.mesh;
  const auto& to_welded = mapped.prepared.welded.input_to_welded;
  std::vector<uint32_t> own_faces;
  if (!input_faces) own_faces = welded_input_faces(input, mapped);
  const std::vector<uint32_t>& input_face = input_faces ? *input_faces : own_faces;
  if (input_face.size() != welded.face_count() || oriented.size() != welded.face_count())
    return std::nullopt;
  std::optional<SphereLocator> own_locator;
  const SphereLocator& locator =
      shared_or_own_locator(shared_locator, own_locator, mapped.map.sphere, oriented);
  const FaceColors face_colors(look, colors);
  const auto color_at = [&](const SphereHit& hit, Rgba& color) {
    const uint32_t face = input_face[hit.triangle];
    // The input corner of each map corner (same welded vertex).
    std::array<uint32_t, 3> vertex{};
    for (int k = 0; k < 3; ++k)
      for (uint32_t c : input.face(face))
        if (to_welded[c] == oriented[hit.triangle][k]) vertex[k] = c;
    color = face_colors.at(face, vertex, hit.barycentric);
    return true;
  };
  bake_texels(baked, locator, frame, size, threads, should_stop, color_at);
  return baked;
}

std::optional<BakedBaseColor> bake_base_color_closest(
    const OriginalSurface& original, const MappedMesh& mapped, std::span<const Triangle> oriented,
    int size, int threads, const std::function<bool()>* should_stop, DecodedImages* images,
    const OctahedralFrame& frame, const SphereLocator* shared_locator) {
  const StopCheck stop(should_stop);
  if (!original.mesh || !original.look || !coloured(*original.look) || size <= 0 ||
      original.triangles.empty())
    return std::nullopt;
  const PolygonMesh& input = *original.mesh;
  const GltfAppearance& look = *original.look;
  BakedBaseColor baked;
  DecodedImages own;
  const std::vector<BaseColor> colors =
      base_colors(look, images ? *images : own, baked.images_decoded, stop);
  baked.factors_only =
      std::none_of(colors.begin(), colors.end(), [](const BaseColor& c) { return c.image; }) &&
      std::none_of(look.primitives.begin(), look.primitives.end(),
                   [](const auto& p) { return p.has("COLOR_0"); });
  const PolygonMesh& envelope = mapped.prepared.welded.mesh;
  if (oriented.size() != envelope.face_count()) return std::nullopt;
  stop.check();
  const TriangleTree tree(input.positions, original.triangles);
  stop.check();
  std::optional<SphereLocator> own_locator;
  const SphereLocator& locator =
      shared_or_own_locator(shared_locator, own_locator, mapped.map.sphere, oriented);
  const FaceColors face_colors(look, colors);
  const auto color_at = [&](const SphereHit& hit, Rgba& color) {
    const Triangle& t = oriented[hit.triangle];
    Vec3 point;  // the envelope's point at the texel
    for (int k = 0; k < 3; ++k) point += envelope.positions[t[k]] * hit.barycentric[k];
    const TriangleTree::Closest closest = tree.closest(point);
    if (closest.squared_distance == std::numeric_limits<double>::max()) return false;
    const Triangle& o = original.triangles[closest.triangle];
    const auto& p = input.positions;
    color = face_colors.at(original.face[closest.triangle], o,
                           barycentric(closest.point, p[o[0]], p[o[1]], p[o[2]]));
    return true;
  };
  bake_texels(baked, locator, frame, size, threads, should_stop, color_at);
  return baked;
}

std::optional<std::vector<std::array<float, 3>>> colors_closest(
    const OriginalSurface& original, std::span<const Vec3> points, int threads,
    const std::function<bool()>* should_stop, DecodedImages* images) {
  const StopCheck stop(should_stop);
  if (!original.mesh || !original.look || !coloured(*original.look) || original.triangles.empty())
    return std::nullopt;
  const PolygonMesh& input = *original.mesh;
  const GltfAppearance& look = *original.look;
  DecodedImages own;
  size_t decoded = 0;
  const std::vector<BaseColor> colors = base_colors(look, images ? *images : own, decoded, stop);
  stop.check();
  const TriangleTree tree(input.positions, original.triangles);
  const FaceColors face_colors(look, colors);
  std::vector<std::array<float, 3>> out(points.size(), {0.5f, 0.5f, 0.5f});
  ParallelStop point_stop(should_stop, 4096);
  parallel_for(points.size(), resolve_threads(threads), [&](size_t v) {
    if (point_stop.skip(v)) return;
    const TriangleTree::Closest closest = tree.closest(points[v]);
    if (closest.squared_distance == std::numeric_limits<double>::max()) return;
    const Triangle& o = original.triangles[closest.triangle];
    const auto& p = input.positions;
    const Rgba c = face_colors.at(original.face[closest.triangle], o,
                                  barycentric(closest.point, p[o[0]], p[o[1]], p[o[2]]));
    for (int k = 0; k < 3; ++k) out[v][k] = static_cast<float>(std::clamp(c[k], 0.0, 1.0));
  });
  point_stop.throw_if_stopped();
  return out;
}

}  // namespace spheremap
