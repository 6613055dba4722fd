// Line-oriented tokenizer shared by the OBJ, OFF and ASCII STL readers: lines end in "\n",
// "\r\n" or a lone "\r", '#' comments, numbers parsed with from_chars (locale independent,
// no allocation).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

namespace spheremap {

class TextReader {
 public:
  TextReader(std::string_view text, std::string format) : text_(text), format_(std::move(format)) {}

  // A line ending in '\' continues on the next (OBJ): next_line() then returns them joined
  // by a space, and line_number() is the last of them.
  void join_continued_lines() { join_continued_ = true; }

  // Advances to the next line; false at the end. Comments and '\r' are stripped.
  bool next_line();
  size_t line_number() const { return line_number_; }
  std::string_view rest() const { return line_; }

  // Next whitespace-separated token of the current line, empty when none is left.
  std::string_view token();
  double number(std::string_view what);
  long long integer(std::string_view what);
  [[noreturn]] void fail(const std::string& message) const;

 private:
  // The next line of the text, without its comment and trailing blanks.
  std::string_view physical_line();

  std::string_view text_;
  std::string format_;
  bool join_continued_ = false;
  std::string joined_;  // continued lines, joined (line_ then views it)
  std::string_view line_;
  size_t pos_ = 0;
  size_t line_number_ = 0;
};

// Reads a whole file; throws InputError("io") naming the path on failure.
std::string read_file(const std::string& path);

}  // namespace spheremap
