// Splitting a text line into whitespace-separated tokens, as the OBJ and PLY readers do.
#pragma once

#include <string_view>
#include <vector>

namespace tdvo {

// `text` without a UTF-8 byte-order mark at its start: some Windows editors write one, and it
// is no part of the first line of a text file (cfg files, OBJ, GOM lists, calibration files;
// readTextFile in file_io.h).
inline std::string_view withoutUtf8Bom(std::string_view text) {
  return text.substr(0, 3) == "\xEF\xBB\xBF" ? text.substr(3) : text;
}

// Whitespace within a line (the line end '\n' is the readers' own concern).
inline bool isSpace(char c) {
  return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f';
}

// The line's tokens, as views into it; `tokens` is reused (cleared first).
inline void tokenize(std::string_view line, std::vector<std::string_view>& tokens) {
  tokens.clear();
  size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && isSpace(line[i]))
      ++i;
    const size_t start = i;
    while (i < line.size() && !isSpace(line[i]))
      ++i;
    if (i > start) tokens.push_back(line.substr(start, i - start));
  }
}

}  // namespace tdvo
