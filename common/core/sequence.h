// Frame-numbered file sequences: printf-style patterns such as "seq/%04d.obj.gz".
#pragma once

#include <optional>
#include <string>

namespace tdvo {

// Checks that `pattern` holds exactly one integer conversion (%d, %Nd or %0Nd; "%%" is a
// literal percent sign). Throws Error naming `what` (e.g. "InputMeshPattern") otherwise.
void checkFramePattern(const std::string& pattern, const std::string& what);
// checkFramePattern for a pattern of files inside an app's output folder (3dvo-dec's
// OutputMeshPattern): it must also be a relative path (an absolute one would be read as inside
// the folder, or not at all, depending on how it is joined).
void checkOutputFramePattern(const std::string& pattern, const std::string& what);

// The file name of frame `frame`: the pattern with its conversion replaced by the number.
std::string framePath(const std::string& pattern, int frame);

// A literal path as the text of a pattern (or of a path that may be read as one): each '%'
// doubled, so that a folder named "take%d" stays that folder.
std::string escapePercent(const std::string& literal);
// The literal path a pattern text without a conversion stands for: each "%%" one '%'.
std::string unescapePercent(const std::string& text);

// The file of the lowest frame number above `number` that exists (the first file after a gap in
// a sequence), if any. Only a pattern whose conversion is in the file name, not in a folder name,
// is looked at; its folder is listed once (the cost is that of its entries).
std::optional<std::string> firstFileAfter(const std::string& pattern, int number);

// The frame number whose framePath(pattern) is `path` exactly, if there is one (a path that
// only looks alike, e.g. with other padding, is none).
std::optional<int> frameOfPath(const std::string& pattern, const std::string& path);

}  // namespace tdvo
