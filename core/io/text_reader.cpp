#include "core/io/text_reader.h"

#include <charconv>
#include <cstring>
#include <fstream>
#include <sstream>

#include "core/mesh/input_error.h"

namespace spheremap {

std::string_view TextReader::physical_line() {
  size_t end = text_.find('\n', pos_);
  if (end == std::string_view::npos) end = text_.size();
  size_t next = end + 1;
  // A lone '\r' ends a line too (classic Mac OS files: PrusaSlicer's test STLs); "\r\n" is
  // one ending. memchr, not find_first_of: it scans at memchr's speed.
  if (const void* cr = std::memchr(text_.data() + pos_, '\r', end - pos_)) {
    const size_t at = size_t(static_cast<const char*>(cr) - text_.data());
    if (at + 1 < end) end = at, next = at + 1;
  }
  std::string_view line = text_.substr(pos_, end - pos_);
  pos_ = next;
  ++line_number_;
  if (size_t hash = line.find('#'); hash != std::string_view::npos) line = line.substr(0, hash);
  while (!line.empty() && (line.back() == '\r' || line.back() == ' ' || line.back() == '\t'))
    line.remove_suffix(1);
  return line;
}

bool TextReader::next_line() {
  if (pos_ >= text_.size()) return false;
  line_ = physical_line();
  if (!join_continued_ || !line_.ends_with('\\')) return true;
  // Only continued lines are copied; the loop ends at a line without a backslash, or at the end.
  joined_.clear();
  while (line_.ends_with('\\')) {
    joined_.append(line_.substr(0, line_.size() - 1));
    joined_ += ' ';
    if (pos_ >= text_.size()) {
      line_ = {};
      break;
    }
    line_ = physical_line();
  }
  joined_.append(line_);
  line_ = joined_;
  return true;
}

// Plain loops: find_first_of / find_first_not_of with a two-character set search the set
// for every character (a third of reading an OBJ).
std::string_view TextReader::token() {
  auto blank = [](char c) { return c == ' ' || c == '\t'; };
  size_t start = 0;
  while (start < line_.size() && blank(line_[start])) ++start;
  if (start == line_.size()) {
    line_ = {};
    return {};
  }
  size_t end = start;
  while (end < line_.size() && !blank(line_[end])) ++end;
  std::string_view tok = line_.substr(start, end - start);
  line_ = line_.substr(end);
  return tok;
}

double TextReader::number(std::string_view what) {
  std::string_view tok = token();
  if (!tok.empty() && tok[0] == '+') tok.remove_prefix(1);
  double value = 0;
  auto [ptr, ec] = std::from_chars(tok.data(), tok.data() + tok.size(), value);
  if (tok.empty() || ec != std::errc() || ptr != tok.data() + tok.size())
    fail("expected a number for " + std::string(what) + ", found '" + std::string(tok) + "'");
  return value;
}

long long TextReader::integer(std::string_view what) {
  std::string_view tok = token();
  long long value = 0;
  auto [ptr, ec] = std::from_chars(tok.data(), tok.data() + tok.size(), value);
  if (tok.empty() || ec != std::errc() || ptr != tok.data() + tok.size())
    fail("expected an integer for " + std::string(what) + ", found '" + std::string(tok) + "'");
  return value;
}

void TextReader::fail(const std::string& message) const {
  throw InputError("parse", format_ + " line " + std::to_string(line_number_) + ": " + message);
}

std::string read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError("io", "cannot open '" + path + "'");
  std::ostringstream buffer;
  buffer << in.rdbuf();
  if (in.bad()) throw InputError("io", "cannot read '" + path + "'");
  return std::move(buffer).str();
}

}  // namespace spheremap
