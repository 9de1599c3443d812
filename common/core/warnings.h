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

// While one exists, a message identical to one already said during its life is not said again:
// a run that reads a file more than once (the encoder's bounds pass, Quality's trial and the
// coding) says what the reader left out once. Scopes nest (the outermost one's life counts) and
// are process-wide, as the handler is; runApp and tdvo::Encoder::encode open one. It remembers
// the first 65,536 distinct messages until it ends (later ones are said every time).
class WarnOnceScope {
 public:
  WarnOnceScope();
  ~WarnOnceScope();
  WarnOnceScope(const WarnOnceScope&) = delete;
  WarnOnceScope& operator=(const WarnOnceScope&) = delete;
};

// While one exists, warnings are dropped, and not remembered by a WarnOnceScope: work done again
// later for real (the Quality search's trial codings) warns then. Process-wide; scopes nest.
class SilenceWarningsScope {
 public:
  SilenceWarningsScope();
  ~SilenceWarningsScope();
  SilenceWarningsScope(const SilenceWarningsScope&) = delete;
  SilenceWarningsScope& operator=(const SilenceWarningsScope&) = delete;
};

}  // namespace tdvo
