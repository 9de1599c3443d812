#include "common/file_io.h"

#include <unistd.h>
#include <zlib.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>

#include "common/error.h"
#include "common/interrupt.h"

namespace tdvo {

namespace {

std::string systemError() {
  return std::strerror(errno);
}

struct FileCloser {
  void operator()(std::FILE* f) const {
    if (f) std::fclose(f);
  }
};
using FilePtr = std::unique_ptr<std::FILE, FileCloser>;

}  // namespace

namespace {

[[noreturn]] void tooLarge(const std::string& path, uint64_t maxBytes, const std::string& what) {
  throw Error(path + ": more than " + std::to_string(maxBytes) + " bytes: too large for " + what);
}

}  // namespace

std::vector<uint8_t> readFileBytes(const std::string& path, uint64_t maxBytes, const char* what) {
  FilePtr f(std::fopen(path.c_str(), "rb"));
  if (!f) throw Error(path + ": cannot open: " + systemError());
  std::vector<uint8_t> data;
  uint8_t buffer[1 << 16];
  size_t n;
  while ((n = std::fread(buffer, 1, sizeof buffer, f.get())) > 0) {
    if (n > maxBytes - data.size()) tooLarge(path, maxBytes, what);
    data.insert(data.end(), buffer, buffer + n);
  }
  if (std::ferror(f.get())) throw Error(path + ": read error: " + systemError());
  return data;
}

void readFileMaybeGzChunks(const std::string& path,
                           const std::function<void(const char* data, size_t size)>& consume) {
  // gzopen reads plain files transparently, so one path serves both.
  FilePtr probe(std::fopen(path.c_str(), "rb"));
  if (!probe) throw Error(path + ": cannot open: " + systemError());
  probe.reset();
  gzFile gz = gzopen(path.c_str(), "rb");
  if (!gz) throw Error(path + ": cannot open: " + systemError());
  struct GzCloser {
    gzFile gz;
    ~GzCloser() { gzclose(gz); }
  } closer{gz};
  char buffer[1 << 16];
  int n;
  while ((n = gzread(gz, buffer, sizeof buffer)) > 0)
    consume(buffer, static_cast<size_t>(n));
  int errnum = Z_OK;
  const char* message = gzerror(gz, &errnum);
  if (n < 0 || errnum != Z_OK) throw Error(path + ": cannot decompress: " + message);
}

std::string readFileMaybeGz(const std::string& path, uint64_t maxBytes) {
  std::string text;
  readFileMaybeGzChunks(path, [&](const char* data, size_t size) {
    if (size > maxBytes - text.size()) tooLarge(path, maxBytes, "an input file");
    text.append(data, size);
  });
  return text;
}

namespace {

// Writes `path` completely or not at all (removed on failure); errors name `shown`, the file
// name the user knows. The file is in the interrupt registry (interrupt.h) from before it is
// created; the returned handle is dropped by the caller once the file is renamed into place.
uint64_t writeWhole(const std::string& path, const std::string& shown, const void* data,
                    size_t size) {
  FilePtr f;
  uint64_t handle;
  {
    const auto lock = InterruptRegistry::lock();
    handle = InterruptRegistry::add(path);
    f.reset(std::fopen(path.c_str(), "wb"));
    if (!f) {
      const std::string why = systemError();
      InterruptRegistry::drop(handle);
      throw Error(shown + ": cannot create: " + why);
    }
  }
  bool ok = std::fwrite(data, 1, size, f.get()) == size;
  ok = (std::fflush(f.get()) == 0) && ok;
  if (!ok) {
    const std::string why = systemError();
    f.reset();
    const auto lock = InterruptRegistry::lock();
    std::remove(path.c_str());
    InterruptRegistry::drop(handle);
    throw Error(shown + ": write error: " + why);
  }
  return handle;
}

}  // namespace

void writeFileAtomic(const std::string& path, const void* data, size_t size) {
  const std::string temp = path + ".tmp" + std::to_string(::getpid());
  const uint64_t handle = writeWhole(temp, path, data, size);
  const auto lock = InterruptRegistry::lock();
  if (std::rename(temp.c_str(), path.c_str()) != 0) {
    const std::string why = systemError();
    std::remove(temp.c_str());
    InterruptRegistry::drop(handle);
    throw Error(path + ": cannot rename temporary file into place: " + why);
  }
  InterruptRegistry::drop(handle);
}

StagedFiles::~StagedFiles() {
  if (committed_) return;
  // A failed (or partly renamed) run: its files go, under whichever name they stand.
  const auto lock = InterruptRegistry::lock();
  for (const Entry& e : entries_) {
    std::remove(e.renamed ? e.path.c_str() : (e.path + ".partial").c_str());
    InterruptRegistry::drop(e.handle);
  }
}

void StagedFiles::write(const std::string& path, const void* data, size_t size) {
  entries_.reserve(entries_.size() + 1);  // so that the push_back cannot lose a written file
  entries_.push_back({path, writeWhole(path + ".partial", path, data, size), false});
}

void StagedFiles::commit() {
  for (Entry& e : entries_) {
    const auto lock = InterruptRegistry::lock();
    if (std::rename((e.path + ".partial").c_str(), e.path.c_str()) != 0)
      throw Error(e.path + ": cannot rename staged output into place: " + systemError());
    // Until every file is in place, an interruption removes the renamed ones too: a run's
    // output is there completely or not at all.
    InterruptRegistry::drop(e.handle);
    e.handle = InterruptRegistry::add(e.path);
    e.renamed = true;
  }
  const auto lock = InterruptRegistry::lock();
  for (const Entry& e : entries_)
    InterruptRegistry::drop(e.handle);
  committed_ = true;
}

void makeDirectories(const std::string& path) {
  if (path.empty()) return;
  std::error_code ec;
  std::filesystem::create_directories(path, ec);
  if (ec) throw Error(path + ": cannot create folder: " + ec.message());
}

}  // namespace tdvo
