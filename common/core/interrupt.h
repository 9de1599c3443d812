// Removal of a run's unfinished output when it is interrupted by SIGINT, SIGTERM or SIGHUP.
//
// Output files are written under temporary names and renamed when the run has succeeded
// (file_io.h). A failed run removes them as its exceptions unwind; an interrupted one does not
// unwind, so the names of every output file that exists but is not final yet are kept in a
// registry, and on one of those signals a cleanup removes them all and the process then dies of
// the signal as it would have without the cleanup (exit status 128 + signal number in a shell).
//
// The cleanup does not run in a signal handler: installInterruptCleanup() blocks the three
// signals in the calling thread (and so in every thread created after it) and starts a thread
// that waits for them with sigwait(), so the cleanup is ordinary code that may take the
// registry's mutex. It removes the files while holding that mutex and ends the process before
// releasing it, so a file being created under the mutex is either seen by the cleanup or never
// created. SIGKILL cannot be caught: after `kill -9` staged files may remain, but still never
// under a final name.
#pragma once

#include <cstdint>
#include <mutex>
#include <string>

namespace tdvo {

// Starts the cleanup thread; call it first thing in main, before any other thread exists
// (runApp does). Later calls do nothing.
void installInterruptCleanup();

// The registry. Hold the lock while creating, renaming or removing a registered file, and
// register a path before the file is created: the cleanup then never misses a file.
class InterruptRegistry {
 public:
  static std::unique_lock<std::mutex> lock();
  // Adds a path to remove on interruption (a file, or an empty folder); returns its handle.
  // The lock must be held.
  static uint64_t add(const std::string& path);
  // Adds a folder to remove with everything in it on interruption (a staging folder).
  static uint64_t addTree(const std::string& path);
  // Adds a backup to put back on interruption: `backup` is renamed to `path` (a commit under
  // way restores the previous run's file it replaced).
  static uint64_t addRestore(const std::string& backup, const std::string& path);
  // Removes a path from the registry (the file was renamed into place, or removed).
  // The lock must be held.
  static void drop(uint64_t handle);
  // Number of registered paths (for tests).
  static size_t size();
};

}  // namespace tdvo
