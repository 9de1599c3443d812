// No data lost: an interrupted run leaves no file under a final name and no staged file
// (common/interrupt.h, common/file_io.h). The apps from TDVO_BIN_DIR are started as child
// processes and sent SIGTERM or SIGINT as soon as their first staged output file appears; the
// staging itself (registry, partly failed commit) is checked in-process.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include "common/error.h"
#include "common/file_io.h"
#include "common/interrupt.h"
#include "common/obj_io.h"
#include "tests/test_support.h"

namespace tdvo {
namespace {

using test::TempDir;

const std::string kBin = TDVO_BIN_DIR;
constexpr int kFrames = 200;

// Starts `program args...` in `folder` with stdout and stderr discarded; returns its pid.
pid_t start(const TempDir& folder, const std::string& program,
            const std::vector<std::string>& args) {
  std::vector<std::string> all = {program};
  all.insert(all.end(), args.begin(), args.end());
  const pid_t pid = fork();
  if (pid == 0) {
    if (chdir(folder.path().c_str()) != 0) _exit(127);
    std::FILE* null = std::freopen("/dev/null", "w", stdout);
    null = null ? std::freopen("/dev/null", "w", stderr) : null;
    std::vector<char*> argv;
    for (std::string& a : all)
      argv.push_back(a.data());
    argv.push_back(nullptr);
    execv(program.c_str(), argv.data());
    _exit(127);
  }
  return pid;
}

bool hasStagedFile(const std::filesystem::path& folder) {
  std::error_code ec;
  for (const auto& entry : std::filesystem::recursive_directory_iterator(folder, ec))
    if (entry.path().extension() == ".partial") return true;
  return false;
}

// Waits until a staged file appears under `folder` (or the child ends), then sends `signal`
// and returns the child's wait status.
int interruptWhenStaging(pid_t pid, const std::filesystem::path& folder, int signal) {
  // A guard against a child that never stages anything, not a measurement.
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::minutes(5);
  int status = 0;
  while (!hasStagedFile(folder)) {
    if (waitpid(pid, &status, WNOHANG) == pid) {
      ADD_FAILURE() << "the child ended before it staged a file";
      return status;
    }
    if (std::chrono::steady_clock::now() > deadline) {
      ADD_FAILURE() << "no staged file appeared";
      break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  kill(pid, signal);
  waitpid(pid, &status, 0);
  return status;
}

// Files (recursively, relative) under a folder, folders excluded.
std::vector<std::string> files(const std::filesystem::path& folder) {
  std::vector<std::string> names;
  for (const auto& entry : std::filesystem::recursive_directory_iterator(folder))
    if (!entry.is_directory())
      names.push_back(std::filesystem::relative(entry.path(), folder).string());
  std::sort(names.begin(), names.end());
  return names;
}

class InterruptTest : public testing::Test {
 protected:
  void SetUp() override {
    std::filesystem::create_directories(dir_.path() / "in");
    const std::vector<Mesh> frames = test::wobblingSphere(3, kFrames);  // 642 vertices
    for (int f = 0; f < kFrames; ++f) {
      char name[32];
      std::snprintf(name, sizeof name, "in/%04d.obj", f);
      test::writeText(dir_.file(name), formatObj(frames[f]));
      inputs_.push_back(name);
    }
  }

  std::vector<std::string> encoderArgs() const {
    return {"--InputMeshPattern=in/%04d.obj",
            "--FrameCount=" + std::to_string(kFrames),
            "--GridBits=12",
            "--GOMSize=20",
            "-o",
            "x.3dvo",
            "--ReconMeshPattern=recon-%04d.obj"};
  }

  TempDir dir_{"interrupt"};
  std::vector<std::string> inputs_;
};

TEST_F(InterruptTest, EncoderLeavesNothing) {
  for (int signal : {SIGTERM, SIGINT}) {
    SCOPED_TRACE(signal);
    const pid_t pid = start(dir_, kBin + "/3dvo-enc", encoderArgs());
    const int status = interruptWhenStaging(pid, dir_.path(), signal);
    ASSERT_TRUE(WIFSIGNALED(status)) << "status " << status;
    EXPECT_EQ(WTERMSIG(status), signal);
    // Only the input is left: no stream, no reconstruction, nothing staged.
    EXPECT_EQ(files(dir_.path()), inputs_);
  }
}

TEST_F(InterruptTest, DecoderLeavesNothing) {
  std::vector<std::string> args = encoderArgs();
  args.pop_back();  // no reconstruction
  const pid_t encoder = start(dir_, kBin + "/3dvo-enc", args);
  int status = 0;
  waitpid(encoder, &status, 0);
  ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << status;
  const pid_t pid = start(dir_, kBin + "/3dvo-dec", {"-i", "x.3dvo", "-o", "out"});
  status = interruptWhenStaging(pid, dir_.path() / "out", SIGTERM);
  ASSERT_TRUE(WIFSIGNALED(status)) << "status " << status;
  EXPECT_EQ(WTERMSIG(status), SIGTERM);
  EXPECT_TRUE(!std::filesystem::exists(dir_.path() / "out") || files(dir_.path() / "out").empty());
  std::vector<std::string> expected = inputs_;
  expected.push_back("x.3dvo");
  std::sort(expected.begin(), expected.end());
  EXPECT_EQ(files(dir_.path()), expected);
}

// ---- The staging itself ----

TEST(Staging, RegisteredFromCreationUntilCommitted) {
  TempDir dir("staging");
  const size_t before = InterruptRegistry::size();
  {
    StagedFiles out;
    out.write(dir.file("a"), "a");
    out.write(dir.file("b"), "b");
    EXPECT_EQ(InterruptRegistry::size(), before + 2);
    EXPECT_TRUE(std::filesystem::exists(dir.file("a.partial")));
    out.commit();
    EXPECT_EQ(InterruptRegistry::size(), before);
  }
  EXPECT_EQ(test::readText(dir.file("a")), "a");
  EXPECT_EQ(test::readText(dir.file("b")), "b");
  writeFileAtomic(dir.file("c"), "c");
  EXPECT_EQ(InterruptRegistry::size(), before);
  EXPECT_EQ(test::listFolder(dir.path()), (std::vector<std::string>{"a", "b", "c"}));
}

TEST(Staging, FailedRunLeavesNothing) {
  TempDir dir("staging");
  const size_t before = InterruptRegistry::size();
  {
    StagedFiles out;
    out.write(dir.file("a"), "a");
    EXPECT_EQ(InterruptRegistry::size(), before + 1);
  }
  EXPECT_EQ(InterruptRegistry::size(), before);
  EXPECT_TRUE(test::listFolder(dir.path()).empty());
}

TEST(Staging, CommitThatFailsHalfwayLeavesNothing) {
  // The second file cannot be renamed into place (a non-empty folder has its name): the first,
  // already renamed, is removed again with the staged second.
  TempDir dir("staging");
  std::filesystem::create_directories(dir.path() / "b" / "full");
  const size_t before = InterruptRegistry::size();
  {
    StagedFiles out;
    out.write(dir.file("a"), "a");
    out.write(dir.file("b"), "b");
    EXPECT_THROW(out.commit(), Error);
  }
  EXPECT_EQ(InterruptRegistry::size(), before);
  EXPECT_EQ(test::listFolder(dir.path()), std::vector<std::string>{"b"});
}

}  // namespace
}  // namespace tdvo
