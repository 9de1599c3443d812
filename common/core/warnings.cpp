#include "common/core/warnings.h"

#include <cstdio>
#include <mutex>
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

}  // namespace

WarningHandler setWarningHandler(WarningHandler h) {
  std::lock_guard<std::mutex> lock(warningMutex());
  return std::exchange(handler(), std::move(h));
}

void warn(const std::string& message) {
  std::lock_guard<std::mutex> lock(warningMutex());
  if (handler())
    handler()(message);
  else
    std::fprintf(stderr, "warning: %s\n", message.c_str());
}

}  // namespace tdvo
