// The shared frame of every 3DVO command-line app: errors become one line on stderr,
// "<app>: error: <message>", and exit code 1; internal errors (bugs) exit with code 2; SIGINT,
// SIGTERM and SIGHUP remove the run's unfinished output files first (interrupt.h).
#pragma once

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <exception>
#include <new>
#include <stdexcept>
#include <string>

#include "common/core/error.h"
#include "common/core/file_io.h"
#include "common/core/interrupt.h"
#include "common/core/warnings.h"

namespace tdvo {

template <class Body>
int runApp(const char* app, Body body) {
  // Before any thread exists: an interrupted run removes its unfinished output files.
  installInterruptCleanup();
  // No output of the run replaces or deletes a file it has read (file_io.h).
  protectFilesRead(true);
  // What the libraries leave out or change of an input is said on stderr, with the app's name.
  setWarningHandler([app](const std::string& message) {
    std::fprintf(stderr, "%s: warning: %s\n", app, message.c_str());
  });
  try {
    int status = 0;
    {
      // A file the run reads twice warns once; the closing counts ("the same in N more
      // files") are said when the body ends, before its error if it failed.
      WarnOnceScope once;
      status = body();
    }
    // What the app printed (its report, its summary) must have reached standard output: a full
    // disk or a closed file there is an error, not a success with a lost report.
    errno = 0;
    if (std::fflush(stdout) != 0 || std::ferror(stdout))
      throw Error(std::string("cannot write to standard output (") +
                  (errno != 0 ? std::strerror(errno) : "a write failed") + ")");
    return status;
  } catch (const Error& e) {
    std::fprintf(stderr, "%s: error: %s\n", app, e.what());
    return 1;
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr, "%s: error: out of memory\n", app);
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: internal error (please report): %s\n", app, e.what());
    return 2;
  }
}

}  // namespace tdvo
