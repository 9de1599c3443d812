#include "encoder/encoder_params.h"

#include <algorithm>
#include <cmath>
#include <thread>

#include "common/core/error.h"
#include "common/core/mesh_io.h"
#include "common/core/sequence.h"

namespace tdvo {

void EncoderParams::registerOptions(OptionTable& t) {
  t.section("Input");
  t.add("InputMeshPattern", inputMeshPattern,
        "input mesh frames as a printf pattern, e.g. seq/%04d.obj: OBJ, PLY (.ply) or glTF "
        "(.gltf, .glb) by extension (.obj.gz and .ply.gz read through zlib); or one .gltf/.glb "
        "without %d whose animation's keyframes are the frames 0 .. N-1");
  t.add("FirstFrame", firstFrame, 0, static_cast<int>(kMaxFirstFrame),
        "frame number of the first input frame (the InputMeshPattern file number; with a "
        "Dataset its frame number, frames.first + index; not set: the dataset's first frame, "
        "else 0); recorded in the stream, the decoder names its output with these numbers");
  t.add("FrameCount", frameCount, 0, static_cast<int>(kMaxFrames),
        "number of frames to code; 0 = every consecutive frame from FirstFrame until the "
        "first missing input file (or the dataset's last frame)");
  t.add("FrameRate", frameRate, 0.001, 1000,
        "frames per second (rate figures, stream header); not set: the Dataset's frames.rate, "
        "or a glTF animation's evenly spaced key times, else 25");
  t.section("Quality");
  t.add("Quality", quality, -1, 100,
        "one knob for the geometry's rate and precision, 0 (coarsest) .. 100 (finest): a "
        "target step of 1/2^(5 + Quality/10) of the object's size, reached by the grid and "
        "quantiser (GridFit object, GridBits, MotionQuantStep) that code up to three windows of "
        "9 frames spread over the sequence at the least rate + distortion, then B meshes (BMeshGap "
        "8; PMeshMode d3dmc) or, with "
        "afxic or BMeshGap 0, keyframes by rate and distortion; GridFit, Lambda, BMeshGap, "
        "BMeshQuantStep, BMeshLambdaGrowth and keyframe keys set are kept; GridBits or "
        "MotionQuantStep set = "
        "coding by hand (Quality changes nothing); -1 = off (every key at its own value)");
  t.section("Geometry");
  t.add("GridBits", gridBits, 8, 20,
        "precision of the integer grid: 2^GridBits - 1 steps span the sequence's bounding box "
        "(GridFit sequence) or the object's own size (GridFit object)");
  t.addEnum("GridFit", gridFit, {{"sequence", GridFit::kSequence}, {"object", GridFit::kObject}},
            "what GridBits spans: sequence = the bounding box of all frames; object = the "
            "largest extent of any one frame, the grid getting the further bits (up to 20) its "
            "path across the scene needs, so a moving object keeps its precision");
  t.add("GOMSize", gomSize, 1, static_cast<int>(kMaxGomFrames),
        "frames per group of meshes (GOM); a GOM starts with an I mesh unless it continues "
        "the previous GOM (RandomAccessPeriod)");
  t.add("GOMListFile", gomListFile,
        "instead of GOMSize: a GOM list file (3dvo-recon's goms.txt): one '<first frame> "
        "<frame count>' line per GOM, frames counted from FirstFrame, tiling the coded frames");
  t.add("RandomAccessPeriod", randomAccessPeriod, 0, 1000000,
        "a random access point (an I mesh with its vertex order, decodable on its own) every "
        "this many GOMs; the GOMs between continue the previous GOM's connectivity with P "
        "meshes only, where it is unchanged; 0 = only the first GOM (P-mesh modes only)");
  t.addEnum(
      "PMeshMode", pmeshMode,
      {{"d3dmc", PMeshMode::kD3dmc}, {"intra", PMeshMode::kIntra}, {"afxic", PMeshMode::kAfxic}},
      "coding of the frames after a GOM's first: d3dmc = P meshes (octree motion "
      "clustering, spatial prediction, CABAC); intra = every frame an I mesh; afxic = "
      "P meshes as per-vertex temporal DPCM (AFX-IC-style reference, no clustering)");
  t.add("DracoSpeed", dracoSpeed, 0, 10, "Draco speed for I meshes: 0 = smallest, 10 = fastest");
  t.add("IMeshQuantStep", iMeshQuantStep, 1, kMaxMotionQuantStep,
        "quantiser step of the I meshes in grid units: each coordinate rounded to the nearest "
        "multiple of it (1 = lossless on the grid)");
  t.add("InputTriangleOrder", inputTriangleOrder,
        "1: the decoder outputs the input's triangle list (same triangles, order and corner "
        "rotation); 0: the same triangles in Draco's order and rotation, which saves the "
        "triangle list's share of the VERTEX_ORDER units (vertices come out in the input's "
        "order either way)");
  t.section("Attributes (texture coordinates and normals of the input meshes)");
  t.add("TextureCoordinates", textureCoordinates,
        "1: the input's texture coordinates (OBJ vt, PLY u/v, glTF TEXCOORD_0) are carried, "
        "coded once per I mesh, exactly (they must not change within a GOM of P meshes); "
        "0: dropped");
  t.addEnum("Normals", normals,
            {{"auto", NormalsChoice::kAuto},
             {"coded", NormalsChoice::kCoded},
             {"computed", NormalsChoice::kComputed},
             {"none", NormalsChoice::kNone}},
            "the input's normals (OBJ vn, PLY nx/ny/nz, glTF NORMAL): auto = coded exactly "
            "once per I mesh when they are the same in every frame coded from it, else "
            "computed; coded = always coded (an error when they change within a GOM of P "
            "meshes); computed = the decoder computes per-vertex normals of every frame from "
            "the decoded geometry; none = dropped");
  t.add("UVQuantBits", uvQuantBits, 0, kMaxAttributeQuantBits,
        "0: texture coordinates coded exactly (the float32 values as read); b > 0: rounded to "
        "multiples of 2^-b (e.g. 12 for a 4096-texel texture), far fewer bytes; values must "
        "stay below 2^(24-b)");
  t.add("NormalQuantBits", normalQuantBits, 0, kMaxAttributeQuantBits,
        "0: coded normals exactly (the float32 values as read); b > 0: components rounded to "
        "multiples of 2^-b (not renormalised)");
  t.section("P meshes (PMeshMode d3dmc)");
  t.add("MotionQuantStep", motionQuantStep, 1, kMaxMotionQuantStep,
        "quantiser step of motion residuals in grid units (1 = lossless on the grid)");
  t.add("Lambda", lambda, -1, 1e12,
        "rate-distortion trade-off J = D + Lambda * R of the octree clustering (D in squared "
        "grid units, R in bits; 0 = smallest distortion; -1 = automatic: 0 at "
        "MotionQuantStep 1, else 0.1 * MotionQuantStep^2)");
  t.add("MaxOctreeDepth", maxOctreeDepth, 0, 20,
        "deepest octree level of the motion clustering (capped at the stream's grid bits)");
  t.section("Keyframes (PMeshMode d3dmc or afxic)");
  t.add("KeyframeCount", keyframeCount, 0, static_cast<int>(kMaxGomFrames),
        "keyframes per GOM, its first and last frame included (2 or more; 1 is an error); the "
        "frames between are linear interpolations; 0 = every frame is a keyframe");
  t.add("KeyframeMaxError", keyframeMaxError, 0, 1e9,
        "instead of KeyframeCount: add keyframes until no interpolated coordinate is off by "
        "more than this many grid units; 0 = off");
  t.add("KeyframeLambda", keyframeLambda, -1, 1e12,
        "instead of KeyframeCount and KeyframeMaxError: keyframes chosen per GOM to minimise "
        "J = D + KeyframeLambda * R (D: squared error of every frame against the quantised "
        "input, in grid units; R: P-mesh bits), never worse in J than every frame a keyframe; "
        "0 = off; -1 = automatic: 0.4 * MotionQuantStep^2");
  t.section("B meshes (PMeshMode d3dmc)");
  t.add("BMeshGap", bMeshGap, 0, static_cast<int>(kMaxGomFrames),
        "keyframes every this many frames of a GOM (and its last frame), and each frame "
        "between two keyframes coded as a B mesh: a P mesh predicted from the interpolation "
        "of the nearest decoded frames around it, halving the interval (hierarchical B "
        "frames); 0 = off (frames between keyframes are interpolations); excludes the "
        "Keyframe keys");
  t.add("BMeshQuantStep", bMeshQuantStep, -1, kMaxMotionQuantStep,
        "quantiser step of the B meshes' motion residuals in grid units; -1 = automatic: 2 * "
        "MotionQuantStep");
  t.add("BMeshLambdaGrowth", bMeshLambdaGrowth, 1, 16,
        "the B meshes' Lambda grows by this factor per level of the halving below the first "
        "(the middle frame between two keyframes has the B meshes' Lambda, the middles of "
        "its halves this times more, ...); 1 = the same Lambda at every level");
  t.section("Speed");
  t.add("Threads", threads, 0, 256,
        "GOMs encoded in parallel (0 = hardware concurrency); the stream, the MD5 lines and "
        "the reconstruction are identical for any value");
  t.section("Textures");
  t.add("Dataset", dataset,
        "dataset folder (docs/dataset.md) with the cameras and their videos: when set, every "
        "camera's texture is coded; without InputMeshPattern its meshes are the geometry");
  t.addEnum("TextureMode", textureMode,
            {{"bbox", TextureBoxMode::kBox}, {"full", TextureBoxMode::kFull}},
            "what each camera's H.264 pictures cover: bbox = the object's macroblock-aligned "
            "bounding box over the sequence; full = the whole camera frame");
  t.addEnum("TexturePadding", texturePadding,
            {{"mb128", TexturePadding::kMb128},
             {"none", TexturePadding::kNone},
             {"extrapolate", TexturePadding::kExtrapolate}},
            "pixels outside the object's shape: none = left as they are; mb128 = macroblocks "
            "the shape does not touch set to Y=Cb=Cr=128; extrapolate = mb128 plus MPEG-4-style "
            "repetitive padding inside the shape's boundary macroblocks");
  t.add("TextureQP", textureQp, 1, 51, "H.264 constant QP (when TextureBitrate is 0)");
  t.add("TextureBitrate", textureBitrate, 0, 1000000,
        "H.264 average bitrate per camera in kbit/s instead of a constant QP; 0 = off");
  t.add("TexturePreset", texturePreset, "x264 preset (ultrafast .. placebo)");
  t.add("TextureBoxMargin", textureBoxMargin, 0, 1024,
        "bbox mode: pixels added around the input geometry's shape before aligning the box "
        "(room for the decoded geometry's shape)");
  t.section("Output");
  t.add("BitstreamFile", bitstreamFile, "the .3dvo stream to write", "-o");
  t.add("ReconMeshPattern", reconMeshPattern,
        "optional: write the encoder's reconstruction as mesh frames (printf pattern filled "
        "with the input's frame numbers, like the decoder's output; OBJ, or PLY / glTF by a "
        ".ply, .gltf or .glb extension)");
  // Keys whose being set changes what the encoder does (Encoder::params, resolveQuality): the
  // effective configuration prints them as comments while unset, so that read back as a cfg
  // file it gives the same run.
  t.derivedWhenUnset("FirstFrame", "with a Dataset, its frames.first");
  t.derivedWhenUnset("FrameRate",
                     "with a Dataset, its frames.rate; with a glTF animation, its key times");
  const std::string byQuality = "chosen by Quality unless Quality is -1";
  t.derivedWhenUnset("GridFit", byQuality);
  t.derivedWhenUnset("GridBits", byQuality + "; setting it codes by hand");
  t.derivedWhenUnset("MotionQuantStep", byQuality + "; setting it codes by hand");
  t.derivedWhenUnset("IMeshQuantStep",
                     "with Quality on, P meshes and GridBits and MotionQuantStep not set, "
                     "Quality's trial chooses 1 or MotionQuantStep");
  const std::string keyframes =
      "unless a keyframe key is set, Quality chooses the keyframes: by BMeshGap with d3dmc, "
      "else by rate and distortion";
  t.derivedWhenUnset("KeyframeCount", keyframes);
  t.derivedWhenUnset("KeyframeMaxError", keyframes);
  t.derivedWhenUnset("KeyframeLambda", keyframes);
  t.derivedWhenUnset("BMeshGap",
                     "Quality (not coding by hand) codes B meshes, BMeshGap 8, with PMeshMode "
                     "d3dmc unless a keyframe key is set");
  // Set where no B meshes are coded, these are an error (C55): unset, they stay unset.
  const std::string bMeshesOnly = "used where B meshes are coded; set where none are, an error";
  t.derivedWhenUnset("BMeshQuantStep", bMeshesOnly);
  t.derivedWhenUnset("BMeshLambdaGrowth", bMeshesOnly);
}

double EncoderParams::effectiveLambda() const {
  return lambdaFor(motionQuantStep);
}

double EncoderParams::lambdaFor(int quantStep) const {
  if (lambda >= 0) return lambda;
  return quantStep == 1 ? 0.0 : kAutoLambdaFactor * quantStep * quantStep;
}

int EncoderParams::effectiveBMeshQuantStep() const {
  if (bMeshQuantStep > 0) return bMeshQuantStep;
  return std::min(kAutoBMeshQuantFactor * motionQuantStep, int{kMaxMotionQuantStep});
}

double EncoderParams::bMeshLambda(int level) const {
  return lambdaFor(effectiveBMeshQuantStep()) * std::pow(bMeshLambdaGrowth, level - 1);
}

double EncoderParams::effectiveKeyframeLambda() const {
  if (keyframeLambda >= 0) return keyframeLambda;
  return kAutoKeyframeLambdaFactor * motionQuantStep * motionQuantStep;
}

int EncoderParams::threadCount() const {
  if (threads > 0) return threads;
  const unsigned hardware = std::thread::hardware_concurrency();
  return hardware > 0 ? static_cast<int>(hardware) : 1;
}

// A GOM list may hold any GOM the stream can carry.
static_assert(static_cast<uint32_t>(kGomListMaxCount) == kMaxGomFrames);

GomList EncoderParams::goms(size_t frameCount) const {
  if (!gomListFile.empty()) return readGomList(gomListFile, frameCount);
  check(gomSize >= 1, "GOMSize must be at least 1");
  GomList list;
  for (size_t first = 0; first < frameCount; first += static_cast<size_t>(gomSize))
    list.emplace_back(static_cast<int>(first),
                      static_cast<int>(std::min(static_cast<size_t>(gomSize), frameCount - first)));
  return list;
}

std::vector<std::pair<size_t, size_t>> EncoderParams::randomAccessRuns(size_t gomCount) const {
  const size_t period = pmeshMode == PMeshMode::kIntra || randomAccessPeriod == 1
                            ? 1
                            : static_cast<size_t>(randomAccessPeriod);
  std::vector<std::pair<size_t, size_t>> runs;
  for (size_t g = 0; g < gomCount; ++g)
    if (runs.empty() || (period != 0 && g % period == 0))
      runs.emplace_back(g, 1);
    else
      ++runs.back().second;
  return runs;
}

void EncoderParams::validate() const {
  check(!inputMeshPattern.empty() || !dataset.empty(),
        "InputMeshPattern is not set, nor a Dataset with meshes (see --help)");
  check(!bitstreamFile.empty(), "BitstreamFile is not set (see --help)");
  if (!inputMeshPattern.empty() && !isMeshAnimationFile(inputMeshPattern))
    checkFramePattern(inputMeshPattern, "InputMeshPattern");
  if (!reconMeshPattern.empty()) checkFramePattern(reconMeshPattern, "ReconMeshPattern");
  validateCoding();
}

void EncoderParams::validateCoding() const {
  check(keyframeCount != 1,
        "KeyframeCount 1 is not possible: a GOM's first and last frames are always keyframes "
        "(set 2 or more, or 0 for every frame)");
  check(!(keyframeCount > 0 && keyframeMaxError > 0),
        "KeyframeCount and KeyframeMaxError exclude each other: set one of them");
  check(lambda == -1 || lambda >= 0, "Lambda must be -1 (automatic), 0 or positive");
  check(keyframeLambda == -1 || keyframeLambda >= 0,
        "KeyframeLambda must be -1 (automatic), 0 (off) or positive");
  check(keyframeLambda == 0 || (keyframeCount == 0 && keyframeMaxError == 0),
        "KeyframeLambda excludes KeyframeCount and KeyframeMaxError: set one of them");
  check(pmeshMode != PMeshMode::kIntra ||
            (keyframeCount == 0 && keyframeMaxError == 0 && keyframeLambda == 0),
        "keyframes need P meshes: PMeshMode intra codes every frame");
  check(bMeshGap != 1, "BMeshGap 1 leaves no frame between keyframes: set 2 or more, or 0 (off)");
  check(bMeshQuantStep == -1 || bMeshQuantStep >= 1,
        "BMeshQuantStep must be -1 (automatic) or 1 or more");
  check(bMeshGap == 0 || pmeshMode == PMeshMode::kD3dmc,
        "B meshes (BMeshGap) need PMeshMode d3dmc");
  check(bMeshGap == 0 || (keyframeCount == 0 && keyframeMaxError == 0 && keyframeLambda == 0),
        "BMeshGap chooses the keyframes itself: it excludes KeyframeCount, KeyframeMaxError and "
        "KeyframeLambda");
  // Before any frame is read: a bad GOM list is found at once.
  // (FrameCount 0, all frames, is checked once the frames are counted.)
  if (!gomListFile.empty() && frameCount > 0) goms(static_cast<size_t>(frameCount));
}

}  // namespace tdvo
