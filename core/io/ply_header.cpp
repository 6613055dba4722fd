#include "core/io/ply_header.h"

#include <algorithm>
#include <charconv>

#include "core/mesh/counted.h"
#include "core/mesh/input_error.h"

namespace spheremap::ply {
namespace {

struct TypeName {
  std::string_view name;
  Type type;
};
constexpr TypeName kTypeNames[] = {
    {"char", Type::kInt8},      {"int8", Type::kInt8},       {"uchar", Type::kUint8},
    {"uint8", Type::kUint8},    {"short", Type::kInt16},     {"int16", Type::kInt16},
    {"ushort", Type::kUint16},  {"uint16", Type::kUint16},   {"int", Type::kInt32},
    {"int32", Type::kInt32},    {"uint", Type::kUint32},     {"uint32", Type::kUint32},
    {"float", Type::kFloat32},  {"float32", Type::kFloat32}, {"double", Type::kFloat64},
    {"float64", Type::kFloat64}};

// Splits a header line into words (spaces and tabs).
std::vector<std::string_view> words(std::string_view line) {
  std::vector<std::string_view> out;
  size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
    const size_t start = i;
    while (i < line.size() && line[i] != ' ' && line[i] != '\t') ++i;
    if (i > start) out.push_back(line.substr(start, i - start));
  }
  return out;
}

class HeaderParser {
 public:
  explicit HeaderParser(std::string_view bytes) : bytes_(bytes) {}

  Header parse() {
    if (!next_line() || line_ != "ply") fail("the file does not begin with the line 'ply'");
    bool have_format = false;
    while (true) {
      if (!next_line()) fail("the header has no 'end_header' line");
      const std::vector<std::string_view> w = words(line_);
      if (w.empty()) continue;
      if (w[0] == "end_header") break;
      if (w[0] == "comment" || w[0] == "obj_info") continue;
      if (w[0] == "format") {
        read_format(w);
        have_format = true;
      } else if (w[0] == "element") {
        read_element(w);
      } else if (w[0] == "property") {
        read_property(w);
      } else if (header_.elements.empty()) {
        // A free text line before the first element (Blender 2.4 wrote "Created by
        // Blender3D ..." without "comment"): read as the comment it is, as other readers
        // do. After it, a line that is no keyword is an error (a misspelt "property").
        continue;
      } else {
        fail("unknown header keyword '" + std::string(w[0]) + "'");
      }
    }
    if (!have_format) fail("the header has no 'format' line");
    // Past the end when "end_header" is the file's last line without a line end.
    header_.data_offset = std::min(pos_, bytes_.size());
    header_.lines = line_number_;
    check_counts();
    return std::move(header_);
  }

 private:
  // Lines end in "\n" or "\r\n", or in "\r" alone (classic Mac; Rhinoceros 6 writes it, the
  // Draco test data's Box.ply): the first line's end says which, so the byte after
  // "end_header" is never taken for one (binary data may begin with 0x0A).
  bool next_line() {
    if (pos_ >= bytes_.size()) return false;
    if (pos_ == 0) {
      const size_t first = bytes_.find_first_of("\r\n");
      cr_only_ = first != std::string_view::npos && bytes_[first] == '\r' &&
                 (first + 1 == bytes_.size() || bytes_[first + 1] != '\n');
    }
    size_t end = bytes_.find(cr_only_ ? '\r' : '\n', pos_);
    if (end == std::string_view::npos) end = bytes_.size();
    line_ = bytes_.substr(pos_, end - pos_);
    if (!line_.empty() && line_.back() == '\r') line_.remove_suffix(1);
    pos_ = end + 1;
    ++line_number_;
    return true;
  }

  [[noreturn]] void fail(const std::string& message) const {
    throw InputError("parse", "PLY header line " + std::to_string(line_number_) + ": " + message);
  }

  Type type_named(std::string_view name) const {
    for (const TypeName& t : kTypeNames)
      if (t.name == name) return t.type;
    fail("unknown property type '" + std::string(name) + "'");
  }

  void read_format(const std::vector<std::string_view>& w) {
    if (w.size() != 3 || w[2] != "1.0") fail("expected 'format <encoding> 1.0'");
    if (w[1] == "ascii")
      header_.encoding = Encoding::kAscii;
    else if (w[1] == "binary_little_endian")
      header_.encoding = Encoding::kBinaryLittleEndian;
    else if (w[1] == "binary_big_endian")
      header_.encoding = Encoding::kBinaryBigEndian;
    else
      fail("unknown format '" + std::string(w[1]) + "'");
  }

  void read_element(const std::vector<std::string_view>& w) {
    if (w.size() != 3) fail("expected 'element <name> <count>'");
    Element element;
    element.name = w[1];
    auto [ptr, ec] = std::from_chars(w[2].data(), w[2].data() + w[2].size(), element.count);
    if (ec != std::errc() || ptr != w[2].data() + w[2].size())
      fail("the count of element '" + element.name + "' is not a number: '" + std::string(w[2]) +
           "'");
    header_.elements.push_back(std::move(element));
  }

  void read_property(const std::vector<std::string_view>& w) {
    if (header_.elements.empty()) fail("a property before any element");
    Property p;
    if (w.size() == 5 && w[1] == "list") {
      p.is_list = true;
      p.count_type = type_named(w[2]);
      if (!is_integer(p.count_type)) fail("a list count of type '" + std::string(w[2]) + "'");
      p.type = type_named(w[3]);
      p.name = w[4];
    } else if (w.size() == 3 && w[1] != "list") {
      p.type = type_named(w[1]);
      p.name = w[2];
    } else {
      fail("expected 'property <type> <name>' or 'property list <type> <type> <name>'");
    }
    header_.elements.back().properties.push_back(std::move(p));
  }

  // Every element's count against the bytes after the header, before anything is
  // allocated for it: a forged count is refused here, not by the allocator.
  void check_counts() const {
    const uint64_t after = bytes_.size() - std::min(bytes_.size(), header_.data_offset);
    // ASCII: the last value of the file needs no separator after it.
    const uint64_t available = after + (header_.encoding == Encoding::kAscii ? 1 : 0);
    for (const Element& e : header_.elements) {
      if (e.count == 0) continue;
      const uint64_t each = e.min_bytes(header_.encoding);
      if (each == 0)
        fail("element '" + e.name + "' has no properties but a count of " +
             std::to_string(e.count));
      if (e.count > available / each)
        fail("element '" + e.name + "' declares " + counted(e.count, "entry", "entries") +
             " of at least " + counted(each, "byte") + " each, but only " + counted(after, "byte") +
             (after == 1 ? " follows" : " follow") + " the header");
    }
  }

  std::string_view bytes_;
  std::string_view line_;
  size_t pos_ = 0, line_number_ = 0;
  bool cr_only_ = false;
  Header header_;
};

}  // namespace

size_t type_size(Type type) {
  switch (type) {
    case Type::kInt8:
    case Type::kUint8:
      return 1;
    case Type::kInt16:
    case Type::kUint16:
      return 2;
    case Type::kInt32:
    case Type::kUint32:
    case Type::kFloat32:
      return 4;
    case Type::kFloat64:
      return 8;
  }
  return 0;
}

bool is_integer(Type type) {
  return type != Type::kFloat32 && type != Type::kFloat64;
}

uint64_t Element::min_bytes(Encoding encoding) const {
  uint64_t total = 0;
  for (const Property& p : properties) {
    if (encoding == Encoding::kAscii)
      total += 2;  // "0 " (a list: its count of 0)
    else
      total += type_size(p.is_list ? p.count_type : p.type);
  }
  return total;
}

Header parse_header(std::string_view bytes) {
  return HeaderParser(bytes).parse();
}

}  // namespace spheremap::ply
