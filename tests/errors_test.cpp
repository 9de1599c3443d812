// The malformed-input catalogue (docs/errors.md), one test per row: each builds the row's input,
// runs the app from TDVO_BIN_DIR on it and checks the row's exit code, that stderr is exactly one
// "<app>: error: " line containing the row's message, and that no file was left behind. The rows
// are read from docs/errors.md itself, so the page cannot drift from what the apps print, and a
// test checks that every row has a test and every test a row.
//
// Malformed streams that must get past the CRC check are built with UnitWriter from the units
// of a small correct stream (6 frames of a 42-vertex sphere, 10-bit grid, two d3dmc GOMs of 3
// frames: units SH, GH, I, P, P, GH, I, P, P). Exhaustive variants (every truncation length,
// one flipped bit in every byte) run at library level after the rows.
#include <draco/compression/encode.h>
#include <draco/mesh/mesh.h>
#include <draco/point_cloud/point_cloud.h>
#include <gtest/gtest.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <map>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "bitstream/attributes_syntax.h"
#include "bitstream/syntax.h"
#include "bitstream/units.h"
#include "common/core/error.h"
#include "common/core/gltf_io.h"
#include "common/core/obj_io.h"
#include "common/core/ply_io.h"
#include "common/core/warnings.h"
#include "common/entropy/cabac.h"
#include "common/media/png_io.h"
#include "common/views/image.h"
#include "decoder/imesh_decoder.h"
#include "decoder/stream_decoder.h"
#include "decoder/texture/h264_decoder.h"
#include "encoder/h264_encoder.h"
#include "encoder/imesh_encoder.h"
#include "encoder/sequence_encoder.h"
#include "tests/stream_units.h"
#include "tests/test_support.h"

namespace tdvo {
namespace {

using test::CommandResult;
using test::TempDir;

const std::string kBin = TDVO_BIN_DIR;

// ---- The catalogue page ----

struct Row {
  std::string message;  // the stable part of the error line
  int exitCode = -1;
};

// Splits a markdown table row at unescaped '|'; "\|" becomes '|'.
std::vector<std::string> cells(const std::string& line) {
  std::vector<std::string> out;
  std::string cell;
  for (size_t i = 1; i < line.size(); ++i) {
    if (line[i] == '\\' && i + 1 < line.size() && line[i + 1] == '|') {
      cell += '|';
      ++i;
    } else if (line[i] == '|') {
      out.push_back(cell);
      cell.clear();
    } else {
      cell += line[i];
    }
  }
  return out;
}

// Rows "| ID | input | `message` | exit |" of docs/errors.md, ID like S01 (the four-character
// PY rows are the Python module's: tools/python/tests/test_errors.py tests them).
const std::map<std::string, Row>& catalogue() {
  static const std::map<std::string, Row> rows = [] {
    std::map<std::string, Row> out;
    const std::string page = test::readText(std::string(TDVO_SOURCE_DIR) + "/docs/errors.md");
    for (const std::string& line : test::lines(page)) {
      if (line.rfind("| ", 0) != 0) continue;
      const std::vector<std::string> c = cells(line);
      if (c.size() != 4) continue;
      std::string id = c[0];
      id.erase(std::remove(id.begin(), id.end(), ' '), id.end());
      if (id.size() != 3 || !std::isupper(static_cast<unsigned char>(id[0])) ||
          !std::isdigit(static_cast<unsigned char>(id[1])))
        continue;
      const size_t open = c[2].find('`'), close = c[2].rfind('`');
      if (open == std::string::npos || close <= open) continue;
      Row row;
      row.message = c[2].substr(open + 1, close - open - 1);
      row.exitCode = std::atoi(c[3].c_str());
      EXPECT_TRUE(out.emplace(id, row).second) << "row " << id << " appears twice";
    }
    return out;
  }();
  return rows;
}

std::set<std::string>& testedRows() {
  static std::set<std::string> ids;
  return ids;
}

bool registerRow(const char* id) {
  return testedRows().insert(id).second;
}

// A test for catalogue row ID.
#define CATALOGUE_TEST(ID)                                 \
  [[maybe_unused]] const bool kRow##ID = registerRow(#ID); \
  TEST_F(ErrorsTest, ID)

// ---- Streams ----

using test::join;
using test::split;
using test::Unit;

// Offsets of the units in a stream.
std::vector<size_t> unitOffsets(const std::vector<uint8_t>& stream) {
  UnitReader reader(stream.data(), stream.size(), "offsets");
  std::vector<size_t> offsets;
  UnitView u;
  while (reader.next(u))
    offsets.push_back(u.offset);
  return offsets;
}

template <class T>
T parse(const Unit& unit) {
  ByteReader reader(unit.payload.data(), unit.payload.size(), "parse", 0);
  T value;
  transfer(reader, value);
  return value;
}

void putU16(std::vector<uint8_t>& p, size_t at, uint16_t v) {
  p[at] = static_cast<uint8_t>(v);
  p[at + 1] = static_cast<uint8_t>(v >> 8);
}
void putU32(std::vector<uint8_t>& p, size_t at, uint32_t v) {
  for (int i = 0; i < 4; ++i)
    p[at + i] = static_cast<uint8_t>(v >> (8 * i));
}
void putF64(std::vector<uint8_t>& p, size_t at, double v) {
  std::memcpy(&p[at], &v, 8);
}

// Byte offsets of fields in the payloads (docs/bitstream.md, sections 2 and 3).
constexpr size_t kShVersion = 0, kShFirstFrame = 2, kShFrameCount = 6, kShFrameRate = 10,
                 kShGridBits = 18, kShOrigin = 19, kShStep = 43;
constexpr size_t kGhFirstFrame = 0, kGhFrameCount = 4, kGhMode = 6, kGhRandomAccess = 7,
                 kGhQuantStep = 8, kGhDepth = 10, kGhNumKeyframes = 11, kGhDelta = 13;
constexpr size_t kImFrame = 0, kImQuantStep = 4;  // section 4

constexpr int kFrames = 6, kGridBits = 10;

// The correct stream the malformed ones are made from, and the decoder's MD5 lines for it.
const std::vector<uint8_t>& baseStream() {
  static const std::vector<uint8_t> stream = [] {
    EncoderParams params;
    params.gridBits = kGridBits;
    params.gomSize = 3;
    params.frameCount = kFrames;
    params.pmeshMode = PMeshMode::kD3dmc;
    const std::vector<Mesh> frames = test::wobblingSphere(1, kFrames);
    return encodeSequence(params, gridForSequence(frames, kGridBits), frames, {},
                          [](int, const IntMesh&) {})
        .stream;
  }();
  return stream;
}

std::vector<Unit> baseUnits() {
  return split(baseStream());
}

// The base stream's I-mesh payload (unit 2) after its im_frame.
std::vector<uint8_t> dracoPayload() {
  return parse<IMeshUnit>(baseUnits()[2]).im_draco_payload;
}

std::vector<uint8_t> iMeshUnitPayload(uint32_t frame, const std::vector<uint8_t>& draco) {
  IMeshUnit im;
  im.im_frame = frame;
  im.im_draco_payload = draco;
  return serialise(im);
}

// The base Draco payload with its connectivity counts replaced (test_support.h).
std::vector<uint8_t> dracoWithCounts(uint32_t vertices, uint32_t faces, uint32_t symbols) {
  return test::withDracoCounts(dracoPayload(), vertices, faces, symbols);
}

// A Draco I-mesh payload with its attribute descriptor patched: the descriptor (num_attributes
// 1, POSITION, int32, 3 components, not normalized) is found by its bytes and its data type,
// components and attribute count replaced.
std::vector<uint8_t> dracoWithDescriptor(std::vector<uint8_t> p, uint8_t attributes,
                                         uint8_t dataType, uint8_t components) {
  const uint8_t descriptor[] = {1, 0, 5, 3, 0};
  auto at = std::search(p.begin() + 12, p.end(), std::begin(descriptor), std::end(descriptor));
  EXPECT_NE(at, p.end()) << "no POSITION int32 x 3 descriptor found";
  if (at == p.end()) return p;
  at[0] = attributes;
  at[2] = dataType;
  at[3] = components;
  return p;
}

// A Draco payload of any geometry, encoded by Draco itself.
std::vector<uint8_t> dracoEncode(draco::PointCloud& geometry, bool mesh) {
  draco::Encoder encoder;
  draco::EncoderBuffer buffer;
  const draco::Status status =
      mesh ? encoder.EncodeMeshToBuffer(static_cast<draco::Mesh&>(geometry), &buffer)
           : encoder.EncodePointCloudToBuffer(geometry, &buffer);
  EXPECT_TRUE(status.ok()) << status.error_msg_string();
  return std::vector<uint8_t>(buffer.data(), buffer.data() + buffer.size());
}

// One triangle (or, with mesh false, a point cloud of its 3 points) with a 3-component
// POSITION attribute of type int32 or float32.
std::vector<uint8_t> dracoTriangle(draco::DataType type, bool mesh) {
  draco::Mesh m;
  draco::PointCloud pc;
  draco::PointCloud& geometry = mesh ? static_cast<draco::PointCloud&>(m) : pc;
  geometry.set_num_points(3);
  if (mesh) m.AddFace({draco::PointIndex(0), draco::PointIndex(1), draco::PointIndex(2)});
  draco::GeometryAttribute attribute;
  attribute.Init(draco::GeometryAttribute::POSITION, nullptr, 3, type, false, 12, 0);
  const int id = geometry.AddAttribute(attribute, true, 3);
  for (int i = 0; i < 3; ++i) {
    const float f[3] = {float(i == 1), float(i == 2), 0};
    const int32_t n[3] = {i == 1, i == 2, 0};
    geometry.attribute(id)->SetAttributeValue(
        draco::AttributeValueIndex(i),
        type == draco::DT_FLOAT32 ? static_cast<const void*>(f) : static_cast<const void*>(n));
  }
  return dracoEncode(geometry, mesh);
}

// A P-mesh payload coding one AFX-IC residual `value` for vertex 0, component x (then stops).
std::vector<uint8_t> afxicResidualPayload(int32_t value) {
  CabacEncoder encoder;
  ContextModel contexts[6];
  encodeSignedUEGk(encoder, contexts, 6, value, 0, 12);
  return encoder.finish();
}

// The base units with GOM 0 turned into an afxic GOM (same keyframes, no octree depth).
std::vector<Unit> afxicUnits() {
  std::vector<Unit> units = baseUnits();
  std::vector<uint8_t>& gh = units[1].payload;
  gh[kGhMode] = static_cast<uint8_t>(PMeshMode::kAfxic);
  gh.erase(gh.begin() + kGhDepth);
  return units;
}

// The base units with GOM 0 turned into a GOM of B meshes (gh_pmesh_mode 3) with
// gh_bmesh_quant_step `step`; its frames are all keyframes, so it has no B mesh.
std::vector<Unit> bMeshUnits(uint16_t step) {
  std::vector<Unit> units = baseUnits();
  std::vector<uint8_t>& gh = units[1].payload;
  gh[kGhMode] = kGhD3dmcBMeshes;
  gh.insert(gh.begin() + kGhDepth + 1,
            {static_cast<uint8_t>(step), static_cast<uint8_t>(step >> 8)});
  return units;
}

// `goms` d3dmc GOMs of `gomFrames` frames of a static flat n x n sheet (n^2 vertices), the
// keyframes of each GOM its first and last frame: encoded as GOMs of 2 frames, then renumbered.
// The frames between keyframes cost no bytes, so the decoded output per stream byte is as
// large as the caller likes (docs/robustness.md, "Limits and decoding work").
std::vector<Unit> staticSheetUnits(int n, uint16_t gomFrames, int goms) {
  Mesh sheet = test::waveSheet(n, n, 1)[0];
  for (Vec3d& p : sheet.positions)
    p[2] = 0;
  const std::vector<Mesh> frames(2 * goms, sheet);
  EncoderParams params;
  params.gridBits = kGridBits;
  params.gomSize = 2;
  params.frameCount = 2 * goms;
  params.pmeshMode = PMeshMode::kD3dmc;
  std::vector<Unit> units = split(encodeSequence(params, gridForSequence(frames, kGridBits), frames,
                                                 {}, [](int, const IntMesh&) {})
                                      .stream);
  EXPECT_EQ(units.size(), 1u + 4u * goms);  // SH, then GH, I, VO, P per GOM
  putU32(units[0].payload, kShFrameCount, uint32_t{gomFrames} * goms);
  for (int g = 0; g < goms; ++g) {
    const uint32_t first = uint32_t{gomFrames} * g;
    putU32(units[1 + 4 * g].payload, kGhFirstFrame, first);
    putU16(units[1 + 4 * g].payload, kGhFrameCount, gomFrames);
    putU16(units[1 + 4 * g].payload, kGhDelta, static_cast<uint16_t>(gomFrames - 1));
    putU32(units[2 + 4 * g].payload, 0, first);                  // im_frame
    putU32(units[3 + 4 * g].payload, 0, first);                  // vo_frame
    putU32(units[4 + 4 * g].payload, 0, first + gomFrames - 1);  // pm_frame
  }
  return units;
}

// staticSheetUnits(n, gomFrames, 1) with one width x height camera in the sequence header (the
// sheet in front of it, a 16 x 16 texture box) and the texture units of its first
// `textureUnits` frames (a flat grey 16 x 16 picture, IDR first).
std::vector<Unit> texturedSheetUnits(int n, uint16_t gomFrames, uint16_t width, uint16_t height,
                                     int textureUnits) {
  std::vector<Unit> units = staticSheetUnits(n, gomFrames, 1);
  SequenceHeader sh = parse<SequenceHeader>(units[0]);
  CameraParameters camera;
  camera.cam_width = width;
  camera.cam_height = height;
  camera.cam_fx = camera.cam_fy = width;
  camera.cam_cx = width / 2.0;
  camera.cam_cy = height / 2.0;
  camera.cam_translation[2] = 3;
  sh.cameras.push_back(camera);
  units[0].payload = serialise(sh);
  H264Settings settings;
  settings.width = settings.height = 16;
  settings.qp = 30;
  H264Encoder encoder(settings);
  const YuvPicture grey(16, 16);
  for (int f = 0; f < textureUnits; ++f) {
    TextureUnit tx;
    tx.tx_frame = static_cast<uint32_t>(f);
    tx.tx_access_unit = encoder.encode(grey, f == 0);
    units.push_back({static_cast<uint8_t>(UnitType::kTexture), serialise(tx)});
  }
  return units;
}

// Stream bytes from its start through unit `index` (its CRC included).
uint64_t bytesThrough(const std::vector<Unit>& units, size_t index) {
  uint64_t bytes = sizeof kStreamMagic;
  for (size_t i = 0; i <= index; ++i)
    bytes += kUnitOverhead + units[i].payload.size();
  return bytes;
}

// ---- Running the apps ----

class ErrorsTest : public testing::Test {
 protected:
  // Every file under the folder, relative.
  std::vector<std::string> tree() const {
    std::vector<std::string> names;
    for (const auto& entry : std::filesystem::recursive_directory_iterator(dir_.path()))
      names.push_back(std::filesystem::relative(entry.path(), dir_.path()).string());
    std::sort(names.begin(), names.end());
    return names;
  }

  // Runs `app` (3dvo-enc or 3dvo-dec) with `args` in the test folder and checks the result
  // against catalogue row `id`: its exit code, one "<app>: error: " line holding its message,
  // and no new file (an output folder "out" may remain, empty: it existed before).
  void expectRow(const std::string& id, const std::string& app,
                 const std::vector<std::string>& args) {
    SCOPED_TRACE("catalogue row " + id);
    std::filesystem::create_directories(dir_.path() / "out");
    const std::vector<std::string> before = tree();
    const CommandResult r = test::run(dir_, kBin + "/" + app, args);
    auto it = catalogue().find(id);
    ASSERT_NE(it, catalogue().end())
        << "row " << id << " is not in docs/errors.md; got " << r.exitCode << ": " << r.err;
    const Row& row = it->second;
    EXPECT_EQ(r.exitCode, row.exitCode) << r.err;
    const std::vector<std::string> errLines = test::lines(r.err);
    ASSERT_EQ(errLines.size(), 1u) << r.err;
    EXPECT_EQ(errLines[0].rfind(app + ": error: ", 0), 0u) << errLines[0];
    EXPECT_NE(errLines[0].find(row.message), std::string::npos)
        << "expected '" << row.message << "' in: " << errLines[0];
    EXPECT_EQ(tree(), before) << "files were left behind";
  }

  // Writes `stream` as x.3dvo and runs the decoder on it against row `id`.
  void expectStreamRow(const std::string& id, const std::vector<uint8_t>& stream) {
    test::writeBytes(dir_.file("x.3dvo"), stream);
    expectRow(id, "3dvo-dec", {"-i", "x.3dvo", "-o", "out"});
  }
  void expectUnitsRow(const std::string& id, const std::vector<Unit>& units) {
    expectStreamRow(id, join(units));
  }

  // Writes frames in/000.obj ... (the OBJ text of `frame0` first) and runs the encoder with
  // `extra` arguments (which come last) against row `id`.
  void expectObjRow(const std::string& id, const std::string& frame0, int frames = 1,
                    const std::vector<std::string>& extra = {}) {
    writeInput(frame0, frames);
    std::vector<std::string> args = encoderArgs(frames);
    args.insert(args.end(), extra.begin(), extra.end());
    expectRow(id, "3dvo-enc", args);
  }

  void writeInput(const std::string& frame0, int frames) {
    std::filesystem::create_directories(dir_.path() / "in");
    const std::vector<Mesh> good = test::wobblingSphere(1, frames);
    for (int f = 0; f < frames; ++f) {
      char name[32];
      std::snprintf(name, sizeof name, "in/%03d.obj", f);
      test::writeText(dir_.file(name), f == 0 && !frame0.empty() ? frame0 : formatObj(good[f]));
    }
  }

  static std::vector<std::string> encoderArgs(int frames) {
    return {"--InputMeshPattern=in/%03d.obj", "--FrameCount=" + std::to_string(frames),
            "--GridBits=10", "-o", "out/x.3dvo"};
  }

  void expectCfgRow(const std::string& id, const std::string& cfg,
                    const std::vector<std::string>& extra = {}) {
    writeInput("", 1);
    test::writeText(dir_.file("x.cfg"), cfg);
    std::vector<std::string> args = encoderArgs(1);
    args.push_back("-c");
    args.push_back("x.cfg");
    args.insert(args.end(), extra.begin(), extra.end());
    expectRow(id, "3dvo-enc", args);
  }

  // A copy of the conformance rig in rig/ with `from` replaced by `to` in its dataset.json.
  void copyRig(const std::string& from, const std::string& to) {
    const std::string rig = dir_.file("rig");
    std::filesystem::copy(std::string(TDVO_SOURCE_DIR) + "/conformance/inputs/rig", rig,
                          std::filesystem::copy_options::recursive);
    std::string json = test::readText(rig + "/dataset.json");
    ASSERT_NE(json.find(from), std::string::npos) << from;
    json.replace(json.find(from), from.size(), to);
    test::writeText(rig + "/dataset.json", json);
  }

  // copyRig, coded (one frame, textures) against row `id`.
  void expectRigRow(const std::string& id, const std::string& from, const std::string& to) {
    copyRig(from, to);
    expectRow(id, "3dvo-enc", {"--Dataset=rig", "--FrameCount=1", "-o", "out/x.3dvo"});
  }

  // Texture rows decode without -o: what a failed textured decode leaves in its output folder
  // is the output-safety rows' business; these rows are about the error.
  void expectTextureRow(const std::string& id, const std::vector<Unit>& units) {
    test::writeBytes(dir_.file("x.3dvo"), join(units));
    expectRow(id, "3dvo-dec", {"-i", "x.3dvo"});
  }

  TempDir dir_{"errors"};
};

TEST(Catalogue, EveryRowHasATestAndEveryTestARow) {
  ASSERT_GT(catalogue().size(), 50u) << "docs/errors.md was not read";
  for (const auto& [id, row] : catalogue()) {
    EXPECT_TRUE(testedRows().count(id)) << "row " << id << " has no test";
    EXPECT_FALSE(row.message.empty()) << id;
  }
  for (const std::string& id : testedRows())
    EXPECT_TRUE(catalogue().count(id)) << "test " << id << " has no row in docs/errors.md";
}

TEST(Catalogue, BaseStreamDecodes) {
  const std::vector<uint8_t>& s = baseStream();
  StreamDecoder decoder(s.data(), s.size(), "base");
  decoder.setPictureDecoder(makeH264Decoder);
  int frames = 0;
  decoder.decode([&](int, const IntMesh&) { ++frames; });
  EXPECT_EQ(frames, kFrames);
  const std::vector<Unit> units = baseUnits();
  ASSERT_EQ(units.size(), 11u);
  const uint8_t expected[11] = {1, 2, 3, 6, 4, 4, 2, 3, 6, 4, 4};
  for (size_t i = 0; i < units.size(); ++i)
    EXPECT_EQ(units[i].type, expected[i]) << i;
}

// ---- Stream container ----

CATALOGUE_TEST(S01) {
  expectRow("S01", "3dvo-dec", {"-i", "x.3dvo", "-o", "out"});
}

CATALOGUE_TEST(S02) {
  expectStreamRow("S02", {});
  expectStreamRow("S02", {'3', 'D', 'V'});
  const std::string obj = "v 0 0 0\n";
  expectStreamRow("S02", std::vector<uint8_t>(obj.begin(), obj.end()));
}

CATALOGUE_TEST(S03) {
  expectStreamRow("S03", {'3', 'D', 'V', 'O'});
}

CATALOGUE_TEST(S04) {
  // A cut at every unit boundary after the sequence header.
  const std::vector<uint8_t>& s = baseStream();
  const std::vector<size_t> offsets = unitOffsets(s);
  for (size_t i = 1; i < offsets.size(); ++i)
    expectStreamRow("S04", std::vector<uint8_t>(s.begin(), s.begin() + offsets[i]));
}

CATALOGUE_TEST(S05) {
  const std::vector<uint8_t>& s = baseStream();
  for (size_t offset : unitOffsets(s))
    for (size_t keep : {size_t{1}, size_t{4}})
      expectStreamRow("S05", std::vector<uint8_t>(s.begin(), s.begin() + offset + keep));
  std::vector<uint8_t> extra = s;
  extra.push_back(2);
  expectStreamRow("S05", extra);
}

CATALOGUE_TEST(S06) {
  const std::vector<uint8_t>& s = baseStream();
  const std::vector<size_t> offsets = unitOffsets(s);
  for (size_t i = 0; i < offsets.size(); ++i) {
    const size_t end = i + 1 < offsets.size() ? offsets[i + 1] : s.size();
    for (size_t cut : {offsets[i] + kUnitHeaderSize, (offsets[i] + end) / 2, end - 1})
      expectStreamRow("S06", std::vector<uint8_t>(s.begin(), s.begin() + cut));
  }
}

CATALOGUE_TEST(S07) {
  std::vector<uint8_t> s = baseStream();
  const std::vector<size_t> offsets = unitOffsets(s);
  s[offsets[2] - 1] ^= 0x01;  // the CRC of unit 1
  expectStreamRow("S07", s);
}

CATALOGUE_TEST(S08) {
  // One flipped bit in the type, payload or CRC of each unit (the bit moves along): the CRC
  // catches every one. Flips in unit_size are rows S06 and S09.
  const std::vector<uint8_t>& s = baseStream();
  const std::vector<size_t> offsets = unitOffsets(s);
  for (size_t i = 0; i < offsets.size(); ++i) {
    const size_t end = i + 1 < offsets.size() ? offsets[i + 1] : s.size();
    for (size_t at : {offsets[i], offsets[i] + kUnitHeaderSize, (offsets[i] + end) / 2, end - 1}) {
      std::vector<uint8_t> bad = s;
      bad[at] ^= static_cast<uint8_t>(1u << (at % 8));
      expectStreamRow("S08", bad);
    }
  }
}

CATALOGUE_TEST(S09) {
  std::vector<uint8_t> s = baseStream();
  s[4 + 4] = 0x40;  // unit 0's unit_size becomes 0x4000002F > 2^30
  expectStreamRow("S09", s);
}

CATALOGUE_TEST(S10) {
  std::vector<Unit> units = baseUnits();
  units[0].type = 9;
  expectUnitsRow("S10", units);
}

CATALOGUE_TEST(S11) {
  for (uint8_t type : {uint8_t{0}, uint8_t{200}, uint8_t{255}}) {
    std::vector<Unit> units = baseUnits();
    units[1].type = type;
    expectUnitsRow("S11", units);
  }
}

CATALOGUE_TEST(S12) {
  std::vector<Unit> units = baseUnits();
  units.push_back(units[6]);
  expectUnitsRow("S12", units);
}

// ---- Sequence header ----

CATALOGUE_TEST(H01) {
  for (uint16_t version : {uint16_t{0}, uint16_t{1}, uint16_t{65535}}) {
    std::vector<Unit> units = baseUnits();
    putU16(units[0].payload, kShVersion, version);
    expectUnitsRow("H01", units);
  }
}

CATALOGUE_TEST(H02) {
  std::vector<Unit> units = baseUnits();
  putU32(units[0].payload, kShFrameCount, 0);
  expectUnitsRow("H02", units);
}

CATALOGUE_TEST(H03) {
  std::vector<Unit> units = baseUnits();
  putU32(units[0].payload, kShFrameCount, 0xFFFFFFFF);  // -1 as a 32-bit integer
  expectUnitsRow("H03", units);
}

CATALOGUE_TEST(H04) {
  for (double rate : {0.0, -25.0, 1001.0, std::nan(""), HUGE_VAL}) {
    std::vector<Unit> units = baseUnits();
    putF64(units[0].payload, kShFrameRate, rate);
    expectUnitsRow("H04", units);
  }
}

CATALOGUE_TEST(H05) {
  for (uint8_t bits : {uint8_t{0}, uint8_t{7}, uint8_t{21}, uint8_t{255}}) {
    std::vector<Unit> units = baseUnits();
    units[0].payload[kShGridBits] = bits;
    expectUnitsRow("H05", units);
  }
}

CATALOGUE_TEST(H06) {
  for (double step : {0.0, -1.0, std::nan(""), HUGE_VAL}) {
    std::vector<Unit> units = baseUnits();
    putF64(units[0].payload, kShStep, step);
    expectUnitsRow("H06", units);
  }
}

CATALOGUE_TEST(H12) {
  std::vector<Unit> units = baseUnits();
  putF64(units[0].payload, kShStep, 1e308);
  expectUnitsRow("H12", units);
}

// The camera of texturedSheetUnits(3, 2, 64, 48, 1) ("cam", 64 x 48): byte offsets of its fields
// in the sequence header (docs/bitstream.md section 2: after sh_attributes_present at 51 and
// sh_num_cameras at 52), checked against the values written.
constexpr size_t kCamName = 56, kCamWidth = 59, kCamHeight = 61, kCamFx = 63, kCamFy = 71,
                 kCamCx = 79, kCamRotation = 135, kTxBoxX = 231;

std::vector<Unit> oneCameraUnits() {
  std::vector<Unit> units = texturedSheetUnits(3, 2, 64, 48, 1);
  const std::vector<uint8_t>& p = units[0].payload;
  EXPECT_EQ(std::string(p.begin() + kCamName, p.begin() + kCamName + 3), "cam");
  EXPECT_EQ(p[kCamWidth] | p[kCamWidth + 1] << 8, 64);
  EXPECT_EQ(p[kCamHeight] | p[kCamHeight + 1] << 8, 48);
  double fx = 0, r0 = 0;
  std::memcpy(&fx, &p[kCamFx], 8);
  std::memcpy(&r0, &p[kCamRotation], 8);
  EXPECT_EQ(fx, 64.0);
  EXPECT_EQ(r0, 1.0);
  EXPECT_EQ(p[kTxBoxX] | p[kTxBoxX + 1] << 8, 0);
  return units;
}

CATALOGUE_TEST(H13) {
  for (const size_t at : {kCamWidth, kCamHeight})
    for (const uint16_t size : {uint16_t{1}, uint16_t{16385}}) {
      std::vector<Unit> units = oneCameraUnits();
      putU16(units[0].payload, at, size);
      expectUnitsRow("H13", units);
    }
}

CATALOGUE_TEST(H14) {
  for (const size_t at : {kCamFx, kCamFy})
    for (const double f : {0.0, -1.0}) {
      std::vector<Unit> units = oneCameraUnits();
      putF64(units[0].payload, at, f);
      expectUnitsRow("H14", units);
    }
}

CATALOGUE_TEST(H15) {
  std::vector<Unit> units = oneCameraUnits();
  putF64(units[0].payload, kCamCx, std::nan(""));
  expectUnitsRow("H15", units);
  units = oneCameraUnits();
  putF64(units[0].payload, kCamRotation + 8 * 4, HUGE_VAL);
  expectUnitsRow("H15", units);
}

CATALOGUE_TEST(H16) {
  std::vector<Unit> units = oneCameraUnits();
  putU16(units[0].payload, kTxBoxX, 8);
  expectUnitsRow("H16", units);
}

CATALOGUE_TEST(H17) {
  // A second camera "cbm" (the first one's fields again), then renamed "cam".
  std::vector<Unit> units = oneCameraUnits();
  std::vector<uint8_t>& p = units[0].payload;
  const size_t cameraBytes = kTxBoxX + 8 - (kCamName - 2);
  std::vector<uint8_t> second(p.begin() + kCamName - 2, p.begin() + kTxBoxX + 8);
  second[3] = 'b';
  p.insert(p.begin() + kTxBoxX + 8, second.begin(), second.end());
  putU16(p, 52, 2);
  SequenceHeader sh = parse<SequenceHeader>(units[0]);  // valid so far
  ASSERT_EQ(sh.cameras.size(), 2u);
  p[kTxBoxX + 8 + 3] = 'a';
  ASSERT_EQ(cameraBytes, second.size());
  expectUnitsRow("H17", units);
}

CATALOGUE_TEST(H18) {
  for (const uint8_t bad : {uint8_t{0xFF}, uint8_t{0}}) {
    std::vector<Unit> units = oneCameraUnits();
    units[0].payload[kCamName + 1] = bad;
    expectUnitsRow("H18", units);
  }
}

CATALOGUE_TEST(H07) {
  for (int axis = 0; axis < 3; ++axis) {
    std::vector<Unit> units = baseUnits();
    putF64(units[0].payload, kShOrigin + 8 * axis, axis == 1 ? -HUGE_VAL : std::nan(""));
    expectUnitsRow("H07", units);
  }
}

CATALOGUE_TEST(H08) {
  std::vector<Unit> units = baseUnits();
  units[0].payload.resize(kShStep + 4);
  expectUnitsRow("H08", units);
}

CATALOGUE_TEST(H09) {
  std::vector<Unit> units = baseUnits();
  units[0].payload.clear();
  expectUnitsRow("H09", units);
}

CATALOGUE_TEST(H10) {
  std::vector<Unit> units = baseUnits();
  units[0].payload.push_back(0);
  expectUnitsRow("H10", units);
}

CATALOGUE_TEST(H11) {
  std::vector<Unit> units = baseUnits();
  putU32(units[0].payload, kShFirstFrame, 1000000001);
  expectUnitsRow("H11", units);
}

// ---- GOM header ----

CATALOGUE_TEST(G01) {
  std::vector<Unit> units = baseUnits();
  putU32(units[1].payload, kGhFirstFrame, 1);
  expectUnitsRow("G01", units);
  units = baseUnits();
  putU32(units[6].payload, kGhFirstFrame, 2);  // the second GOM overlaps the first
  expectUnitsRow("G01", units);
}

CATALOGUE_TEST(G02) {
  std::vector<Unit> units = baseUnits();
  putU32(units[0].payload, kShFrameCount, 5);  // the second GOM (frames 3-5) runs past it
  expectUnitsRow("G02", units);
}

CATALOGUE_TEST(G03) {
  std::vector<Unit> units = baseUnits();
  putU16(units[1].payload, kGhFrameCount, 0);
  expectUnitsRow("G03", units);
}

CATALOGUE_TEST(G04) {
  std::vector<Unit> units = baseUnits();
  units[1].payload[kGhMode] = 4;
  expectUnitsRow("G04", units);
}

CATALOGUE_TEST(G05) {
  std::vector<Unit> units = baseUnits();
  putU16(units[1].payload, kGhQuantStep, 0);
  expectUnitsRow("G05", units);
  units = baseUnits();
  putU16(units[1].payload, kGhQuantStep, 4097);
  expectUnitsRow("G05", units);
}

CATALOGUE_TEST(G06) {
  std::vector<Unit> units = baseUnits();
  units[1].payload[kGhDepth] = 11;  // <= 20, but deeper than the 10-bit grid
  expectUnitsRow("G06", units);
}

CATALOGUE_TEST(G07) {
  std::vector<Unit> units = baseUnits();
  units[1].payload[kGhDepth] = 21;
  expectUnitsRow("G07", units);
}

CATALOGUE_TEST(G08) {
  for (uint16_t count : {uint16_t{0}, uint16_t{1}, uint16_t{4}}) {
    std::vector<Unit> units = baseUnits();
    putU16(units[1].payload, kGhNumKeyframes, count);
    expectUnitsRow("G08", units);
  }
}

CATALOGUE_TEST(G09) {
  std::vector<Unit> units = baseUnits();
  putU16(units[1].payload, kGhDelta, 0);
  expectUnitsRow("G09", units);
  units = baseUnits();
  putU16(units[1].payload, kGhDelta, 2);  // leaves no room for the third keyframe
  expectUnitsRow("G09", units);
}

CATALOGUE_TEST(G10) {
  // Two keyframes (offsets 0 and 1) in a GOM of 3 frames: the last is not the last frame.
  std::vector<Unit> units = baseUnits();
  std::vector<uint8_t>& gh = units[1].payload;
  putU16(gh, kGhNumKeyframes, 2);
  putU16(gh, kGhDelta, 1);
  gh.resize(kGhDelta + 2);
  expectUnitsRow("G10", units);
}

CATALOGUE_TEST(G11) {
  std::vector<Unit> units = baseUnits();
  units.erase(units.begin() + 6);  // the second GOM header: its I mesh comes instead
  expectUnitsRow("G11", units);
}

CATALOGUE_TEST(G12) {
  // 65535 frames of a 2500-vertex sheet from about 1 KB: 1.6 x 10^8 decoded vertex-frames.
  expectUnitsRow("G12", staticSheetUnits(50, 65535, 1));
}

// The encoder says when its stream is one that decoders with their default limits refuse
// (here the G12 stream: more decoded output per stream byte than MaxVertexFramesPerByte), as
// tdvo::Encoder::encode does for the stream it returns; a stream within the limits passes in
// silence.
TEST(EncoderWarnings, StreamsDefaultDecodersRefuseAreSaid) {
  std::vector<std::string> said;
  const WarningHandler before =
      setWarningHandler([&](const std::string& message) { said.push_back(message); });
  warnIfDecodersRefuse(join(staticSheetUnits(50, 65535, 1)));
  warnIfDecodersRefuse(join(staticSheetUnits(50, 3, 1)));
  setWarningHandler(before);
  ASSERT_EQ(said.size(), 1u);
  EXPECT_NE(said[0].find("decoders with their default limits refuse this stream: the stream: "),
            std::string::npos)
      << said[0];
  EXPECT_NE(said[0].find("(MaxVertexFramesPerByte)"), std::string::npos) << said[0];
}

// A WarnOnceScope says each message once; nested scopes share the outermost one's memory, which
// ends with it; what a SilenceWarningsScope drops is not remembered (said later, it is said).
TEST(EncoderWarnings, OnceAndSilencedScopes) {
  std::vector<std::string> said;
  const WarningHandler before =
      setWarningHandler([&](const std::string& message) { said.push_back(message); });
  {
    WarnOnceScope once;
    {
      SilenceWarningsScope quiet;
      warn("b");
    }
    warn("a");
    {
      WarnOnceScope inner;
      warn("a");
      warn("b");
    }
    warn("b");
  }
  warn("a");
  // The memory is bounded: past 65,536 distinct messages, new ones are not remembered.
  size_t count = 0;
  setWarningHandler([&](const std::string&) { ++count; });
  {
    WarnOnceScope once;
    for (int i = 0; i <= 65536; ++i)
      warn("m" + std::to_string(i));
    warn("m0");
    warn("m65536");
  }
  setWarningHandler(before);
  EXPECT_EQ(said, (std::vector<std::string>{"a", "b", "a"}));
  EXPECT_EQ(count, 65538u);
}

// warnForFile: inside a scope the first file's message of a kind is said, the other files'
// are counted (a file said twice counts once) and summed up when the outermost scope ends;
// outside a scope every message is said.
TEST(EncoderWarnings, PerFileWarningsAreSummedUp) {
  std::vector<std::string> said;
  const WarningHandler before =
      setWarningHandler([&](const std::string& message) { said.push_back(message); });
  {
    WarnOnceScope once;
    warnForFile("k", "f0: k");
    warnForFile("k", "f1: k");
    warnForFile("k", "f1: k");
    {
      WarnOnceScope inner;
      warnForFile("k", "f2: k");
      warnForFile("j", "f2: j");
    }
    EXPECT_EQ(said, (std::vector<std::string>{"f0: k", "f2: j"}));
  }
  warnForFile("k", "f0: k");
  warnForFile("k", "f1: k");
  setWarningHandler(before);
  EXPECT_EQ(said,
            (std::vector<std::string>{"f0: k", "f2: j", "k: the same in 2 more files or frames",
                                      "f0: k", "f1: k"}));
}

// A WarningHold keeps a thread's warnings (and nothing of other threads'), say() says them in
// order, as the calls would have; silenced warnings are not kept.
TEST(EncoderWarnings, HeldWarningsAreSaidInOrder) {
  std::vector<std::string> said;
  const WarningHandler before =
      setWarningHandler([&](const std::string& message) { said.push_back(message); });
  {
    WarnOnceScope once;
    std::vector<HeldWarning> first, second;
    std::thread other([&] {
      WarningHold hold;
      warnForFile("k", "f1: k");
      warn("b");
      second = hold.release();
    });
    {
      WarningHold hold;
      warnForFile("k", "f0: k");
      {
        SilenceWarningsScope quiet;
        warn("quiet");
      }
      warn("a");
      other.join();
      first = hold.release();
    }
    EXPECT_TRUE(said.empty());
    say(first);
    say(second);
  }
  setWarningHandler(before);
  EXPECT_EQ(said,
            (std::vector<std::string>{"f0: k", "a", "b", "k: the same in 1 more file or frame"}));
}

// 3dvo-enc reads the first frames more than once (the bounds pass, Quality's trial, the coding):
// what the reader leaves out of a file is said once, for the first file, and the number of other
// files it holds for at the end.
TEST(EncoderWarnings, AFileReadMoreThanOnceWarnsOnce) {
  TempDir dir("warn-once");
  std::filesystem::create_directories(dir.path() / "w");
  for (int k = 0; k < 6; ++k)
    test::writeText(dir.file("w/000" + std::to_string(k) + ".obj"),
                    "v 0 0 0 0.5 0.5 0.5\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nf 1 2 4\n"
                    "f 1 3 4\nf 2 3 4\n");
  const CommandResult r =
      test::run(dir, kBin + "/3dvo-enc", {"--InputMeshPattern=w/%04d.obj", "-o", "w.3dvo"});
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const auto count = [&](const std::string& line) {
    size_t n = 0;
    for (size_t at = r.err.find(line); at != std::string::npos; at = r.err.find(line, at + 1))
      ++n;
    return n;
  };
  EXPECT_EQ(count("w/0000.obj:1: values after x y z"), 1u) << r.err;
  EXPECT_EQ(count(".obj:1: values after x y z"), 1u) << r.err;
  EXPECT_EQ(count("values after x y z on 'v' lines (w, or vertex colours) are left out: the "
                  "same in 5 more files or frames"),
            1u)
      << r.err;
}

CATALOGUE_TEST(G13) {
  // One 16384 x 16384 camera: a 268-megapixel shape mask per texture unit from 2 KB of stream.
  expectUnitsRow("G13", texturedSheetUnits(10, 2, 16384, 16384, 1));
}

CATALOGUE_TEST(G14) {
  // A 2048 x 1024 camera (2^21 pixels, within one picture's allowance) and 16 x 16 texture
  // pictures of a few hundred bytes: with a limit of 4096 pixels per byte, the first texture
  // units pass and the limit stops the decoder before frame 20.
  test::writeBytes(dir_.file("x.3dvo"), join(texturedSheetUnits(10, 20, 2048, 1024, 20)));
  // No -o: the empty camera folders a failed run leaves are issue 18 item 10, not this row.
  expectRow("G14", "3dvo-dec", {"-i", "x.3dvo", "--MaxTexturePixelsPerByte=4096"});
}

// ---- I mesh ----

CATALOGUE_TEST(I01) {
  std::vector<Unit> units = baseUnits();
  putU32(units[2].payload, kImFrame, 4);
  expectUnitsRow("I01", units);
  units = baseUnits();
  putU32(units[7].payload, 0, 5);
  expectUnitsRow("I01", units);
}

CATALOGUE_TEST(I02) {
  std::vector<Unit> units = baseUnits();
  units.erase(units.begin() + 2);  // the P mesh of frame 1 comes where the I mesh belongs
  expectUnitsRow("I02", units);
}

CATALOGUE_TEST(I03) {
  std::vector<Unit> units = baseUnits();
  units[2].payload.resize(2);
  expectUnitsRow("I03", units);
}

CATALOGUE_TEST(I04) {
  for (const std::vector<uint8_t>& draco :
       {std::vector<uint8_t>{}, std::vector<uint8_t>{'D', 'R', 'A'},
        std::vector<uint8_t>{'d', 'r', 'a', 'c', 'o', 2, 2, 1, 1, 0, 0}}) {
    std::vector<Unit> units = baseUnits();
    units[2].payload = iMeshUnitPayload(0, draco);
    expectUnitsRow("I04", units);
  }
}

CATALOGUE_TEST(I05) {
  std::vector<uint8_t> draco = dracoPayload();
  draco[6] = 1;  // bitstream version 2.1
  std::vector<Unit> units = baseUnits();
  units[2].payload = iMeshUnitPayload(0, draco);
  expectUnitsRow("I05", units);
}

CATALOGUE_TEST(I06) {
  std::vector<Unit> units = baseUnits();
  units[2].payload = iMeshUnitPayload(0, dracoTriangle(draco::DT_INT32, false));
  expectUnitsRow("I06", units);
}

CATALOGUE_TEST(I07) {
  std::vector<uint8_t> draco = dracoPayload();
  draco[10] |= 0x80;  // flags: metadata present
  std::vector<Unit> units = baseUnits();
  units[2].payload = iMeshUnitPayload(0, draco);
  expectUnitsRow("I07", units);
}

CATALOGUE_TEST(I08) {
  // The counts Draco 1.5.5 would allocate for before failing (16 GB at 2^30 vertices and
  // 7e8 faces; docs/robustness.md): rejected before Draco sees them.
  std::vector<Unit> units = baseUnits();
  units[2].payload = iMeshUnitPayload(0, dracoWithCounts(1u << 30, 700000000, 699999999));
  expectUnitsRow("I08", units);
}

CATALOGUE_TEST(I09) {
  std::vector<Unit> units = baseUnits();
  units[2].payload = iMeshUnitPayload(0, dracoWithCounts(100, 700000000, 699999999));
  expectUnitsRow("I09", units);
}

CATALOGUE_TEST(I10) {
  std::vector<Unit> units = baseUnits();
  units[2].payload = iMeshUnitPayload(0, dracoWithCounts(100, 200, 201));
  expectUnitsRow("I10", units);
}

CATALOGUE_TEST(I11) {
  std::vector<uint8_t> draco = dracoPayload();
  draco.resize(draco.size() / 2);
  std::vector<Unit> units = baseUnits();
  units[2].payload = iMeshUnitPayload(0, draco);
  expectUnitsRow("I11", units);
}

CATALOGUE_TEST(I12) {
  std::vector<Unit> units = baseUnits();
  units[2].payload = iMeshUnitPayload(0, dracoTriangle(draco::DT_FLOAT32, true));
  expectUnitsRow("I12", units);
}

CATALOGUE_TEST(I13) {
  // The stream's grid shrinks to 8 bits (and GOM 0's octree with it): the I mesh's 10-bit
  // coordinates fall outside.
  std::vector<Unit> units = baseUnits();
  units[0].payload[kShGridBits] = 8;
  units[1].payload[kGhDepth] = 8;
  expectUnitsRow("I13", units);
}

CATALOGUE_TEST(I14) {
  // Five triangles on edge 0-1 (sequential Draco coding keeps them): 5 x 4 = 20 pairs of
  // triangles on a shared edge, more than 3 x 5. Thousands of them would make gigabytes of wings.
  draco::Mesh m;
  m.set_num_points(7);
  for (int i = 0; i < 5; ++i)
    m.AddFace({draco::PointIndex(0), draco::PointIndex(1), draco::PointIndex(i + 2)});
  draco::GeometryAttribute attribute;
  attribute.Init(draco::GeometryAttribute::POSITION, nullptr, 3, draco::DT_INT32, false, 12, 0);
  const int id = m.AddAttribute(attribute, true, 7);
  for (int i = 0; i < 7; ++i) {
    const int32_t p[3] = {10 * i, i == 1 ? 50 : 0, i > 1 ? 20 * i : 0};
    m.attribute(id)->SetAttributeValue(draco::AttributeValueIndex(i), p);
  }
  draco::Encoder encoder;
  encoder.SetEncodingMethod(draco::MESH_SEQUENTIAL_ENCODING);
  draco::EncoderBuffer buffer;
  ASSERT_TRUE(encoder.EncodeMeshToBuffer(m, &buffer).ok());
  std::vector<Unit> units = baseUnits();
  const std::vector<uint8_t> draco(buffer.data(), buffer.data() + buffer.size());
  units[2].payload = iMeshUnitPayload(0, draco);
  // Its vertex order: Draco's order, triangles as decoded.
  const IntMesh decoded = decodeIMesh(draco, kGridBits, "I14");
  MeshOrder order;
  order.numVertices = static_cast<uint32_t>(decoded.positions.size());
  for (uint32_t v = 0; v < decoded.positions.size(); ++v)
    order.vertexOutput.push_back(v);
  order.triangles = decoded.triangles;
  CabacWriterIo writer;
  codeMeshOrder(writer, decoded, order, false);
  VertexOrderUnit vo;
  vo.vo_num_vertices = order.numVertices;
  vo.vo_triangle_order = 0;
  vo.vo_cabac_payload = writer.finish();
  units[3].payload = serialise(vo);
  expectUnitsRow("I14", units);
}

CATALOGUE_TEST(I15) {
  // Draco would size the attribute's values as points x components x type size.
  std::vector<Unit> units = baseUnits();
  units[2].payload = iMeshUnitPayload(0, dracoWithDescriptor(dracoPayload(), 1, 5, 255));
  expectUnitsRow("I15", units);
  units[2].payload = iMeshUnitPayload(0, dracoWithDescriptor(dracoPayload(), 1, 10, 3));
  expectUnitsRow("I15", units);
}

CATALOGUE_TEST(I16) {
  std::vector<Unit> units = baseUnits();
  units[2].payload = iMeshUnitPayload(0, dracoWithDescriptor(dracoPayload(), 100, 5, 3));
  expectUnitsRow("I16", units);
}

CATALOGUE_TEST(I17) {
  // The largest counts the I-mesh limits allow (I08, I09), in a stream of under 1 KB: Draco
  // would allocate about 0.8 GB for them before finding the payload too short (the mesh-memory
  // limit, docs/robustness.md "Memory"). Lifted, counts of 2^18 vertices and 2^19 faces (also
  // refused by default) reach Draco, which then fails on the payload (I11), not on the limit.
  std::vector<Unit> units = baseUnits();
  units[2].payload = iMeshUnitPayload(0, dracoWithCounts(kMaxVertices, kMaxTriangles, 100));
  expectUnitsRow("I17", units);
  units[2].payload = iMeshUnitPayload(0, dracoWithCounts(1u << 18, 1u << 19, 100));
  expectUnitsRow("I17", units);
  const CommandResult lifted =
      test::run(dir_, kBin + "/3dvo-dec", {"-i", "x.3dvo", "--MaxMeshMemoryPerByte=0"});
  EXPECT_EQ(lifted.exitCode, 1) << lifted.err;
  EXPECT_EQ(lifted.err.find("MaxMeshMemoryPerByte"), std::string::npos) << lifted.err;
  EXPECT_NE(lifted.err.find("Draco cannot decode im_draco_payload"), std::string::npos)
      << lifted.err;
}

// im_quant_step follows im_frame (4 bytes).
CATALOGUE_TEST(I18) {
  std::vector<Unit> units = baseUnits();
  putU16(units[2].payload, kImQuantStep, 0);
  expectUnitsRow("I18", units);
}

CATALOGUE_TEST(I19) {
  std::vector<Unit> units = baseUnits();
  putU16(units[2].payload, kImQuantStep, 4097);
  expectUnitsRow("I19", units);
}

CATALOGUE_TEST(I20) {
  // The base I mesh's lossless values (10-bit grid) read as multiples of 4: those above
  // (2^10 - 1) / 4 = 255 would leave the grid once multiplied.
  std::vector<Unit> units = baseUnits();
  putU16(units[2].payload, kImQuantStep, 4);
  expectUnitsRow("I20", units);
}

// ---- Vertex order ----

// A VERTEX_ORDER unit for frame 0 (triangle list coded) with `bins` as its CABAC payload, each
// bin coded with a fresh context (the decoder's contexts all start equiprobable too, and each
// context of the payloads built here is used once, or only with equal bins).
std::vector<uint8_t> vertexOrderPayload(const std::vector<unsigned>& bins, bool sameContext) {
  CabacEncoder encoder;
  ContextModel shared;
  for (unsigned bin : bins) {
    ContextModel fresh;
    encoder.encodeBin(sameContext ? shared : fresh, bin);
  }
  VertexOrderUnit vo = parse<VertexOrderUnit>(baseUnits()[3]);
  vo.vo_cabac_payload = encoder.finish();
  return serialise(vo);
}

CATALOGUE_TEST(V01) {
  std::vector<Unit> units = baseUnits();
  units.erase(units.begin() + 3);  // the P mesh of frame 1 where the vertex order belongs
  expectUnitsRow("V01", units);
}

CATALOGUE_TEST(V02) {
  std::vector<Unit> units = baseUnits();
  putU32(units[3].payload, 0, 4);
  expectUnitsRow("V02", units);
}

CATALOGUE_TEST(V03) {
  std::vector<Unit> units = baseUnits();
  units[3].payload[8] = 2;
  expectUnitsRow("V03", units);
}

CATALOGUE_TEST(V04) {
  // Vertices 0 and 1 both get output index 0 (two zero deltas, both predicted from vertex 0).
  std::vector<Unit> units = baseUnits();
  units[3].payload = vertexOrderPayload({0, 0}, true);
  expectUnitsRow("V04", units);
}

CATALOGUE_TEST(V05) {
  // Vertex 0 gets -1: nonzero, negative, magnitude 1.
  std::vector<Unit> units = baseUnits();
  units[3].payload = vertexOrderPayload({1, 1, 0}, false);
  expectUnitsRow("V05", units);
}

CATALOGUE_TEST(V06) {
  std::vector<Unit> units = baseUnits();
  units[3].payload.push_back(0);
  units[3].payload.push_back(0);
  expectUnitsRow("V06", units);
}

CATALOGUE_TEST(V08) {
  std::vector<Unit> units = baseUnits();
  putU32(units[3].payload, 4, 43);  // one more than the I mesh's 42 vertices
  expectUnitsRow("V08", units);
}

CATALOGUE_TEST(V07) {
  std::vector<Unit> units = baseUnits();
  units[3].payload.resize(9);  // vo_frame, vo_num_vertices and vo_triangle_order only
  expectUnitsRow("V07", units);
}

// A writer that codes whatever it is given (the syntax's own writer refuses out-of-range values;
// the values below binarise as the decoder reads them: same class as the largest allowed).
struct LaxWriterIo : CabacWriterIo {
  void require(bool, const char*) const {}
  void require(bool, const std::string&) const {}
};

// The base stream's VERTEX_ORDER unit (frame 0: 42 vertices, 80 triangles, input triangle order)
// with degenerate triangles at `positions` of its output list (`triangles`: the degenerate
// ones; a position beyond the list makes a {0, 0, 0}).
std::vector<uint8_t> vertexOrderWithDegenerate(const std::vector<uint32_t>& positions,
                                               const std::vector<Triangle>& triangles) {
  const std::vector<Unit> units = baseUnits();
  const IntMesh decoded = decodeIMesh(dracoPayload(), kGridBits, "base");
  VertexOrderUnit vo = parse<VertexOrderUnit>(units[3]);
  MeshOrder order;
  order.numVertices = vo.vo_num_vertices;
  CabacReaderIo reader(vo.vo_cabac_payload.data(), vo.vo_cabac_payload.size(), "base");
  codeMeshOrder(reader, decoded, order, true);
  EXPECT_EQ(order.numVertices, 42u);
  EXPECT_EQ(order.triangles.size(), 80u);
  for (size_t k = 0; k < positions.size() && k < triangles.size(); ++k)
    order.triangles.insert(order.triangles.begin() + positions[k], triangles[k]);
  order.degenerate = positions;
  LaxWriterIo writer;
  codeMeshOrder(writer, decoded, order, true);
  vo.vo_cabac_payload = writer.finish();
  return serialise(vo);
}

CATALOGUE_TEST(V09) {
  // 81 degenerate triangles for an I mesh of 80 triangles.
  std::vector<uint32_t> positions;
  for (uint32_t p = 80; p <= 160; ++p)
    positions.push_back(p);
  std::vector<Unit> units = baseUnits();
  units[3].payload = vertexOrderWithDegenerate(positions, {});
  expectUnitsRow("V09", units);
}

CATALOGUE_TEST(V10) {
  // One degenerate triangle at position 81 of a list of 81 triangles.
  std::vector<Unit> units = baseUnits();
  units[3].payload = vertexOrderWithDegenerate({81}, {});
  expectUnitsRow("V10", units);
}

CATALOGUE_TEST(V11) {
  // A degenerate triangle with output vertex 42 of 42.
  std::vector<Unit> units = baseUnits();
  units[3].payload = vertexOrderWithDegenerate({0}, {{41, 42, 41}});
  expectUnitsRow("V11", units);
}

// ---- Attributes ----

// The base stream's frames with texture coordinates (per corner) and normals (the same in
// every frame: coded once per I mesh): units SH, GH, I, VO, AT, P, P, GH, I, VO, AT, P, P.
std::vector<Unit> attributeUnits() {
  static const std::vector<uint8_t> stream = [] {
    EncoderParams params;
    params.gridBits = kGridBits;
    params.gomSize = 3;
    params.pmeshMode = PMeshMode::kD3dmc;
    std::vector<Mesh> frames = test::wobblingSphere(1, kFrames);
    test::addAttributes(frames, true, true);
    return encodeSequence(params, gridForSequence(frames, kGridBits), frames, {},
                          [](int, const IntMesh&) {})
        .stream;
  }();
  std::vector<Unit> units = split(stream);
  EXPECT_EQ(units.size(), 13u);
  EXPECT_EQ(units[4].type, static_cast<uint8_t>(UnitType::kAttributes));
  return units;
}

// Byte offsets in the ATTRIBUTES payload (per-corner texture coordinates, per-vertex normals).
constexpr size_t kAtFrame = 0, kAtUvMode = 4, kAtUvOrigin = 6, kAtNumUvs = 7, kAtNormalMode = 11,
                 kAtPayload = 13;
constexpr size_t kShAttributesPresent = kShStep + 8;

CATALOGUE_TEST(A01) {
  // The base stream (no ATTRIBUTES units) saying it has them.
  std::vector<Unit> units = baseUnits();
  units[0].payload[kShAttributesPresent] = 1;
  expectUnitsRow("A01", units);
}

CATALOGUE_TEST(A02) {
  std::vector<Unit> units = attributeUnits();
  putU32(units[4].payload, kAtFrame, 4);
  expectUnitsRow("A02", units);
}

CATALOGUE_TEST(A03) {
  std::vector<Unit> units = attributeUnits();
  units[4].payload[kAtUvMode] = 3;
  expectUnitsRow("A03", units);
}

CATALOGUE_TEST(A04) {
  // 80 triangles have 240 corners: more values than that would be values no corner uses, so a
  // count is bounded by the I mesh, itself bounded by the stream's bytes.
  std::vector<Unit> units = attributeUnits();
  putU32(units[4].payload, kAtNumUvs, 241);
  expectUnitsRow("A04", units);
  putU32(units[4].payload, kAtNumUvs, 0xFFFFFFFF);
  expectUnitsRow("A04", units);
}

CATALOGUE_TEST(A05) {
  std::vector<Unit> units = attributeUnits();
  units[4].payload[kAtNormalMode] = 4;
  expectUnitsRow("A05", units);
}

CATALOGUE_TEST(A06) {
  std::vector<Unit> units = attributeUnits();
  units[4].payload.resize(kAtNumUvs + 2);
  expectUnitsRow("A06", units);
}

CATALOGUE_TEST(A07) {
  std::vector<Unit> units = attributeUnits();
  units[4].payload.push_back(0);
  units[4].payload.push_back(0);
  expectUnitsRow("A07", units);
}

CATALOGUE_TEST(A08) {
  // The payload cut to its first half.
  std::vector<Unit> units = attributeUnits();
  units[4].payload.resize(kAtPayload + (units[4].payload.size() - kAtPayload) / 2);
  expectUnitsRow("A08", units);
}

CATALOGUE_TEST(A09) {
  // Per-vertex texture coordinates (no indices first), the first value's key moved by
  // +(2^32 - 1) from its prediction 0: past any float's bit pattern.
  std::vector<Unit> units = attributeUnits();
  ByteReader reader(units[4].payload.data(), units[4].payload.size(), "at", 0);
  AttributesUnit at;
  at.maxValues = 240;
  transfer(reader, at);
  at.at_uv_mode = static_cast<uint8_t>(UvMode::kPerVertex);
  LaxWriterIo writer;
  AttributeContexts ctx;
  int64_t delta = 0xFFFFFFFFll;
  order_detail::codeSigned(writer, "at_uv_delta", ctx.uv[0], delta, UINT32_MAX);
  at.at_cabac_payload = writer.finish();
  units[4].payload = serialise(at);
  expectUnitsRow("A09", units);
}

CATALOGUE_TEST(A10) {
  // The first corner's index (the indices come before the values) beyond the values.
  std::vector<Unit> units = attributeUnits();
  ByteReader reader(units[4].payload.data(), units[4].payload.size(), "at", 0);
  AttributesUnit at;
  at.maxValues = 240;
  transfer(reader, at);
  ASSERT_EQ(at.at_num_uvs, 69u);  // 42 vertices and 27 seam values
  LaxWriterIo writer;
  AttributeContexts ctx;
  unsigned notNew = 0;
  writer.bin("at_uv_new", ctx.uvNew, notNew);
  uint32_t index = 100;  // within the binarisation's class of 68, beyond it
  order_detail::codeUnsigned(writer, "at_uv_index", ctx.uvIndex, index, 68);
  at.at_cabac_payload = writer.finish();
  units[4].payload = serialise(at);
  expectUnitsRow("A10", units);
}

CATALOGUE_TEST(A11) {
  std::vector<Unit> units = attributeUnits();
  ASSERT_EQ(units[4].payload[kAtUvOrigin], 0);  // OBJ's convention, as the frames give it
  units[4].payload[kAtUvOrigin] = 2;
  expectUnitsRow("A11", units);
}

// The ATTRIBUTES base stream itself decodes, with its attributes in every frame (the helper is
// not the cause of A02-A11).
TEST(Attributes, BaseStreamDecodes) {
  const std::vector<uint8_t> stream = join(attributeUnits());
  StreamDecoder decoder(stream.data(), stream.size(), "in.3dvo");
  int frames = 0;
  decoder.decode([&](int, const IntMesh& m) {
    EXPECT_EQ(m.attributes.uvs.size(), 69u);
    EXPECT_EQ(m.attributes.normals.size(), 42u);
    ++frames;
  });
  EXPECT_EQ(frames, kFrames);
}

// A valid degenerate triangle decodes, in place (the helper above is not the cause of V09-V11).
TEST(VertexOrder, DegenerateTriangleDecodesInPlace) {
  std::vector<Unit> units = baseUnits();
  units[3].payload = vertexOrderWithDegenerate({5}, {{3, 3, 7}});
  const std::vector<uint8_t> stream = join(units);
  StreamDecoder decoder(stream.data(), stream.size(), "in.3dvo");
  decoder.setPictureDecoder(makeH264Decoder);
  std::vector<IntMesh> frames;
  decoder.decode([&](int, const IntMesh& m) { frames.push_back(m); });
  ASSERT_FALSE(frames.empty());
  ASSERT_EQ(frames[0].triangles.size(), 81u);
  EXPECT_EQ(frames[0].triangles[5], (Triangle{3, 3, 7}));
}

CATALOGUE_TEST(G15) {
  std::vector<Unit> units = baseUnits();
  units[1].payload[kGhRandomAccess] = 0;
  expectUnitsRow("G15", units);
}

CATALOGUE_TEST(G16) {
  std::vector<Unit> units = baseUnits();
  units[1].payload[kGhRandomAccess] = 2;
  expectUnitsRow("G16", units);
}

CATALOGUE_TEST(G17) {
  std::vector<Unit> units = bMeshUnits(2);
  {  // valid in version 4 (every frame a keyframe: no B mesh)
    const std::vector<uint8_t> stream = join(units);
    StreamDecoder decoder(stream.data(), stream.size(), "in.3dvo");
    int frames = 0;
    decoder.decode([&](int, const IntMesh&) { ++frames; });
    EXPECT_EQ(frames, kFrames);
  }
  putU16(units[0].payload, kShVersion, 3);
  expectUnitsRow("G17", units);
}

CATALOGUE_TEST(G18) {
  for (uint16_t step : {uint16_t{0}, uint16_t{4097}})
    expectUnitsRow("G18", bMeshUnits(step));
}

// ---- P mesh ----

CATALOGUE_TEST(P01) {
  std::vector<Unit> units = baseUnits();
  putU32(units[4].payload, 0, 2);
  expectUnitsRow("P01", units);
}

CATALOGUE_TEST(P02) {
  std::vector<Unit> units = baseUnits();
  units[4] = units[2];  // an I mesh where the P mesh of frame 1 belongs
  expectUnitsRow("P02", units);
  units = baseUnits();
  units.erase(units.begin() + 5);  // GOM 1's header where frame 2's P mesh belongs
  expectUnitsRow("P02", units);
}

CATALOGUE_TEST(P03) {
  std::vector<Unit> units = baseUnits();
  units[4].payload.resize(2);
  expectUnitsRow("P03", units);
}

CATALOGUE_TEST(P04) {
  std::vector<Unit> units = baseUnits();
  units[4].payload.resize(4);  // pm_frame only
  expectUnitsRow("P04", units);
}

CATALOGUE_TEST(P05) {
  std::vector<Unit> units = baseUnits();
  units[4].payload.push_back(0);
  units[4].payload.push_back(0);
  expectUnitsRow("P05", units);
  // One byte, too short for the next codeword the decoder starts on it: the same message (it
  // read as a truncated payload).
  units = baseUnits();
  units[4].payload.push_back(0);
  test::writeBytes(dir_.file("one.3dvo"), join(units));
  const test::CommandResult r = test::run(dir_, kBin + "/3dvo-dec", {"-i", "one.3dvo"});
  EXPECT_EQ(r.exitCode, 1);
  EXPECT_NE(r.err.find(": 1 unexpected bytes after the payload's end"), std::string::npos) << r.err;
}

CATALOGUE_TEST(P06) {
  std::vector<Unit> units = afxicUnits();
  std::vector<uint8_t> payload(4, 0);
  putU32(payload, 0, 1);
  const std::vector<uint8_t> cabac = afxicResidualPayload((1 << 21) + 1);
  payload.insert(payload.end(), cabac.begin(), cabac.end());
  units[4].payload = payload;
  expectUnitsRow("P06", units);
}

CATALOGUE_TEST(P07) {
  // Residual 1000 is in range, but times the quantiser step 4096 the motion is not.
  std::vector<Unit> units = afxicUnits();
  putU16(units[1].payload, kGhQuantStep, 4096);
  std::vector<uint8_t> payload(4, 0);
  putU32(payload, 0, 1);
  const std::vector<uint8_t> cabac = afxicResidualPayload(1000);
  payload.insert(payload.end(), cabac.begin(), cabac.end());
  units[4].payload = payload;
  expectUnitsRow("P07", units);
}

CATALOGUE_TEST(P08) {
  std::vector<Unit> units = baseUnits();
  std::vector<uint8_t>& p = units[4].payload;
  p.resize(4 + (p.size() - 4) / 2);
  expectUnitsRow("P08", units);
}

// ---- Texture units ----

// A textured stream: the committed conformance stream with 3 cameras.
std::vector<Unit> textureUnits() {
  return split(test::readBytes(std::string(TDVO_SOURCE_DIR) +
                               "/conformance/streams/texture_bbox_mb128_g3.3dvo"));
}

// Payload offsets of the NAL units of a texture unit (after each start code; tx_frame and
// tx_camera take the first 6 bytes).
std::vector<size_t> nalStarts(const std::vector<uint8_t>& p) {
  std::vector<size_t> starts;
  for (size_t b = 6; b + 3 <= p.size(); ++b)
    if (p[b] == 0 && p[b + 1] == 0 && p[b + 2] == 1) starts.push_back(b + 3);
  return starts;
}

std::vector<size_t> textureUnitIndices(const std::vector<Unit>& units) {
  std::vector<size_t> textures;
  for (size_t i = 0; i < units.size(); ++i)
    if (units[i].type == static_cast<uint8_t>(UnitType::kTexture)) textures.push_back(i);
  return textures;
}

CATALOGUE_TEST(T01) {
  std::vector<Unit> units = textureUnits();
  int spsSeen = 0;
  for (size_t i : textureUnitIndices(units))
    for (size_t nal : nalStarts(units[i].payload))
      if (units[i].payload[4] == 0 && units[i].payload[5] == 0 &&  // tx_camera 0
          (units[i].payload[nal] & 0x1f) == 7 && ++spsSeen == 2) {
        units[i].payload.at(nal + 4) ^= 0x5a;  // inside log2_max_frame_num_minus4 and after
        expectTextureRow("T01", units);
        return;
      }
  FAIL() << "camera 0 has no second SPS in the stream";
}

CATALOGUE_TEST(T02) {
  const std::vector<Unit> units = textureUnits();
  const std::vector<size_t> textures = textureUnitIndices(units);
  ASSERT_GE(textures.size(), 3u);
  for (size_t which : {textures.front(), textures[textures.size() / 2], textures.back()}) {
    SCOPED_TRACE("texture unit " + std::to_string(which));
    std::vector<Unit> damaged = units;
    std::vector<uint8_t>& p = damaged[which].payload;
    // The slice data is the last NAL unit.
    const size_t lastNal = nalStarts(p).back();
    ASSERT_LT(lastNal + 8, p.size());
    p[lastNal + (p.size() - lastNal) / 2] ^= 0x5a;
    expectTextureRow("T02", damaged);
  }
}

// ---- 3dvo-dec options ----

CATALOGUE_TEST(D01) {
  expectRow("D01", "3dvo-dec", {"-o", "out"});
}

CATALOGUE_TEST(D02) {
  test::writeBytes(dir_.file("x.3dvo"), baseStream());
  std::string log;
  for (int f = 0; f < kFrames; ++f)
    log += "MD5 frame=" + std::to_string(f) + " geometry=00000000000000000000000000000000\n";
  test::writeText(dir_.file("x.md5"), log);
  expectRow("D02", "3dvo-dec", {"-i", "x.3dvo", "-o", "out", "--verify", "x.md5"});
}

CATALOGUE_TEST(D03) {
  test::writeBytes(dir_.file("x.3dvo"), baseStream());
  test::writeText(dir_.file("x.md5"), "# no MD5 lines\n");
  expectRow("D03", "3dvo-dec", {"-i", "x.3dvo", "-o", "out", "--verify", "x.md5"});
}

CATALOGUE_TEST(D04) {
  // A log with the right lines plus one more frame.
  test::writeBytes(dir_.file("x.3dvo"), baseStream());
  const CommandResult good = test::run(dir_, kBin + "/3dvo-dec", {"-i", "x.3dvo"});
  ASSERT_EQ(good.exitCode, 0) << good.err;
  std::string log;
  for (const std::string& line : test::linesStartingWith(good.out, "MD5 "))
    log += line + "\n";
  log += "MD5 frame=6 geometry=00000000000000000000000000000000\n";
  test::writeText(dir_.file("x.md5"), log);
  expectRow("D04", "3dvo-dec", {"-i", "x.3dvo", "-o", "out", "--verify", "x.md5"});
}

CATALOGUE_TEST(D12) {
  // The log of the base stream; then the same stream with its grid moved: every grid integer,
  // so every frame line, is the same, but every OBJ coordinate differs.
  test::writeBytes(dir_.file("x.3dvo"), baseStream());
  const CommandResult good = test::run(dir_, kBin + "/3dvo-dec", {"-i", "x.3dvo"});
  ASSERT_EQ(good.exitCode, 0) << good.err;
  std::string log;
  for (const std::string& line : test::linesStartingWith(good.out, "MD5 "))
    log += line + "\n";
  test::writeText(dir_.file("x.md5"), log);
  std::vector<Unit> units = baseUnits();
  putF64(units[0].payload, kShOrigin, 1000.0);
  test::writeBytes(dir_.file("x.3dvo"), join(units));
  expectRow("D12", "3dvo-dec", {"-i", "x.3dvo", "-o", "out", "--verify", "x.md5"});
}

CATALOGUE_TEST(D05) {
  test::writeBytes(dir_.file("x.3dvo"), baseStream());
  test::writeText(dir_.file("file"), "in the way\n");
  expectRow("D05", "3dvo-dec", {"-i", "x.3dvo", "-o", "file/out"});
}

CATALOGUE_TEST(D06) {
  test::writeBytes(dir_.file("x.3dvo"), baseStream());
  expectRow("D06", "3dvo-dec", {"-i", "x.3dvo", "-o", "out", "--verify", "/dev/zero"});
}

CATALOGUE_TEST(D08) {
  test::writeBytes(dir_.file("x.3dvo"), baseStream());
  expectRow("D08", "3dvo-dec", {"-i", "x.3dvo", "-o", "out", "--FirstFrame=6"});
}

CATALOGUE_TEST(D07) {
  test::writeBytes(dir_.file("x.3dvo"), baseStream());
  expectRow("D07", "3dvo-dec", {"-i", "x.3dvo", "-o", "out", "--FirstFrame=4", "--FrameCount=3"});
}

CATALOGUE_TEST(D09) {
  test::writeBytes(dir_.file("x.3dvo"), baseStream());
  std::filesystem::create_directories(dir_.path() / "out");
  test::writeText(dir_.file("out/old.obj"), "another run\n");
  expectRow("D09", "3dvo-dec", {"-i", "x.3dvo", "-o", "out"});
  EXPECT_EQ(test::readText(dir_.file("out/old.obj")), "another run\n");
}

CATALOGUE_TEST(D10) {
  std::filesystem::create_directories(dir_.path() / "out");
  test::writeBytes(dir_.file("out/x.3dvo"), baseStream());
  expectRow("D10", "3dvo-dec", {"-i", "out/x.3dvo", "-o", "out", "--Overwrite"});
  EXPECT_EQ(test::readBytes(dir_.file("out/x.3dvo")), baseStream());
}

CATALOGUE_TEST(D11) {
  test::writeBytes(dir_.file("x.3dvo"), baseStream());
  test::writeText(dir_.file("file"), "in the way\n");
  expectRow("D11", "3dvo-dec", {"-i", "x.3dvo", "-o", "file"});
  EXPECT_EQ(test::readText(dir_.file("file")), "in the way\n");
}

// ---- OBJ input (3dvo-enc) ----

const std::string kTriangle = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";

CATALOGUE_TEST(O01) {
  writeInput("", 1);
  std::filesystem::remove(dir_.file("in/000.obj"));
  expectRow("O01", "3dvo-enc", encoderArgs(1));
}

CATALOGUE_TEST(O02) {
  expectObjRow("O02", "v 0 0 0\nv 0.3.1 0 0\n");
}

CATALOGUE_TEST(O03) {
  for (const char* number : {"nan", "inf", "-inf"})
    expectObjRow("O03", kTriangle + "v 0 " + number + " 1\nf 1 2 3\n");
}

CATALOGUE_TEST(O18) {
  expectObjRow("O18", kTriangle + "v 0 1e301 1\nf 1 2 3\n");
}

CATALOGUE_TEST(O19) {
  std::string fan = "v 0 0 0\n";
  for (int i = 0; i <= 5000; ++i)
    fan += "v " + std::to_string(std::cos(i * 1e-3)) + " " + std::to_string(std::sin(i * 1e-3)) +
           " 0\n";
  for (int i = 0; i < 5000; ++i)
    fan += "f 1 " + std::to_string(i + 2) + " " + std::to_string(i + 3) + "\n";
  expectObjRow("O19", fan);
}

CATALOGUE_TEST(O04) {
  expectObjRow("O04", kTriangle + "v 1 2\nf 1 2 3\n");
}

CATALOGUE_TEST(O05) {
  expectObjRow("O05", kTriangle + "f 1 2\n");
}

CATALOGUE_TEST(O06) {
  for (const char* index : {"0", "x", "1.5", "/2"})
    expectObjRow("O06", kTriangle + "f 1 2 " + index + "\n");
}

CATALOGUE_TEST(O07) {
  expectObjRow("O07", kTriangle + "f 1 2 3\nf 1 9 2\n");
}

CATALOGUE_TEST(O08) {
  expectObjRow("O08", kTriangle + "f -5 1 2\n");
}

CATALOGUE_TEST(O09) {
  expectObjRow("O09", kTriangle + "f 1 2 3\nl 1 2\n");
}

CATALOGUE_TEST(O10) {
  expectObjRow("O10", kTriangle);
}

CATALOGUE_TEST(O11) {
  expectObjRow("O11", "# nothing\n");
}

CATALOGUE_TEST(O12) {
  writeInput("", 1);
  test::writeText(dir_.file("in/000.obj"), std::string("\x1f\x8b\x08\x00garbage", 11));
  expectRow("O12", "3dvo-enc", encoderArgs(1));
}

CATALOGUE_TEST(O13) {
  expectObjRow("O13", kTriangle + "f 1 2 2\n");
}

CATALOGUE_TEST(O14) {
  // Frame 1 of a d3dmc GOM has other vertices than frame 0.
  writeInput("", 2);
  test::writeText(dir_.file("in/001.obj"), kTriangle + "f 1 2 3\n");
  std::vector<std::string> args = encoderArgs(2);
  args.push_back("--PMeshMode=d3dmc");
  expectRow("O14", "3dvo-enc", args);
}

// O14 under Quality: its trial codes a window in the middle of the 20-frame GOM (frames 6 .. 14),
// as a GOM of its own, and meets the odd frame 12 first; the message is still the encode's,
// naming the GOM's first frame, not the window's.
TEST_F(ErrorsTest, O14UnderQualityNamesTheGomsFirstFrame) {
  writeInput("", 20);
  test::writeText(dir_.file("in/012.obj"), kTriangle + "f 1 2 3\n");
  const CommandResult r = test::run(
      dir_, kBin + "/3dvo-enc",
      {"--InputMeshPattern=in/%03d.obj", "--FrameCount=20", "--GOMSize=20", "-o", "x.3dvo"});
  EXPECT_EQ(r.exitCode, 1);
  EXPECT_NE(r.err.find("in/012.obj: 3 vertices, but the GOM's first frame (in/000.obj) has 42"),
            std::string::npos)
      << r.err;
  EXPECT_FALSE(std::filesystem::exists(dir_.file("x.3dvo")));
}

CATALOGUE_TEST(O15) {
  // Same vertex count, other triangles.
  writeInput("", 2);
  Mesh m = test::wobblingSphere(1, 2)[1];
  std::swap(m.triangles[0], m.triangles[1]);
  test::writeText(dir_.file("in/001.obj"), formatObj(m));
  std::vector<std::string> args = encoderArgs(2);
  args.push_back("--PMeshMode=d3dmc");
  expectRow("O15", "3dvo-enc", args);
}

CATALOGUE_TEST(O16) {
  // A frame that never ends (and has no line break): refused after its first MiB.
  writeInput("", 1);
  std::filesystem::remove(dir_.file("in/000.obj"));
  std::filesystem::create_symlink("/dev/zero", dir_.file("in/000.obj"));
  expectRow("O16", "3dvo-enc", encoderArgs(1));
}

CATALOGUE_TEST(O17) {
  expectObjRow("O17", "v 0 0 0\nv 5e-324 0 0\nv 0 5e-324 0\nf 1 2 3\n");
}

// ---- 3dvo-dec mesh output options ----

CATALOGUE_TEST(D13) {
  test::writeBytes(dir_.file("x.3dvo"), baseStream());
  expectRow("D13", "3dvo-dec", {"-i", "x.3dvo", "-o", "out", "--MeshFormat=stl"});
}

CATALOGUE_TEST(D14) {
  test::writeBytes(dir_.file("x.3dvo"), baseStream());
  expectRow("D14", "3dvo-dec", {"-i", "x.3dvo", "--AnimationFile=anim.glb"});
}

CATALOGUE_TEST(D15) {
  test::writeBytes(dir_.file("x.3dvo"), baseStream());
  for (const char* name : {"anim.gltf", "sub/anim.glb"})
    expectRow("D15", "3dvo-dec",
              {"-i", "x.3dvo", "-o", "out", std::string("--AnimationFile=") + name});
}

CATALOGUE_TEST(D16) {
  test::writeBytes(dir_.file("x.3dvo"), baseStream());
  expectRow("D16", "3dvo-dec",
            {"-i", "x.3dvo", "-o", "out", "--MeshFormat=glb", "--AnimationFile=0000.glb"});
}

CATALOGUE_TEST(D17) {
  std::filesystem::create_directories(dir_.path() / "in");
  test::writeText(dir_.file("in/000.obj"), "v 0 0 0\nv 1e100 0 0\nv 0 1e100 0\nf 1 2 3\n");
  ASSERT_EQ(test::run(dir_, kBin + "/3dvo-enc", {"--InputMeshPattern=in/%03d.obj", "-o", "x.3dvo"})
                .exitCode,
            0);
  expectRow("D17", "3dvo-dec", {"-i", "x.3dvo", "-o", "out", "--MeshFormat=gltf"});
}

CATALOGUE_TEST(D19) {
  // 20000 frames of a 9-vertex sheet (a few hundred bytes): refused at the first frame, before
  // the animation holds any.
  test::writeBytes(dir_.file("x.3dvo"), join(staticSheetUnits(3, 20000, 1)));
  expectRow("D19", "3dvo-dec",
            {"-i", "x.3dvo", "-o", "out", "--MeshFormat=none", "--AnimationFile=a.glb"});
}

CATALOGUE_TEST(D18) {
  test::writeBytes(dir_.file("x.3dvo"), baseStream());
  expectRow("D18", "3dvo-dec",
            {"-i", "x.3dvo", "-o", "out", "--MeshFormat=ply", "--OutputMeshPattern=f%03d.obj"});
}

CATALOGUE_TEST(D20) {
  test::writeBytes(dir_.file("x.3dvo"), baseStream());
  expectRow("D20", "3dvo-dec", {"-i", "x.3dvo", "-o", "out", "--OutputMeshPattern=/tmp/f%04d.obj"});
}

// ---- PLY and glTF input (3dvo-enc) ----

// Frame 0 of the usual sphere, as a file `name` in in/, and the encoder's arguments for it.
std::vector<std::string> meshInput(const TempDir& dir, const std::string& name,
                                   const std::string& data) {
  std::filesystem::create_directories(dir.path() / "in");
  test::writeText(dir.file("in/" + name), data);
  const std::string ext = name.substr(name.find('.'));
  return {"--InputMeshPattern=in/%03d" + ext, "--FrameCount=1", "--GridBits=10", "-o",
          "out/x.3dvo"};
}

const Mesh& errorSphere() {
  static const Mesh m = test::wobblingSphere(1, 1)[0];
  return m;
}

const std::string kPlyHead =
    "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
    "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";

CATALOGUE_TEST(Y01) {
  expectRow("Y01", "3dvo-enc", meshInput(dir_, "000.ply", formatObj(errorSphere())));
}

CATALOGUE_TEST(Y02) {
  expectRow("Y02", "3dvo-enc",
            meshInput(dir_, "000.ply", "ply\nformat binary_middle_endian 1.0\nend_header\n"));
}

CATALOGUE_TEST(Y03) {
  expectRow("Y03", "3dvo-enc",
            meshInput(dir_, "000.ply", "ply\nformat ascii 1.0\nelement vertex 3\n"));
}

CATALOGUE_TEST(Y04) {
  std::string head = kPlyHead;
  head.erase(head.find("property float z\n"), 17);
  expectRow("Y04", "3dvo-enc", meshInput(dir_, "000.ply", head + "0 0\n1 0\n0 1\n3 0 1 2\n"));
}

CATALOGUE_TEST(Y05) {
  const std::string head = kPlyHead.substr(0, kPlyHead.find("element face"));
  expectRow("Y05", "3dvo-enc",
            meshInput(dir_, "000.ply", head + "end_header\n0 0 0\n1 0 0\n0 1 0\n"));
}

CATALOGUE_TEST(Y06) {
  const std::string ply = formatPly(errorSphere());
  const size_t body = ply.find("end_header\n") + 11;
  expectRow("Y06", "3dvo-enc", meshInput(dir_, "000.ply", ply.substr(0, body + 2 * 24 + 10)));
}

CATALOGUE_TEST(Y07) {
  expectRow("Y07", "3dvo-enc", meshInput(dir_, "000.ply", formatPly(errorSphere()) + "\n\n"));
}

CATALOGUE_TEST(Y08) {
  std::string ply = formatPly(errorSphere());
  ply[ply.size() - 4] = 99;  // the last face's last index (little-endian int)
  expectRow("Y08", "3dvo-enc", meshInput(dir_, "000.ply", ply));
}

CATALOGUE_TEST(Y09) {
  expectRow("Y09", "3dvo-enc",
            meshInput(dir_, "000.ply", kPlyHead + "0 0 0\n1 0 0\n0 1 x\n3 0 1 2\n"));
}

CATALOGUE_TEST(Y10) {
  for (const char* bad : {"nan", "inf"})
    expectRow("Y10", "3dvo-enc",
              meshInput(dir_, "000.ply", kPlyHead + "0 0 0\n1 0 0\n0 1 " + bad + "\n3 0 1 2\n"));
}

CATALOGUE_TEST(Y16) {
  expectRow("Y16", "3dvo-enc",
            meshInput(dir_, "000.ply", kPlyHead + "0 0 0\n1 0 0\n0 1 1e301\n3 0 1 2\n"));
}

CATALOGUE_TEST(Y11) {
  expectRow("Y11", "3dvo-enc",
            meshInput(dir_, "000.ply", kPlyHead + "0 0 0\n1 0 0\n0 1 0\n2 0 1\n"));
}

CATALOGUE_TEST(Y12) {
  expectRow("Y12", "3dvo-enc",
            meshInput(dir_, "000.ply", kPlyHead + "0 0 0\n1 0 0\n0 1 0\n3 0 1 1\n"));
}

CATALOGUE_TEST(Y13) {
  std::string head = kPlyHead;
  head.replace(head.find("list uchar"), 10, "list uint");
  expectRow("Y13", "3dvo-enc",
            meshInput(dir_, "000.ply", head + "0 0 0\n1 0 0\n0 1 0\n70000 0 1 2\n"));
}

CATALOGUE_TEST(Y14) {
  expectRow("Y14", "3dvo-enc",
            meshInput(dir_, "000.ply", "ply\nformat ascii 1.0\nelement vertex 67108865\n"));
}

CATALOGUE_TEST(Y15) {
  meshInput(dir_, "000.ply", "");
  std::filesystem::remove(dir_.file("in/000.ply"));
  std::filesystem::create_symlink("/dev/zero", dir_.file("in/000.ply"));
  expectRow(
      "Y15", "3dvo-enc",
      {"--InputMeshPattern=in/%03d.ply", "--FrameCount=1", "--GridBits=10", "-o", "out/x.3dvo"});
}

// The sphere as a .gltf (data-URI buffer; accessors: 0 POSITION, 1 indices) to edit.
nlohmann::json sphereGltf() {
  return nlohmann::json::parse(formatGltf(errorSphere(), GltfContainer::kGltf));
}

CATALOGUE_TEST(F01) {
  expectRow("F01", "3dvo-enc", meshInput(dir_, "000.gltf", "not json"));
}

CATALOGUE_TEST(F02) {
  nlohmann::json j = sphereGltf();
  j.erase("asset");
  expectRow("F02", "3dvo-enc", meshInput(dir_, "000.gltf", j.dump()));
}

CATALOGUE_TEST(F03) {
  std::string glb = formatGltf(errorSphere(), GltfContainer::kGlb);
  glb[4] = 1;  // version 1
  expectRow("F03", "3dvo-enc", meshInput(dir_, "000.glb", glb));
}

CATALOGUE_TEST(F04) {
  nlohmann::json j = sphereGltf();
  j["extras"] = std::vector<int>(kMaxGltfJsonValues, 0);
  expectRow("F04", "3dvo-enc", meshInput(dir_, "000.gltf", j.dump()));
}

CATALOGUE_TEST(F05) {
  std::string nested = "0";
  for (int i = 0; i < 70; ++i)
    nested = "[" + nested + "]";
  std::string text = sphereGltf().dump();
  text.insert(text.size() - 1, ",\"extras\":" + nested);
  expectRow("F05", "3dvo-enc", meshInput(dir_, "000.gltf", text));
}

CATALOGUE_TEST(F06) {
  nlohmann::json j = sphereGltf();
  std::filesystem::create_directories(dir_.path() / "in");
  const nlohmann::json::number_unsigned_t length = j["buffers"][0]["byteLength"];
  test::writeText(dir_.file("in/b.bin"), std::string(length, '\0'));
  j["buffers"][0]["uri"] = "b.bin";
  j["buffers"][1] = {{"uri", "./b.bin"}, {"byteLength", length}};
  expectRow("F06", "3dvo-enc", meshInput(dir_, "000.gltf", j.dump()));
}

CATALOGUE_TEST(F07) {
  // A second buffer without uri, written into the GLB's JSON chunk (padded to 4 bytes).
  const std::string glb = formatGltf(errorSphere(), GltfContainer::kGlb);
  const uint32_t jsonLength = static_cast<uint8_t>(glb[12]) | static_cast<uint8_t>(glb[13]) << 8;
  nlohmann::json j = nlohmann::json::parse(glb.substr(20, jsonLength));
  j["buffers"][1] = {{"byteLength", 4}};
  std::string json = j.dump();
  while (json.size() % 4)
    json += ' ';
  const std::string bin = glb.substr(20 + jsonLength);
  auto le = [](uint32_t v) {
    std::string s(4, '\0');
    for (int i = 0; i < 4; ++i)
      s[i] = static_cast<char>(v >> (8 * i));
    return s;
  };
  const std::string out = "glTF" + le(2) +
                          le(static_cast<uint32_t>(20 + json.size() + bin.size())) +
                          le(static_cast<uint32_t>(json.size())) + "JSON" + json + bin;
  expectRow("F07", "3dvo-enc", meshInput(dir_, "000.glb", out));
}

CATALOGUE_TEST(F08) {
  nlohmann::json j = sphereGltf();
  j["accessors"][0]["count"] = 43;
  expectRow("F08", "3dvo-enc", meshInput(dir_, "000.gltf", j.dump()));
}

CATALOGUE_TEST(F09) {
  // Index 5 of the indices accessor (uint32) is set to 99 in the data-URI buffer.
  Mesh m = errorSphere();
  m.triangles[1][2] = 99;
  expectRow("F09", "3dvo-enc", meshInput(dir_, "000.gltf", formatGltf(m, GltfContainer::kGltf)));
}

CATALOGUE_TEST(F10) {
  nlohmann::json j = sphereGltf();
  j["meshes"][0]["primitives"][0]["mode"] = 1;
  expectRow("F10", "3dvo-enc", meshInput(dir_, "000.gltf", j.dump()));
}

CATALOGUE_TEST(F11) {
  nlohmann::json j = sphereGltf();
  j["accessors"][0]["sparse"] = {{"count", 1},
                                 {"indices", {{"bufferView", 1}, {"componentType", 5125}}},
                                 {"values", {{"bufferView", 0}}}};
  expectRow("F11", "3dvo-enc", meshInput(dir_, "000.gltf", j.dump()));
}

CATALOGUE_TEST(F12) {
  nlohmann::json j = sphereGltf();
  for (int i = 0; i < 400; ++i) {
    j["nodes"][i] = {{"mesh", 0}};
    j["scenes"][0]["nodes"][i] = i;
  }
  expectRow("F12", "3dvo-enc", meshInput(dir_, "000.gltf", j.dump()));
}

CATALOGUE_TEST(F23) {
  nlohmann::json j = sphereGltf();
  j["nodes"][1] = {{"children", {0}}};
  j["scenes"][0]["nodes"] = {0, 1};
  expectRow("F23", "3dvo-enc", meshInput(dir_, "000.gltf", j.dump()));
}

CATALOGUE_TEST(F24) {
  nlohmann::json j = sphereGltf();
  j["nodes"][0]["skin"] = 0;
  j["skins"] = {{{"joints", {0}}}};
  expectRow("F24", "3dvo-enc", meshInput(dir_, "000.gltf", j.dump()));
}

CATALOGUE_TEST(F25) {
  nlohmann::json j = sphereGltf();
  j["scene"] = 2;
  expectRow("F25", "3dvo-enc", meshInput(dir_, "000.gltf", j.dump()));
}

// The tinygltf-independent animated file: our writer's 6-frame animation (one run).
std::string sphereAnimation(int frames) {
  GltfAnimationWriter writer(25.0);
  for (const Mesh& m : test::wobblingSphere(1, frames))
    writer.add(m);
  return writer.finish();
}

CATALOGUE_TEST(F13) {
  // The weights sampler's key times (accessor after the 5 targets) edited in the JSON chunk:
  // a written .gltf of the same model is easier to edit, so the .glb is converted.
  const std::string glb = sphereAnimation(6);
  const uint32_t jsonLength = static_cast<uint8_t>(glb[12]) | static_cast<uint8_t>(glb[13]) << 8;
  nlohmann::json j = nlohmann::json::parse(glb.substr(20, jsonLength));
  const int input = j["animations"][0]["samplers"][0]["input"];
  const int view = j["accessors"][input]["bufferView"];
  // Key times 0 and 1/25 swapped in the BIN chunk.
  std::string out = glb;
  const size_t at = 20 + jsonLength + 8 + j["bufferViews"][view].value("byteOffset", 0);
  for (int b = 0; b < 4; ++b)
    std::swap(out[at + b], out[at + 4 + b]);
  expectRow("F13", "3dvo-enc", meshInput(dir_, "000.glb", out));
}

CATALOGUE_TEST(F14) {
  const std::string glb = sphereAnimation(6);
  const uint32_t jsonLength = static_cast<uint8_t>(glb[12]) | static_cast<uint8_t>(glb[13]) << 8;
  nlohmann::json j = nlohmann::json::parse(glb.substr(20, jsonLength));
  const int output = j["animations"][0]["samplers"][0]["output"];
  std::string json = glb.substr(20, jsonLength);
  // 30 weights -> 29: the same JSON length.
  const std::string from = "\"count\":30";
  size_t pos = 0;
  for (int seen = 0;; ++seen) {
    pos = json.find("{\"bufferView\"", pos + 1);
    if (seen == output) break;
  }
  const size_t count = json.find(from, pos);
  ASSERT_NE(count, std::string::npos);
  json.replace(count, from.size(), "\"count\":29");
  std::string out = glb;
  out.replace(20, jsonLength, json);
  expectRow("F14", "3dvo-enc", meshInput(dir_, "000.glb", out));
}

CATALOGUE_TEST(F15) {
  meshInput(dir_, "seq.glb", sphereAnimation(6));
  expectRow(
      "F15", "3dvo-enc",
      {"--InputMeshPattern=in/seq.glb", "--FirstFrame=6", "--GridBits=10", "-o", "out/x.3dvo"});
}

CATALOGUE_TEST(F16) {
  meshInput(dir_, "seq.glb", sphereAnimation(6));
  expectRow("F16", "3dvo-enc",
            {"--InputMeshPattern=in/seq.glb", "--FirstFrame=4", "--FrameCount=4", "--GridBits=10",
             "-o", "out/x.3dvo"});
}

CATALOGUE_TEST(F17) {
  nlohmann::json j = sphereGltf();
  j["extensionsUsed"] = {"KHR_draco_mesh_compression"};
  j["extensionsRequired"] = {"KHR_draco_mesh_compression"};
  expectRow("F17", "3dvo-enc", meshInput(dir_, "000.gltf", j.dump()));
}

CATALOGUE_TEST(F18) {
  // 100,000 vertices (no indices: a triangle per 3) whose POSITION accessor is also the output
  // of a STEP scale animation with 100,000 key times: 10^10 vertex-frames from 1.6 MB.
  const size_t n = 99999;
  std::string bin(n * 12 + n * 4, '\0');
  for (size_t i = 0; i < n; ++i) {
    const float p[3] = {static_cast<float>(i % 97) + 1, static_cast<float>(i % 89) + 1,
                        static_cast<float>(i / 97) + 1};
    std::memcpy(&bin[i * 12], p, 12);
    const float t = static_cast<float>(i);
    std::memcpy(&bin[n * 12 + i * 4], &t, 4);
  }
  nlohmann::json j;
  j["asset"] = {{"version", "2.0"}};
  j["buffers"] = {{{"uri", "b.bin"}, {"byteLength", bin.size()}}};
  j["bufferViews"] = {{{"buffer", 0}, {"byteLength", n * 12}},
                      {{"buffer", 0}, {"byteOffset", n * 12}, {"byteLength", n * 4}}};
  j["accessors"] = {{{"bufferView", 0},
                     {"componentType", 5126},
                     {"count", n},
                     {"type", "VEC3"},
                     {"min", {1, 1, 1}},
                     {"max", {97, 89, 1031}}},
                    {{"bufferView", 1},
                     {"componentType", 5126},
                     {"count", n},
                     {"type", "SCALAR"},
                     {"min", {0}},
                     {"max", {n - 1}}}};
  j["meshes"] = {{{"primitives", {{{"attributes", {{"POSITION", 0}}}}}}}};
  j["nodes"] = {{{"mesh", 0}}};
  j["animations"] = {
      {{"samplers", {{{"input", 1}, {"output", 0}, {"interpolation", "STEP"}}}},
       {"channels", {{{"sampler", 0}, {"target", {{"node", 0}, {"path", "scale"}}}}}}}};
  std::filesystem::create_directories(dir_.path() / "in");
  test::writeText(dir_.file("in/b.bin"), bin);
  test::writeText(dir_.file("in/seq.gltf"), j.dump());
  expectRow("F18", "3dvo-enc",
            {"--InputMeshPattern=in/seq.gltf", "--GridBits=10", "-o", "out/x.3dvo"});
}

CATALOGUE_TEST(F19) {
  nlohmann::json j = sphereGltf();
  for (int i = 0; i < 300; ++i) {
    j["meshes"][0]["primitives"][0]["targets"][i] = {{"POSITION", 0}};
    j["meshes"][0]["weights"][i] = 1;
  }
  expectRow("F19", "3dvo-enc", meshInput(dir_, "000.gltf", j.dump()));
}

CATALOGUE_TEST(F20) {
  nlohmann::json j = sphereGltf();
  j["buffers"][0]["uri"] = "b.bin";
  expectRow("F20", "3dvo-enc", meshInput(dir_, "000.gltf", j.dump()));
}

CATALOGUE_TEST(F21) {
  meshInput(dir_, "000.gltf", "");
  std::filesystem::remove(dir_.file("in/000.gltf"));
  std::filesystem::create_symlink("/dev/zero", dir_.file("in/000.gltf"));
  expectRow(
      "F21", "3dvo-enc",
      {"--InputMeshPattern=in/%03d.gltf", "--FrameCount=1", "--GridBits=10", "-o", "out/x.3dvo"});
}

CATALOGUE_TEST(F22) {
  // The file exists: it is refused for where it is, not read into the mesh.
  nlohmann::json j = sphereGltf();
  const nlohmann::json::number_unsigned_t length = j["buffers"][0]["byteLength"];
  test::writeText(dir_.file("b.bin"), std::string(length, '\0'));
  j["buffers"][0]["uri"] = "../b.bin";
  expectRow("F22", "3dvo-enc", meshInput(dir_, "000.gltf", j.dump()));
}

// ---- cfg and options (3dvo-enc) ----

CATALOGUE_TEST(C01) {
  writeInput("", 1);
  std::vector<std::string> args = encoderArgs(1);
  args.push_back("-c");
  args.push_back("missing.cfg");
  expectRow("C01", "3dvo-enc", args);
}

CATALOGUE_TEST(C02) {
  expectCfgRow("C02", "GridBits : 10\n\nFrobnicate : 10\n");
}

CATALOGUE_TEST(C03) {
  expectCfgRow("C03", "GridBits 10\n");
}

CATALOGUE_TEST(C04) {
  expectCfgRow("C04", " : 10\n");
}

CATALOGUE_TEST(C05) {
  expectCfgRow("C05", "GridBits : 30\n");
}

CATALOGUE_TEST(C06) {
  expectCfgRow("C06", "GridBits : -1\n");
}

CATALOGUE_TEST(C07) {
  for (const char* value : {"ten", "", "10.5", "0x10", "99999999999999999999"})
    expectCfgRow("C07", std::string("GOMSize : ") + value + "\n");
}

CATALOGUE_TEST(C08) {
  for (const char* value : {"fast", "nan", "1e999", ""})
    expectCfgRow("C08", std::string("Lambda : ") + value + "\n");
}

CATALOGUE_TEST(C09) {
  expectCfgRow("C09", "PMeshMode : p\n");
}

CATALOGUE_TEST(C10) {
  writeInput("", 1);
  std::vector<std::string> args = encoderArgs(1);
  args.push_back("-c");
  expectRow("C10", "3dvo-enc", args);
}

CATALOGUE_TEST(C11) {
  writeInput("", 1);
  std::vector<std::string> args = encoderArgs(1);
  args.push_back("--GridBits");
  expectRow("C11", "3dvo-enc", args);
}

CATALOGUE_TEST(C12) {
  writeInput("", 1);
  std::vector<std::string> args = encoderArgs(1);
  args.push_back("GridBits=10");
  expectRow("C12", "3dvo-enc", args);
}

CATALOGUE_TEST(C13) {
  writeInput("", 1);
  expectRow("C13", "3dvo-enc", {"-o", "out/x.3dvo"});
}

CATALOGUE_TEST(C14) {
  writeInput("", 1);
  expectRow("C14", "3dvo-enc", {"--InputMeshPattern=in/%03d.obj"});
}

CATALOGUE_TEST(C15) {
  expectCfgRow("C15", "InputMeshPattern : in/000.obj\n");
}

CATALOGUE_TEST(C16) {
  expectCfgRow("C16", "InputMeshPattern : in/%03d-%d.obj\n");
}

CATALOGUE_TEST(C17) {
  for (const char* pattern : {"in/%s.obj", "in/%x", "in/%-3d.obj", "in/%", "in/%999d"})
    expectCfgRow("C17", std::string("InputMeshPattern : ") + pattern + "\n");
}

CATALOGUE_TEST(C18) {
  expectCfgRow("C18", "PMeshMode : d3dmc\nKeyframeCount : 2\nKeyframeMaxError : 1\n");
}

CATALOGUE_TEST(C19) {
  expectCfgRow("C19", "PMeshMode : intra\nKeyframeCount : 2\n");
}

CATALOGUE_TEST(C20) {
  expectCfgRow("C20", "", {"-o", "no-such-folder/x.3dvo"});
}

CATALOGUE_TEST(C36) {
  expectCfgRow("C36", "", {"-o", "./in/../in/000.obj"});
  EXPECT_EQ(parseObj(test::readText(dir_.file("in/000.obj")), "in/000.obj").positions.size(), 42u);
}

CATALOGUE_TEST(C37) {
  expectCfgRow("C37", "GridBits : 10\n", {"-o", "x.cfg"});
  EXPECT_EQ(test::readText(dir_.file("x.cfg")), "GridBits : 10\n");
}

CATALOGUE_TEST(C38) {
  expectCfgRow("C38", "ReconMeshPattern : in/%03d.obj\n");
}

CATALOGUE_TEST(C51) {
  // Frame 2 exists but is not coded (FrameCount 1): still the input's.
  writeInput("", 3);
  const std::string before = test::readText(dir_.file("in/002.obj"));
  std::vector<std::string> args = encoderArgs(1);
  args.push_back("--BitstreamFile=in/002.obj");
  expectRow("C51", "3dvo-enc", args);
  EXPECT_EQ(test::readText(dir_.file("in/002.obj")), before);
}

CATALOGUE_TEST(C39) {
  expectCfgRow("C39", "", {"-o", "out"});
}

CATALOGUE_TEST(C40) {
  const int s = socket(AF_UNIX, SOCK_STREAM, 0);
  ASSERT_GE(s, 0);
  sockaddr_un address = {};
  address.sun_family = AF_UNIX;
  const std::string path = dir_.file("sock");
  ASSERT_LT(path.size(), sizeof address.sun_path);
  std::strcpy(address.sun_path, path.c_str());
  ASSERT_EQ(bind(s, reinterpret_cast<const sockaddr*>(&address), sizeof address), 0);
  expectCfgRow("C40", "", {"-o", "sock"});
  close(s);
  EXPECT_TRUE(std::filesystem::is_socket(path));
}

CATALOGUE_TEST(C41) {
  expectCfgRow("C41", "ReconMeshPattern : out/r%d.obj\n", {"-o", "out/r0.obj"});
}

CATALOGUE_TEST(C42) {
  expectCfgRow("C42", "GridBits : 10\n\nGridBitz : 10\n");
}

CATALOGUE_TEST(C43) {
  expectCfgRow("C43", "PMeshMode : d3dmc\nKeyframeCount : 1\n");
}

CATALOGUE_TEST(C44) {
  expectCfgRow("C44", "PMeshMode : d3dmc\nKeyframeCount : 3\nKeyframeLambda : -1\n");
}

CATALOGUE_TEST(C52) {
  for (const char* key : {"KeyframeCount : 3", "KeyframeMaxError : 4", "KeyframeLambda : -1"})
    expectCfgRow("C52", std::string("PMeshMode : d3dmc\nBMeshGap : 4\n") + key + "\n");
}

CATALOGUE_TEST(C53) {
  for (const char* mode : {"afxic", "intra"})
    expectCfgRow("C53", std::string("PMeshMode : ") + mode + "\nBMeshGap : 4\n");
}

CATALOGUE_TEST(C55) {
  for (const char* key : {"BMeshQuantStep : 16\n", "BMeshLambdaGrowth : 3\n"})
    for (const char* cfg :
         {"Quality : -1\n", "KeyframeCount : 3\n", "PMeshMode : afxic\n", "GridBits : 10\n"})
      expectCfgRow("C55", std::string(cfg) + key);
}

CATALOGUE_TEST(C54) {
  expectCfgRow("C54", "PMeshMode : d3dmc\nBMeshGap : 1\n");
}

CATALOGUE_TEST(C45) {
  expectCfgRow("C45", "PMeshMode : d3dmc\nKeyframeLambda : -0.5\n");
}

CATALOGUE_TEST(C46) {
  expectCfgRow("C46", "PMeshMode : d3dmc\nLambda : -0.5\n");
}

// GOMListFile rows: the list is goms.txt beside x.cfg (one coded frame unless the cfg says so).
CATALOGUE_TEST(C21) {
  expectCfgRow("C21", "GOMListFile : missing.txt\n");
}

CATALOGUE_TEST(C22) {
  for (const char* line : {"1 x", "1", "1 1 1", "1 1.5", "one 1"}) {
    test::writeText(dir_.file("goms.txt"), std::string("0 1\n") + line + "\n");
    expectCfgRow("C22", "GOMListFile : goms.txt\n");
  }
}

CATALOGUE_TEST(C23) {
  test::writeText(dir_.file("goms.txt"), "1 1\n");
  expectCfgRow("C23", "GOMListFile : goms.txt\n");
}

CATALOGUE_TEST(C24) {
  test::writeText(dir_.file("goms.txt"), "0 1\n2 1\n");
  expectCfgRow("C24", "GOMListFile : goms.txt\n");
}

CATALOGUE_TEST(C25) {
  test::writeText(dir_.file("goms.txt"), "0 1\n0 1\n");
  expectCfgRow("C25", "GOMListFile : goms.txt\n");
}

CATALOGUE_TEST(C26) {
  for (const char* count : {"0", "-1", "65536"}) {
    test::writeText(dir_.file("goms.txt"), std::string("0 ") + count + "\n");
    expectCfgRow("C26", "GOMListFile : goms.txt\n");
  }
}

CATALOGUE_TEST(C27) {
  test::writeText(dir_.file("goms.txt"), "0 2\n");
  expectCfgRow("C27", "GOMListFile : goms.txt\n");
}

CATALOGUE_TEST(C28) {
  test::writeText(dir_.file("goms.txt"), "0 2\n");
  expectCfgRow("C28", "GOMListFile : goms.txt\nFrameCount : 3\n");
}

CATALOGUE_TEST(C29) {
  for (const char* text : {"", "# no GOM\n\n"}) {
    test::writeText(dir_.file("goms.txt"), text);
    expectCfgRow("C29", "GOMListFile : goms.txt\n");
  }
}

CATALOGUE_TEST(C30) {
  writeInput("", 1);
  std::vector<std::string> args = encoderArgs(1);
  args.push_back("-c");
  args.push_back("/dev/zero");
  expectRow("C30", "3dvo-enc", args);
  expectCfgRow("C30", "GOMListFile : /dev/zero\n");
}

CATALOGUE_TEST(C35) {
  // FrameCount not set and not even the first frame's file: nothing to code.
  expectRow("C35", "3dvo-enc",
            {"--InputMeshPattern=in/%03d.obj", "--GridBits=10", "-o", "out/x.3dvo"});
}

CATALOGUE_TEST(C31) {
  // Geometry frame 6 with the textures of a dataset of frames 0 .. 5.
  writeInput("", 7);
  expectRow("C31", "3dvo-enc",
            {"--InputMeshPattern=in/%03d.obj", "--FirstFrame=6", "--FrameCount=1",
             "--Dataset=" + std::string(TDVO_SOURCE_DIR) + "/conformance/inputs/rig",
             "--GridBits=10", "-o", "out/x.3dvo"});
}

CATALOGUE_TEST(C32) {
  // A dataset at 2000 frames per second, more than a stream carries, and no FrameRate.
  expectRigRow("C32", "\"rate\": 25.0", "\"rate\": 2000");
}

CATALOGUE_TEST(C33) {
  expectRigRow("C33", "\"description\": \"", "\"description\": \"" + std::string(4097, 'x'));
}

CATALOGUE_TEST(C47) {
  copyRig("\"count\": 6", "\"count\": 3");
  std::filesystem::remove(dir_.file("rig/meshes/0001.obj"));
  expectRow("C47", "3dvo-enc", {"--Dataset=rig", "-o", "out/x.3dvo"});
}

CATALOGUE_TEST(C48) {
  // cam01 made 1 x 16 pixels, its pictures too.
  copyRig("\"name\": \"cam01\",\n      \"width\": 96,\n      \"height\": 80,",
          "\"name\": \"cam01\",\n      \"width\": 1,\n      \"height\": 16,");
  for (const std::string name : {"0000.png", "mask_0000.png", "background.png"})
    test::writeBytes(dir_.file("rig/cam01/" + name),
                     encodePng(Image(1, 16, name == "mask_0000.png" ? 1 : 3, 255)));
  expectRow("C48", "3dvo-enc", {"--Dataset=rig", "--FrameCount=1", "-o", "out/x.3dvo"});
}

CATALOGUE_TEST(C49) {
  expectRigRow("C49", "\"description\": \"", "\"description\": \"a\\u0000b");
}

CATALOGUE_TEST(C50) {
  expectRigRow("C50", "\"first\": 0", "\"first\": 1000000001");
}

CATALOGUE_TEST(C34) {
  expectRigRow("C34", "\"name\": \"cam01\"", "\"name\": \"" + std::string(256, 'c') + "\"");
}

// ---- Calibration (dataset.json) and images (3dvo-import) ----

// A valid dataset x/dataset.json: one 8 x 6 camera, one frame x/cam/0000.png. Each row's input
// replaces `from` by `to` in its text.
class DatasetRows : public ErrorsTest {
 protected:
  static std::string datasetText() {
    return R"({"format": "3dvo-dataset", "version": 1, "frames": {"count": 1},
 "cameras": [{"name": "cam", "width": 8, "height": 6, "fx": 10, "fy": 10, "cx": 3.5, "cy": 2.5,
   "R": [[1, 0, 0], [0, 1, 0], [0, 0, 1]], "t": [0, 0, 5], "images": "cam/%04d.png"}]}
)";
  }
  void writeDataset(const std::string& from = "", const std::string& to = "") {
    std::filesystem::create_directories(dir_.path() / "x" / "cam");
    std::string text = datasetText();
    if (!from.empty()) {
      const size_t at = text.find(from);
      ASSERT_NE(at, std::string::npos) << from;
      text.replace(at, from.size(), to);
    }
    test::writeText(dir_.file("x/dataset.json"), text);
    test::writeBytes(dir_.file("x/cam/0000.png"), encodePng(Image(8, 6, 3, 128)));
  }
  // Two frames of RGBA images (the alpha is the shape) and meshes: what 3dvo-metrics' texture
  // mode, 3dvo-recon and 3dvo-render read.
  void writeTwoFrames() {
    std::filesystem::create_directories(dir_.path() / "x" / "cam");
    std::filesystem::create_directories(dir_.path() / "x" / "m");
    test::writeText(dir_.file("x/dataset.json"),
                    R"({"format": "3dvo-dataset", "version": 1, "frames": {"count": 2},
 "meshes": "m/%04d.obj",
 "cameras": [{"name": "cam", "width": 8, "height": 6, "fx": 10, "fy": 10, "cx": 3.5, "cy": 2.5,
   "R": [[1, 0, 0], [0, 1, 0], [0, 0, 1]], "t": [0, 0, 5], "images": "cam/%04d.png",
   "alphaMask": true}]}
)");
    for (const char* frame : {"0000", "0001"}) {
      test::writeBytes(dir_.file("x/cam/" + std::string(frame) + ".png"),
                       encodePng(Image(8, 6, 4, 200)));
      test::writeText(dir_.file("x/m/" + std::string(frame) + ".obj"),
                      "v -0.5 -0.5 0\nv 0.5 -0.5 0\nv 0 0.5 0\nf 1 2 3\n");
    }
  }
  void expectDatasetRow(const std::string& id, const std::string& from = "",
                        const std::string& to = "") {
    writeDataset(from, to);
    expectRow(id, "3dvo-import", {"-i", "x/dataset.json", "--Format=dataset", "-o", "out"});
  }
};

#define DATASET_TEST(ID)                                   \
  [[maybe_unused]] const bool kRow##ID = registerRow(#ID); \
  TEST_F(DatasetRows, ID)

TEST_F(DatasetRows, TheValidDatasetImports) {
  writeDataset();
  const CommandResult r = test::run(dir_, kBin + "/3dvo-import",
                                    {"-i", "x/dataset.json", "--Format=dataset", "-o", "out"});
  EXPECT_EQ(r.exitCode, 0) << r.err;
}

DATASET_TEST(J01) {
  expectRow("J01", "3dvo-import", {"-i", "x/dataset.json", "--Format=dataset", "-o", "out"});
}

DATASET_TEST(J22) {
  writeDataset();
  const std::string before = test::readText(dir_.file("x/dataset.json"));
  expectRow("J22", "3dvo-import", {"-i", "x/dataset.json", "--Format=dataset", "-o", "x"});
  EXPECT_EQ(test::readText(dir_.file("x/dataset.json")), before);
}

DATASET_TEST(J02) {
  expectDatasetRow("J02", "\"frames\"", "\"frames\" {");
  expectDatasetRow("J02", "[[1", "[[1e999");  // a number beyond double
}

DATASET_TEST(J21) {
  std::filesystem::create_directories(dir_.path() / "x");
  std::filesystem::create_symlink("/dev/zero", dir_.file("x/dataset.json"));
  expectRow("J21", "3dvo-import", {"-i", "x/dataset.json", "--Format=dataset", "-o", "out"});
}

DATASET_TEST(J03) {
  expectDatasetRow("J03", "3dvo-dataset", "3dvo-datasets");
}

DATASET_TEST(J04) {
  expectDatasetRow("J04", "\"version\": 1", "\"version\": 2");
}

DATASET_TEST(J05) {
  expectDatasetRow("J05", "\"t\": [0, 0, 5], ", "");
}

DATASET_TEST(J27) {
  expectDatasetRow("J27", "\"count\": 1}", "\"count\": 1, \"rate\": 25, \"rate\": 50}");
}

DATASET_TEST(J06) {
  expectDatasetRow("J06", "\"name\"", "\"colour\": 1, \"name\"");
}

DATASET_TEST(J07) {
  for (const char* fx : {"\"ten\"", "null", "[10]"})
    expectDatasetRow("J07", "\"fx\": 10", std::string("\"fx\": ") + fx);
}

DATASET_TEST(J08) {
  for (const char* width : {"0", "-8", "32768", "8.5"})
    expectDatasetRow("J08", "\"width\": 8", std::string("\"width\": ") + width);
}

DATASET_TEST(J09) {
  expectDatasetRow("J09", "\"count\": 1", "\"count\": 0");
}

DATASET_TEST(J10) {
  for (const char* fx : {"0", "-10"})
    expectDatasetRow("J10", "\"fx\": 10", std::string("\"fx\": ") + fx);
}

DATASET_TEST(J11) {
  for (const char* r : {"[[2, 0, 0], [0, 1, 0], [0, 0, 1]]", "[[1, 0, 0], [0, 1, 0], [0, 0, -1]]"})
    expectDatasetRow("J11", "[[1, 0, 0], [0, 1, 0], [0, 0, 1]]", r);
}

DATASET_TEST(J12) {
  expectDatasetRow("J12", "[[1, 0, 0], [0, 1, 0], [0, 0, 1]]", "[[1, 0, 0], [0, 1, 0]]");
}

DATASET_TEST(J13) {
  expectDatasetRow("J13", "\"images\": \"cam/%04d.png\"",
                   "\"images\": \"cam/%04d.png\", \"video\": \"cam.mp4\"");
  expectDatasetRow("J13", ", \"images\": \"cam/%04d.png\"", "");
}

DATASET_TEST(J14) {
  expectDatasetRow("J14", "}]}",
                   "}, {\"name\": \"cam\", \"width\": 8, \"height\": 6, "
                   "\"fx\": 10, \"fy\": 10, \"cx\": 3.5, \"cy\": 2.5, \"R\": "
                   "[[1, 0, 0], [0, 1, 0], [0, 0, 1]], \"t\": [0, 0, 5], "
                   "\"images\": \"cam/%04d.png\"}]}");
}

DATASET_TEST(J23) {
  // The apps that write files named by cameras read datasets through the same check (the other
  // refused names: DatasetJson.CameraNamesMustBeFileNames).
  expectDatasetRow("J23", "\"name\": \"cam\"", "\"name\": \"../..\"");
  expectRow("J23", "3dvo-recon", {"-i", "x", "-o", "out", "--WriteSilhouettes=true"});
  expectRow("J23", "3dvo-render", {"-i", "x", "-o", "out"});
}

DATASET_TEST(J24) {
  writeTwoFrames();
  expectRow(
      "J24", "3dvo-metrics",
      {"--ReferenceDataset=x", "--TestDataset=x", "--FrameCount=1", "--CsvFile=x/cam/0001.png"});
  EXPECT_EQ(test::readBytes(dir_.file("x/cam/0001.png")), encodePng(Image(8, 6, 4, 200)));
}

DATASET_TEST(J25) {
  writeTwoFrames();
  expectRow("J25", "3dvo-recon", {"-i", "x", "-o", "x/cam", "--Overwrite"});
  EXPECT_EQ(test::readBytes(dir_.file("x/cam/0000.png")), encodePng(Image(8, 6, 4, 200)));
}

DATASET_TEST(J26) {
  writeTwoFrames();
  expectRow("J26", "3dvo-render", {"-i", "x", "-o", "out", "--Mp4=out/0001.png"});
}

DATASET_TEST(J15) {
  expectDatasetRow("J15", "cam/%04d.png", "cam/%s.png");
}

DATASET_TEST(J16) {
  writeDataset();
  std::filesystem::remove(dir_.file("x/cam/0000.png"));
  expectRow("J16", "3dvo-import", {"-i", "x/dataset.json", "--Format=dataset", "-o", "out"});
}

DATASET_TEST(J17) {
  writeDataset();
  test::writeText(dir_.file("x/cam/0000.png"), "P6 8 6 255\n");
  expectRow("J17", "3dvo-import", {"-i", "x/dataset.json", "--Format=dataset", "-o", "out"});
}

DATASET_TEST(J18) {
  writeDataset();
  test::writeBytes(dir_.file("x/cam/0000.png"), encodePng(Image(9, 6, 3, 128)));
  expectRow("J18", "3dvo-import", {"-i", "x/dataset.json", "--Format=dataset", "-o", "out"});
}

// PNG decoding itself (the images a texture encoder reads), at library level: decodePng throws
// the Error that an app turns into its error line and exit code 1.
std::string pngErrorOf(const std::vector<uint8_t>& bytes) {
  try {
    decodePng(bytes, "x.png");
  } catch (const Error& e) {
    return e.what();
  }
  return "no error";
}

[[maybe_unused]] const bool kRowJ19 = registerRow("J19");
TEST(ImageRows, J19) {
  const std::vector<uint8_t> png = encodePng(Image(16, 16, 3, 7));
  const std::vector<uint8_t> cut(png.begin(), png.end() - 20);
  const std::string e = pngErrorOf(cut);
  EXPECT_NE(e.find(catalogue().at("J19").message), std::string::npos) << e;
}

[[maybe_unused]] const bool kRowJ20 = registerRow("J20");
TEST(ImageRows, J20) {
  const std::string e = pngErrorOf(test::readBytes(
      std::string(TDVO_SOURCE_DIR) + "/fuzz/regressions/png/ihdr-32767x32767-in-69-bytes.png"));
  EXPECT_NE(e.find(catalogue().at("J20").message), std::string::npos) << e;
}

// ---- Decoding work (kDefaultMaxVertexFramesPerByte) ----

// Frames decoded from `stream` with the decoding-work limit `limit`; the Error's message in
// `error` when it throws.
int decodeWithLimit(const std::vector<uint8_t>& stream, uint64_t limit, std::string& error) {
  int frames = 0;
  try {
    StreamDecoder decoder(stream.data(), stream.size(), "x.3dvo");
    decoder.setPictureDecoder(makeH264Decoder);
    decoder.setMaxVertexFramesPerByte(limit);
    decoder.decode([&](int, const IntMesh&) { ++frames; });
  } catch (const Error& e) {
    error = e.what();
  }
  return frames;
}

// The limit compares the output declared by all GOMs so far with the bytes read so far, through
// the I mesh that declares it: exactly, at the GOM it is exceeded in; 0 lifts it.
TEST(DecodingWork, OutputPerStreamByteIsLimitedOverAllGoms) {
  // Two GOMs, the second (frames 100-399) three times as long as the first, so that the total
  // declared output per byte grows at the second GOM's I mesh.
  const int n = 20, gomFrames = 100, lastFrames = 300;
  std::vector<Unit> units = staticSheetUnits(n, gomFrames, 2);
  putU32(units[0].payload, kShFrameCount, gomFrames + lastFrames);
  putU16(units[5].payload, kGhFrameCount, lastFrames);
  putU16(units[5].payload, kGhDelta, lastFrames - 1);
  putU32(units[8].payload, 0, gomFrames + lastFrames - 1);  // pm_frame
  const std::vector<uint8_t> stream = join(units);
  const uint64_t gomOutput = uint64_t{gomFrames} * n * n, total = gomOutput * 4;
  const uint64_t bytes0 = bytesThrough(units, 2), bytes1 = bytesThrough(units, 6);
  const uint64_t need0 = (gomOutput + bytes0 - 1) / bytes0;  // for GOM 0
  const uint64_t need1 = (total + bytes1 - 1) / bytes1;      // for both
  ASSERT_GT(need1, need0) << "the GOMs cannot tell a total limit from a per-GOM one";
  const std::vector<size_t> offsets = unitOffsets(stream);
  std::string error;
  EXPECT_EQ(decodeWithLimit(stream, need1, error), gomFrames + lastFrames) << error;
  EXPECT_EQ(decodeWithLimit(stream, 0, error), gomFrames + lastFrames) << error;

  EXPECT_EQ(decodeWithLimit(stream, need1 - 1, error), gomFrames);
  EXPECT_EQ(error, "x.3dvo: unit 5 (GOM_HEADER) at byte " + std::to_string(offsets[5]) + ": " +
                       std::to_string(lastFrames) + " frames x " + std::to_string(n * n) +
                       " vertices take the decoded output to " + std::to_string(total) +
                       " vertex-frames from " + std::to_string(bytes1) +
                       " stream bytes, more than the limit of " + std::to_string(need1 - 1) +
                       " vertex-frames per stream byte (MaxVertexFramesPerByte)");
  error.clear();
  EXPECT_EQ(decodeWithLimit(stream, need0 - 1, error), 0);
  EXPECT_NE(error.find("unit 1 (GOM_HEADER) at byte " + std::to_string(offsets[1]) + ": "),
            std::string::npos)
      << error;
}

// 3dvo-dec's MaxVertexFramesPerByte sets the limit; 0 lifts it.
TEST(DecodingWork, TheDecoderOptionSetsTheLimit) {
  const std::vector<Unit> units = staticSheetUnits(20, 100, 1);
  const uint64_t bytes = bytesThrough(units, 2), need = (uint64_t{100} * 400 + bytes - 1) / bytes;
  TempDir dir("decoding-work");
  test::writeBytes(dir.file("x.3dvo"), join(units));
  const std::string dec = kBin + "/3dvo-dec";
  for (const uint64_t limit : {need, uint64_t{0}}) {
    const CommandResult r =
        test::run(dir, dec, {"-i", "x.3dvo", "--MaxVertexFramesPerByte=" + std::to_string(limit)});
    EXPECT_EQ(r.exitCode, 0) << r.err;
    EXPECT_EQ(test::linesStartingWith(r.out, "MD5 frame=").size(), 100u) << limit;
  }
  const CommandResult r =
      test::run(dir, dec, {"-i", "x.3dvo", "--MaxVertexFramesPerByte=" + std::to_string(need - 1)});
  EXPECT_EQ(r.exitCode, 1);
  EXPECT_NE(r.err.find("more than the limit of " + std::to_string(need - 1) + " vertex-frames"),
            std::string::npos)
      << r.err;
}

// ---- Exhaustive variants, at library level ----

// The Error message of decoding `stream`; "" when it decodes.
std::string decodeError(const std::vector<uint8_t>& stream) {
  try {
    StreamDecoder decoder(stream.data(), stream.size(), "x.3dvo");
    decoder.setPictureDecoder(makeH264Decoder);
    decoder.decode([](int, const IntMesh&) {});
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

bool containsAny(const std::string& s, const std::vector<std::string>& parts) {
  for (const std::string& p : parts)
    if (s.find(p) != std::string::npos) return true;
  return false;
}

TEST(ErrorsExhaustive, EveryTruncationIsRejected) {
  const std::vector<uint8_t>& s = baseStream();
  for (size_t length = 0; length < s.size(); ++length) {
    const std::string e = decodeError(std::vector<uint8_t>(s.begin(), s.begin() + length));
    EXPECT_TRUE(containsAny(e, {"not a 3DVO stream", "truncated"})) << length << ": " << e;
  }
}

TEST(ErrorsExhaustive, AFlippedBitInEveryByteIsRejected) {
  const std::vector<uint8_t>& s = baseStream();
  const std::vector<size_t> offsets = unitOffsets(s);
  for (size_t at = 0; at < s.size(); ++at) {
    std::vector<uint8_t> bad = s;
    bad[at] ^= static_cast<uint8_t>(1u << (at % 8));
    const std::string e = decodeError(bad);
    bool inSize = false;
    for (size_t o : offsets)
      inSize = inSize || (at > o && at < o + kUnitHeaderSize);
    if (at < 4)
      EXPECT_NE(e.find("not a 3DVO stream"), std::string::npos) << at << ": " << e;
    else if (inSize)
      EXPECT_TRUE(containsAny(e, {"CRC mismatch", "runs past the end", "exceeds the 1 GiB"}))
          << at << ": " << e;
    else
      EXPECT_NE(e.find("CRC mismatch"), std::string::npos) << at << ": " << e;
  }
}

// Every Draco speed the encoder offers writes what the decoder's pre-check of Draco's header
// accepts (the encoder decodes its own payload with decodeIMesh, which runs the check).
TEST(ErrorsExhaustive, DracoCountCheckAcceptsEveryEncoderSpeed) {
  const Mesh mesh = test::wobblingSphere(2, 1)[0];
  const Grid grid = gridForSequence({mesh}, 12);
  for (int speed = 0; speed <= 10; ++speed) {
    SCOPED_TRACE(speed);
    const IMeshEncoding e = encodeIMesh(grid.quantise(mesh), 12, speed);
    EXPECT_EQ(e.decoded.positions.size(), mesh.positions.size());
  }
}

}  // namespace
}  // namespace tdvo
