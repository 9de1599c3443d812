// The GOM list: how a sequence is cut into groups of meshes (GOMs), as text. 3dvo-recon writes
// it (goms.txt) for its tracked GOMs, whose lengths vary with the motion; 3dvo-enc codes such
// GOMs as one stream when its cfg key GOMListFile names the list (docs/reconstruction.md,
// "GOM list"; docs/options.md).
//
// Format: `#` starts a comment; every other non-empty line is `<first frame> <frame count>`.
// The GOMs follow each other from frame 0 without gap or overlap, each 1 .. kGomListMaxCount
// frames long.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace tdvo {

// (first frame, frame count) per GOM, in frame order.
using GomList = std::vector<std::pair<int, int>>;

// The longest GOM a list may hold: the stream's limit on gh_frame_count (kMaxGomFrames in
// bitstream/syntax.h, which the encoder checks against this value).
constexpr int kGomListMaxCount = 65535;

// The list as text, with a comment line first.
std::string formatGomList(const GomList& goms);

// Parses a GOM list; `name` (the file name) starts every message. Each line is checked as it
// is read, and an Error names the file and line: not two integers; a GOM that does not start
// where the previous one ended (a gap, or an overlap with the previous GOM), or a first GOM not
// at frame 0; a count outside 1 .. kGomListMaxCount; and, when `frameCount` > 0, a GOM that
// ends beyond frame frameCount - 1, or a last GOM that ends before it (the GOMs must tile
// frames 0 .. frameCount - 1 exactly). A list without GOMs is an error naming the file.
GomList parseGomList(const std::string& text, const std::string& name, size_t frameCount = 0);

// Reads the GOM list file `path` (an Error names it when it cannot be read) and parses it as
// parseGomList does.
GomList readGomList(const std::string& path, size_t frameCount = 0);

// GOM starts: the first frame of each GOM that is a random access point (where decoding can
// start; every GOM unless RandomAccessPeriod > 1), as 3dvo-dec writes them (gom_starts.txt
// beside its output) and 3dvo-render and 3dvo-metrics read them. Integers separated by white space
// or commas, `#` comments; returned sorted, without repeats. Errors name the file and line.
std::vector<int> readGomStarts(const std::string& path);
// The GOM starts as text readGomStarts reads: a comment line, then one frame per line.
std::string formatGomStarts(const std::vector<uint32_t>& starts);
constexpr const char* kGomStartsFileName = "gom_starts.txt";

}  // namespace tdvo
