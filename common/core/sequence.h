// Frame-numbered file sequences: printf-style patterns such as "seq/%04d.obj.gz".
#pragma once

#include <optional>
#include <string>

namespace tdvo {

// Checks that `pattern` holds exactly one integer conversion (%d, %Nd or %0Nd; "%%" is a
// literal percent sign). Throws Error naming `what` (e.g. "InputMeshPattern") otherwise.
void checkFramePattern(const std::string& pattern, const std::string& what);

// The file name of frame `frame`: the pattern with its conversion replaced by the number.
std::string framePath(const std::string& pattern, int frame);

// The frame number whose framePath(pattern) is `path` exactly, if there is one (a path that
// only looks alike, e.g. with other padding, is none).
std::optional<int> frameOfPath(const std::string& pattern, const std::string& path);

}  // namespace tdvo
