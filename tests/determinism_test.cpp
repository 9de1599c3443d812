// Determinism: the same input and cfg give byte-identical streams, from run to run, from build
// to build and for any thread count.
//
// Across runs and builds: every conformance cfg is encoded again by this build's 3dvo-enc (from
// TDVO_BIN_DIR) and the stream must equal the committed one byte for byte. The committed streams
// were made by a Release build (-O3), so in a Release build this is a run-to-run check, in the
// sanitizer build of scripts/sanitize.sh (-O2 and instrumented; CI runs it) a check across build
// configurations, and in a Debug build a Debug-versus-Release check (docs/robustness.md,
// "Determinism").
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include "tests/test_support.h"

namespace tdvo {
namespace {

using test::CommandResult;
using test::TempDir;

const std::string kEncoder = std::string(TDVO_BIN_DIR) + "/3dvo-enc";
const std::filesystem::path kConformance = std::filesystem::path(TDVO_SOURCE_DIR) / "conformance";

std::vector<std::string> conformanceNames() {
  std::vector<std::string> names;
  for (const auto& entry : std::filesystem::directory_iterator(kConformance / "cfg"))
    if (entry.path().extension() == ".cfg") names.push_back(entry.path().stem().string());
  std::sort(names.begin(), names.end());
  return names;
}

// Encodes conformance cfg `name` in a fresh folder (its inputs linked in as inputs/) with
// `extra` options; returns the stream.
std::vector<uint8_t> encodeConformance(const std::string& name,
                                       const std::vector<std::string>& extra = {}) {
  TempDir dir("determinism");
  std::filesystem::create_directory_symlink(kConformance / "inputs", dir.path() / "inputs");
  std::vector<std::string> args = {"-c", (kConformance / "cfg" / (name + ".cfg")).string(),
                                   "--BitstreamFile=x.3dvo"};
  args.insert(args.end(), extra.begin(), extra.end());
  const CommandResult r = test::run(dir, kEncoder, args);
  EXPECT_EQ(r.exitCode, 0) << r.err;
  if (r.exitCode != 0) return {};
  return test::readBytes(dir.file("x.3dvo"));
}

class ConformanceReencoding : public testing::TestWithParam<std::string> {};

TEST_P(ConformanceReencoding, GivesTheCommittedStream) {
  const std::vector<uint8_t> committed =
      test::readBytes((kConformance / "streams" / (GetParam() + ".3dvo")).string());
  const std::vector<uint8_t> again = encodeConformance(GetParam());
  ASSERT_EQ(again.size(), committed.size());
  const auto mismatch = std::mismatch(again.begin(), again.end(), committed.begin());
  EXPECT_TRUE(mismatch.first == again.end())
      << "first difference at byte " << (mismatch.first - again.begin());
}

INSTANTIATE_TEST_SUITE_P(Conformance, ConformanceReencoding, testing::ValuesIn(conformanceNames()),
                         [](const testing::TestParamInfo<std::string>& info) {
                           return info.param;
                         });

TEST(Determinism, AnyThreadCountGivesTheSameStream) {
  // Three GOMs (5 + 5 + 2 frames) coded on 1, 2 and 3 threads.
  const std::vector<uint8_t> one = encodeConformance("d3dmc_q4_g5", {"--Threads=1"});
  ASSERT_FALSE(one.empty());
  for (const char* threads : {"--Threads=2", "--Threads=3", "--Threads=0"}) {
    SCOPED_TRACE(threads);
    EXPECT_TRUE(encodeConformance("d3dmc_q4_g5", {threads}) == one);
  }
}

}  // namespace
}  // namespace tdvo
