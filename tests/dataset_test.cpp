// The dataset layout (dataset.json), PNG images and video input.
#include "common/media/dataset.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "common/core/error.h"
#include "common/core/file_io.h"
#include "common/media/png_io.h"
#include "common/media/video_reader.h"
#include "common/views/image.h"

using namespace tdvo;
namespace fs = std::filesystem;

namespace {

class TempFolder {
 public:
  explicit TempFolder(const std::string& tag)
      : path_(fs::temp_directory_path() / ("tdvo_" + tag + "_" + std::to_string(::getpid()))) {
    fs::remove_all(path_);
    fs::create_directories(path_);
  }
  ~TempFolder() { fs::remove_all(path_); }
  std::string str() const { return path_.string(); }
  std::string operator/(const std::string& name) const { return (path_ / name).string(); }

 private:
  fs::path path_;
};

Dataset smallDataset(const std::string& folder) {
  Dataset d;
  d.folder = folder;
  d.description = "test \"quoted\" description";
  d.firstFrame = 3;
  d.frameCount = 2;
  d.frameRate = 30;
  d.up = Vec3d{0, 0, -1};
  d.meshes = "meshes/%04d.obj";
  for (int i = 0; i < 2; ++i) {
    DatasetCamera dc;
    Camera& c = dc.camera;
    c.name = "cam" + std::to_string(i);
    c.width = 8;
    c.height = 6;
    c.fx = 10.25 + i;
    c.fy = 10.5;
    c.cx = 3.5;
    c.cy = 2.5;
    c.distortion = {-0.1 * i, 0.01, 0, 0, 0};
    c.R = rotationFromRodrigues({0.1, 0.2 * i, 0.3});
    c.t = {0.1, -2, 1.0 / 3.0};
    dc.images = c.name + "/%02d.png";
    dc.masks = c.name + "/mask.png";  // a still mask for every frame
    d.cameras.push_back(dc);
  }
  return d;
}

std::string text(const std::string& path) {
  const std::vector<uint8_t> bytes = readFileBytes(path);
  return std::string(bytes.begin(), bytes.end());
}

void expectError(const std::string& json, const std::string& fragment) {
  try {
    parseDataset(json, "d.json", ".");
    ADD_FAILURE() << "no error for: " << json;
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos)
        << "message '" << e.what() << "' lacks '" << fragment << "'";
  }
}

const char* kMinimal = R"({"format": "3dvo-dataset", "version": 1, "frames": {"count": 1},
  "cameras": [{"name": "a", "width": 4, "height": 3, "fx": 1, "fy": 1, "cx": 1, "cy": 1,
               "R": [[1,0,0],[0,1,0],[0,0,1]], "t": [0,0,0], "images": "a.png"}]})";

std::string replaced(std::string s, const std::string& from, const std::string& to) {
  const size_t at = s.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return s.replace(at, from.size(), to);
}

}  // namespace

TEST(Dataset, WriteReadRoundTripIsExact) {
  TempFolder dir("dataset_rt");
  const Dataset d = smallDataset(dir.str());
  writeDataset(d, dir.str());
  const Dataset r = readDataset(dir.str());
  EXPECT_EQ(r.description, d.description);
  EXPECT_EQ(r.firstFrame, 3);
  EXPECT_EQ(r.frameCount, 2);
  EXPECT_EQ(r.frameRate, 30);
  ASSERT_TRUE(r.up.has_value());
  EXPECT_EQ(*r.up, (Vec3d{0, 0, -1}));
  ASSERT_EQ(r.cameras.size(), 2u);
  for (size_t i = 0; i < 2; ++i) {
    const Camera &a = d.cameras[i].camera, &b = r.cameras[i].camera;
    EXPECT_EQ(a.name, b.name);
    EXPECT_EQ(a.width, b.width);
    EXPECT_EQ(a.fx, b.fx);  // doubles survive the JSON text exactly
    EXPECT_EQ(a.R, b.R);
    EXPECT_EQ(a.t, b.t);
    EXPECT_EQ(a.distortion.k1, b.distortion.k1);
    EXPECT_EQ(r.cameras[i].images, d.cameras[i].images);
  }
  EXPECT_EQ(r.framePath(r.cameras[0].images, 1), dir / "cam0/04.png");
  EXPECT_EQ(r.framePath(r.cameras[1].masks, 1), dir / "cam1/mask.png");
  EXPECT_EQ(r.framePath(r.meshes, 0), dir / "meshes/0003.obj");
  // Formatting is deterministic and stable under a read/write cycle.
  EXPECT_EQ(formatDataset(r, dir.str()), text(dir / "dataset.json"));
  // The sign of a zero given is kept (it was written as 0.0).
  Dataset z = r;
  z.cameras[0].camera.t[0] = -0.0;
  z.up = Vec3d{-0.0, 1, 0};
  const std::string zeros = formatDataset(z, dir.str());
  EXPECT_NE(zeros.find("\"up\": [-0.0, 1.0, 0.0]"), std::string::npos) << zeros;
  EXPECT_NE(zeros.find("\"t\": [-0.0, "), std::string::npos) << zeros;
}

TEST(Dataset, PathsAreRewrittenRelativeToTheOutputFolder) {
  TempFolder dir("dataset_rel");
  Dataset d = smallDataset(dir / "source");
  d.cameras[0].video = "/abs/video.avi";
  d.cameras[0].images.clear();
  d.cameras[0].masks.clear();
  writeDataset(d, dir / "out/nested");
  const Dataset r = readDataset(dir / "out/nested/dataset.json");
  EXPECT_EQ(r.cameras[0].video, "/abs/video.avi");
  EXPECT_EQ(r.cameras[1].images, "../../source/cam1/%02d.png");
  EXPECT_EQ(fs::path(r.framePath(r.cameras[1].images, 0)).lexically_normal(),
            fs::path(dir / "source/cam1/03.png"));
}

// A folder name holding '%' (here "take%d") and an output folder that is a symbolic link: the
// written dataset.json reads back to the same files (image and mesh sequences, a still mask, a
// video, whose path is literal). Before, the folder's '%d' became a second frame conversion,
// and paths were relative to the link rather than to its target.
TEST(Dataset, WrittenPathsReadBackToTheSameFiles) {
  TempFolder dir("dataset_percent");
  Dataset d = smallDataset(dir / "take%d");
  d.cameras[1].images.clear();
  d.cameras[1].video = "v%d.avi";  // literal
  fs::create_directories(fs::path(dir / "real/deep"));
  fs::create_directory_symlink(fs::path(dir / "real/deep"), fs::path(dir / "link"));
  writeDataset(d, dir / "link");
  const Dataset r = readDataset(dir / "link/dataset.json");
  const auto same = [](const std::string& a, const std::string& b) {
    return fs::weakly_canonical(a) == fs::weakly_canonical(b);
  };
  EXPECT_EQ(r.cameras[0].images, "../../take%%d/cam0/%02d.png");
  EXPECT_TRUE(same(r.framePath(r.cameras[0].images, 1), dir / "take%d/cam0/04.png"))
      << r.framePath(r.cameras[0].images, 1);
  EXPECT_TRUE(same(r.framePath(r.cameras[0].masks, 0), dir / "take%d/cam0/mask.png"))
      << r.framePath(r.cameras[0].masks, 0);
  EXPECT_TRUE(same(r.framePath(r.meshes, 0), dir / "take%d/meshes/0003.obj"))
      << r.framePath(r.meshes, 0);
  EXPECT_TRUE(same(r.resolve(r.cameras[1].video), dir / "take%d/v%d.avi"))
      << r.resolve(r.cameras[1].video);
}

// JSON text is UTF-8: a name that is not (a folder named with byte 0xFF) cannot be written, and
// that is an Error saying so (it was an internal error from the JSON library).
TEST(Dataset, ANameThatIsNotUtf8IsAnErrorWhenWritten) {
  TempFolder dir("dataset_utf8");
  const Dataset d = smallDataset(dir / "take\xff");
  try {
    formatDataset(d, dir.str());
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("take\\xff/"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("is not UTF-8 text"), std::string::npos) << e.what();
  }
}

TEST(Dataset, StructuralErrorsNameTheField) {
  EXPECT_NO_THROW(parseDataset(kMinimal, "d.json", "."));
  expectError("{", "d.json: invalid JSON");
  expectError(replaced(kMinimal, "\"version\": 1", "\"version\": 2"), "version 2 is not supported");
  expectError(replaced(kMinimal, "\"fx\": 1,", ""), "cameras[0]: missing field \"fx\"");
  expectError(replaced(kMinimal, "\"fx\": 1", "\"fx\": -1"), "fx and fy must be positive");
  expectError(replaced(kMinimal, "\"fx\": 1", "\"fx\": \"1\""),
              "cameras[0].fx: must be a finite number");
  expectError(replaced(kMinimal, "\"cy\": 1", "\"cy\": 1, \"colour\": 2"),
              "cameras[0]: unknown field \"colour\"");
  expectError(replaced(kMinimal, "[0,1,0]", "[0,2,0]"), "cameras[0].R: not a rotation");
  expectError(replaced(kMinimal, "[0,0,1]]", "[0,0,-1]]"), "cameras[0].R: not a rotation");
  expectError(
      replaced(kMinimal, "\"images\": \"a.png\"", "\"images\": \"a.png\", \"video\": \"v.mp4\""),
      "exactly one of \"images\" and \"video\"");
  expectError(replaced(kMinimal, "\"images\": \"a.png\"", "\"images\": \"a%d%d.png\""),
              "more than one frame-number conversion");
  expectError(replaced(kMinimal, "\"width\": 4", "\"width\": 4.5"),
              "cameras[0].width: must be an integer");
  expectError(replaced(kMinimal, "{\"count\": 1}", "{\"count\": 0}"),
              "frames.count: 0 out of range");
  expectError(replaced(kMinimal, "{\"count\": 1}", "{\"count\": 9223372036854775808}"),
              "frames.count: 9223372036854775808 out of range");  // not as a negative number
  const std::string two = replaced(kMinimal, "\"images\": \"a.png\"}",
                                   "\"images\": \"a.png\"}, {\"name\": \"a\", \"width\": 4, "
                                   "\"height\": 3, \"fx\": 1, \"fy\": 1, \"cx\": 1, \"cy\": 1, "
                                   "\"R\": [[1,0,0],[0,1,0],[0,0,1]], \"t\": [0,0,0], "
                                   "\"images\": \"b.png\"}");
  expectError(two, "camera name 'a' repeats");
  // Values whose squares overflow or underflow (the renderer normalises up, measures t).
  expectError(replaced(kMinimal, "\"t\": [0,0,0]", "\"t\": [1e300,0,1e300]"),
              "cameras[0].t: components must be within 1e150 in magnitude");
  const std::string withUp = replaced(kMinimal, "\"frames\"", "\"up\": [0,1,0], \"frames\"");
  EXPECT_NO_THROW(parseDataset(withUp, "d.json", "."));
  for (const char* up : {"[1e160,1e160,1e160]", "[1e-160,1e-160,1e-160]"})
    expectError(replaced(withUp, "[0,1,0]", up),
                "d.json: up: its largest component must be between 1e-150 and 1e150");
  expectError(replaced(withUp, "[0,1,0]", "[0,0,0]"), "up must not be the zero vector");
}

// Camera names name output folders: anything but one plain file name is refused, so that no name
// can choose where an app writes (../.., absolute names, separators, control characters).
TEST(Dataset, CameraNamesMustBeFileNames) {
  for (const char* json : {"..", ".", "../..", "../../escape", "/tmp/x", "a/b", "a\\\\b", "a\\tb",
                           "a\\u0000b", "a\\u007fb"})
    expectError(replaced(kMinimal, "\"name\": \"a\"", std::string("\"name\": \"") + json + "\""),
                "cameras[0].name: camera name '");
  expectError(replaced(kMinimal, "\"name\": \"a\"", "\"name\": \"" + std::string(256, 'n') + "\""),
              "cannot name a folder");
  // A tab is shown escaped: the error stays one line.
  expectError(replaced(kMinimal, "\"name\": \"a\"", "\"name\": \"a\\tb\""), "'a\\x09b'");
  for (const std::string fine : {"cam0", "Camera 1", "..a", "a.b", "dinoSR0001"})
    EXPECT_NO_THROW(checkCameraName(fine, "x")) << fine;
  EXPECT_NO_THROW(checkCameraName(std::string(255, 'n'), "x"));
}

TEST(Dataset, FileValidationAndFrameReading) {
  TempFolder dir("dataset_files");
  Dataset d = smallDataset(dir.str());
  d.meshes.clear();
  fs::create_directories(dir / "cam0");
  fs::create_directories(dir / "cam1");
  for (int i = 0; i < 2; ++i) {
    for (int f = 3; f <= 4; ++f) {
      Image image(8, 6, 3, static_cast<uint8_t>(10 * f + i));
      image.at(1, 2, 0) = 200;
      writePng(dir / ("cam" + std::to_string(i) + "/0" + std::to_string(f) + ".png"), image);
    }
    Image mask(8, 6, 1, 0);
    mask.at(3, 3) = 255;
    mask.at(4, 3) = 100;  // below the 128 threshold: background
    writePng(dir / ("cam" + std::to_string(i) + "/mask.png"), mask);
  }
  EXPECT_NO_THROW(validateDatasetFiles(d));
  CameraFrames frames(d, 1);
  const Image f1 = frames.frame(1);
  EXPECT_EQ(f1.channels, 3);
  EXPECT_EQ(f1.at(0, 0, 0), 41);
  EXPECT_EQ(f1.at(1, 2, 0), 200);
  ASSERT_TRUE(frames.hasMasks());
  const Image m = frames.mask(0);
  EXPECT_EQ(m.at(3, 3), 255);
  EXPECT_EQ(m.at(4, 3), 0);
  EXPECT_THROW(frames.frame(2), Error);  // only two frames

  // A wrong size and a missing frame are reported with the file's name.
  writePng(dir / "cam0/04.png", Image(9, 6, 3));
  try {
    validateDatasetFiles(d);
    ADD_FAILURE() << "size mismatch not detected";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("cam0/04.png: image is 9x6 but camera 'cam0' is 8x6"),
              std::string::npos)
        << e.what();
  }
  fs::remove(dir / "cam0/04.png");
  try {
    validateDatasetFiles(d);
    ADD_FAILURE() << "missing frame not detected";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("cam0/04.png"), std::string::npos) << e.what();
  }
}

TEST(Image, PngRoundTripAllChannelCounts) {
  TempFolder dir("png");
  for (int channels = 1; channels <= 4; ++channels) {
    Image image(13, 7, channels);
    for (size_t i = 0; i < image.pixels.size(); ++i)
      image.pixels[i] = static_cast<uint8_t>(i * 37 + channels);
    const std::string path = dir / ("i" + std::to_string(channels) + ".png");
    writePng(path, image);
    EXPECT_EQ(readPng(path), image);
    EXPECT_EQ(encodePng(image), encodePng(image));
    // The fast setting: other bytes, the same pixels.
    const std::vector<uint8_t> fast = encodePng(image, PngEffort::kFast);
    EXPECT_NE(fast, encodePng(image));
    EXPECT_EQ(decodePng(fast, "fast.png"), image);
    int w = 0, h = 0;
    readPngSize(path, w, h);
    EXPECT_EQ(w, 13);
    EXPECT_EQ(h, 7);
  }
  // Corrupt and truncated files give errors naming the file.
  std::vector<uint8_t> bytes = encodePng(Image(20, 20, 3, 7));
  EXPECT_THROW(decodePng(std::vector<uint8_t>(bytes.begin(), bytes.begin() + 40), "cut.png"),
               Error);
  bytes[8 + 8 + 1] ^= 0xff;  // IHDR width, breaks its CRC
  try {
    decodePng(bytes, "bad.png");
    ADD_FAILURE();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("bad.png"), std::string::npos);
  }
  EXPECT_THROW(decodePng({1, 2, 3}, "tiny.png"), Error);
}

TEST(Image, ConvertChannels) {
  Image rgba(2, 1, 4);
  rgba.pixels = {255, 0, 0, 10, 0, 0, 255, 20};
  const Image grey = convertChannels(rgba, 1);
  EXPECT_EQ(grey.pixels, (std::vector<uint8_t>{77, 29}));
  const Image rgb = convertChannels(grey, 3);
  EXPECT_EQ(rgb.pixels, (std::vector<uint8_t>{77, 77, 77, 29, 29, 29}));
  const Image ga = convertChannels(rgba, 2);
  EXPECT_EQ(ga.pixels, (std::vector<uint8_t>{77, 10, 29, 20}));
}

TEST(Video, ReadsTheRealCameraVideos) {
  const std::string video = std::string(TDVO_SHARED_DATA_DIR) + "/multiview/uu-4cam/cam1/video.avi";
  if (!fs::exists(video))
    GTEST_SKIP() << "real data not found: " << video << " (../shared/data absent)";
  VideoReader reader(video);
  EXPECT_EQ(reader.width(), 644);
  EXPECT_EQ(reader.height(), 486);
  EXPECT_NEAR(reader.frameRate(), 25, 1e-9);
  Image f0, f1, f2;
  ASSERT_TRUE(reader.read(f0));
  ASSERT_TRUE(reader.read(f1));
  ASSERT_TRUE(reader.read(f2));
  EXPECT_EQ(f0.channels, 3);
  EXPECT_EQ(reader.position(), 3);
  // A dataset camera that names the video reads the same frames, in and out of order.
  Dataset d;
  d.frameCount = 3;
  DatasetCamera dc;
  dc.camera.name = "cam1";
  dc.camera.width = 644;
  dc.camera.height = 486;
  dc.video = video;
  d.cameras.push_back(dc);
  EXPECT_NO_THROW(validateDatasetFiles(d));
  CameraFrames frames(d, 0);
  EXPECT_EQ(frames.frame(2), f2);
  EXPECT_EQ(frames.frame(0), f0);
  EXPECT_EQ(frames.frame(1), f1);
  EXPECT_THROW(
      VideoReader(std::string(TDVO_SHARED_DATA_DIR) + "/multiview/uu-4cam/cam1/config.xml"), Error);
}
