#include "core/io/text_reader.h"

#include <charconv>
#include <fstream>
#include <sstream>

#include "core/mesh/input_error.h"

namespace spheremap {

bool TextReader::next_line() {
  if (pos_ >= text_.size()) return false;
  size_t end = text_.find('\n', pos_);
  if (end == std::string_view::npos) end = text_.size();
  line_ = text_.substr(pos_, end - pos_);
  pos_ = end + 1;
  ++line_number_;
  if (size_t hash = line_.find('#'); hash != std::string_view::npos) line_ = line_.substr(0, hash);
  while (!line_.empty() && (line_.back() == '\r' || line_.back() == ' ' || line_.back() == '\t'))
    line_.remove_suffix(1);
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
