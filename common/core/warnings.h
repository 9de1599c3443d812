// Warnings: what a reader or coder leaves out or changes of its input is said, never done
// silently. The library calls warn(); the handler decides where it goes: by default a line
// "warning: <message>" on stderr; the apps prefix their name (common/core/app.h), and a program
// may collect or silence them (setWarningHandler).
#pragma once

#include <functional>
#include <string>

namespace tdvo {

using WarningHandler = std::function<void(const std::string& message)>;

// Replaces the handler (an empty one restores the default); returns the previous one. Not
// thread-safe against concurrent warn() calls: set it before work starts.
WarningHandler setWarningHandler(WarningHandler handler);

// Hands `message` (no "warning:" prefix, no newline) to the handler. Safe to call from several
// threads at once (calls are serialised).
void warn(const std::string& message);

}  // namespace tdvo
