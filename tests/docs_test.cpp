// The documentation against the apps (docs/options.md says this test exists): every cfg key that
// 3dvo-enc and 3dvo-dec --help list has a row on docs/options.md and every row there is a key of
// the app, and every app takes --help and --version and fails when its output cannot be
// written (docs/user-guide.md, "Every app").
#include <gtest/gtest.h>

#include <regex>
#include <set>
#include <string>

#include "tests/test_support.h"

namespace tdvo {
namespace {

const std::string kBin = TDVO_BIN_DIR;

// The keys --help lists: lines "  Key ..." (two spaces, a capital letter).
std::set<std::string> helpKeys(const std::string& app) {
  test::TempDir dir("docs-help");
  const test::CommandResult r = test::run(dir, kBin + "/" + app, {"--help"});
  EXPECT_EQ(r.exitCode, 0) << app << ": " << r.err;
  std::set<std::string> keys;
  const std::regex line("^  ([A-Z][A-Za-z0-9]*)( |$)");
  size_t start = 0;
  while (start < r.out.size()) {
    size_t end = r.out.find('\n', start);
    if (end == std::string::npos) end = r.out.size();
    std::smatch m;
    const std::string text = r.out.substr(start, end - start);
    if (std::regex_search(text, m, line)) keys.insert(m[1]);
    start = end + 1;
  }
  return keys;
}

// The keys of docs/options.md's rows ("| `Key` ..." in the tables) under "## <app>".
std::set<std::string> pageKeys(const std::string& app) {
  const std::string page = test::readText(std::string(TDVO_SOURCE_DIR) + "/docs/options.md");
  const size_t from = page.find("\n## " + app + "\n");
  EXPECT_NE(from, std::string::npos) << "docs/options.md has no section ## " << app;
  if (from == std::string::npos) return {};
  size_t to = page.find("\n## ", from + 1);
  if (to == std::string::npos) to = page.size();
  const std::string section = page.substr(from, to - from);
  std::set<std::string> keys;
  const std::regex row("\n\\| `([A-Za-z0-9]+)`");
  for (std::sregex_iterator it(section.begin(), section.end(), row), end; it != end; ++it)
    keys.insert((*it)[1]);
  return keys;
}

void expectSameKeys(const std::string& app) {
  const std::set<std::string> help = helpKeys(app), page = pageKeys(app);
  EXPECT_GT(help.size(), 10u) << app << " --help was not read";
  for (const std::string& key : help)
    EXPECT_TRUE(page.count(key)) << app << " key " << key << " has no row in docs/options.md";
  for (const std::string& key : page)
    EXPECT_TRUE(help.count(key)) << "docs/options.md row " << key << " is not a key of " << app;
}

TEST(Docs, EveryEncoderKeyHasARowInOptionsAndEveryRowIsAKey) {
  expectSameKeys("3dvo-enc");
}

TEST(Docs, EveryDecoderKeyHasARowInOptionsAndEveryRowIsAKey) {
  expectSameKeys("3dvo-dec");
}

TEST(Docs, EveryAppTakesHelpAndVersion) {
  test::TempDir dir("docs-apps");
  for (const char* app : {"3dvo-enc", "3dvo-dec", "3dvo-metrics", "3dvo-render", "3dvo-recon",
                          "3dvo-import", "3dvo-synth", "3dvo-sample", "3dvo-play", "3dvo-rd"}) {
    for (const char* option : {"--help", "-h", "--version"}) {
      const test::CommandResult r = test::run(dir, kBin + "/" + app, {option});
      EXPECT_EQ(r.exitCode, 0) << app << " " << option << ": " << r.err;
      EXPECT_FALSE(r.out.empty()) << app << " " << option;
    }
    // A bad argument is the user's error, exit code 1 (2 means an internal error).
    const test::CommandResult r = test::run(dir, kBin + "/" + app, {"--no-such-option"});
    EXPECT_EQ(r.exitCode, 1) << app << ": " << r.err;
    EXPECT_NE(r.err.find(std::string(app) + ": error: "), std::string::npos) << r.err;
  }
}

// docs/dataset.md's example is the start of what 3dvo-synth writes (it had gone stale).
TEST(Docs, TheDatasetExampleIsWhatSynthWrites) {
  test::TempDir dir("docs-synth");
  const test::CommandResult r = test::run(dir, kBin + "/3dvo-synth", {"-o", "rig"});
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const std::string page = test::readText(std::string(TDVO_SOURCE_DIR) + "/docs/dataset.md");
  const size_t example = page.find("The start of the dataset `3dvo-synth -o DIR` writes:");
  ASSERT_NE(example, std::string::npos);
  const size_t from = page.find("```json\n", example), to = page.find("    },\n", from);
  ASSERT_NE(from, std::string::npos);
  ASSERT_NE(to, std::string::npos);
  const std::string shown = page.substr(from + 8, to + 7 - (from + 8));
  const std::string written = test::readText(dir.file("rig/dataset.json"));
  EXPECT_EQ(written.substr(0, shown.size()), shown);
}

// What an app prints must reach standard output: when it cannot (a full disk, here /dev/full),
// the run is an error with exit status 1 and says so, instead of a success with a lost report.
TEST(Docs, EveryAppFailsWhenItsOutputCannotBeWritten) {
  test::TempDir dir("docs-full");
  for (const char* app : {"3dvo-enc", "3dvo-dec", "3dvo-metrics", "3dvo-render", "3dvo-recon",
                          "3dvo-import", "3dvo-synth", "3dvo-sample", "3dvo-play", "3dvo-rd"}) {
    for (const char* option : {"--help", "--version"}) {
      const std::string command =
          test::shellQuote(kBin + "/" + app) + " " + option + " > /dev/full";
      const test::CommandResult r = test::run(dir, "/bin/sh", {"-c", command});
      EXPECT_EQ(r.exitCode, 1) << app << " " << option << ": " << r.err;
      EXPECT_NE(r.err.find(std::string(app) + ": error: cannot write to standard output"),
                std::string::npos)
          << app << " " << option << ": " << r.err;
    }
  }
}

}  // namespace
}  // namespace tdvo
