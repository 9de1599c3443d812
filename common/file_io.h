// Whole-file reading and atomic writing.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace tdvo {

// Reads a whole file into memory. Throws Error naming the file when it cannot be opened or read.
std::vector<uint8_t> readFileBytes(const std::string& path);

// Reads a whole file, decompressing it when it is gzip-compressed (through zlib).
std::string readFileMaybeGz(const std::string& path);

// Writes `size` bytes to `path` atomically: to a temporary name in the same folder first, then
// renamed over `path`, so that no half-written file ever stands under the final name.
void writeFileAtomic(const std::string& path, const void* data, size_t size);
inline void writeFileAtomic(const std::string& path, const std::string& text) {
  writeFileAtomic(path, text.data(), text.size());
}

// Output files of one run, staged under temporary names ("<path>.partial") and renamed to their
// final names together by commit(). If the run fails before commit(), the destructor removes
// the staged files, so a failed run leaves no output under a final name.
class StagedFiles {
 public:
  StagedFiles() = default;
  StagedFiles(const StagedFiles&) = delete;
  StagedFiles& operator=(const StagedFiles&) = delete;
  ~StagedFiles();
  void write(const std::string& path, const void* data, size_t size);
  void write(const std::string& path, const std::string& text) {
    write(path, text.data(), text.size());
  }
  void commit();

 private:
  std::vector<std::string> paths_;
  bool committed_ = false;
};

// Creates a folder and its parents when missing. Throws Error on failure.
void makeDirectories(const std::string& path);

}  // namespace tdvo
