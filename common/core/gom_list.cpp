#include "common/core/gom_list.h"

#include <algorithm>
#include <cstdlib>
#include <limits>
#include <sstream>

#include "common/core/error.h"
#include "common/core/file_io.h"

namespace tdvo {

namespace {

// "frame 4" or "frames 4 .. 7".
std::string frames(long long first, long long last) {
  return first == last ? "frame " + std::to_string(first)
                       : "frames " + std::to_string(first) + " .. " + std::to_string(last);
}

std::string isOrAre(long long first, long long last) {
  return first == last ? " is" : " are";
}

}  // namespace

std::string formatGomList(const GomList& goms) {
  std::string text =
      "# 3dvo-recon GOM list: one GOM per line, <first frame> <frame count>, frames counted "
      "from the first output frame (0 = FirstFrame)\n";
  for (const auto& g : goms)
    text += std::to_string(g.first) + " " + std::to_string(g.second) + "\n";
  return text;
}

GomList parseGomList(const std::string& text, const std::string& name, size_t frameCount) {
  GomList goms;
  std::istringstream in(text);
  std::string line;
  int lineNumber = 0, previousLine = 0;
  long long next = 0;  // the frame the next GOM must start at
  auto where = [&]() { return name + ":" + std::to_string(lineNumber) + ": "; };
  while (std::getline(in, line)) {
    ++lineNumber;
    const size_t hash = line.find('#');
    if (hash != std::string::npos) line.resize(hash);
    std::istringstream fields(line);
    long long first, count;
    std::string extra;
    if (!(fields >> first)) {
      check(line.find_first_not_of(" \t\r") == std::string::npos,
            where() + "expected '<first frame> <frame count>'");
      continue;
    }
    check(static_cast<bool>(fields >> count) && !(fields >> extra),
          where() + "expected '<first frame> <frame count>'");
    if (first != next) {
      const std::string starts = "GOM starts at frame " + std::to_string(first);
      if (goms.empty()) throw Error(where() + "the first " + starts + "; it must start at frame 0");
      if (first > next)
        throw Error(where() + starts + ", expected " + std::to_string(next) + ": " +
                    frames(next, first - 1) + isOrAre(next, first - 1) + " in no GOM");
      throw Error(where() + starts + ", expected " + std::to_string(next) +
                  ": it overlaps the GOM of line " + std::to_string(previousLine));
    }
    check(count >= 1 && count <= kGomListMaxCount,
          where() + "frame count must be in 1 .. " + std::to_string(kGomListMaxCount));
    const long long last = first + count - 1;
    check(last < std::numeric_limits<int>::max(),
          where() + "GOM ends beyond frame " + std::to_string(std::numeric_limits<int>::max() - 1));
    const long long coded = static_cast<long long>(frameCount);
    if (frameCount > 0 && last >= coded)
      throw Error(where() + "GOM of " + frames(first, last) + " goes beyond the coded " +
                  frames(0, coded - 1));
    goms.emplace_back(static_cast<int>(first), static_cast<int>(count));
    next = last + 1;
    previousLine = lineNumber;
  }
  check(!goms.empty(), name + ": no GOM listed");
  const long long coded = static_cast<long long>(frameCount);
  if (frameCount > 0 && next != coded)
    throw Error(name + ":" + std::to_string(previousLine) + ": the last GOM ends at frame " +
                std::to_string(next - 1) + ": " + frames(next, coded - 1) + " of the coded " +
                frames(0, coded - 1) + isOrAre(next, coded - 1) + " in no GOM");
  return goms;
}

GomList readGomList(const std::string& path, size_t frameCount) {
  return parseGomList(readTextFile(path, kMaxCfgFileBytes, "a GOM list"), path, frameCount);
}

std::vector<int> readGomStarts(const std::string& path) {
  std::istringstream in(readTextFile(path, kMaxCfgFileBytes, "a GOM list"));
  std::vector<int> starts;
  std::string line;
  int lineNumber = 0;
  while (std::getline(in, line)) {
    ++lineNumber;
    line = line.substr(0, line.find('#'));
    std::replace(line.begin(), line.end(), ',', ' ');
    std::istringstream fields(line);
    std::string token;
    while (fields >> token) {
      char* end = nullptr;
      const long v = std::strtol(token.c_str(), &end, 10);
      check(end && *end == 0 && v >= 0 && v < (1L << 30),
            path + ":" + std::to_string(lineNumber) + ": '" + token +
                "' is not a frame index (a non-negative integer)");
      starts.push_back(static_cast<int>(v));
    }
  }
  std::sort(starts.begin(), starts.end());
  starts.erase(std::unique(starts.begin(), starts.end()), starts.end());
  return starts;
}

std::string formatGomStarts(const std::vector<uint32_t>& starts) {
  std::string text = "# first frame of each GOM that is a random access point (3dvo-dec)\n";
  for (uint32_t start : starts)
    text += std::to_string(start) + "\n";
  return text;
}

}  // namespace tdvo
