#include "core/io/mni_obj.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <string>
#include <vector>

#include "core/io/shown_bytes.h"
#include "core/mesh/counted.h"
#include "core/mesh/input_error.h"

namespace spheremap {
namespace {

constexpr std::string_view kObjectLetters = "PLMTQFXV";

// Whitespace-separated tokens of the whole text, with the line of each for messages.
class Tokens {
 public:
  explicit Tokens(std::string_view text) : text_(text) {}

  std::string_view next() {
    while (pos_ < text_.size() && is_space(text_[pos_])) line_ += text_[pos_++] == '\n';
    const size_t start = pos_;
    while (pos_ < text_.size() && !is_space(text_[pos_])) ++pos_;
    return text_.substr(start, pos_ - start);
  }
  // `what`, and `index` unless it is kNone, name the value in a message: no string is made
  // per token.
  static constexpr uint64_t kNone = UINT64_MAX;
  double number(std::string_view what, uint64_t index = kNone) {
    const std::string_view t = next();
    double value = 0;
    const auto [end, error] = std::from_chars(t.data(), t.data() + t.size(), value);
    if (t.empty() || error != std::errc() || end != t.data() + t.size() || !std::isfinite(value))
      fail("expected a number for " + named(what, index) + ", found " + shown(t));
    return value;
  }
  uint64_t count(std::string_view what, uint64_t index = kNone) {
    const std::string_view t = next();
    uint64_t value = 0;
    const auto [end, error] = std::from_chars(t.data(), t.data() + t.size(), value);
    if (t.empty() || error != std::errc() || end != t.data() + t.size())
      fail("expected a non-negative integer for " + named(what, index) + ", found " + shown(t));
    return value;
  }
  // `n` more tokens of at least one character and one separator each must fit in what
  // is left: checked before a vector of n is allocated.
  void need(uint64_t n, uint64_t per_item, const std::string& what) const {
    const uint64_t left = (text_.size() - pos_ + 1) / 2;
    if (per_item == 0 || n > left / per_item)
      fail(what + " (" + std::to_string(n) + ") is more than the " + std::to_string(left) +
           " numbers the rest of the file can hold");
  }
  [[noreturn]] void fail(const std::string& message) const {
    throw InputError("parse", "MNI obj line " + std::to_string(line_) + ": " + message);
  }

 private:
  static std::string named(std::string_view what, uint64_t index) {
    std::string out(what);
    if (index != kNone) out.append(1, ' ').append(std::to_string(index));
    return out;
  }
  static bool is_space(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r'; }
  static std::string shown(std::string_view t) {
    return t.empty() ? "the end of the file" : shown_prefix(t);
  }
  std::string_view text_;
  size_t pos_ = 0;
  size_t line_ = 1;
};

}  // namespace

bool looks_like_mni_obj(std::string_view text) {
  size_t start = 0;
  while (start < text.size() &&
         std::string_view(" \t\r\n").find(text[start]) != std::string_view::npos)
    ++start;
  return start + 1 < text.size() && kObjectLetters.find(text[start]) != std::string_view::npos &&
         (text[start + 1] == ' ' || text[start + 1] == '\t');
}

PolygonMesh parse_mni_obj(std::string_view text, const MeshLimits& limits) {
  Tokens tokens(text);
  const std::string_view letter = tokens.next();
  if (letter != "P")
    throw InputError("empty", "MNI obj: the file holds a '" + std::string(letter) +
                                  "' object (lines, markers, text or a quad mesh), not a 'P' "
                                  "polygon surface: spheremap maps triangle surfaces");
  for (const char* property : {"ambient", "diffuse", "specular", "specular exponent", "opacity"})
    tokens.number(property);
  const uint64_t points = tokens.count("the number of points");
  if (points > limits.max_vertices || points > UINT32_MAX)
    throw InputError("too_large",
                     "MNI obj: " + counted(points, "point") + ", over the limit of " +
                         std::to_string(std::min<uint64_t>(limits.max_vertices, UINT32_MAX)));
  tokens.need(points, 6, "the number of points");  // a position and a normal each
  PolygonMesh mesh;
  mesh.positions.resize(points);
  for (uint64_t v = 0; v < points; ++v) {
    Vec3& p = mesh.positions[v];
    p.x = tokens.number("point", v);
    p.y = tokens.number("point", v);
    p.z = tokens.number("point", v);
  }
  for (uint64_t v = 0; v < points; ++v)
    for (int k = 0; k < 3; ++k) tokens.number("normal", v);

  const uint64_t items = tokens.count("the number of polygons");
  const uint64_t flag = tokens.count("the colour flag");
  if (flag > 2) tokens.fail("the colour flag is " + std::to_string(flag) + ", not 0, 1 or 2");
  const uint64_t colours = flag == 0 ? 1 : flag == 1 ? items : points;
  tokens.need(colours, 4, "the number of colours");
  for (uint64_t c = 0; c < 4 * colours; ++c) tokens.number("colour", c / 4);

  tokens.need(items, 1, "the number of polygons");
  std::vector<uint64_t> ends(items);
  for (uint64_t k = 0; k < items; ++k) {
    ends[k] = tokens.count("the end index of polygon", k);
    const uint64_t start = k ? ends[k - 1] : 0;
    if (ends[k] < start + 3)
      tokens.fail("polygon " + std::to_string(k) + " ends at index " + std::to_string(ends[k]) +
                  ", " + (ends[k] < start ? "before" : "less than 3 after") +
                  " the previous one's end (" + std::to_string(start) + ")");
  }
  const uint64_t corners = items ? ends.back() : 0;
  if (corners - 2 * items > limits.max_triangles)
    throw InputError("too_large", "MNI obj: " + std::to_string(corners - 2 * items) +
                                      " triangles, over the limit of " +
                                      std::to_string(limits.max_triangles));
  tokens.need(corners, 1, "the number of polygon corners");
  mesh.indices.reserve(corners);
  mesh.offsets.reserve(items + 1);
  std::vector<uint32_t> polygon;
  for (uint64_t k = 0; k < items; ++k) {
    polygon.clear();
    for (uint64_t c = k ? ends[k - 1] : 0; c < ends[k]; ++c) {
      const uint64_t index = tokens.count("corner", c);
      if (index >= points)
        tokens.fail("polygon " + std::to_string(k) + " names point " + std::to_string(index) +
                    ", but the file has " + counted(points, "point"));
      polygon.push_back(static_cast<uint32_t>(index));
    }
    mesh.add_face(polygon);
  }
  return mesh;
}

}  // namespace spheremap
