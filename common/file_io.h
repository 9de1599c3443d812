// Whole-file reading and atomic writing.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace tdvo {

// Size limits of the files read whole (docs/robustness.md, "Input files"): a file above its
// limit (or a device such as /dev/zero that never ends) is refused with an error naming it,
// after reading at most the limit.
constexpr uint64_t kMaxCfgFileBytes = uint64_t{1} << 20;     // cfg files, GOM lists
constexpr uint64_t kMaxTextFileBytes = uint64_t{1} << 24;    // dataset.json, calibration, paths
constexpr uint64_t kMaxBinaryFileBytes = uint64_t{1} << 30;  // images, texture files

// Reads a whole file into memory. Throws Error naming the file when it cannot be opened or read,
// or when it holds more than `maxBytes` bytes (`what` names the kind of file in that message:
// "x.cfg: more than 1048576 bytes: too large for a cfg file").
std::vector<uint8_t> readFileBytes(const std::string& path, uint64_t maxBytes = kMaxBinaryFileBytes,
                                   const char* what = "an input file");

// Reads a file chunk by chunk, decompressing it when it is gzip-compressed (through zlib), and
// hands each chunk (at most 64 KiB) to `consume`: memory does not grow with the file.
void readFileMaybeGzChunks(const std::string& path,
                           const std::function<void(const char* data, size_t size)>& consume);

// Reads a whole file, decompressing it when it is gzip-compressed; at most `maxBytes` bytes
// after decompression (Error beyond that).
std::string readFileMaybeGz(const std::string& path, uint64_t maxBytes = kMaxBinaryFileBytes);

// Writes `size` bytes to `path` atomically: to a temporary name in the same folder first, then
// renamed over `path`, so that no half-written file ever stands under the final name.
// The temporary file is removed if the run is interrupted (interrupt.h).
void writeFileAtomic(const std::string& path, const void* data, size_t size);
inline void writeFileAtomic(const std::string& path, const std::string& text) {
  writeFileAtomic(path, text.data(), text.size());
}

// Output files of one run, staged under temporary names ("<path>.partial") and renamed to their
// final names together by commit(). If the run fails before commit() has renamed them all, the
// destructor removes them (staged or already renamed), so a failed run leaves no output under a
// final name; an interrupted one neither (interrupt.h: the files are in the interrupt registry
// from before they are created until commit() is done).
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
  struct Entry {
    std::string path;  // final name
    uint64_t handle;   // in the interrupt registry
    bool renamed;      // commit() has moved it to its final name
  };
  std::vector<Entry> entries_;
  bool committed_ = false;
};

// Creates a folder and its parents when missing. Throws Error on failure.
void makeDirectories(const std::string& path);

}  // namespace tdvo
