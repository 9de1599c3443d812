#include "common/core/warnings.h"

#include <cstdio>
#include <mutex>
#include <set>
#include <string>
#include <utility>

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
};

OnceState& onceState() {
  static OnceState state;
  return state;
}

}  // namespace

WarningHandler setWarningHandler(WarningHandler h) {
  std::lock_guard<std::mutex> lock(warningMutex());
  return std::exchange(handler(), std::move(h));
}

void warn(const std::string& message) {
  std::lock_guard<std::mutex> lock(warningMutex());
  OnceState& once = onceState();
  if (once.silenced > 0) return;
  // (At most kRemembered messages are remembered: past them, messages are said every time, so
  // a long run's distinct warnings cannot grow this set without bound.)
  constexpr size_t kRemembered = 1 << 16;
  if (once.depth > 0 && once.said.count(message)) return;
  if (once.depth > 0 && once.said.size() < kRemembered) once.said.insert(message);
  if (handler())
    handler()(message);
  else
    std::fprintf(stderr, "warning: %s\n", message.c_str());
}

WarnOnceScope::WarnOnceScope() {
  std::lock_guard<std::mutex> lock(warningMutex());
  ++onceState().depth;
}

WarnOnceScope::~WarnOnceScope() {
  std::lock_guard<std::mutex> lock(warningMutex());
  OnceState& once = onceState();
  if (--once.depth == 0) once.said.clear();
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
