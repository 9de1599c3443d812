#include "common/core/warnings.h"

#include <algorithm>
#include <cstdio>
#include <map>
#include <mutex>
#include <set>
#include <string>
#include <utility>
#include <vector>

namespace tdvo {

namespace {

std::mutex& warningMutex() {
  static std::mutex mutex;
  return mutex;
}

WarningHandler& handler() {
  static WarningHandler h;
  return h;
}

// The open WarnOnceScopes and what was said during the outermost one.
struct OnceState {
  int depth = 0;
  int silenced = 0;  // open SilenceWarningsScopes
  std::set<std::string> said;
  // warnForFile kinds said during the outermost scope -> (the order they were first said in,
  // the number of files' messages not said).
  std::map<std::string, std::pair<size_t, size_t>> kinds;
};

// At most this many distinct messages and kinds are remembered: past them, messages are said
// every time, so a long run's distinct warnings cannot grow the memory without bound.
constexpr size_t kRemembered = 1 << 16;

void sayNow(const std::string& message) {
  if (handler())
    handler()(message);
  else
    std::fprintf(stderr, "warning: %s\n", message.c_str());
}

OnceState& onceState() {
  static OnceState state;
  return state;
}

}  // namespace

WarningHandler setWarningHandler(WarningHandler h) {
  std::lock_guard<std::mutex> lock(warningMutex());
  return std::exchange(handler(), std::move(h));
}

namespace {
thread_local WarningHold* tHold = nullptr;  // this thread's innermost WarningHold
}  // namespace

// True when this thread's innermost WarningHold kept the warning (kind null: warn()'s).
bool holdWarning(const std::string* kind, const std::string& message) {
  if (!tHold) return false;
  {
    std::lock_guard<std::mutex> lock(warningMutex());
    if (onceState().silenced > 0) return true;  // dropped, as warn() would
  }
  tHold->held_.push_back({kind ? *kind : std::string(), message, kind != nullptr});
  return true;
}

WarningHold::WarningHold() : outer_(tHold) {
  tHold = this;
}

WarningHold::~WarningHold() {
  tHold = outer_;
}

std::vector<HeldWarning> WarningHold::release() {
  return std::exchange(held_, {});
}

void say(const std::vector<HeldWarning>& warnings) {
  for (const HeldWarning& w : warnings)
    if (!w.forFile)
      warn(w.message);
    else
      warnForFile(w.kind, w.message);
}

void warn(const std::string& message) {
  if (holdWarning(nullptr, message)) return;
  std::lock_guard<std::mutex> lock(warningMutex());
  OnceState& once = onceState();
  if (once.silenced > 0) return;
  if (once.depth > 0 && once.said.count(message)) return;
  if (once.depth > 0 && once.said.size() < kRemembered) once.said.insert(message);
  sayNow(message);
}

void warnForFile(const std::string& kind, const std::string& message) {
  if (holdWarning(&kind, message)) return;
  std::lock_guard<std::mutex> lock(warningMutex());
  OnceState& once = onceState();
  if (once.silenced > 0) return;
  if (once.depth > 0) {
    // The same file again (read more than once): nothing new. (Past kRemembered messages a
    // file read twice counts twice; 3dvo-enc's coding pass does not warn again,
    // encodeSequence.)
    if (once.said.count(message)) return;
    if (once.said.size() < kRemembered) once.said.insert(message);
    auto it = once.kinds.find(kind);
    if (it != once.kinds.end()) {
      ++it->second.second;
      return;
    }
    if (once.kinds.size() < kRemembered)
      once.kinds.emplace(kind, std::pair<size_t, size_t>{once.kinds.size(), 0});
  }
  sayNow(message);
}

WarnOnceScope::WarnOnceScope() {
  std::lock_guard<std::mutex> lock(warningMutex());
  ++onceState().depth;
}

WarnOnceScope::~WarnOnceScope() {
  std::lock_guard<std::mutex> lock(warningMutex());
  OnceState& once = onceState();
  if (--once.depth > 0) return;
  once.said.clear();
  std::map<std::string, std::pair<size_t, size_t>> kinds;
  kinds.swap(once.kinds);
  if (once.silenced > 0) return;
  // In the order the kinds were first said.
  std::vector<std::pair<size_t, std::string>> order;  // (first said, the line)
  for (const auto& [kind, at] : kinds)
    if (at.second > 0)
      order.emplace_back(at.first, kind + ": the same in " + std::to_string(at.second) +
                                       " more file" + (at.second == 1 ? "" : "s") + " or frame" +
                                       (at.second == 1 ? "" : "s"));
  std::sort(order.begin(), order.end());
  for (const auto& [first, line] : order) {
    try {
      sayNow(line);
    } catch (...) {
      // A handler that throws cannot be answered from a destructor; the rest is not said.
      return;
    }
  }
}

SilenceWarningsScope::SilenceWarningsScope() {
  std::lock_guard<std::mutex> lock(warningMutex());
  ++onceState().silenced;
}

SilenceWarningsScope::~SilenceWarningsScope() {
  std::lock_guard<std::mutex> lock(warningMutex());
  --onceState().silenced;
}

}  // namespace tdvo
