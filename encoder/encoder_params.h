// The encoder's parameters: every cfg key of 3dvo-enc, bound in one option table.
#pragma once

#include <cstddef>
#include <string>
#include <utility>
#include <vector>

#include "bitstream/syntax.h"
#include "common/core/config.h"
#include "common/core/gom_list.h"
#include "common/core/grid.h"
#include "encoder/texture_padding.h"

namespace tdvo {

// What each camera's H.264 pictures cover: the whole frame, or the object's macroblock-aligned
// bounding box over the sequence.
enum class TextureBoxMode { kFull = 0, kBox = 1 };

// What the stream carries of the input's normals (docs/user-guide.md, "Texture coordinates and
// normals"): auto = coded once per I mesh when they are the same in every frame coded from it,
// else computed; coded = always coded (an error when they change within a GOM of P meshes);
// computed = the decoder computes per-vertex normals of every frame; none = dropped.
enum class NormalsChoice { kAuto, kCoded, kComputed, kNone };

struct EncoderParams {
  // Input
  std::string inputMeshPattern;
  int firstFrame = 0;
  int frameCount = 0;  // 0: every frame from firstFrame until a file is missing (input_frames.h)
  double frameRate = 25.0;
  // Quality (encoder/quality.h): < 0 = off, every key at its own value
  int quality = 50;
  // Geometry
  int gridBits = 12;
  GridFit gridFit = GridFit::kSequence;  // what spans 2^gridBits - 1 grid steps
  int gomSize = 16;
  std::string gomListFile;     // when set, the GOMs it lists replace GOMSize (see goms())
  int randomAccessPeriod = 1;  // a random access point every this many GOMs (0: first only)
  PMeshMode pmeshMode = PMeshMode::kD3dmc;
  int dracoSpeed = 0;
  int iMeshQuantStep = 1;          // the I meshes' quantiser step (im_quant_step), grid units
  bool inputTriangleOrder = true;  // the decoder outputs the input's triangle list
  // Attributes
  bool textureCoordinates = true;  // carry the input's texture coordinates
  NormalsChoice normals = NormalsChoice::kAuto;
  int uvQuantBits = 0;  // 0: texture coordinates exactly, else multiples of 2^-bits
  int normalQuantBits = 0;
  // Not a cfg key: set by encodeSequence from the input (its first frame has texture
  // coordinates or normals that the two keys above keep): the stream has ATTRIBUTES units.
  bool attributesPresent = false;
  // P meshes
  int motionQuantStep = 1;
  double lambda = -1.0;  // < 0: automatic, see effectiveLambda()
  int maxOctreeDepth = 20;
  // Keyframes (P-mesh modes): 0 / 0 / 0 = every frame a keyframe
  int keyframeCount = 0;
  double keyframeMaxError = 0;
  double keyframeLambda = 0;  // > 0: RD keyframe choice; -1: automatic (effectiveKeyframeLambda)
  // B meshes (d3dmc): > 0: keyframes every bMeshGap frames of a GOM (and its last frame), the
  // frames between coded as B meshes; 0 = off
  int bMeshGap = 0;
  int bMeshQuantStep = -1;       // the B meshes' quantiser; -1: automatic (effectiveBMeshQuantStep)
  double bMeshLambdaGrowth = 2;  // a B mesh's Lambda times this per level below the first
  // Speed
  int threads = 1;  // GOMs encoded in parallel; 0 = hardware concurrency (see threadCount())
  // Textures (coded when Dataset is set)
  std::string dataset;
  TextureBoxMode textureMode = TextureBoxMode::kBox;
  TexturePadding texturePadding = TexturePadding::kMb128;
  int textureQp = 28;
  int textureBitrate = 0;
  std::string texturePreset = "medium";
  int textureBoxMargin = 8;
  // Output
  std::string bitstreamFile;
  std::string reconMeshPattern;

  // The rate-distortion lambda the P-mesh encoder uses: Lambda when set (>= 0); otherwise 0
  // for MotionQuantStep 1 (lossless on the grid) and kAutoLambdaFactor * MotionQuantStep^2
  // above, so that coarser residual quantisation also means coarser clustering.
  static constexpr double kAutoLambdaFactor = 0.1;
  double effectiveLambda() const;
  // The same for P meshes of quantiser `quantStep` (B meshes have their own).
  double lambdaFor(int quantStep) const;
  // BMeshQuantStep when set (> 0), else kAutoBMeshQuantFactor * MotionQuantStep (at most
  // kMaxMotionQuantStep): docs/prediction.md, "B meshes", says how it was chosen.
  static constexpr int kAutoBMeshQuantFactor = 2;
  int effectiveBMeshQuantStep() const;
  // The Lambda of a B mesh at `level` of the halving of its keyframe interval (1: the middle
  // frame, 2: the middles of the halves, ...): lambdaFor(effectiveBMeshQuantStep()) times
  // BMeshLambdaGrowth^(level - 1). Deeper B meshes are references of fewer frames (the last
  // level of none), so their motion is worth fewer bits: docs/prediction.md, "B meshes".
  double bMeshLambda(int level) const;
  // The lambda of the rate-distortion keyframe choice (squared grid units per bit): 0 when
  // KeyframeLambda is 0 (off); KeyframeLambda when > 0; automatic (-1):
  // kAutoKeyframeLambdaFactor * MotionQuantStep^2 (docs/options.md says how it was chosen).
  static constexpr double kAutoKeyframeLambdaFactor = 0.4;
  double effectiveKeyframeLambda() const;
  // Threads to use: Threads, or the hardware concurrency (at least 1) when Threads is 0.
  int threadCount() const;
  // The GOMs of a sequence of `frameCount` frames, (first frame, frame count) in stream frame
  // numbers, tiling frames 0 .. frameCount - 1 in order: those GOMListFile lists (read and
  // checked here; an Error names the file and line of what is wrong), else GOMSize frames each,
  // the last one shorter when GOMSize does not divide frameCount. Each GOM starts with an I mesh
  // and, with textures, an IDR picture; keyframes are chosen inside each GOM.
  GomList goms(size_t frameCount) const;
  // The runs of `gomCount` GOMs (those of goms()), (first GOM, GOM count), each from one random
  // access point to the next: RandomAccessPeriod GOMs each (the last one shorter), all GOMs in
  // one run for 0, and every GOM a run of its own with PMeshMode intra. The GOMs of a run are
  // coded one after the other (each may continue the previous one's connectivity); runs are
  // independent, and each starts with an I mesh.
  std::vector<std::pair<size_t, size_t>> randomAccessRuns(size_t gomCount) const;

  // Binds every field to its cfg key (the single list of keys; docs/options.md mirrors it).
  void registerOptions(OptionTable& table);
  // Checks what single-key ranges cannot: required keys, patterns, the GOM list against
  // FrameCount. Throws Error.
  void validate() const;
  // The same without the input and output file keys (frames given from memory, encoder/encoder.h).
  void validateCoding() const;
};

}  // namespace tdvo
