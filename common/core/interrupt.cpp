#include "common/core/interrupt.h"

#include <pthread.h>
#include <signal.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <thread>

namespace tdvo {

namespace {

std::mutex gMutex;
// What the cleanup does with one registered path.
struct Entry {
  std::string path;
  std::string backup;  // non-empty: rename backup to path (restore) instead of removing path
  bool tree = false;   // remove a folder with everything in it
};

std::map<uint64_t, Entry> gPaths;  // handle -> entry; handles grow with time
uint64_t gNextHandle = 0;

sigset_t interruptSignals() {
  sigset_t set;
  sigemptyset(&set);
  sigaddset(&set, SIGINT);
  sigaddset(&set, SIGTERM);
  sigaddset(&set, SIGHUP);
  return set;
}

[[noreturn]] void cleanupThread(sigset_t set) {
  int signal = 0;
  while (sigwait(&set, &signal) != 0) {
  }
  // Held until the process is gone, so no registered file can be created after the removal.
  gMutex.lock();
  // Newest first: files before the folders they may be in, a commit's last steps first.
  for (auto it = gPaths.rbegin(); it != gPaths.rend(); ++it) {
    const Entry& e = it->second;
    std::error_code ec;
    if (!e.backup.empty())
      std::rename(e.backup.c_str(), e.path.c_str());
    else if (e.tree)
      std::filesystem::remove_all(e.path, ec);
    else
      std::remove(e.path.c_str());
  }
  // Die of the signal itself: default action, unblocked in this thread, raised at it.
  struct sigaction action = {};
  action.sa_handler = SIG_DFL;
  sigemptyset(&action.sa_mask);
  sigaction(signal, &action, nullptr);
  sigset_t one;
  sigemptyset(&one);
  sigaddset(&one, signal);
  pthread_sigmask(SIG_UNBLOCK, &one, nullptr);
  raise(signal);
  // Not reached for the three signals (their default action ends the process).
  std::_Exit(128 + signal);
}

}  // namespace

void installInterruptCleanup() {
  static std::once_flag once;
  std::call_once(once, [] {
    const sigset_t set = interruptSignals();
    pthread_sigmask(SIG_BLOCK, &set, nullptr);
    std::thread(cleanupThread, set).detach();
  });
}

std::unique_lock<std::mutex> InterruptRegistry::lock() {
  return std::unique_lock<std::mutex>(gMutex);
}

uint64_t InterruptRegistry::add(const std::string& path) {
  gPaths.emplace(gNextHandle, Entry{path, "", false});
  return gNextHandle++;
}

uint64_t InterruptRegistry::addTree(const std::string& path) {
  gPaths.emplace(gNextHandle, Entry{path, "", true});
  return gNextHandle++;
}

uint64_t InterruptRegistry::addRestore(const std::string& backup, const std::string& path) {
  gPaths.emplace(gNextHandle, Entry{path, backup, false});
  return gNextHandle++;
}

void InterruptRegistry::drop(uint64_t handle) {
  gPaths.erase(handle);
}

size_t InterruptRegistry::size() {
  const std::unique_lock<std::mutex> held = lock();
  return gPaths.size();
}

}  // namespace tdvo
