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
  if (once.depth > 0 && !once.said.insert(message).second) return;
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
