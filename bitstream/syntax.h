// The 3DVO high-level syntax: one struct per syntax structure, fields named after the syntax
// elements of docs/bitstream.md, and one transfer() per structure that both writes and parses
// it (see byte_io.h). Semantic limits are checked here, so a parsed structure can be trusted by
// the decoder.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "bitstream/byte_io.h"

namespace tdvo {

// The bytes of one syntax structure (a unit payload), written by its transfer().
template <class T>
std::vector<uint8_t> serialise(T value) {
  ByteWriter writer;
  transfer(writer, value);
  return writer.take();
}

// Bumped whenever the syntax or the decoding process changes; conformance streams are then
// regenerated (conformance/README.md). A decoder reads kMinSyntaxVersion .. kSyntaxVersion.
// Version 2 is version 3 without ATTRIBUTES units: its sequence header has no
// sh_attributes_present (read as 0), which is the only place the versions differ. Version 4
// adds B meshes (gh_pmesh_mode kGhD3dmcBMeshes); its streams without them are version 3's but
// for sh_syntax_version. Version 5 adds im_quant_step to the I mesh (read as 1 before).
// Version 6 adds at_uv_origin to the ATTRIBUTES unit (read as 0, the bottom row, before).
constexpr uint16_t kSyntaxVersion = 6;
constexpr uint16_t kMinSyntaxVersion = 2;

// Limits a decoder checks before it allocates anything (docs/bitstream.md, "Limits").
constexpr uint32_t kMaxFrames = 1000000;
constexpr uint32_t kMaxFirstFrame = 1000000000;  // the input's frame number of frame 0
constexpr uint32_t kMaxGomFrames = 65535;
constexpr uint32_t kMaxVertices = 1u << 24;
constexpr uint32_t kMaxTriangles = 1u << 25;

enum class PMeshMode : uint8_t {
  kIntra = 0,  // every frame of the GOM is an I mesh
  kD3dmc = 1,  // one I mesh, then P meshes (octree motion clustering, spatial prediction)
  kAfxic = 2,  // one I mesh, then P meshes as per-vertex temporal DPCM (AFX-IC-style reference)
};

constexpr uint16_t kMaxCameras = 64;
// A camera's image size (cam_width, cam_height), pixels.
constexpr uint16_t kMinImageSize = 2;
constexpr uint16_t kMaxImageSize = 16384;
constexpr uint16_t kMaxCameraNameBytes = 255;
constexpr uint16_t kMaxDescriptionBytes = 4096;

// True when `s` is well-formed UTF-8 (no overlong forms, surrogates or code points past
// U+10FFFF) without NUL bytes: the texts of the stream are written into JSON.
inline bool isValidText(const std::string& s) {
  size_t i = 0;
  while (i < s.size()) {
    const unsigned char c = static_cast<unsigned char>(s[i]);
    if (c == 0) return false;
    int more = 0;
    uint32_t cp = 0, min = 0;
    if (c < 0x80) {
      ++i;
      continue;
    } else if ((c & 0xE0) == 0xC0) {
      more = 1, cp = c & 0x1F, min = 0x80;
    } else if ((c & 0xF0) == 0xE0) {
      more = 2, cp = c & 0x0F, min = 0x800;
    } else if ((c & 0xF8) == 0xF0) {
      more = 3, cp = c & 0x07, min = 0x10000;
    } else {
      return false;
    }
    if (i + static_cast<size_t>(more) >= s.size()) return false;
    for (int k = 1; k <= more; ++k) {
      const unsigned char d = static_cast<unsigned char>(s[i + k]);
      if ((d & 0xC0) != 0x80) return false;
      cp = (cp << 6) | (d & 0x3F);
    }
    if (cp < min || cp > 0x10FFFF || (cp >= 0xD800 && cp <= 0xDFFF)) return false;
    i += static_cast<size_t>(more) + 1;
  }
  return true;
}

// A text: `lengthName` (u16, 0 .. maxBytes, or 1 .. when `nonEmpty`), then that many bytes of
// UTF-8 (`name`).
template <class Io>
void transferText(Io& io, const char* lengthName, const char* name, std::string& s,
                  uint16_t maxBytes, bool nonEmpty) {
  uint16_t length = static_cast<uint16_t>(std::min<size_t>(s.size(), UINT16_MAX));
  io.u16(lengthName, length, nonEmpty ? 1 : 0, maxBytes);
  std::vector<uint8_t> bytes(s.begin(), s.end());
  io.bytes(name, bytes, length);
  if (Io::kReading) s.assign(bytes.begin(), bytes.end());
  io.require(isValidText(s), std::string(name) + " must be UTF-8 text without NUL bytes");
}

// One calibrated camera (docs/cameras.md conventions) and the texture box its pictures cover.
struct CameraParameters {
  std::string cam_name = "cam";            // the input dataset's camera name
  uint16_t cam_width = 0, cam_height = 0;  // image size, pixels
  double cam_fx = 1, cam_fy = 1, cam_cx = 0, cam_cy = 0;
  double cam_k1 = 0, cam_k2 = 0, cam_p1 = 0, cam_p2 = 0, cam_k3 = 0;
  double cam_rotation[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};  // world -> camera, row-major
  double cam_translation[3] = {0, 0, 0};
  uint16_t tx_box_x = 0, tx_box_y = 0;             // multiples of 16
  uint16_t tx_box_width = 16, tx_box_height = 16;  // multiples of 16
};

template <class Io>
void transfer(Io& io, CameraParameters& c) {
  transferText(io, "cam_name_length", "cam_name", c.cam_name, kMaxCameraNameBytes, true);
  io.u16("cam_width", c.cam_width, kMinImageSize, kMaxImageSize);
  io.u16("cam_height", c.cam_height, kMinImageSize, kMaxImageSize);
  double* const values[] = {&c.cam_fx, &c.cam_fy, &c.cam_cx, &c.cam_cy, &c.cam_k1,
                            &c.cam_k2, &c.cam_p1, &c.cam_p2, &c.cam_k3};
  static const char* const kNames[] = {"cam_fx", "cam_fy", "cam_cx", "cam_cy", "cam_k1",
                                       "cam_k2", "cam_p1", "cam_p2", "cam_k3"};
  for (int i = 0; i < 9; ++i)
    io.f64(kNames[i], *values[i]);
  for (double& r : c.cam_rotation)
    io.f64("cam_rotation", r);
  for (double& t : c.cam_translation)
    io.f64("cam_translation", t);
  bool finite = true;
  for (double* v : values)
    finite = finite && std::isfinite(*v);
  for (double r : c.cam_rotation)
    finite = finite && std::isfinite(r);
  for (double t : c.cam_translation)
    finite = finite && std::isfinite(t);
  io.require(finite, "camera parameters must be finite");
  io.require(c.cam_fx > 0 && c.cam_fy > 0, "cam_fx and cam_fy must be positive");
  const uint32_t paddedWidth = (c.cam_width + 15u) / 16 * 16;
  const uint32_t paddedHeight = (c.cam_height + 15u) / 16 * 16;
  io.u16("tx_box_x", c.tx_box_x, 0, paddedWidth - 16);
  io.u16("tx_box_y", c.tx_box_y, 0, paddedHeight - 16);
  io.u16("tx_box_width", c.tx_box_width, 16, paddedWidth - c.tx_box_x);
  io.u16("tx_box_height", c.tx_box_height, 16, paddedHeight - c.tx_box_y);
  io.require(c.tx_box_x % 16 == 0 && c.tx_box_y % 16 == 0 && c.tx_box_width % 16 == 0 &&
                 c.tx_box_height % 16 == 0,
             "the texture box must be whole 16x16 macroblocks");
}

struct SequenceHeader {
  uint16_t sh_syntax_version = kSyntaxVersion;
  uint32_t sh_first_frame = 0;  // the input's frame number of stream frame 0
  uint32_t sh_frame_count = 0;
  double sh_frame_rate = 25.0;
  uint8_t sh_grid_bits = 12;
  double sh_grid_origin[3] = {0, 0, 0};
  double sh_grid_step = 1.0;
  // Version 3 on: 1 = every VERTEX_ORDER unit is followed by an ATTRIBUTES unit.
  uint8_t sh_attributes_present = 0;
  std::vector<CameraParameters> cameras;  // sh_num_cameras; textures are coded when > 0
  // Present when sh_num_cameras > 0: the input dataset's fields the rest does not code.
  std::string sh_description;  // free text
  uint8_t sh_up_present = 0;
  double sh_up[3] = {0, 1, 0};  // the world's up direction, when sh_up_present
};

template <class Io>
void transfer(Io& io, SequenceHeader& sh) {
  io.u16("sh_syntax_version", sh.sh_syntax_version);
  io.require(sh.sh_syntax_version >= kMinSyntaxVersion && sh.sh_syntax_version <= kSyntaxVersion,
             "sh_syntax_version " + std::to_string(sh.sh_syntax_version) +
                 " is not supported (this decoder reads versions " +
                 std::to_string(kMinSyntaxVersion) + " to " + std::to_string(kSyntaxVersion) + ")");
  io.u32("sh_first_frame", sh.sh_first_frame, 0, kMaxFirstFrame);
  io.u32("sh_frame_count", sh.sh_frame_count, 1, kMaxFrames);
  io.f64("sh_frame_rate", sh.sh_frame_rate);
  io.require(std::isfinite(sh.sh_frame_rate) && sh.sh_frame_rate > 0 && sh.sh_frame_rate <= 1000,
             "sh_frame_rate must be in (0, 1000]");
  io.u8("sh_grid_bits", sh.sh_grid_bits, 8, 20);
  io.f64("sh_grid_origin_x", sh.sh_grid_origin[0]);
  io.f64("sh_grid_origin_y", sh.sh_grid_origin[1]);
  io.f64("sh_grid_origin_z", sh.sh_grid_origin[2]);
  io.f64("sh_grid_step", sh.sh_grid_step);
  io.require(std::isfinite(sh.sh_grid_origin[0]) && std::isfinite(sh.sh_grid_origin[1]) &&
                 std::isfinite(sh.sh_grid_origin[2]),
             "sh_grid_origin must be finite");
  io.require(std::isfinite(sh.sh_grid_step) && sh.sh_grid_step > 0,
             "sh_grid_step must be finite and positive");
  // Every grid point's world position (origin + q * step, docs/bitstream.md section 2) is then
  // finite: its far corner is.
  const double span = static_cast<double>((int64_t{1} << sh.sh_grid_bits) - 1) * sh.sh_grid_step;
  io.require(std::isfinite(sh.sh_grid_origin[0] + span) &&
                 std::isfinite(sh.sh_grid_origin[1] + span) &&
                 std::isfinite(sh.sh_grid_origin[2] + span),
             "the grid's far corner, sh_grid_origin + (2^sh_grid_bits - 1) * sh_grid_step, must "
             "be finite");
  // The one difference between versions 2 and 3 (a version 2 stream has no ATTRIBUTES units).
  if (sh.sh_syntax_version >= 3)
    io.u8("sh_attributes_present", sh.sh_attributes_present, 0, 1);
  else
    sh.sh_attributes_present = 0;
  uint16_t numCameras = static_cast<uint16_t>(sh.cameras.size());
  io.u16("sh_num_cameras", numCameras, 0, kMaxCameras);
  if (Io::kReading) sh.cameras.resize(numCameras);
  for (CameraParameters& c : sh.cameras)
    transfer(io, c);
  for (size_t i = 0; i < sh.cameras.size(); ++i)
    for (size_t j = 0; j < i; ++j)
      io.require(sh.cameras[i].cam_name != sh.cameras[j].cam_name,
                 "cam_name '" + sh.cameras[i].cam_name + "' is given to two cameras");
  if (sh.cameras.empty()) return;
  transferText(io, "sh_description_length", "sh_description", sh.sh_description,
               kMaxDescriptionBytes, false);
  io.u8("sh_up_present", sh.sh_up_present, 0, 1);
  if (!sh.sh_up_present) return;
  io.f64("sh_up_x", sh.sh_up[0]);
  io.f64("sh_up_y", sh.sh_up[1]);
  io.f64("sh_up_z", sh.sh_up[2]);
  io.require(std::isfinite(sh.sh_up[0]) && std::isfinite(sh.sh_up[1]) &&
                 std::isfinite(sh.sh_up[2]) &&
                 (sh.sh_up[0] != 0 || sh.sh_up[1] != 0 || sh.sh_up[2] != 0),
             "sh_up must be finite and not zero");
}

constexpr uint16_t kMaxMotionQuantStep = 4096;

// gh_pmesh_mode: a PMeshMode, or (syntax version 4) kGhD3dmcBMeshes: d3dmc P meshes whose
// frames between two keyframes are B meshes (P meshes predicted from the interpolation of two
// decoded frames, docs/bitstream.md, "B meshes") instead of interpolated frames.
constexpr uint8_t kGhD3dmcBMeshes = 3;
constexpr uint16_t kMinBMeshSyntaxVersion = 4;

struct GomHeader {
  uint32_t gh_first_frame = 0;
  uint16_t gh_frame_count = 1;
  uint8_t gh_pmesh_mode = 0;  // PMeshMode or kGhD3dmcBMeshes
  // Present unless gh_pmesh_mode is intra:
  // 1: a random access point, the GOM starts with an I mesh (and its VERTEX_ORDER); 0: the GOM
  // continues the previous GOM's connectivity, its first frame is a P mesh predicted from the
  // previous GOM's last frame.
  uint8_t gh_random_access = 1;
  uint16_t gh_motion_quant_step = 1;  // residual quantiser step, grid units
  uint8_t gh_max_octree_depth = 12;   // d3dmc only; the decoder checks <= sh_grid_bits
  uint16_t gh_bmesh_quant_step = 0;   // kGhD3dmcBMeshes only: the B meshes' quantiser step
  // Keyframes: offsets in the GOM, ascending, first 0 and last gh_frame_count - 1; coded as
  // gh_num_keyframes and the gaps gh_keyframe_delta between consecutive keyframes.
  std::vector<uint16_t> keyframes{0};
};

// The P-mesh coding of a GOM (kGhD3dmcBMeshes codes its P and B meshes as d3dmc does), and
// whether the frames between its keyframes are B meshes.
inline PMeshMode codingMode(const GomHeader& gh) {
  return gh.gh_pmesh_mode == kGhD3dmcBMeshes ? PMeshMode::kD3dmc
                                             : static_cast<PMeshMode>(gh.gh_pmesh_mode);
}
inline bool hasBMeshes(const GomHeader& gh) {
  return gh.gh_pmesh_mode == kGhD3dmcBMeshes;
}

template <class Io>
void transfer(Io& io, GomHeader& gh) {
  io.u32("gh_first_frame", gh.gh_first_frame, 0, kMaxFrames - 1);
  io.u16("gh_frame_count", gh.gh_frame_count, 1, kMaxGomFrames);
  io.u8("gh_pmesh_mode", gh.gh_pmesh_mode, 0, kGhD3dmcBMeshes);
  if (gh.gh_pmesh_mode == static_cast<uint8_t>(PMeshMode::kIntra)) return;
  io.u8("gh_random_access", gh.gh_random_access, 0, 1);
  io.u16("gh_motion_quant_step", gh.gh_motion_quant_step, 1, kMaxMotionQuantStep);
  if (codingMode(gh) == PMeshMode::kD3dmc)
    io.u8("gh_max_octree_depth", gh.gh_max_octree_depth, 0, 20);
  if (gh.gh_pmesh_mode == kGhD3dmcBMeshes)
    io.u16("gh_bmesh_quant_step", gh.gh_bmesh_quant_step, 1, kMaxMotionQuantStep);
  uint16_t count = static_cast<uint16_t>(gh.keyframes.size());
  const uint16_t minCount = gh.gh_frame_count == 1 ? 1 : 2;
  io.u16("gh_num_keyframes", count, minCount, gh.gh_frame_count);
  if (Io::kReading) gh.keyframes.assign(1, 0);
  for (uint16_t i = 1; i < count; ++i) {
    const uint16_t previous = gh.keyframes[i - 1];
    // Each gap leaves room for the keyframes still to come.
    const uint32_t maxDelta = uint32_t{gh.gh_frame_count} - 1 - previous - (count - 1 - i);
    uint16_t delta = Io::kReading ? 0 : static_cast<uint16_t>(gh.keyframes[i] - previous);
    io.u16("gh_keyframe_delta", delta, 1, maxDelta);
    if (Io::kReading) gh.keyframes.push_back(static_cast<uint16_t>(previous + delta));
  }
  io.require(gh.keyframes.back() == gh.gh_frame_count - 1,
             "the last keyframe must be the GOM's last frame");
}

// An I mesh: a Draco mesh whose POSITION attribute holds the grid integers divided by
// im_quant_step (syntax version 5; 1 before): the decoded positions are Draco's values times
// im_quant_step, so an I mesh can be coded coarser than the grid.
constexpr uint16_t kMinIMeshQuantStepSyntaxVersion = 5;
// The largest value Draco's POSITION attribute may hold: the largest grid integer divided by
// im_quant_step, rounded down (the encoder clamps to it, the decoder rejects what exceeds it).
constexpr int32_t iMeshMaxValue(int gridBits, int imQuantStep) {
  return ((int32_t{1} << gridBits) - 1) / imQuantStep;
}
struct IMeshUnit {
  uint16_t syntaxVersion = kSyntaxVersion;  // not coded: the stream's, set before reading
  uint32_t im_frame = 0;
  uint16_t im_quant_step = 1;
  std::vector<uint8_t> im_draco_payload;
};

template <class Io>
void transfer(Io& io, IMeshUnit& im) {
  io.u32("im_frame", im.im_frame, 0, kMaxFrames - 1);
  if (im.syntaxVersion >= kMinIMeshQuantStepSyntaxVersion)
    io.u16("im_quant_step", im.im_quant_step, 1, kMaxMotionQuantStep);
  else
    im.im_quant_step = 1;
  io.rest("im_draco_payload", im.im_draco_payload);
}

// The output order of the I mesh just before it (order_syntax.h); its payload is CABAC-coded.
struct VertexOrderUnit {
  uint32_t vo_frame = 0;
  uint32_t vo_num_vertices = 1;   // output vertices (<= the I mesh's; copies Draco made merge)
  uint8_t vo_triangle_order = 1;  // 1: the input's triangle list is coded; 0: coding order
  std::vector<uint8_t> vo_cabac_payload;
};

template <class Io>
void transfer(Io& io, VertexOrderUnit& vo) {
  io.u32("vo_frame", vo.vo_frame, 0, kMaxFrames - 1);
  io.u32("vo_num_vertices", vo.vo_num_vertices, 1, kMaxVertices);
  io.u8("vo_triangle_order", vo.vo_triangle_order, 0, 1);
  io.rest("vo_cabac_payload", vo.vo_cabac_payload);
}

// Texture coordinates and normals of the I mesh just before it (after its VERTEX_ORDER unit),
// in its output order; its payload is CABAC-coded (attributes_syntax.h).
enum class UvMode : uint8_t {
  kNone = 0,
  kPerVertex = 1,  // one per output vertex; the index triangles are the output triangles
  kPerCorner = 2,  // at_num_uvs values and an index per output triangle corner
};
enum class NormalMode : uint8_t {
  kNone = 0,
  kPerVertex = 1,
  kPerCorner = 2,
  kComputed = 3,  // not coded: the decoder computes per-vertex normals of every frame
};

// Quantised values (a *_quant_bits above 0) are integers q with value q * 2^-bits, |q| < 2^24.
constexpr uint8_t kMaxAttributeQuantBits = 24;
constexpr int32_t kMaxAttributeQuantValue = (1 << 24) - 1;

struct AttributesUnit {
  uint32_t at_frame = 0;
  uint8_t at_uv_mode = 0;        // UvMode
  uint8_t at_uv_quant_bits = 0;  // at_uv_mode != 0; 0: the float32 values exactly
  // at_uv_mode != 0, syntax version 6 on (0 before): where v = 0 lies in the texture image,
  // a UvOrigin (0: its bottom row, as in OBJ and PLY; 1: its top row, as in glTF). The
  // values are coded as given; a decoder writing a format of the other origin writes 1 - v.
  uint8_t at_uv_origin = 0;
  uint32_t at_num_uvs = 0;           // at_uv_mode 2
  uint8_t at_normal_mode = 0;        // NormalMode
  uint8_t at_normal_quant_bits = 0;  // at_normal_mode 1 or 2; 0: exactly
  uint32_t at_num_normals = 0;       // at_normal_mode 2
  std::vector<uint8_t> at_cabac_payload;
  // Not coded: the bound of at_num_uvs and at_num_normals, 3 x the output triangles of the I
  // mesh (set before parsing), and the stream's sh_syntax_version.
  uint32_t maxValues = 0;
  uint16_t syntaxVersion = kSyntaxVersion;
};

constexpr uint16_t kMinUvOriginSyntaxVersion = 6;

template <class Io>
void transfer(Io& io, AttributesUnit& at) {
  io.u32("at_frame", at.at_frame, 0, kMaxFrames - 1);
  io.u8("at_uv_mode", at.at_uv_mode, 0, 2);
  if (at.at_uv_mode != static_cast<uint8_t>(UvMode::kNone))
    io.u8("at_uv_quant_bits", at.at_uv_quant_bits, 0, kMaxAttributeQuantBits);
  if (at.at_uv_mode != static_cast<uint8_t>(UvMode::kNone) &&
      at.syntaxVersion >= kMinUvOriginSyntaxVersion)
    io.u8("at_uv_origin", at.at_uv_origin, 0, 1);
  else if (Io::kReading)
    at.at_uv_origin = 0;
  if (at.at_uv_mode == static_cast<uint8_t>(UvMode::kPerCorner))
    io.u32("at_num_uvs", at.at_num_uvs, 1, at.maxValues);
  io.u8("at_normal_mode", at.at_normal_mode, 0, 3);
  if (at.at_normal_mode == static_cast<uint8_t>(NormalMode::kPerVertex) ||
      at.at_normal_mode == static_cast<uint8_t>(NormalMode::kPerCorner))
    io.u8("at_normal_quant_bits", at.at_normal_quant_bits, 0, kMaxAttributeQuantBits);
  if (at.at_normal_mode == static_cast<uint8_t>(NormalMode::kPerCorner))
    io.u32("at_num_normals", at.at_num_normals, 1, at.maxValues);
  io.rest("at_cabac_payload", at.at_cabac_payload);
}

// A P mesh: positions only, predicted from the previous decoded frame of the GOM; the payload
// is CABAC-coded (pmesh_syntax.h).
struct PMeshUnit {
  uint32_t pm_frame = 0;
  std::vector<uint8_t> pm_cabac_payload;
};

template <class Io>
void transfer(Io& io, PMeshUnit& pm) {
  io.u32("pm_frame", pm.pm_frame, 0, kMaxFrames - 1);
  io.rest("pm_cabac_payload", pm.pm_cabac_payload);
}

// One camera's texture picture of one frame: an H.264 access unit (Annex B) of the camera's
// texture box (docs/bitstream.md, "Textures").
struct TextureUnit {
  uint32_t tx_frame = 0;
  uint16_t tx_camera = 0;
  std::vector<uint8_t> tx_access_unit;
};

template <class Io>
void transfer(Io& io, TextureUnit& tx) {
  io.u32("tx_frame", tx.tx_frame, 0, kMaxFrames - 1);
  io.u16("tx_camera", tx.tx_camera, 0, kMaxCameras - 1);
  io.rest("tx_access_unit", tx.tx_access_unit);
}

}  // namespace tdvo
