// Warnings: what a reader or coder leaves out or changes of its input is said, never done
// silently. The library calls warn(); the handler decides where it goes: by default a line
// "warning: <message>" on stderr; the apps prefix their name (common/core/app.h), and a program
// may collect or silence them (setWarningHandler).
#pragma once

#include <functional>
#include <string>
#include <vector>

namespace tdvo {

using WarningHandler = std::function<void(const std::string& message)>;

// Replaces the handler (an empty one restores the default); returns the previous one. Not
// thread-safe against concurrent warn() calls: set it before work starts.
WarningHandler setWarningHandler(WarningHandler handler);

// Hands `message` (no "warning:" prefix, no newline) to the handler. Safe to call from several
// threads at once (calls are serialised).
void warn(const std::string& message);

// warn() for a message that names one input file of a sequence: `kind` is the message without
// the file's name (the same for every file it holds for). Inside a WarnOnceScope the first file's
// message is said; later files' messages of the same kind are counted, not said, and when the
// outermost scope ends one line says "<kind>: the same in N more files or frames". Outside a scope
// it is warn(message).
void warnForFile(const std::string& kind, const std::string& message);

// A warning kept by a WarningHold: the arguments of its warnForFile() or warn() call.
struct HeldWarning {
  std::string kind, message;
  bool forFile = false;  // warnForFile(kind, message); else warn(message)
};

// While one exists on a thread, that thread's warn() and warnForFile() calls are kept (unless a
// SilenceWarningsScope drops them), not said; say() then says them in the order they came, so
// that work done on several threads (frames read in parallel) warns in a fixed order. Holds
// nest on a thread (the innermost one keeps). What a hold kept and was not released ends with it
// (work that failed: its error is what is said).
class WarningHold {
 public:
  WarningHold();
  ~WarningHold();
  WarningHold(const WarningHold&) = delete;
  WarningHold& operator=(const WarningHold&) = delete;
  // What was kept so far (moved out).
  std::vector<HeldWarning> release();

 private:
  WarningHold* outer_;
  std::vector<HeldWarning> held_;
  friend bool holdWarning(const std::string* kind, const std::string& message);
};

// Says held warnings, in order, as warn() or warnForFile() would have.
void say(const std::vector<HeldWarning>& warnings);

// While one exists, a message identical to one already said during its life is not said again:
// a run that reads a file more than once (the encoder's bounds pass, Quality's trial and the
// coding) says what the reader left out once. Scopes nest (the outermost one's life counts) and
// are process-wide, as the handler is; runApp and tdvo::Encoder::encode open one. It remembers
// the first 65,536 distinct messages until it ends (later ones are said every time). When the
// outermost one ends it says how many more files each warnForFile kind held for.
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
