// Whole-file reading and atomic writing.
#pragma once

#include <sys/stat.h>
#include <sys/types.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <functional>
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace tdvo {

// Size limits of the files read whole (docs/robustness.md, "Input files"): a file above its
// limit (or a device such as /dev/zero that never ends) is refused with an error naming it,
// after reading at most the limit.
constexpr uint64_t kMaxCfgFileBytes = uint64_t{1} << 20;     // cfg files, GOM lists
constexpr uint64_t kMaxTextFileBytes = uint64_t{1} << 24;    // dataset.json, calibration, paths
constexpr uint64_t kMaxBinaryFileBytes = uint64_t{1} << 30;  // images, texture files

// The files this process has read, by identity (device, inode and modification time, so that a
// later file given a deleted one's inode is another file): every reader of 3DVO notes the file
// it opens. In the apps (runApp, app.h, turns it on) OutputFolder::commit() then refuses to
// delete one and StagedFiles (every output file) to replace one, whichever app read it and
// whether or not the app listed it among its inputs (docs/robustness.md, "No data lost"). A
// program using the library, which may mean to rewrite what it read, decides for itself.
void noteFileRead(std::FILE* file);
void noteFileRead(const std::string& path);  // for files a library opens by name (FFmpeg)
// Whether `st` (a stat result) is a file this process has read.
bool wasFileRead(const struct stat& st);
// Turns the protection of the files read on or off (off by default); returns the old setting.
bool protectFilesRead(bool on);
bool filesReadAreProtected();

// Reads a whole file into memory. Throws Error naming the file when it cannot be opened or read,
// or when it holds more than `maxBytes` bytes (`what` names the kind of file in that message:
// "x.cfg: more than 1048576 bytes: too large for a cfg file").
std::vector<uint8_t> readFileBytes(const std::string& path, uint64_t maxBytes = kMaxBinaryFileBytes,
                                   const char* what = "an input file");

// Reads a whole text file as readFileBytes does, without a UTF-8 byte-order mark at its start
// (text_tokens.h, withoutUtf8Bom): cfg files, GOM lists, calibration files.
std::string readTextFile(const std::string& path, uint64_t maxBytes, const char* what);

// Reads a file chunk by chunk, decompressing it when it is gzip-compressed (through zlib), and
// hands each chunk (at most 64 KiB) to `consume`: memory does not grow with the file.
void readFileMaybeGzChunks(const std::string& path,
                           const std::function<void(const char* data, size_t size)>& consume);

// Reads a whole file, decompressing it when it is gzip-compressed; at most `maxBytes` bytes
// after decompression (Error beyond that).
std::string readFileMaybeGz(const std::string& path, uint64_t maxBytes = kMaxBinaryFileBytes);

// What every output file promises (docs/robustness.md, "No data lost"):
// - it is written under a fresh staged name beside its final name ("<name>.partial", or
//   "<name>.<k>.partial" when that exists), created exclusively and never through a symbolic
//   link (O_EXCL | O_NOFOLLOW), and renamed into place when the run has succeeded;
// - an output named through a symbolic link replaces the link's target, not the link;
// - a character device (/dev/null) or FIFO is written to in place, never replaced; a folder,
//   block device or socket is refused;
// - a run that fails, also while committing, leaves the previous run's files as they were.

// The outputs of one run that are put in place together (commitAll): each puts its new files
// in place while keeping the previous ones (putInPlace); when every output is in place, all
// of them forget how to undo that at once, under the interrupt registry's lock (keepNew), and
// then remove what they replaced (removePrevious). A later output that fails takes the
// earlier ones back (takeBack), and every output then removes what it staged (discard, as its
// destructor would; in reverse order, so that a file staged inside a folder another output
// created goes before that folder). An interruption before keepNew takes them all back.
class CommittableOutput {
 public:
  virtual ~CommittableOutput() = default;
  virtual void putInPlace() = 0;      // Error on failure, with this output as it was
  virtual void takeBack() = 0;        // after putInPlace: the previous files back in place
  virtual void keepNew() = 0;         // after putInPlace, the registry's lock held by the caller
  virtual void removePrevious() = 0;  // after keepNew: the previous files removed
  virtual void discard() = 0;         // not in place: the staged files removed (idempotent)
  void commit();                      // this output alone: commitAll({this})
};

// Commits `outputs` as one: every one in place, or (an Error) none, each as it was. A run with
// several outputs (3dvo-render's folder and --Mp4) commits them with this, never one by one.
void commitAll(const std::vector<CommittableOutput*>& outputs);

// Writes `size` bytes to `path` atomically (a StagedFiles of one file).
void writeFileAtomic(const std::string& path, const void* data, size_t size);
inline void writeFileAtomic(const std::string& path, const std::string& text) {
  writeFileAtomic(path, text.data(), text.size());
}

// Output files of one run, staged (see above) and put in place together by commit(). If the
// run fails before commit(), the destructor removes the staged files. If commit() fails
// halfway, it undoes what it did: files it renamed into place are removed, and a previous file
// it replaced is restored from the backup it kept (a second hard link) until every file was in
// place. An interrupted run does the same (interrupt.h: every staged file, new final file and
// backup is in the interrupt registry while the commit is under way).
class StagedFiles : public CommittableOutput {
 public:
  StagedFiles() = default;
  StagedFiles(const StagedFiles&) = delete;
  StagedFiles& operator=(const StagedFiles&) = delete;
  ~StagedFiles();
  void write(const std::string& path, const void* data, size_t size);
  void write(const std::string& path, const std::string& text) {
    write(path, text.data(), text.size());
  }
  // Stages an empty regular file for `path` (created exclusively, as above) and returns its
  // name, for a writer that opens files by name (FFmpeg): the caller fills and closes it before
  // commit(). A device or FIFO is refused here (such a writer seeks).
  std::string stage(const std::string& path);
  void putInPlace() override;
  void takeBack() override;
  void keepNew() override;
  void removePrevious() override;
  void discard() override;

 private:
  struct Entry {
    std::string shown;          // the name the caller gave
    std::string target;         // the file written: `shown` with symbolic links followed
    std::string staged;         // the staged file
    std::string backup;         // the previous file's backup while committing
    std::vector<uint8_t> data;  // a special file's bytes, written by commit()
    uint64_t handle = 0;        // the staged file in the interrupt registry
    uint64_t backupHandle = 0;  // the backup's restore in the registry
    uint64_t finalHandle = 0;   // a new final file's removal in the registry
    bool special = false;       // a character device or FIFO
    bool renamed = false;       // commit() has moved it to its final name
  };
  void rollBack();
  void checkNew(const std::string& path, const std::string& target);
  std::vector<Entry> entries_;
  std::map<std::string, std::string> targets_;  // written file (absolute) -> name given
  bool committed_ = false;
};

// A run's input files by identity (device and inode, links followed), so that an output
// naming one of them, under any spelling or through any link, is refused before anything is
// written: "OUTPUT: is the input INPUT (the same file); refusing to overwrite it".
// A frame-numbered sequence (a pattern with frames firstNumber .. firstNumber + count - 1) is
// added as its pattern: an output is refused when its path, links resolved, is the path of one
// of those frames, whether that file exists or not, at a cost that does not grow with count.
class InputFiles {
 public:
  void add(const std::string& path);  // a missing file (or an empty name) is ignored
  // `role` names what the files are in the message ("the input", "this run's output").
  void addPattern(const std::string& pattern, int firstNumber, int count,
                  const std::string& role = "the input");
  void checkOutput(const std::string& output) const;

 private:
  struct Pattern {
    std::string given, resolved;  // as given; absolute, with the links of its folders resolved
    int64_t first, count;
    std::string role;
  };
  std::map<std::pair<dev_t, ino_t>, std::string> files_;
  std::vector<Pattern> patterns_;
};

// An app's output folder (docs/user-guide.md, "Output folders"). The constructor refuses a
// folder that is not empty unless `overwrite` is set, refuses to replace a folder that holds
// one of `inputs`, creates the folder if missing and a hidden staging folder inside it. Files
// are written into the staging folder (write() takes their final path inside the folder;
// subfolders are made as needed); commit() moves the previous contents aside, moves the staged
// entries into place and then removes the previous contents, so that the folder holds exactly
// this run's output; a failure puts everything back. A run that fails or is interrupted
// before commit() leaves the folder as it was (removed again if this run created it, with any
// parents it created).
class OutputFolder : public CommittableOutput {
 public:
  OutputFolder(const std::string& folder, bool overwrite,
               const std::vector<std::string>& inputs = {});
  OutputFolder(const OutputFolder&) = delete;
  OutputFolder& operator=(const OutputFolder&) = delete;
  ~OutputFolder();
  // `path` is a file inside the folder (e.g. folder + "/cam0/0000.png").
  void write(const std::string& path, const void* data, size_t size);
  void write(const std::string& path, const std::string& text) {
    write(path, text.data(), text.size());
  }
  void putInPlace() override;
  void takeBack() override;
  void keepNew() override;
  void removePrevious() override;
  void discard() override;
  const std::string& folder() const { return folder_; }

 private:
  std::string folder_, staging_;
  std::vector<std::string> previous_;  // the folder's entries when the run started
  uint64_t stagingHandle_ = 0;
  std::vector<std::pair<std::string, uint64_t>> created_;  // folders made, outermost first
  // Between putInPlace and keepNew: the previous entries moved aside into `aside_`, the new
  // ones in place, and the interrupt registry's handles that would undo that.
  std::string aside_;
  std::vector<std::string> movedAside_, movedIn_;
  std::vector<uint64_t> undoHandles_;
  bool committed_ = false;
};

// Creates a folder and its parents when missing. Throws Error on failure.
void makeDirectories(const std::string& path);

}  // namespace tdvo
