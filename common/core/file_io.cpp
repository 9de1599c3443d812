#include "common/core/file_io.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zlib.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <tuple>

#include "common/core/error.h"
#include "common/core/interrupt.h"
#include "common/core/sequence.h"
#include "common/core/text_tokens.h"
#include "common/core/warnings.h"

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

namespace {

// A file by device, inode and modification time: the time tells a file read from a later one
// that was given the inode after the first was deleted (a long-lived program, the Python module,
// reads and deletes many files), and a file changed since it was read is another file.
using FileVersion = std::tuple<dev_t, ino_t, int64_t, int64_t>;
FileVersion versionOf(const struct stat& st) {
  return {st.st_dev, st.st_ino, int64_t(st.st_mtim.tv_sec), int64_t(st.st_mtim.tv_nsec)};
}

struct ReadFiles {
  std::mutex mutex;
  std::set<FileVersion> files;
};
ReadFiles& readFiles() {
  static ReadFiles registry;
  return registry;
}

void noteStat(const struct stat& st) {
  if (!S_ISREG(st.st_mode)) return;  // devices, FIFOs: nothing a folder's removal destroys
  ReadFiles& r = readFiles();
  const std::lock_guard<std::mutex> lock(r.mutex);
  r.files.insert(versionOf(st));
}

}  // namespace

void noteFileRead(std::FILE* file) {
  struct stat st;
  if (file && ::fstat(::fileno(file), &st) == 0) noteStat(st);
}

void noteFileRead(const std::string& path) {
  struct stat st;
  if (::stat(path.c_str(), &st) == 0) noteStat(st);
}

namespace {
std::atomic<bool> protectingFilesRead{false};
}  // namespace

bool protectFilesRead(bool on) {
  return protectingFilesRead.exchange(on);
}

bool filesReadAreProtected() {
  return protectingFilesRead.load();
}

bool wasFileRead(const struct stat& st) {
  ReadFiles& r = readFiles();
  const std::lock_guard<std::mutex> lock(r.mutex);
  return r.files.count(versionOf(st)) > 0;
}

std::vector<uint8_t> readFileBytes(const std::string& path, uint64_t maxBytes, const char* what) {
  FilePtr f(std::fopen(path.c_str(), "rb"));
  if (!f) throw Error(path + ": cannot open: " + systemError());
  noteFileRead(f.get());
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

std::string readTextFile(const std::string& path, uint64_t maxBytes, const char* what) {
  const std::vector<uint8_t> bytes = readFileBytes(path, maxBytes, what);
  return std::string(
      withoutUtf8Bom(std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size())));
}

void readFileMaybeGzChunks(const std::string& path,
                           const std::function<void(const char* data, size_t size)>& consume) {
  // gzopen reads plain files transparently, so one path serves both.
  FilePtr probe(std::fopen(path.c_str(), "rb"));
  if (!probe) throw Error(path + ": cannot open: " + systemError());
  noteFileRead(probe.get());
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

namespace fs = std::filesystem;

// Where the data of an output named `shown` goes.
struct OutputTarget {
  std::string path;      // the file to replace: `shown` with symbolic links followed
  bool special = false;  // a character device or FIFO: written in place, never replaced
};

// Follows symbolic links to the file they name (which may not exist yet): an output through a
// link replaces the link's target, never the link. A character device (/dev/null) or FIFO is
// written to as it is; a folder, block device or socket is refused.
OutputTarget resolveOutput(const std::string& shown) {
  struct stat st;
  if (::stat(shown.c_str(), &st) == 0) {
    if (S_ISCHR(st.st_mode) || S_ISFIFO(st.st_mode)) return {shown, true};
    if (S_ISDIR(st.st_mode)) throw Error(shown + ": is a folder, not a file");
    if (!S_ISREG(st.st_mode))
      throw Error(shown + ": is a block device or socket; refusing to write to it");
  }
  std::string current = shown;
  for (int hops = 0; hops < 40; ++hops) {
    struct stat ls;
    if (::lstat(current.c_str(), &ls) != 0 || !S_ISLNK(ls.st_mode)) return {current, false};
    std::vector<char> buffer(static_cast<size_t>(ls.st_size > 0 ? ls.st_size : 255) + 2);
    const ssize_t n = ::readlink(current.c_str(), buffer.data(), buffer.size());
    if (n < 0 || static_cast<size_t>(n) >= buffer.size())
      throw Error(shown + ": cannot read the symbolic link " + current);
    const fs::path target(std::string(buffer.data(), static_cast<size_t>(n)));
    current = target.is_absolute() ? target.string()
                                   : (fs::path(current).parent_path() / target).string();
  }
  throw Error(shown + ": too many levels of symbolic links");
}

// Writes all of `data` to `fd`; false (errno set) on failure.
bool writeAll(int fd, const void* data, size_t size) {
  const char* p = static_cast<const char*>(data);
  while (size > 0) {
    const ssize_t n = ::write(fd, p, size);
    if (n < 0) {
      if (errno == EINTR) continue;
      return false;
    }
    p += n;
    size -= static_cast<size_t>(n);
  }
  return true;
}

// Opens a new file exclusively (O_EXCL | O_NOFOLLOW: never an existing file, never through a
// link), registered in the interrupt registry from before it exists. The name is
// "<base>.partial", or "<base>.<k>.partial" when that exists (a leftover, or a planted link).
int createStaged(const std::string& base, const std::string& shown, std::string& staged,
                 uint64_t& handle) {
  const auto lock = InterruptRegistry::lock();
  for (int k = 0; k < 1000; ++k) {
    staged = k == 0 ? base + ".partial" : base + "." + std::to_string(k) + ".partial";
    handle = InterruptRegistry::add(staged);
    const int fd =
        ::open(staged.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0666);
    if (fd >= 0) return fd;
    const int error = errno;
    InterruptRegistry::drop(handle);
    if (error != EEXIST) throw Error(shown + ": cannot create: " + std::strerror(error));
  }
  throw Error(shown + ": cannot create: no free staging name beside it");
}

// Writes `size` bytes to a new staged file (createStaged), completely or not at all (removed
// on failure). Returns the registry handle; errors name `shown`.
uint64_t writeStaged(const std::string& base, const std::string& shown, const void* data,
                     size_t size, std::string& staged) {
  uint64_t handle = 0;
  const int fd = createStaged(base, shown, staged, handle);
  const bool written = writeAll(fd, data, size);
  int error = errno;
  const bool closed = ::close(fd) == 0;
  if (written && !closed) error = errno;
  if (!written || !closed) {
    const std::string why = std::strerror(error);
    const auto lock = InterruptRegistry::lock();
    ::unlink(staged.c_str());
    InterruptRegistry::drop(handle);
    throw Error(shown + ": write error: " + why);
  }
  return handle;
}

// Writes to a character device or FIFO in place (opened without O_CREAT or O_TRUNC; refused
// if it has become a regular file since it was looked at).
void writeSpecial(const std::string& path, const void* data, size_t size) {
  const int fd = ::open(path.c_str(), O_WRONLY | O_NOCTTY | O_CLOEXEC);
  if (fd < 0) throw Error(path + ": cannot open: " + systemError());
  struct stat st;
  if (::fstat(fd, &st) != 0 || !(S_ISCHR(st.st_mode) || S_ISFIFO(st.st_mode))) {
    ::close(fd);
    throw Error(path + ": is no longer a device or FIFO; not written");
  }
  const bool ok = writeAll(fd, data, size);
  const std::string why = systemError();
  ::close(fd);
  if (!ok) throw Error(path + ": write error: " + why);
}

}  // namespace

void writeFileAtomic(const std::string& path, const void* data, size_t size) {
  StagedFiles files;
  files.write(path, data, size);
  files.commit();
}

StagedFiles::~StagedFiles() {
  discard();
}

void StagedFiles::discard() {
  if (committed_) return;
  // A failed run: its staged files go (a failed commit has already put everything back).
  const auto lock = InterruptRegistry::lock();
  for (const Entry& e : entries_)
    if (!e.special && !e.renamed) {
      ::unlink(e.staged.c_str());
      InterruptRegistry::drop(e.handle);
    }
  committed_ = true;  // nothing left to do
}

void StagedFiles::checkNew(const std::string& path, const std::string& target) {
  // A second output of one run to the same file would silently replace the first.
  std::error_code ec;
  const std::string normal = fs::absolute(target, ec).lexically_normal().string();
  const auto [it, added] = targets_.emplace(normal, path);
  if (!added)
    throw Error(path + ": is also written as " + it->second +
                " by this run; one output would replace the other");
  // Nor may an output replace a file this run has read, whatever the app listed as inputs.
  struct stat st;
  if (filesReadAreProtected() && ::stat(target.c_str(), &st) == 0 && wasFileRead(st))
    throw Error(path + ": is a file this run read (an input); refusing to overwrite it");
}

void StagedFiles::write(const std::string& path, const void* data, size_t size) {
  const OutputTarget target = resolveOutput(path);
  checkNew(path, target.path);
  entries_.reserve(entries_.size() + 1);  // so that the push_back cannot lose a written file
  Entry e;
  e.shown = path;
  e.target = target.path;
  e.special = target.special;
  if (e.special) {
    const uint8_t* bytes = static_cast<const uint8_t*>(data);
    e.data.assign(bytes, bytes + size);  // written when the run has succeeded
  } else {
    e.handle = writeStaged(target.path, path, data, size, e.staged);
  }
  entries_.push_back(std::move(e));
}

std::string StagedFiles::stage(const std::string& path) {
  const OutputTarget target = resolveOutput(path);
  checkNew(path, target.path);
  check(!target.special, path + ": is a device or FIFO; this output must be a regular file");
  entries_.reserve(entries_.size() + 1);
  Entry e;
  e.shown = path;
  e.target = target.path;
  ::close(createStaged(target.path, path, e.staged, e.handle));
  entries_.push_back(std::move(e));
  return entries_.back().staged;
}

void StagedFiles::rollBack() {
  const auto lock = InterruptRegistry::lock();
  for (auto it = entries_.rbegin(); it != entries_.rend(); ++it) {
    Entry& e = *it;
    if (e.renamed) {
      if (!e.backup.empty()) {
        // The previous run's file comes back under its name, replacing this run's.
        std::rename(e.backup.c_str(), e.target.c_str());
        InterruptRegistry::drop(e.backupHandle);
      } else {
        ::unlink(e.target.c_str());
        InterruptRegistry::drop(e.finalHandle);
      }
    } else if (!e.backup.empty()) {
      ::unlink(e.backup.c_str());  // a second link: the previous file is still in place
      InterruptRegistry::drop(e.backupHandle);
    }
    e.backup.clear();
  }
}

void StagedFiles::takeBack() {
  rollBack();
}

void StagedFiles::putInPlace() {
  try {
    for (Entry& e : entries_) {
      if (e.special) continue;
      const auto lock = InterruptRegistry::lock();
      struct stat st;
      if (::lstat(e.target.c_str(), &st) == 0 && S_ISREG(st.st_mode)) {
        // Keep the previous file (a second link to it) until every output is in place; an
        // interruption from here on puts it back.
        for (int k = 0;; ++k) {
          check(k < 1000, e.shown + ": cannot keep the previous file: no free backup name");
          const std::string backup = e.target + "." + std::to_string(k) + ".previous";
          e.backupHandle = InterruptRegistry::addRestore(backup, e.target);
          if (::link(e.target.c_str(), backup.c_str()) == 0) {
            e.backup = backup;
            break;
          }
          const int error = errno;
          InterruptRegistry::drop(e.backupHandle);
          if (error != EEXIST)
            throw Error(e.shown + ": cannot keep the previous file while replacing it: " +
                        std::strerror(error));
        }
      }
      // A new file is removed on interruption until the commit is done.
      if (e.backup.empty()) e.finalHandle = InterruptRegistry::add(e.target);
      if (std::rename(e.staged.c_str(), e.target.c_str()) != 0) {
        const std::string why = systemError();
        if (e.backup.empty()) InterruptRegistry::drop(e.finalHandle);
        throw Error(e.shown + ": cannot rename staged output into place: " + why);
      }
      InterruptRegistry::drop(e.handle);
      e.renamed = true;
    }
    for (const Entry& e : entries_)
      if (e.special) writeSpecial(e.target, e.data.data(), e.data.size());
  } catch (...) {
    rollBack();
    throw;
  }
}

void StagedFiles::keepNew() {
  for (Entry& e : entries_) {
    if (!e.renamed) continue;
    InterruptRegistry::drop(e.backup.empty() ? e.finalHandle : e.backupHandle);
  }
  committed_ = true;
}

void StagedFiles::removePrevious() {
  for (Entry& e : entries_)
    if (e.renamed && !e.backup.empty() && ::unlink(e.backup.c_str()) != 0)
      warn(e.shown + ": the previous file's backup " + e.backup + " could not be removed (" +
           systemError() + ")");
}

void InputFiles::add(const std::string& path) {
  struct stat st;
  if (!path.empty() && ::stat(path.c_str(), &st) == 0)
    files_.emplace(std::pair{st.st_dev, st.st_ino}, path);
}

void InputFiles::addPattern(const std::string& pattern, int firstNumber, int count,
                            const std::string& role) {
  if (pattern.empty() || count <= 0) return;
  std::error_code ec;
  const fs::path resolved = fs::weakly_canonical(fs::absolute(pattern, ec), ec);
  patterns_.push_back({pattern,
                       ec ? fs::absolute(pattern).lexically_normal().string() : resolved.string(),
                       firstNumber, count, role});
}

void InputFiles::checkOutput(const std::string& output) const {
  if (output.empty()) return;
  struct stat st;
  if (::stat(output.c_str(), &st) == 0) {
    const auto it = files_.find({st.st_dev, st.st_ino});
    if (it != files_.end())
      throw Error(output + ": is the input " + it->second +
                  " (the same file); refusing to overwrite it");
  }
  if (patterns_.empty()) return;
  std::error_code ec;
  const fs::path absolute = fs::absolute(output, ec);
  if (ec) return;
  const fs::path resolved = fs::weakly_canonical(absolute, ec);
  const std::string path = ec ? absolute.lexically_normal().string() : resolved.string();
  for (const Pattern& p : patterns_) {
    const std::optional<int> frame = frameOfPath(p.resolved, path);
    if (frame && *frame >= p.first && *frame - p.first < p.count)
      throw Error(output + ": is " + p.role + " " + framePath(p.given, *frame) + " (frame " +
                  std::to_string(*frame) + " of " + p.given + "); refusing to overwrite it");
  }
}

namespace {

// True when `path` (links followed) is the folder with identity `folder` or lies inside it.
bool isInside(const std::string& path, const struct stat& folder) {
  if (path.empty()) return false;
  std::error_code ec;
  fs::path p = fs::weakly_canonical(fs::absolute(path, ec), ec);
  if (ec) return false;
  for (;;) {
    struct stat st;
    if (::stat(p.c_str(), &st) == 0 && st.st_dev == folder.st_dev && st.st_ino == folder.st_ino)
      return true;
    if (p == p.parent_path() || p.empty()) return false;
    p = p.parent_path();
  }
}

}  // namespace

OutputFolder::OutputFolder(const std::string& folder, bool overwrite,
                           const std::vector<std::string>& inputs) {
  check(!folder.empty(), "no output folder given");
  folder_ = folder;
  while (folder_.size() > 1 && folder_.back() == '/')
    folder_.pop_back();
  struct stat st;
  if (::stat(folder_.c_str(), &st) == 0) {
    check(S_ISDIR(st.st_mode), folder_ + ": exists and is not a folder");
    std::error_code ec;
    fs::directory_iterator it(folder_, ec);
    if (ec) throw Error(folder_ + ": cannot list the output folder: " + ec.message());
    for (fs::directory_iterator end; it != end; it.increment(ec))
      previous_.push_back(it->path().filename().string());
    if (ec) throw Error(folder_ + ": cannot list the output folder: " + ec.message());
    if (!previous_.empty()) {
      check(overwrite, folder_ + ": the output folder is not empty (it holds " + previous_.front() +
                           "); give --Overwrite to replace its contents");
      for (const std::string& input : inputs)
        check(!isInside(input, st), folder_ + ": --Overwrite would delete the input " + input +
                                        ", which is inside this output folder");
    }
  } else {
    // Missing folders are made outermost first and removed again if the run fails.
    std::vector<fs::path> missing;
    for (fs::path p = fs::path(folder_); !p.empty(); p = p.parent_path()) {
      struct stat ls;
      if (::lstat(p.c_str(), &ls) == 0) break;
      missing.push_back(p);
      if (p == p.parent_path()) break;
    }
    // "q/../x" with q missing would make q, a folder outside the output folder, and leave it.
    for (const fs::path& p : missing)
      check(p.filename() != "..", folder_ + ": goes through " + p.parent_path().string() +
                                      ", which does not exist, and back out ('..')");
    for (auto it = missing.rbegin(); it != missing.rend(); ++it) {
      const auto lock = InterruptRegistry::lock();
      const uint64_t handle = InterruptRegistry::add(it->string());
      if (::mkdir(it->c_str(), 0777) != 0) {
        const int error = errno;
        InterruptRegistry::drop(handle);
        if (error == EEXIST) continue;  // made by someone else meanwhile: not ours to remove
        // Undo the folders made so far (the destructor does not run for a throwing constructor).
        for (auto made = created_.rbegin(); made != created_.rend(); ++made) {
          ::rmdir(made->first.c_str());
          InterruptRegistry::drop(made->second);
        }
        throw Error(folder_ + ": cannot create folder: " + std::strerror(error));
      }
      created_.emplace_back(it->string(), handle);
    }
  }
  const auto lock = InterruptRegistry::lock();
  for (int k = 0;; ++k) {
    staging_ = folder_ + "/.3dvo-staging-" + std::to_string(::getpid()) + "-" + std::to_string(k) +
               ".partial";
    stagingHandle_ = InterruptRegistry::addTree(staging_);
    if (::mkdir(staging_.c_str(), 0700) == 0) break;
    const int error = errno;
    InterruptRegistry::drop(stagingHandle_);
    if (error != EEXIST || k >= 1000) {
      for (auto made = created_.rbegin(); made != created_.rend(); ++made) {
        ::rmdir(made->first.c_str());
        InterruptRegistry::drop(made->second);
      }
      throw Error(folder_ + ": cannot create a staging folder in it: " + std::strerror(error));
    }
  }
}

OutputFolder::~OutputFolder() {
  discard();
}

void OutputFolder::discard() {
  if (committed_) return;
  const auto lock = InterruptRegistry::lock();
  std::error_code ec;
  fs::remove_all(staging_, ec);
  InterruptRegistry::drop(stagingHandle_);
  for (auto made = created_.rbegin(); made != created_.rend(); ++made) {
    ::rmdir(made->first.c_str());
    InterruptRegistry::drop(made->second);
  }
  committed_ = true;  // nothing left to do
}

void OutputFolder::write(const std::string& path, const void* data, size_t size) {
  const fs::path relative =
      fs::path(path).lexically_normal().lexically_relative(fs::path(folder_).lexically_normal());
  check(!relative.empty() && relative != "." && *relative.begin() != "..",
        path + ": is not inside the output folder " + folder_);
  const fs::path staged = fs::path(staging_) / relative;
  int fd;
  {
    const auto lock = InterruptRegistry::lock();
    std::error_code ec;
    fs::create_directories(staged.parent_path(), ec);
    if (ec) throw Error(path + ": cannot create folder: " + ec.message());
    fd = ::open(staged.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0666);
    // The staging folder is this run's own: a file already in it was written by this run.
    if (fd < 0 && errno == EEXIST)
      throw Error(path + ": is written twice by this run (two of its outputs name this file)");
    if (fd < 0) throw Error(path + ": cannot create: " + systemError());
  }
  const bool written = writeAll(fd, data, size);
  int error = errno;
  const bool closed = ::close(fd) == 0;
  if (written && !closed) error = errno;
  if (!written || !closed) throw Error(path + ": write error: " + std::strerror(error));
}

void OutputFolder::putInPlace() {
  const auto lock = InterruptRegistry::lock();
  const std::string stagingName = fs::path(staging_).filename().string();
  // What goes aside: the entries the folder held when the run started (an entry made during
  // the run by someone else, or by this run outside the staging folder, stays) and any other
  // entry in the way of a new one.
  std::vector<std::string> previous, fresh;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(staging_, ec))
    fresh.push_back(entry.path().filename());
  if (ec) throw Error(folder_ + ": cannot list the staged output: " + ec.message());
  for (const std::string& name : previous_) {
    struct stat st;
    if (::lstat((folder_ + "/" + name).c_str(), &st) == 0) previous.push_back(name);
  }
  for (const std::string& name : fresh) {
    struct stat st;
    if (std::find(previous_.begin(), previous_.end(), name) == previous_.end() &&
        ::lstat((folder_ + "/" + name).c_str(), &st) == 0)
      previous.push_back(name);
  }
  // Nothing this run read goes: a file read (noteFileRead) inside what would be replaced stops
  // the commit, the folder as it was. Links are not followed (removing a link removes no data).
  for (const std::string& name : filesReadAreProtected() ? previous : std::vector<std::string>()) {
    const fs::path top = fs::path(folder_) / name;
    auto refuse = [&](const fs::path& file) {
      throw Error(folder_ + ": --Overwrite would delete " + file.string() +
                  ", a file this run read; the folder is as it was");
    };
    struct stat st;
    if (::lstat(top.c_str(), &st) != 0) continue;
    if (wasFileRead(st)) refuse(top);
    if (!S_ISDIR(st.st_mode)) continue;
    for (fs::recursive_directory_iterator it(top, ec), end; !ec && it != end; it.increment(ec))
      if (::lstat(it->path().c_str(), &st) == 0 && wasFileRead(st)) refuse(it->path());
    ec.clear();  // what cannot be listed cannot be removed either
  }
  // The previous contents go aside first (into a hidden folder inside this one), then the new
  // entries come in; any failure moves everything back.
  std::string aside, failure;
  size_t movedPrevious = 0, movedFresh = 0;
  if (!previous.empty()) {
    for (int k = 0; failure.empty(); ++k) {
      aside = folder_ + "/.3dvo-previous-" + std::to_string(::getpid()) + "-" + std::to_string(k);
      if (::mkdir(aside.c_str(), 0700) == 0) break;
      if (errno != EEXIST || k >= 1000) failure = aside + ": " + systemError();
    }
    for (; failure.empty() && movedPrevious < previous.size(); ++movedPrevious) {
      const std::string& name = previous[movedPrevious];
      if (std::rename((folder_ + "/" + name).c_str(), (aside + "/" + name).c_str()) != 0)
        failure = folder_ + "/" + name + ": " + systemError();
    }
    if (!failure.empty() && movedPrevious > 0) --movedPrevious;  // the one that failed
  }
  for (; failure.empty() && movedFresh < fresh.size(); ++movedFresh) {
    const std::string& name = fresh[movedFresh];
    if (std::rename((staging_ + "/" + name).c_str(), (folder_ + "/" + name).c_str()) != 0) {
      failure = folder_ + "/" + name + ": " + systemError();
      break;
    }
  }
  if (!failure.empty()) {
    while (movedFresh > 0) {
      const std::string& name = fresh[--movedFresh];
      std::rename((folder_ + "/" + name).c_str(), (staging_ + "/" + name).c_str());
    }
    while (movedPrevious > 0) {
      const std::string& name = previous[--movedPrevious];
      std::rename((aside + "/" + name).c_str(), (folder_ + "/" + name).c_str());
    }
    if (!aside.empty()) ::rmdir(aside.c_str());
    throw Error(folder_ + ": cannot move the output into place (" + failure +
                "); the folder is as it was");
  }
  // In place, the previous entries kept aside until removePrevious (commitAll: the run's other
  // outputs may still fail). An interruption from here on takes the commit back: the cleanup
  // runs newest first, so the new entries go, then the previous ones come back, then the
  // (empty) aside folder goes.
  aside_ = aside;
  movedAside_ = previous;
  movedIn_ = fresh;
  if (!aside_.empty()) undoHandles_.push_back(InterruptRegistry::add(aside_));
  for (const std::string& name : movedAside_)
    undoHandles_.push_back(
        InterruptRegistry::addRestore(aside_ + "/" + name, folder_ + "/" + name));
  for (const std::string& name : movedIn_)
    undoHandles_.push_back(InterruptRegistry::addTree(folder_ + "/" + name));
}

void OutputFolder::takeBack() {
  const auto lock = InterruptRegistry::lock();
  // The new entries back into the staging folder (which the destructor removes), the previous
  // ones back in place.
  for (auto name = movedIn_.rbegin(); name != movedIn_.rend(); ++name)
    std::rename((folder_ + "/" + *name).c_str(), (staging_ + "/" + *name).c_str());
  for (auto name = movedAside_.rbegin(); name != movedAside_.rend(); ++name)
    std::rename((aside_ + "/" + *name).c_str(), (folder_ + "/" + *name).c_str());
  if (!aside_.empty()) ::rmdir(aside_.c_str());
  for (const uint64_t handle : undoHandles_)
    InterruptRegistry::drop(handle);
  undoHandles_.clear();
  aside_.clear();
  movedAside_.clear();
  movedIn_.clear();
}

void OutputFolder::keepNew() {
  ::rmdir(staging_.c_str());  // empty: every entry was moved in
  for (const uint64_t handle : undoHandles_)
    InterruptRegistry::drop(handle);
  undoHandles_.clear();
  InterruptRegistry::drop(stagingHandle_);
  for (const auto& made : created_)
    InterruptRegistry::drop(made.second);
  committed_ = true;
}

void OutputFolder::removePrevious() {
  if (aside_.empty()) return;
  std::error_code ec;
  fs::remove_all(aside_, ec);
  if (ec)
    warn(folder_ + ": the previous contents, set aside in " + aside_ +
         ", could not all be removed (" + ec.message() + ")");
}

void CommittableOutput::commit() {
  commitAll({this});
}

void commitAll(const std::vector<CommittableOutput*>& outputs) {
  size_t done = 0;
  try {
    for (; done < outputs.size(); ++done)
      outputs[done]->putInPlace();
  } catch (...) {
    while (done > 0)
      outputs[--done]->takeBack();
    for (auto output = outputs.rbegin(); output != outputs.rend(); ++output)
      (*output)->discard();
    throw;
  }
  {
    // All at once: an interruption either takes every output back or none.
    const auto lock = InterruptRegistry::lock();
    for (CommittableOutput* output : outputs)
      output->keepNew();
  }
  for (CommittableOutput* output : outputs)
    output->removePrevious();
}

void makeDirectories(const std::string& path) {
  if (path.empty()) return;
  std::error_code ec;
  std::filesystem::create_directories(path, ec);
  if (ec) throw Error(path + ": cannot create folder: " + ec.message());
}

}  // namespace tdvo
