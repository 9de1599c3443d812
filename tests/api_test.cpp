// The public API (docs/api.md): tdvo::Decoder (pull-style, file or memory, seek) against the
// conformance streams and the push-style StreamDecoder, and tdvo::Encoder (frames from memory)
// against the streams 3dvo-enc made.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "bitstream/units.h"
#include "common/core/error.h"
#include "common/core/gltf_io.h"
#include "common/core/md5.h"
#include "common/core/mesh_io.h"
#include "common/core/sequence.h"
#include "decoder/decoder.h"
#include "decoder/stream_decoder.h"
#include "decoder/texture/h264_decoder.h"
#include "encoder/encoder.h"
#include "encoder/input_frames.h"
#include "encoder/sequence_encoder.h"
#include "stream_units.h"
#include "test_support.h"

using namespace tdvo;
using namespace tdvo::test;
namespace fs = std::filesystem;

namespace {

const fs::path kConformance = fs::path(TDVO_SOURCE_DIR) / "conformance";

std::vector<std::string> conformanceStreams() {
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(kConformance / "streams"))
    if (entry.path().extension() == ".3dvo") names.push_back(entry.path().stem().string());
  std::sort(names.begin(), names.end());
  return names;
}

std::string streamPath(const std::string& name) {
  return (kConformance / "streams" / (name + ".3dvo")).string();
}

// The log's lines of one kind: "geometry=" or " texture ".
std::vector<std::string> logLines(const std::string& name, const std::string& kind) {
  std::vector<std::string> out;
  for (const std::string& line :
       lines(readText((kConformance / "streams" / (name + ".md5")).string())))
    if (line.find(kind) != std::string::npos) out.push_back(line);
  return out;
}

struct Pulled {
  std::vector<std::string> geometry, texture;
  std::vector<DecodedFrame> frames;
};

// Every frame next() gives, from where the decoder stands.
Pulled pullAll(Decoder& decoder, bool keepFrames = false) {
  Pulled out;
  DecodedFrame frame;
  while (decoder.next(frame)) {
    out.geometry.push_back(frame.geometryHashLine());
    for (const DecodedTexture& t : frame.textures)
      out.texture.push_back(textureHashLine(static_cast<int>(frame.number), t.camera, t.picture));
    if (keepFrames) out.frames.push_back(frame);
  }
  return out;
}

}  // namespace

// Every conformance stream, from the file and from memory, gives the MD5 lines of its log:
// geometry lines in order, and (with the H.264 picture decoder) texture lines in order.
TEST(DecoderApi, ConformanceStreamsGiveTheirMd5Lines) {
  const std::vector<std::string> names = conformanceStreams();
  ASSERT_GE(names.size(), 10u);
  for (const std::string& name : names) {
    SCOPED_TRACE(name);
    Decoder fromFile = Decoder::openFile(streamPath(name));
    fromFile.setPictureDecoder(makeH264Decoder);
    const Pulled a = pullAll(fromFile);
    EXPECT_EQ(a.geometry, logLines(name, "geometry="));
    EXPECT_EQ(a.texture, logLines(name, " texture "));
    EXPECT_EQ(a.geometry.size(), fromFile.info().frameCount);

    const std::vector<uint8_t> bytes = readBytes(streamPath(name));
    Decoder fromMemory = Decoder::openMemory(bytes.data(), bytes.size(), name, false);
    const Pulled b = pullAll(fromMemory);  // no picture decoder: geometry only
    EXPECT_EQ(b.geometry, a.geometry);
    EXPECT_TRUE(b.texture.empty());
  }
}

// The header as the push-style decoder reads it; the GOM starts as it finds them; float
// positions are the grid's.
TEST(DecoderApi, HeaderGomStartsAndPositions) {
  for (const std::string& name : conformanceStreams()) {
    SCOPED_TRACE(name);
    const std::vector<uint8_t> bytes = readBytes(streamPath(name));
    StreamDecoder push(bytes.data(), bytes.size(), name);
    std::vector<IntMesh> meshes;
    push.decode([&](int, const IntMesh& mesh) { meshes.push_back(mesh); });

    Decoder decoder = Decoder::openMemory(bytes.data(), bytes.size(), name);
    const StreamInfo& info = decoder.info();
    const SequenceHeader& sh = push.sequenceHeader();
    EXPECT_EQ(info.frameCount, sh.sh_frame_count);
    EXPECT_EQ(info.firstFrame, sh.sh_first_frame);
    EXPECT_EQ(info.frameRate, sh.sh_frame_rate);
    EXPECT_EQ(info.cameras.size(), sh.cameras.size());
    EXPECT_EQ(info.grid.step, push.grid().step);
    std::vector<int64_t> starts;
    for (uint32_t s : push.gomStarts())
      starts.push_back(info.frameNumber(s));
    EXPECT_EQ(decoder.gomStarts(), starts);

    const Pulled pulled = pullAll(decoder, true);
    ASSERT_EQ(pulled.frames.size(), meshes.size());
    for (size_t k = 0; k < meshes.size(); ++k) {
      const DecodedFrame& f = pulled.frames[k];
      EXPECT_EQ(f.index, k);
      EXPECT_EQ(f.number, info.firstFrame + static_cast<int64_t>(k));
      EXPECT_EQ(f.mesh.positions, meshes[k].positions);
      EXPECT_EQ(f.mesh.triangles, meshes[k].triangles);
      ASSERT_EQ(f.positions.size(), meshes[k].positions.size());
      for (size_t v = 0; v < f.positions.size(); ++v) {
        const Vec3d p = info.grid.dequantise(meshes[k].positions[v]);
        for (int a = 0; a < 3; ++a)
          EXPECT_EQ(f.positions[v][a], p[a]);
      }
    }
  }
}

// A seek to any frame gives the same frames from there as decoding from the start, in every
// mode (GOMs that continue the previous one without an I mesh included), also after frames
// were read and when seeking back.
TEST(DecoderApi, SeekGivesTheSameFrames) {
  for (const std::string& name : conformanceStreams()) {
    SCOPED_TRACE(name);
    Decoder decoder = Decoder::openFile(streamPath(name));
    decoder.setPictureDecoder(makeH264Decoder);
    const Pulled all = pullAll(decoder);
    const int64_t first = decoder.info().firstFrame;
    const int64_t count = decoder.info().frameCount;
    for (int64_t n : {count - 1, int64_t{0}, count / 2, count / 3}) {
      SCOPED_TRACE("seek to " + std::to_string(first + n));
      decoder.seek(first + n);
      const Pulled rest = pullAll(decoder);
      EXPECT_EQ(rest.geometry,
                std::vector<std::string>(all.geometry.begin() + n, all.geometry.end()));
      const size_t cameras = decoder.info().cameras.size();
      EXPECT_EQ(rest.texture,
                std::vector<std::string>(all.texture.begin() + n * cameras, all.texture.end()));
    }
    EXPECT_THROW(decoder.seek(first + count), Error);
    EXPECT_THROW(decoder.seek(first - 1), Error);
  }
}

// A seek reads the file again: when the file was replaced meanwhile, that is an error (before,
// the frames after the seek came from the other stream, and info() changed under the caller).
TEST(DecoderApi, SeekRefusesAStreamFileReplacedMeanwhile) {
  const std::vector<std::string> names = conformanceStreams();
  ASSERT_GE(names.size(), 2u);
  test::TempDir dir("api-replaced");
  const std::string path = dir.file("s.3dvo");
  std::filesystem::copy_file(streamPath(names[0]), path);
  Decoder decoder = Decoder::openFile(path);
  DecodedFrame frame;
  ASSERT_TRUE(decoder.next(frame));
  decoder.seek(decoder.info().firstFrame);  // the same file: fine
  std::filesystem::copy_file(streamPath(names[1]), dir.file("other.3dvo"));
  std::filesystem::rename(dir.file("other.3dvo"), path);
  try {
    decoder.seek(decoder.info().firstFrame);
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()), path +
                                         ": the stream file has changed since it was opened "
                                         "(replaced or rewritten): open it again");
  }
}

// Frames come one at a time as they are decoded: a stream cut inside its last GOM's P meshes
// still gives the frames before the cut, then the error the push-style decoder reports.
TEST(DecoderApi, FramesComeBeforeALaterError) {
  const std::string name = "d3dmc_lossless_g8";
  std::vector<uint8_t> bytes = readBytes(streamPath(name));
  bytes.resize(bytes.size() - 40);  // inside the last P mesh
  std::string pushError;
  int pushFrames = 0;
  try {
    StreamDecoder push(bytes.data(), bytes.size(), name);
    push.decode([&](int, const IntMesh&) { ++pushFrames; });
  } catch (const Error& e) {
    pushError = e.what();
  }
  ASSERT_FALSE(pushError.empty());
  Decoder decoder = Decoder::openMemory(bytes.data(), bytes.size(), name);
  DecodedFrame frame;
  int pulled = 0;
  try {
    while (decoder.next(frame))
      ++pulled;
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()), pushError);
  }
  EXPECT_EQ(pulled, pushFrames);
  EXPECT_GE(pulled, 8);  // the whole first GOM, and more
  // The error stays: next() gives no frame of the broken state (it gave wrong frames).
  for (int k = 0; k < 3; ++k) {
    try {
      decoder.next(frame);
      ADD_FAILURE() << "no error after the error";
    } catch (const Error& e) {
      EXPECT_EQ(std::string(e.what()), pushError);
    }
  }
  // seek() starts afresh.
  decoder.seek(decoder.info().firstFrame);
  ASSERT_TRUE(decoder.next(frame));
  EXPECT_EQ(frame.number, decoder.info().firstFrame);
}

// A textured stream's pictures come with their frame; each texture error is the push-style
// decoder's message.
TEST(DecoderApi, TexturedStreamErrorsAreThePushDecodersErrors) {
  const std::string name = "texture_bbox_mb128_g3";
  const std::vector<uint8_t> good = readBytes(streamPath(name));
  for (size_t cut : {good.size() - 1, good.size() - 200, good.size() / 2, size_t{300}}) {
    SCOPED_TRACE("cut at " + std::to_string(cut));
    std::vector<uint8_t> bytes(good.begin(), good.begin() + static_cast<std::ptrdiff_t>(cut));
    std::string pushError;
    try {
      StreamDecoder push(bytes.data(), bytes.size(), name);
      push.setPictureDecoder(makeH264Decoder);
      push.decode([](int, const IntMesh&) {}, [](int, int, const YuvPicture&, const Image&) {});
    } catch (const Error& e) {
      pushError = e.what();
    }
    ASSERT_FALSE(pushError.empty());
    std::string pullError;
    try {
      Decoder decoder = Decoder::openMemory(bytes.data(), bytes.size(), name);
      decoder.setPictureDecoder(makeH264Decoder);
      pullAll(decoder);
    } catch (const Error& e) {
      pullError = e.what();
    }
    EXPECT_EQ(pullError, pushError);
  }
}

TEST(DecoderApi, OpenErrorsNameTheStream) {
  try {
    Decoder::openFile("/nonexistent/x.3dvo");
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/x.3dvo: cannot open"), std::string::npos);
  }
  const uint8_t junk[] = {'3', 'D', 'V', 'P', 0};
  EXPECT_THROW(Decoder::openMemory(junk, sizeof junk, "junk"), Error);
  const uint8_t empty[] = {'3', 'D', 'V', 'O'};
  try {
    Decoder::openMemory(empty, sizeof empty, "empty");
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()),
              "empty: stream ends at the start (expected a SEQUENCE_HEADER unit; truncated "
              "stream)");
  }
}

// Texture lines from a frame's access units, decoded here with one H.264 decoder per camera (as
// a program that decodes pictures itself, e.g. the browser player, does).
struct AccessUnitPictures {
  std::vector<std::unique_ptr<PictureDecoder>> cameras;
  void add(const DecodedFrame& frame, std::vector<std::string>& lines) {
    cameras.resize(frame.textures.size());
    for (const DecodedTexture& t : frame.textures) {
      EXPECT_TRUE(t.picture.y.empty());  // no picture decoder: pictures are the caller's
      ASSERT_FALSE(t.accessUnits.empty());
      auto& decoder = cameras[static_cast<size_t>(t.camera)];
      if (!decoder) decoder = makeH264Decoder("camera " + std::to_string(t.camera));
      YuvPicture picture;
      for (const std::vector<uint8_t>& unit : t.accessUnits)
        picture = decoder->decode(unit, t.box.width, t.box.height);
      lines.push_back(textureHashLine(static_cast<int>(frame.number), t.camera, picture));
    }
  }
};

// A stream given in pieces as it arrives (openArriving) gives every conformance stream's MD5
// lines, its texture lines from the access units the frames carry; frames come as soon as their
// GOM has arrived, before the stream's end.
TEST(DecoderApi, ArrivingStreamGivesItsFramesAsTheyArrive) {
  for (const std::string& name : conformanceStreams()) {
    SCOPED_TRACE(name);
    const std::vector<uint8_t> bytes = readBytes(streamPath(name));
    Decoder decoder = Decoder::openArriving(name);
    decoder.setTextureAccessUnits(true);
    EXPECT_FALSE(decoder.headerArrived());
    EXPECT_FALSE(decoder.canDecodeNext());
    EXPECT_THROW(decoder.info(), Error);
    Pulled got;
    AccessUnitPictures pictures;
    DecodedFrame frame;
    size_t given = 0, framesBeforeTheEnd = 0;
    std::vector<int64_t> startsBeforeTheEnd;
    for (size_t piece = 1; given < bytes.size(); piece = piece * 7 % 997 + 1) {
      const size_t n = std::min(piece, bytes.size() - given);
      decoder.append(bytes.data() + given, n);
      given += n;
      EXPECT_EQ(decoder.bytesArrived(), given);
      while (decoder.canDecodeNext()) {
        ASSERT_TRUE(decoder.next(frame));
        got.geometry.push_back(frame.geometryHashLine());
        pictures.add(frame, got.texture);
        ++framesBeforeTheEnd;
      }
      if (decoder.headerArrived()) startsBeforeTheEnd = decoder.gomStarts();
    }
    decoder.finish();
    while (decoder.next(frame)) {
      got.geometry.push_back(frame.geometryHashLine());
      pictures.add(frame, got.texture);
    }
    EXPECT_EQ(got.geometry, logLines(name, "geometry="));
    EXPECT_EQ(got.texture, logLines(name, " texture "));
    const Decoder whole = Decoder::openFile(streamPath(name));
    Decoder wholeStarts = Decoder::openFile(streamPath(name));
    EXPECT_EQ(decoder.gomStarts(), wholeStarts.gomStarts());
    EXPECT_EQ(decoder.headerHashLine(), whole.headerHashLine());
    // Every GOM but the last can be decoded before the end has arrived.
    if (wholeStarts.gomStarts().size() > 1) {
      EXPECT_GT(framesBeforeTheEnd, 0u);
      EXPECT_EQ(startsBeforeTheEnd, wholeStarts.gomStarts());
    }
  }
}

// A seek into a GOM hands out, with the first frame, the access units of the GOM's earlier
// frames (from the IDR picture on): decoding them in order gives the frame's picture.
TEST(DecoderApi, AccessUnitsAfterASeekIntoAGom) {
  const std::string name = "texture_bbox_mb128_g3";
  Decoder decoder = Decoder::openFile(streamPath(name));
  decoder.setTextureAccessUnits(true);
  const std::vector<std::string> want = logLines(name, " texture ");
  const int64_t first = decoder.info().firstFrame;
  const size_t cameras = decoder.info().cameras.size();
  ASSERT_GT(cameras, 0u);
  decoder.seek(first + 2);  // the GOMs are 3 frames long
  DecodedFrame frame;
  ASSERT_TRUE(decoder.next(frame));
  ASSERT_EQ(frame.textures.size(), cameras);
  EXPECT_EQ(frame.textures[0].accessUnits.size(), 3u);
  std::vector<std::string> got;
  AccessUnitPictures pictures;
  pictures.add(frame, got);
  EXPECT_EQ(got, std::vector<std::string>(want.begin() + 2 * static_cast<std::ptrdiff_t>(cameras),
                                          want.begin() + 3 * static_cast<std::ptrdiff_t>(cameras)));
  ASSERT_TRUE(decoder.next(frame));
  EXPECT_EQ(frame.textures[0].accessUnits.size(), 1u);
}

// An arriving stream: next() before its frame has arrived is an error that leaves the decoder
// usable; a stream cut short, or corrupted, gives after finish() the errors openMemory gives.
TEST(DecoderApi, ArrivingStreamErrors) {
  const std::string name = "d3dmc_lossless_g8";
  const std::vector<uint8_t> good = readBytes(streamPath(name));
  {
    Decoder decoder = Decoder::openArriving(name);
    decoder.append(good.data(), good.size() / 2);
    DecodedFrame frame;
    while (decoder.canDecodeNext())
      ASSERT_TRUE(decoder.next(frame));
    try {
      decoder.next(frame);
      FAIL() << "no error";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("has not arrived yet"), std::string::npos) << e.what();
    }
    decoder.append(good.data() + good.size() / 2, good.size() - good.size() / 2);
    decoder.finish();
    size_t rest = 0;
    while (decoder.next(frame))
      ++rest;
    EXPECT_GT(rest, 0u);
    EXPECT_THROW(decoder.append(good.data(), 1), Error);
  }
  std::vector<std::vector<uint8_t>> bad;
  bad.emplace_back(good.begin(), good.end() - 40);           // cut in the last P mesh
  bad.emplace_back(good.begin(), good.begin() + 30);         // cut in the header
  bad.emplace_back(good.begin(), good.begin() + 2);          // not even the magic
  bad.push_back(good), bad.back()[good.size() / 3] ^= 0x10;  // a flipped bit
  bad.push_back(good), bad.back()[0] = 'X';                  // not a 3DVO stream
  bad.push_back(good), bad.back().push_back(0);              // a byte after the end
  for (const std::vector<uint8_t>& bytes : bad) {
    std::string want, got;
    try {
      Decoder whole = Decoder::openMemory(bytes.data(), bytes.size(), name);
      pullAll(whole);
    } catch (const Error& e) {
      want = e.what();
    }
    try {
      Decoder decoder = Decoder::openArriving(name);
      DecodedFrame frame;
      for (size_t at = 0; at < bytes.size(); at += 100) {
        decoder.append(bytes.data() + at, std::min<size_t>(100, bytes.size() - at));
        while (decoder.canDecodeNext())
          decoder.next(frame);
      }
      decoder.finish();
      while (decoder.next(frame)) {
      }
    } catch (const Error& e) {
      got = e.what();
    }
    ASSERT_FALSE(want.empty());
    EXPECT_EQ(got, want);
  }
}

// What an arriving stream costs is linear in its size: fed in small pieces, with gomStarts() and
// canDecodeNext() asked after every piece (as the web player does), each unit is read a bounded
// number of times (by gomStarts() once, by the decoding once, a GOM header by canDecodeNext()
// once more), not once per call.
TEST(DecoderApi, ArrivingStreamReadsEachUnitABoundedNumberOfTimes) {
  const std::string name = "d3dmc_reuse_g3_ra2";
  const std::vector<uint8_t> bytes = readBytes(streamPath(name));
  const uint64_t units = split(bytes).size();
  ASSERT_GE(countUnits(bytes, UnitType::kGomHeader), 3u);
  const std::vector<int64_t> starts = Decoder::openFile(streamPath(name)).gomStarts();
  const uint64_t before = arrivingUnitsRead();
  Decoder decoder = Decoder::openArriving(name);
  std::vector<std::string> geometry;
  DecodedFrame frame;
  const size_t piece = 16;
  for (size_t given = 0; given < bytes.size(); given += piece) {
    decoder.append(bytes.data() + given, std::min(piece, bytes.size() - given));
    if (decoder.headerArrived()) decoder.gomStarts();
    while (decoder.canDecodeNext()) {
      ASSERT_TRUE(decoder.next(frame));
      geometry.push_back(frame.geometryHashLine());
    }
  }
  decoder.finish();
  while (decoder.next(frame))
    geometry.push_back(frame.geometryHashLine());
  EXPECT_EQ(decoder.gomStarts(), starts);
  EXPECT_EQ(geometry, logLines(name, "geometry="));
  const uint64_t reads = arrivingUnitsRead() - before;
  EXPECT_LE(reads, 3 * units) << reads << " unit reads for " << units << " units ("
                              << bytes.size() / piece << " pieces)";
}

// gomStarts() before finish(), on a stream corrupted in a unit that has arrived, gives the error
// gomStarts() gives for the whole stream, call after call: a GOM header's CRC or syntax, or the
// CRC of any other unit (each unit's CRC is checked).
TEST(DecoderApi, ArrivingStreamGomStartsErrors) {
  const std::string name = "d3dmc_reuse_g3_ra2";
  const std::vector<uint8_t> good = readBytes(streamPath(name));
  std::vector<UnitView> views;
  UnitReader reader(good.data(), good.size(), name);
  for (UnitView unit; reader.next(unit);)
    views.push_back(unit);
  const auto last = [&](UnitType type) {  // the last unit of `type` but for the stream's last
    size_t k = views.size() - 2;
    while (k > 0 && views[k].type != static_cast<uint8_t>(type))
      --k;
    return k;
  };
  const size_t gom = last(UnitType::kGomHeader), pmesh = last(UnitType::kPMesh);
  ASSERT_GT(gom, 1u);
  ASSERT_GT(pmesh, 1u);
  std::vector<std::vector<uint8_t>> bad;
  bad.push_back(good), bad.back()[views[gom].payloadOffset] ^= 0x01;    // a GOM header's CRC
  bad.push_back(good), bad.back()[views[pmesh].payloadOffset] ^= 0x01;  // a P mesh's CRC
  std::vector<Unit> units = split(good);
  units[gom].payload.push_back(0);  // a byte after the GOM header's syntax, the CRC right
  bad.push_back(join(units));
  for (const std::vector<uint8_t>& bytes : bad) {
    std::string want;
    try {
      Decoder::openMemory(bytes.data(), bytes.size(), name).gomStarts();
    } catch (const Error& e) {
      want = e.what();
    }
    ASSERT_FALSE(want.empty());
    Decoder decoder = Decoder::openArriving(name);
    decoder.append(bytes.data(), bytes.size() - 1);  // all but the last unit
    ASSERT_TRUE(decoder.headerArrived());
    for (int call = 0; call < 3; ++call) {
      if (call == 2) {
        decoder.append(&bytes.back(), 1);
        decoder.finish();
      }
      try {
        decoder.gomStarts();
        ADD_FAILURE() << "no error: " << want;
      } catch (const Error& e) {
        EXPECT_EQ(e.what(), want);
      }
    }
  }
}

// tdvo::Encoder with frames from memory makes the very stream (and MD5 lines) 3dvo-enc made from
// the files, for every conformance cfg (textured ones included).
TEST(EncoderApi, FramesFromMemoryGiveTheConformanceStreams) {
  const WorkingDirectory cwd(kConformance);  // the cfgs' paths are relative to it
  int streams = 0;
  for (const auto& entry : fs::directory_iterator("cfg")) {
    ++streams;
    const std::string name = entry.path().stem().string();
    SCOPED_TRACE(name);
    Encoder encoder;
    encoder.readConfig(entry.path().string());
    const EncoderParams& params = encoder.params();
    const int count = resolveFrameCount(params, encoder.dataset());
    std::vector<Mesh> frames;
    // A glTF animation file holds the frames as its keyframes (as 3dvo-enc reads it).
    std::optional<GltfFile> animation;
    if (isMeshAnimationFile(params.inputMeshPattern)) animation.emplace(params.inputMeshPattern);
    for (int k = 0; k < count; ++k)
      frames.push_back(
          animation ? animation->frame(static_cast<size_t>(params.firstFrame + k))
                    : readMesh(inputMeshPath(params, encoder.dataset(), params.firstFrame + k)));
    const EncodedSequence coded = encoder.encode(frames);
    EXPECT_TRUE(coded.stream == readBytes(streamPath(name)));
    std::vector<std::string> expected = lines(readText("streams/" + name + ".md5"));
    EXPECT_EQ(coded.md5Lines, expected);
  }
  EXPECT_GE(streams, 12);
}

TEST(EncoderApi, BadFramesAndKeysAreErrors) {
  std::vector<Mesh> frames = wobblingSphere(1, 3);
  Encoder encoder;
  try {
    encoder.set("GOMSze", "3");
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("GOMSze"), std::string::npos);
  }
  encoder.set("GOMSize", "3");
  EXPECT_NO_THROW(encoder.encode(frames));
  std::vector<Mesh> bad = frames;
  bad[1].triangles[4][2] = static_cast<uint32_t>(bad[1].positions.size());
  try {
    encoder.encode(bad);
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("frame 1: triangle 4: vertex index"), std::string::npos)
        << e.what();
  }
  bad = frames;
  for (Mesh& frame : bad) {  // the same texture coordinates in every frame of the GOM
    frame.attributes.uvs = {{0.5f, 0.5f}};
    frame.attributes.uvTriangles.assign(frame.triangles.size(), Triangle{0, 0, 0});
  }
  EXPECT_NO_THROW(encoder.encode(bad));
  bad[0].attributes.uvTriangles[3][1] = 1;
  try {
    encoder.encode(bad);
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("frame 0: triangle 3: texture-coordinate index 1 out"),
              std::string::npos)
        << e.what();
  }
  bad[0].attributes.uvTriangles.pop_back();
  EXPECT_THROW(encoder.encode(bad), Error);
  // The same values measured from the other row of the image (glTF's) in a GOM of P meshes.
  bad[0].attributes.uvTriangles.assign(bad[0].triangles.size(), Triangle{0, 0, 0});
  bad[2].attributes.uvOrigin = UvOrigin::kTop;
  try {
    encoder.encode(bad);
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("frame 2: texture coordinates measured from the image's "
                                         "top row (glTF's convention), those of the GOM's first "
                                         "frame (frame 0) from its bottom row"),
              std::string::npos)
        << e.what();
  }
  bad = frames;
  bad[2].positions[7][1] = std::nan("");
  EXPECT_THROW(encoder.encode(bad), Error);
  encoder.set("FrameCount", "2");
  EXPECT_THROW(encoder.encode(frames), Error);
  EXPECT_THROW(encoder.encode(std::vector<Mesh>{}), Error);
}

// Frames read on demand (FrameSource) are checked as frames from memory are: each bad frame is
// an Error naming it, before the codec uses it (NaN and infinite positions reached the coder as
// std::logic_error, 1e301 was coded, and an index of 4e8 in every frame took gigabytes).
TEST(EncoderApi, FramesReadOnDemandAreChecked) {
  const std::vector<Mesh> frames = wobblingSphere(1, 3);
  struct Case {
    const char* what;
    std::function<void(Mesh&)> spoil;
    const char* message;
  };
  const std::vector<Case> cases = {
      {"nan", [](Mesh& m) { m.positions[7][1] = std::nan(""); }, "has a non-finite coordinate"},
      {"inf", [](Mesh& m) { m.positions[7][1] = HUGE_VAL; }, "has a non-finite coordinate"},
      {"big", [](Mesh& m) { m.positions[7][1] = 1e301; }, "coordinate"},
      {"index", [](Mesh& m) { m.triangles[4][2] = 400000000u; }, "triangle 4: vertex index"},
      {"empty", [](Mesh& m) { m.triangles.clear(); }, "no faces"}};
  for (const Case& c : cases) {
    SCOPED_TRACE(c.what);
    FrameSource source;
    source.count = frames.size();
    source.name = [](size_t k) { return "source frame " + std::to_string(k); };
    source.read = [&](size_t k) {
      Mesh m = frames[k];
      if (k == 1) c.spoil(m);
      return m;
    };
    Encoder encoder;
    encoder.set("GOMSize", "3");
    try {
      encoder.encode(source);
      ADD_FAILURE() << "no error";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("source frame 1: "), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(c.message), std::string::npos) << e.what();
    }
  }
}

// What the encoder's callbacks give is what the decoder makes of its stream.
TEST(EncoderApi, ReconstructionIsTheDecodersOutput) {
  const std::vector<Mesh> frames = wobblingSphere(2, 7);
  Encoder encoder;
  encoder.set("GOMSize", "4");
  encoder.set("MotionQuantStep", "3");
  std::vector<std::string> recon;
  const EncodedSequence coded = encoder.encode(frames, [&](int frame, const IntMesh& mesh) {
    recon.push_back(geometryHashLine(frame, mesh));
  });
  Decoder decoder = Decoder::openMemory(coded.stream.data(), coded.stream.size());
  const Pulled pulled = pullAll(decoder);
  EXPECT_EQ(pulled.geometry, recon);
  EXPECT_EQ(std::vector<std::string>(coded.md5Lines.begin(), coded.md5Lines.end() - 1), recon);
}
