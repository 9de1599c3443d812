// Texture coding on threads (issue 10): the cameras of a GOM are coded, and decoded, in
// parallel, and nothing observable depends on the thread count. For Threads = 1, 2 and 4 the
// encoder gives the same stream and the same callbacks (same order, on the calling thread),
// the decoder gives the same frames, pictures and shapes in the same order, and a damaged
// stream gives the same error after the same callbacks. Input: the default synthetic rig
// (3dvo-synth -o DIR: 8 cameras of 320x240, 10 frames of the deforming blob).
#include <gtest/gtest.h>

#include <filesystem>
#include <functional>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "bitstream/camera_parameters.h"
#include "bitstream/syntax.h"
#include "bitstream/units.h"
#include "common/core/error.h"
#include "common/core/gom_list.h"
#include "common/core/md5.h"
#include "common/media/dataset.h"
#include "common/media/png_io.h"
#include "common/media/yuv.h"
#include "common/views/image.h"
#include "decoder/stream_decoder.h"
#include "decoder/texture/h264_decoder.h"
#include "encoder/sequence_encoder.h"
#include "encoder/texture_encoder.h"
#include "tests/test_support.h"
#include "tools/multiview/synth_rig.h"

namespace tdvo {
namespace {

const int kThreadCounts[] = {1, 2, 4};

// The rig, written once for the suite.
struct Rig {
  test::TempDir dir{"texture-threads"};
  Dataset dataset;
  std::vector<Mesh> frames;
};

const Rig& rig() {
  static Rig* r = [] {
    auto* rig = new Rig;
    SynthParams synth;  // 3dvo-synth's defaults
    synth.output = rig->dir.file("rig");
    writeSyntheticDataset(synth);
    rig->dataset = readDataset(synth.output);
    rig->frames = readDatasetFrames(rig->dataset, 0, rig->dataset.frameCount);
    return rig;
  }();
  return *r;
}

std::string shapeLine(int frame, int camera, const Image& shape) {
  Md5 md5;
  md5.update(shape.pixels.data(), shape.pixels.size());
  return "shape frame=" + std::to_string(frame) + " cam=" + std::to_string(camera) + " " +
         toHex(md5.finish());
}

// What a run hands to its callbacks, in order, and whether all calls came on the calling thread.
struct Calls {
  std::vector<std::string> lines;
  bool onCallingThread = true;
  std::thread::id caller = std::this_thread::get_id();
  void frame(int frame, const IntMesh& mesh) {
    onCallingThread = onCallingThread && std::this_thread::get_id() == caller;
    lines.push_back(geometryHashLine(frame, mesh));
  }
  void texture(int frame, int camera, const YuvPicture& picture, const Image& shape) {
    onCallingThread = onCallingThread && std::this_thread::get_id() == caller;
    lines.push_back(textureHashLine(frame, camera, picture));
    lines.push_back(shapeLine(frame, camera, shape));
  }
};

struct Encoded {
  std::vector<uint8_t> stream;
  Calls calls;
};

// GOMs of 4 frames (so GOMs run in parallel too, and the last one is shorter), 8 cameras.
Encoded encode(int threads, const std::function<void(EncoderParams&)>& tweak = {}) {
  const Rig& r = rig();
  EncoderParams params;
  params.dataset = r.dataset.folder;
  params.frameCount = static_cast<int>(r.frames.size());
  params.gomSize = 4;
  params.texturePreset = "fast";
  params.threads = threads;
  if (tweak) tweak(params);
  TextureEncoder textures(params, r.dataset, r.frames);
  Encoded e;
  e.stream = encodeSequence(
                 params, gridForSequence(r.frames, params.gridBits), r.frames, {},
                 [&](int frame, const IntMesh& mesh) { e.calls.frame(frame, mesh); }, &textures,
                 [&](int frame, int camera, const YuvPicture& picture, const Image& shape) {
                   e.calls.texture(frame, camera, picture, shape);
                 })
                 .stream;
  return e;
}

// Decodes `stream` on `threads` threads; `error` gets the message of the Error it throws.
Calls decode(const std::vector<uint8_t>& stream, int threads, std::string* error = nullptr) {
  Calls calls;
  StreamDecoder decoder(stream.data(), stream.size(), "rig.3dvo");
  decoder.setPictureDecoder(makeH264Decoder);
  decoder.setThreads(threads);
  try {
    decoder.decode([&](int frame, const IntMesh& mesh) { calls.frame(frame, mesh); },
                   [&](int frame, int camera, const YuvPicture& picture, const Image& shape) {
                     calls.texture(frame, camera, picture, shape);
                   });
  } catch (const Error& e) {
    if (!error) throw;
    *error = e.what();
  }
  return calls;
}

const Encoded& sequentialEncoding() {
  static const Encoded e = encode(1);
  return e;
}

// The texture boxes do not depend on the order in which the frames are shown, nor on how
// many threads show them at once; they are the union of the frames' boxes, and they are what
// the encoder codes with.
TEST(TextureThreads, TextureBoxesDoNotDependOnTheOrderOfTheFrames) {
  const Rig& r = rig();
  EncoderParams params;
  params.frameCount = static_cast<int>(r.frames.size());
  TextureBoxFinder inOrder(params, r.dataset, r.frames.size());
  for (const Mesh& mesh : r.frames)
    inOrder.add(mesh);
  const std::vector<TextureBox> boxes = inOrder.boxes();
  ASSERT_EQ(boxes.size(), r.dataset.cameras.size());

  TextureBoxFinder reversed(params, r.dataset, r.frames.size());
  for (size_t k = r.frames.size(); k-- > 0;)
    reversed.add(r.frames[k]);
  EXPECT_EQ(reversed.boxes(), boxes);

  TextureBoxFinder concurrent(params, r.dataset, r.frames.size());
  std::vector<std::thread> workers;
  for (size_t t = 0; t < 3; ++t)
    workers.emplace_back([&, t] {
      for (size_t k = t; k < r.frames.size(); k += 3)
        concurrent.add(r.frames[k]);
    });
  for (std::thread& w : workers)
    w.join();
  EXPECT_EQ(concurrent.boxes(), boxes);

  // Only the first frame: a box inside the union, and smaller in some camera (the object
  // moves).
  TextureBoxFinder first(params, r.dataset, r.frames.size());
  first.add(r.frames[0]);
  bool smaller = false;
  for (size_t c = 0; c < boxes.size(); ++c) {
    EXPECT_EQ(unite(first.boxes()[c], boxes[c]), boxes[c]) << "camera " << c;
    smaller |= !(first.boxes()[c] == boxes[c]);
  }
  EXPECT_TRUE(smaller);

  // The encoder's cameras carry these boxes.
  const TextureEncoder encoder(params, r.dataset, r.frames);
  for (size_t c = 0; c < boxes.size(); ++c)
    EXPECT_EQ(textureBox(encoder.cameras()[c]), boxes[c]) << "camera " << c;
}

TEST(TextureThreads, EncoderOutputIsTheSameForAnyThreadCount) {
  const Encoded& one = sequentialEncoding();
  // 10 frames: a geometry line each; 8 cameras: a texture and a shape line per camera-frame.
  ASSERT_EQ(one.calls.lines.size(), 10u + 10u * 8u * 2u);
  EXPECT_TRUE(one.calls.onCallingThread);
  for (int threads : kThreadCounts) {
    const Encoded e = encode(threads);
    EXPECT_EQ(e.stream, one.stream) << "Threads=" << threads;
    EXPECT_EQ(e.calls.lines, one.calls.lines) << "Threads=" << threads;
    EXPECT_TRUE(e.calls.onCallingThread) << "Threads=" << threads;
  }
}

TEST(TextureThreads, DecoderOutputIsTheSameForAnyThreadCountAndEqualsTheEncoders) {
  const Encoded& e = sequentialEncoding();
  for (int threads : kThreadCounts) {
    const Calls d = decode(e.stream, threads);
    EXPECT_EQ(d.lines, e.calls.lines) << "Threads=" << threads;
    EXPECT_TRUE(d.onCallingThread) << "Threads=" << threads;
  }
}

// Intra GOMs whose I meshes are coarser than the grid (im_quant_step 3): the texture pass
// decodes each I mesh again from the payload it kept, with its step, and so makes the
// encoder's shapes (with step 1 the mesh would be a third of its size, and its shapes others).
TEST(TextureThreads, IntraIMeshQuantStepShapesAreTheEncoders) {
  const Encoded e = encode(1, [](EncoderParams& p) {
    p.pmeshMode = PMeshMode::kIntra;
    p.iMeshQuantStep = 3;
  });
  ASSERT_EQ(e.calls.lines.size(), 10u + 10u * 8u * 2u);
  EXPECT_EQ(decode(e.stream, 1).lines, e.calls.lines);
  EXPECT_EQ(decode(e.stream, 2).lines, e.calls.lines);
}

// The stream's units, to damage one and write them back.
struct StreamUnits {
  std::vector<uint8_t> types;
  std::vector<std::vector<uint8_t>> payloads;
  explicit StreamUnits(const std::vector<uint8_t>& stream) {
    UnitReader reader(stream.data(), stream.size(), "rig.3dvo");
    UnitView unit;
    while (reader.next(unit)) {
      types.push_back(unit.type);
      payloads.emplace_back(unit.payload, unit.payload + unit.size);
    }
  }
  // The index of the TEXTURE unit of `camera` in `frame`.
  size_t texture(uint32_t frame, uint16_t camera) const {
    for (size_t i = 0; i < types.size(); ++i) {
      if (types[i] != static_cast<uint8_t>(UnitType::kTexture)) continue;
      const TextureUnit tx = parse(i);
      if (tx.tx_frame == frame && tx.tx_camera == camera) return i;
    }
    throw std::logic_error("no such texture unit");
  }
  TextureUnit parse(size_t i) const {
    ByteReader reader(payloads[i].data(), payloads[i].size(), "unit", 0);
    TextureUnit tx;
    transfer(reader, tx);
    return tx;
  }
  void replace(size_t i, TextureUnit tx) { payloads[i] = serialise(std::move(tx)); }
  std::vector<uint8_t> stream(size_t unitCount) const {
    UnitWriter writer;
    for (size_t i = 0; i < unitCount; ++i)
      writer.write(static_cast<UnitType>(types[i]), payloads[i]);
    return writer.bytes();
  }
  std::vector<uint8_t> stream() const { return stream(types.size()); }
};

// A broken picture (camera 2 of frame 5) and, two cameras later in the same frame, a unit of the
// wrong camera: the sequential decoder meets the picture first, and so must every thread count,
// although the later unit is read (and found wrong) while the picture may still be decoding.
// A stream cut inside a GOM's texture units fails at the cut, after every earlier picture.
TEST(TextureThreads, DamagedStreamsGiveTheSameErrorAfterTheSameCallbacks) {
  const StreamUnits units(sequentialEncoding().stream);
  struct Case {
    std::string what, error;  // the error names this
    std::vector<uint8_t> stream;
  };
  std::vector<Case> cases;
  {
    StreamUnits damaged = units;
    const size_t picture = damaged.texture(5, 2), wrongCamera = damaged.texture(5, 4);
    TextureUnit tx = damaged.parse(picture);
    tx.tx_access_unit.resize(tx.tx_access_unit.size() / 2);
    for (size_t b = 8; b < tx.tx_access_unit.size(); ++b)
      tx.tx_access_unit[b] = static_cast<uint8_t>(0xff - tx.tx_access_unit[b]);
    damaged.replace(picture, tx);
    tx = damaged.parse(wrongCamera);
    tx.tx_camera = 7;
    damaged.replace(wrongCamera, tx);
    cases.push_back({"broken picture, then a wrong camera", "H.264", damaged.stream()});
  }
  cases.push_back({"cut before camera 3 of frame 6", "texture of camera 3, frame 6",
                   units.stream(units.texture(6, 3))});

  for (const auto& [what, errorNames, stream] : cases) {
    std::string expectedError;
    const Calls expected = decode(stream, 1, &expectedError);
    EXPECT_NE(expectedError.find(errorNames), std::string::npos) << what << ": " << expectedError;
    EXPECT_GT(expected.lines.size(), 0u) << what;
    for (int threads : kThreadCounts) {
      std::string error;
      const Calls calls = decode(stream, threads, &error);
      EXPECT_EQ(error, expectedError) << what << ", Threads=" << threads;
      EXPECT_EQ(calls.lines, expected.lines) << what << ", Threads=" << threads;
    }
  }
}

// A camera frame missing in the middle of the sequence: every thread count stops with the
// sequential run's error (naming the file), after the same callbacks, although other cameras'
// later pictures may already be coded when it is found.
TEST(TextureThreads, EncoderErrorsAreTheSameForAnyThreadCount) {
  test::TempDir dir("texture-threads-missing");
  const std::string copy = dir.file("rig");
  std::filesystem::copy(rig().dataset.folder, copy, std::filesystem::copy_options::recursive);
  Dataset damaged = readDataset(copy);
  const std::string missing = damaged.framePath(damaged.cameras[3].images, 6);
  ASSERT_TRUE(std::filesystem::remove(missing));
  std::string expectedError;
  std::vector<std::string> expectedLines;
  for (int threads : kThreadCounts) {
    EncoderParams params;
    params.dataset = copy;
    params.frameCount = static_cast<int>(rig().frames.size());
    params.gomSize = 4;
    params.texturePreset = "fast";
    params.threads = threads;
    TextureEncoder textures(params, damaged, rig().frames);
    Calls calls;
    std::string error;
    try {
      encodeSequence(
          params, gridForSequence(rig().frames, params.gridBits), rig().frames, {},
          [&](int frame, const IntMesh& mesh) { calls.frame(frame, mesh); }, &textures,
          [&](int frame, int camera, const YuvPicture& picture, const Image& shape) {
            calls.texture(frame, camera, picture, shape);
          });
    } catch (const Error& e) {
      error = e.what();
    }
    if (threads == 1) {
      EXPECT_NE(error.find(missing), std::string::npos) << error;
      expectedError = error;
      expectedLines = calls.lines;
    }
    EXPECT_EQ(error, expectedError) << "Threads=" << threads;
    EXPECT_EQ(calls.lines, expectedLines) << "Threads=" << threads;
  }
}

// Through the apps: 3dvo-enc and 3dvo-dec with Threads = 1 and 3 give the same stream, the same
// MD5 lines and the same decoded files (meshes, PNG frames, dataset.json, gom_starts.txt).
TEST(TextureThreads, AppsGiveTheSameFilesForAnyThreadCount) {
  test::TempDir dir("texture-threads-apps");
  const std::string bin = TDVO_BIN_DIR;
  std::string firstLog;
  for (const std::string threads : {"1", "3"}) {
    const auto enc = test::run(
        dir, bin + "/3dvo-enc",
        {"--Dataset=" + rig().dataset.folder, "--FrameCount=5", "--GOMSize=3",
         "--TexturePreset=fast", "--Threads=" + threads, "--BitstreamFile=t" + threads + ".3dvo"});
    ASSERT_EQ(enc.exitCode, 0) << enc.err;
    test::writeText(dir.file("enc.log"), enc.out);
    const auto dec = test::run(dir, bin + "/3dvo-dec",
                               {"-i", "t" + threads + ".3dvo", "-o", "out" + threads,
                                "--Threads=" + threads, "--verify", "enc.log"});
    ASSERT_EQ(dec.exitCode, 0) << dec.err;
    if (threads == "1") firstLog = enc.out;
    EXPECT_EQ(test::linesStartingWith(enc.out, "MD5 "), test::linesStartingWith(firstLog, "MD5 "));
  }
  EXPECT_EQ(test::readBytes(dir.file("t1.3dvo")), test::readBytes(dir.file("t3.3dvo")));
  size_t files = 0;
  for (const auto& entry : std::filesystem::recursive_directory_iterator(dir.file("out1"))) {
    if (!entry.is_regular_file()) continue;
    const auto relative = std::filesystem::relative(entry.path(), dir.file("out1"));
    const std::string other = (dir.path() / "out3" / relative).string();
    ASSERT_TRUE(std::filesystem::exists(other)) << relative;
    EXPECT_EQ(test::readBytes(entry.path().string()), test::readBytes(other)) << relative;
    ++files;
  }
  EXPECT_EQ(files, 5u + 5u * 8u + 2u);  // OBJ frames, PNG frames, dataset.json, gom_starts.txt
  // GOMSize 3 over 5 frames: GOMs start at frames 0 and 3 (read as 3dvo-render reads it).
  EXPECT_EQ(readGomStarts(dir.file("out1/gom_starts.txt")), (std::vector<int>{0, 3}));

  // PngCompression=small (the default is fast): other PNG bytes, the same pixels.
  const auto small =
      test::run(dir, bin + "/3dvo-dec", {"-i", "t1.3dvo", "-o", "small", "--PngCompression=small"});
  ASSERT_EQ(small.exitCode, 0) << small.err;
  for (int camera = 0; camera < 8; ++camera) {
    const std::string frame = "/cam" + std::to_string(camera) + "/0004.png";
    const std::vector<uint8_t> fast = test::readBytes(dir.file("out1" + frame));
    const std::vector<uint8_t> smaller = test::readBytes(dir.file("small" + frame));
    EXPECT_NE(fast, smaller) << frame;
    EXPECT_EQ(decodePng(fast, frame), decodePng(smaller, frame)) << frame;
  }
}

}  // namespace
}  // namespace tdvo
