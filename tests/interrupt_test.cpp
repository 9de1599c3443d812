// No data lost: an interrupted run leaves no file under a final name and no staged file
// (common/core/interrupt.h, common/core/file_io.h). The apps from TDVO_BIN_DIR are started as child
// processes and sent SIGTERM or SIGINT as soon as their first staged output file appears; the
// staging itself (registry, partly failed commit) is checked in-process.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include "common/core/error.h"
#include "common/core/file_io.h"
#include "common/core/interrupt.h"
#include "common/core/obj_io.h"
#include "common/core/sequence.h"
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
  // No folder tree is left either: the folder this run made goes with its staged contents.
  EXPECT_FALSE(std::filesystem::exists(dir_.path() / "out"));
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

TEST(Staging, CommitThatFailsHalfwayKeepsThePreviousFiles) {
  // The previous run left a, b and c. The second file cannot be renamed into place (a
  // non-empty folder has taken its name since it was staged): the commit fails, and a, already
  // replaced, gets its previous contents back; c was never touched; nothing staged is left.
  TempDir dir("staging");
  test::writeText(dir.file("a"), "previous a");
  test::writeText(dir.file("c"), "previous c");
  const size_t before = InterruptRegistry::size();
  {
    StagedFiles out;
    out.write(dir.file("a"), "new a");
    out.write(dir.file("b"), "new b");
    out.write(dir.file("c"), "new c");
    std::filesystem::create_directories(dir.path() / "b" / "full");
    EXPECT_THROW(out.commit(), Error);
  }
  EXPECT_EQ(InterruptRegistry::size(), before);
  EXPECT_EQ(test::readText(dir.file("a")), "previous a");
  EXPECT_EQ(test::readText(dir.file("c")), "previous c");
  EXPECT_EQ(test::listFolder(dir.path()), (std::vector<std::string>{"a", "b", "c"}));
}

TEST(Staging, PlantedPartialLinkIsNotFollowed) {
  // A symbolic link planted under the staged name must not redirect the write: the staged
  // file is created exclusively under a fresh name, and the link's target is untouched.
  TempDir dir("staging");
  test::writeText(dir.file("victim"), "precious");
  std::filesystem::create_symlink(dir.file("victim"), dir.file("a.partial"));
  std::filesystem::create_symlink(dir.file("victim"), dir.file("b.partial"));
  {
    StagedFiles out;
    out.write(dir.file("a"), "new a");
    out.commit();
  }
  writeFileAtomic(dir.file("b"), "new b");
  EXPECT_EQ(test::readText(dir.file("victim")), "precious");
  EXPECT_EQ(test::readText(dir.file("a")), "new a");
  EXPECT_EQ(test::readText(dir.file("b")), "new b");
  EXPECT_TRUE(std::filesystem::is_symlink(dir.file("a.partial")));
  EXPECT_EQ(test::listFolder(dir.path()),
            (std::vector<std::string>{"a", "a.partial", "b", "b.partial", "victim"}));
}

TEST(Staging, OutputThroughASymlinkReplacesItsTarget) {
  TempDir dir("staging");
  std::filesystem::create_directories(dir.path() / "data");
  test::writeText(dir.file("data/x.3dvo"), "previous");
  std::filesystem::create_symlink("data/x.3dvo", dir.file("link.3dvo"));
  std::filesystem::create_symlink("data/new.3dvo", dir.file("dangling.3dvo"));
  writeFileAtomic(dir.file("link.3dvo"), "new");
  writeFileAtomic(dir.file("dangling.3dvo"), "created");
  EXPECT_TRUE(std::filesystem::is_symlink(dir.file("link.3dvo")));
  EXPECT_TRUE(std::filesystem::is_symlink(dir.file("dangling.3dvo")));
  EXPECT_EQ(test::readText(dir.file("data/x.3dvo")), "new");
  EXPECT_EQ(test::readText(dir.file("data/new.3dvo")), "created");
}

TEST(Staging, FifoIsWrittenInPlaceNotReplaced) {
  TempDir dir("staging");
  const std::string fifo = dir.file("pipe");
  ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
  // A reader that is already there (non-blocking), so that opening for writing does not wait.
  const int reader = open(fifo.c_str(), O_RDONLY | O_NONBLOCK);
  ASSERT_GE(reader, 0);
  writeFileAtomic(fifo, "through the pipe");
  char buffer[64] = {};
  const ssize_t n = read(reader, buffer, sizeof buffer);
  close(reader);
  EXPECT_EQ(std::string(buffer, n > 0 ? static_cast<size_t>(n) : 0), "through the pipe");
  EXPECT_TRUE(std::filesystem::is_fifo(fifo));
  EXPECT_EQ(test::listFolder(dir.path()), std::vector<std::string>{"pipe"});
}

TEST(Staging, FolderAndSocketAreRefused) {
  TempDir dir("staging");
  std::filesystem::create_directories(dir.path() / "folder" / "inside");
  EXPECT_THROW(writeFileAtomic(dir.file("folder"), "x"), Error);
  EXPECT_TRUE(std::filesystem::exists(dir.path() / "folder" / "inside"));
  const int s = socket(AF_UNIX, SOCK_STREAM, 0);
  ASSERT_GE(s, 0);
  sockaddr_un address = {};
  address.sun_family = AF_UNIX;
  const std::string path = dir.file("socket");
  ASSERT_LT(path.size(), sizeof address.sun_path);
  std::strcpy(address.sun_path, path.c_str());
  ASSERT_EQ(bind(s, reinterpret_cast<const sockaddr*>(&address), sizeof address), 0);
  EXPECT_THROW(writeFileAtomic(path, "x"), Error);
  close(s);
  EXPECT_TRUE(std::filesystem::is_socket(path));
}

// ---- Output folders ----

TEST(OutputFolders, FailedRunLeavesNoFolderTree) {
  TempDir dir("outfolder");
  const size_t before = InterruptRegistry::size();
  {
    OutputFolder out(dir.file("new/deeper/out"), false);
    out.write(dir.file("new/deeper/out/cam0/0000.png"), "png");
    out.write(dir.file("new/deeper/out/0000.obj"), "obj");
  }
  EXPECT_EQ(InterruptRegistry::size(), before);
  EXPECT_TRUE(test::listFolder(dir.path()).empty());
}

// A run's outputs are committed together (commitAll): when a later one cannot be put in place,
// the earlier ones are taken back. Before, 3dvo-render -o DIR --Mp4=FILE (and 3dvo-dec's
// --ExtractTextures folder, leave-one-out's --Csv) replaced the folder, then failed on the
// other output: exit 1 with the folder's earlier contents deleted.
TEST(OutputFolders, CommitAllTakesEveryOutputBackWhenOneFails) {
  TempDir dir("commit-all");
  {
    OutputFolder out(dir.file("out"), false);
    out.write(dir.file("out/old.txt"), "old");
    out.commit();
  }
  test::writeText(dir.file("old.csv"), "old rows");
  const size_t before = InterruptRegistry::size();
  {
    OutputFolder out(dir.file("out"), true);
    out.write(dir.file("out/new.txt"), "new");
    StagedFiles csv;
    csv.write(dir.file("old.csv"), "new rows");
    StagedFiles blocked;
    blocked.write(dir.file("blocked"), "x");
    // A folder in the way of the last output: its rename fails.
    std::filesystem::create_directories(dir.path() / "blocked" / "inside");
    try {
      commitAll({&out, &csv, &blocked});
      ADD_FAILURE() << "no error";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("blocked: cannot rename staged output into place"),
                std::string::npos)
          << e.what();
    }
  }
  EXPECT_EQ(test::listFolder(dir.path() / "out"), std::vector<std::string>{"old.txt"});
  EXPECT_EQ(test::readText(dir.file("out/old.txt")), "old");
  EXPECT_EQ(test::readText(dir.file("old.csv")), "old rows");
  EXPECT_EQ(InterruptRegistry::size(), before);
  // All three in place when nothing is in the way.
  std::filesystem::remove_all(dir.path() / "blocked");
  {
    OutputFolder out(dir.file("out"), true);
    out.write(dir.file("out/new.txt"), "new");
    StagedFiles csv;
    csv.write(dir.file("old.csv"), "new rows");
    commitAll({&out, &csv});
  }
  EXPECT_EQ(test::listFolder(dir.path() / "out"), std::vector<std::string>{"new.txt"});
  EXPECT_EQ(test::readText(dir.file("old.csv")), "new rows");
  EXPECT_EQ(InterruptRegistry::size(), before);
  // A folder this run creates, with another output's file staged inside it: when a later
  // output fails, everything goes, and no empty folder is left (leave-one-out's --Csv inside
  // its -o folder left one).
  {
    OutputFolder out(dir.file("made/deeper"), false);
    out.write(dir.file("made/deeper/a.png"), "png");
    StagedFiles csv;
    csv.write(dir.file("made/deeper/rows.csv"), "rows");
    StagedFiles blocked;
    blocked.write(dir.file("blocked"), "x");
    std::filesystem::create_directories(dir.path() / "blocked" / "inside");
    EXPECT_THROW(commitAll({&out, &csv, &blocked}), Error);
  }
  EXPECT_FALSE(std::filesystem::exists(dir.path() / "made"));
  EXPECT_EQ(InterruptRegistry::size(), before);
}

// An output folder named through a missing folder and back out ("q/../x"): mkdir -p would make
// q, outside the output folder, and a successful run left it; refused before anything is made.
TEST(OutputFolders, AMissingFolderAndBackOutIsRefused) {
  TempDir dir("outfolder-dotdot");
  try {
    OutputFolder out(dir.file("q/../x"), false);
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("/q, which does not exist, and back out ('..')"),
              std::string::npos)
        << e.what();
  }
  EXPECT_TRUE(test::listFolder(dir.path()).empty());
  std::filesystem::create_directories(dir.path() / "q");
  {
    OutputFolder out(dir.file("q/../x"), false);
    out.write(dir.file("q/../x/0000.obj"), "obj");
    out.commit();
  }
  EXPECT_TRUE(std::filesystem::exists(dir.path() / "x" / "0000.obj"));
}

// Two outputs of one run naming the same file: an error saying so (it was "cannot create: File
// exists", as if a file of someone else's were in the way), and the folder is left as it was.
TEST(OutputFolders, AFileWrittenTwiceIsAnErrorSayingSo) {
  TempDir dir("outfolder-twice");
  {
    OutputFolder out(dir.file("out"), false);
    out.write(dir.file("out/0000.glb"), "frame");
    try {
      out.write(dir.file("out/0000.glb"), "animation");
      FAIL() << "no error";
    } catch (const Error& e) {
      EXPECT_EQ(std::string(e.what()),
                dir.file("out/0000.glb") +
                    ": is written twice by this run (two of its outputs name this file)");
    }
  }
  EXPECT_TRUE(test::listFolder(dir.path()).empty());
}

TEST(OutputFolders, CommitHoldsExactlyThisRunsOutput) {
  TempDir dir("outfolder");
  std::filesystem::create_directories(dir.path() / "out" / "cam7");
  test::writeText(dir.file("out/0000.obj"), "previous");
  test::writeText(dir.file("out/cam7/0000.png"), "previous camera");
  EXPECT_THROW(OutputFolder(dir.file("out"), false), Error);  // not empty
  {
    OutputFolder out(dir.file("out"), true);
    out.write(dir.file("out/0000.obj"), "new");
    out.write(dir.file("out/cam0/0000.png"), "new camera");
    EXPECT_THROW(out.write(dir.file("out/../escape"), "x"), Error);
    // Not committed yet: the previous contents are all there.
    EXPECT_EQ(test::readText(dir.file("out/0000.obj")), "previous");
    out.commit();
  }
  EXPECT_EQ(test::listFolder(dir.path() / "out"), (std::vector<std::string>{"0000.obj", "cam0"}));
  EXPECT_EQ(test::readText(dir.file("out/0000.obj")), "new");
  EXPECT_EQ(test::readText(dir.file("out/cam0/0000.png")), "new camera");
  EXPECT_FALSE(std::filesystem::exists(dir.path() / "escape"));
}

TEST(OutputFolders, OverwriteRefusesAFolderHoldingAnInput) {
  TempDir dir("outfolder");
  std::filesystem::create_directories(dir.path() / "out" / "in");
  test::writeText(dir.file("out/in/x.3dvo"), "stream");
  std::filesystem::create_symlink("out/in", dir.file("link"));
  EXPECT_THROW(OutputFolder(dir.file("out"), true, {dir.file("link/x.3dvo")}), Error);
  EXPECT_EQ(test::readText(dir.file("out/in/x.3dvo")), "stream");
}

// Whatever an app lists as its inputs, a file the process read is never deleted by a commit:
// the commit stops with the folder as it was (here a file read in a subfolder, and one read
// by name, as FFmpeg's files are noted); a link to a read file is only a link, and goes.
TEST(OutputFolders, CommitNeverDeletesAFileThisRunRead) {
  const bool was = protectFilesRead(true);  // as runApp does for every app
  TempDir dir("outfolder");
  std::filesystem::create_directories(dir.path() / "out" / "sub");
  test::writeText(dir.file("out/sub/read.cfg"), "Key : 1");
  test::writeText(dir.file("out/0000.obj"), "previous");
  test::writeText(dir.file("elsewhere.txt"), "read elsewhere");
  std::filesystem::create_symlink(dir.file("elsewhere.txt"), dir.file("out/link.txt"));
  readFileBytes(dir.file("elsewhere.txt"));
  {
    OutputFolder out(dir.file("out"), true);
    readTextFile(dir.file("out/sub/read.cfg"), 100, "a cfg file");
    out.write(dir.file("out/0000.obj"), "new");
    try {
      out.commit();
      ADD_FAILURE() << "no error";
    } catch (const Error& e) {
      EXPECT_EQ(std::string(e.what()), dir.file("out") + ": --Overwrite would delete " +
                                           dir.file("out/sub/read.cfg") +
                                           ", a file this run read; the folder is as it was");
    }
  }
  EXPECT_EQ(test::readText(dir.file("out/sub/read.cfg")), "Key : 1");
  EXPECT_EQ(test::readText(dir.file("out/0000.obj")), "previous");
  EXPECT_EQ(test::listFolder(dir.path() / "out"),
            (std::vector<std::string>{"0000.obj", "link.txt", "sub"}));
  std::filesystem::remove_all(dir.path() / "out" / "sub");
  test::writeText(dir.file("out/video.mp4"), "not really a video");
  noteFileRead(dir.file("out/video.mp4"));
  {
    OutputFolder out(dir.file("out"), true);
    out.write(dir.file("out/0000.obj"), "new");
    EXPECT_THROW(out.commit(), Error);
  }
  std::filesystem::remove(dir.path() / "out" / "video.mp4");
  {
    OutputFolder out(dir.file("out"), true);
    out.write(dir.file("out/0000.obj"), "new");
    out.commit();  // the link to a file read goes, the file stays
  }
  EXPECT_EQ(test::listFolder(dir.path() / "out"), (std::vector<std::string>{"0000.obj"}));
  EXPECT_EQ(test::readText(dir.file("elsewhere.txt")), "read elsewhere");
  protectFilesRead(was);
}

// Nor does an output file replace a file the run read (3dvo-import -c x/dataset.json -o x
// replaced the cfg it read with the dataset), under any name or link.
TEST(StagedOutputs, AFileThisRunReadIsNotReplaced) {
  const bool was = protectFilesRead(true);  // as runApp does for every app
  TempDir dir("staged-read");
  test::writeText(dir.file("settings.cfg"), "Key : 1");
  std::filesystem::create_symlink("settings.cfg", dir.file("link.cfg"));
  test::writeText(dir.file("other.txt"), "other");
  readTextFile(dir.file("settings.cfg"), 100, "a cfg file");
  for (const char* name : {"settings.cfg", "link.cfg", "./settings.cfg"}) {
    try {
      writeFileAtomic(dir.file(name), "overwritten");
      ADD_FAILURE() << name << ": no error";
    } catch (const Error& e) {
      EXPECT_EQ(std::string(e.what()),
                dir.file(name) + ": is a file this run read (an input); refusing to overwrite it");
    }
  }
  EXPECT_EQ(test::readText(dir.file("settings.cfg")), "Key : 1");
  writeFileAtomic(dir.file("other.txt"), "replaced");  // never read: replaced as asked
  EXPECT_EQ(test::readText(dir.file("other.txt")), "replaced");
  // A program using the library (protection off, the default) may rewrite what it read.
  protectFilesRead(false);
  writeFileAtomic(dir.file("settings.cfg"), "Key : 2");
  EXPECT_EQ(test::readText(dir.file("settings.cfg")), "Key : 2");
  protectFilesRead(was);
}

// frameOfPath inverts framePath exactly: the same padding, one conversion, "%%" a percent sign.
TEST(FramePattern, FrameOfPathInvertsFramePath) {
  for (const std::string pattern : {"a/%04d.png", "%d.obj", "x%%y/%3d-z.obj.gz"})
    for (const int frame : {0, 7, 42, 12345, -3, 2147483647})
      EXPECT_EQ(frameOfPath(pattern, framePath(pattern, frame)), frame) << pattern << " " << frame;
  EXPECT_EQ(frameOfPath("a/%04d.png", "a/7.png"), std::nullopt);  // other padding
  EXPECT_EQ(frameOfPath("a/%04d.png", "a/00007.png"), std::nullopt);
  EXPECT_EQ(frameOfPath("a/%04d.png", "b/0007.png"), std::nullopt);
  EXPECT_EQ(frameOfPath("a/%04d.png", "a/.png"), std::nullopt);
  EXPECT_EQ(frameOfPath("a/%04d.png", "a/00x7.png"), std::nullopt);
  EXPECT_EQ(frameOfPath("a/%d.png", "a/99999999999.png"), std::nullopt);  // beyond an int
  EXPECT_EQ(frameOfPath("x%%y/%d", "x%y/5"), 5);
}

// A sequence added as a pattern protects each of its frames from being an output, whether the
// file exists or not and under any spelling or link of its folder; other frames and other
// names are not inputs.
TEST(InputFilesTest, APatternProtectsEveryFrameOfTheSequence) {
  test::TempDir dir("input-pattern");
  std::filesystem::create_directories(dir.file("seq"));
  test::writeText(dir.file("seq/0003.png"), "three");
  std::filesystem::create_directory_symlink("seq", dir.file("link"));
  InputFiles inputs;
  inputs.addPattern(dir.file("seq/%04d.png"), 2, 5);  // frames 2 .. 6
  for (const std::string name :
       {"seq/0003.png", "seq/0006.png", "link/0002.png", "seq/../seq/0004.png"}) {
    try {
      inputs.checkOutput(dir.file(name));
      ADD_FAILURE() << name << " was not refused";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(": is the input "), std::string::npos) << e.what();
    }
  }
  for (const std::string name :
       {"seq/0001.png", "seq/0007.png", "seq/3.png", "seq/0003.jpg", "other/0003.png"})
    EXPECT_NO_THROW(inputs.checkOutput(dir.file(name))) << name;
  std::filesystem::create_symlink(dir.file("seq/0003.png"), dir.file("out.csv"));
  EXPECT_THROW(inputs.checkOutput(dir.file("out.csv")), Error);  // a link to frame 3
  EXPECT_EQ(test::readText(dir.file("seq/0003.png")), "three");
}

}  // namespace
}  // namespace tdvo
