// Speed of texture coding and of decoding streams with textures (issue 10):
//
//   TextureShape/<seq>                  the object's shape in one camera: the decoded mesh
//                                       rasterised (common/views/texture_shape.h); items =
//                                       camera-frames/s
//   TextureEncode/<seq>/threads:<n>     TextureEncoder::encodeGom over the first GOM: per camera
//                                       and frame, reading the camera's frame (PNG or video),
//                                       the shape, padding, x264 and the closed-loop H.264
//                                       decode; items = camera-frames/s (with 1 thread: frames/s
//                                       of one camera)
//   TextureDecode/<seq>                 FFmpeg's H.264 decoding of every camera's access units of
//                                       the first GOM; items = camera-frames/s
//   StreamDecode/<seq>/geometry         the same geometry coded without textures, decoded with
//                                       the per-frame MD5 that 3dvo-dec prints; frames/s
//   StreamDecode/<seq>/textures/threads:<n>  the whole stream with textures, decoded with the MD5
//                                       lines that 3dvo-dec prints (geometry and every picture;
//                                       no PNG output) on n threads; frames/s, and the
//                                       real-time factor (frames/s over the frame rate)
//
// Sequences (the output header names them: "sequence.<name>: ..."):
//   rig      3dvo-synth's default rig: 8 cameras of 320x240, the deforming blob (2,562
//            vertices), 10 frames; GOMSize 5. Always present (generated).
//   uu-4cam  ../shared/data/multiview/uu-4cam: 4 cameras of 644x486 MPEG-4 video at 25 fps,
//            the first 50 frames, GOMSize 25. The geometry is 3dvo-recon's reconstruction of
//            frame 0 with cfg/recon/uu-4cam.cfg (about 7,600 vertices; made when the bench
//            starts, ~15 s), the same mesh for every frame. Skipped, with a note in the
//            header, when the data is absent.
// Coding: d3dmc-lossless geometry on a 12-bit grid; TextureMode bbox, TexturePadding mb128,
// TextureQP 28, TexturePreset medium. One thread: CPU time; threads:2: wall time.
//
//   build/bin/texture_bench --benchmark_filter=uu-4cam
#include <benchmark/benchmark.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "bitstream/camera_parameters.h"
#include "common/core/config.h"
#include "common/core/md5.h"
#include "common/core/obj_io.h"
#include "common/media/yuv.h"
#include "common/views/texture_shape.h"
#include "decoder/stream_decoder.h"
#include "decoder/texture/h264_decoder.h"
#include "encoder/sequence_encoder.h"
#include "encoder/texture_encoder.h"
#include "tools/multiview/importers.h"
#include "tools/multiview/synth_rig.h"
#include "tools/recon/recon_params.h"
#include "tools/recon/recon_pipeline.h"

using namespace tdvo;

namespace {

const std::string kUu4Cam = std::string(TDVO_SHARED_DATA_DIR) + "/multiview/uu-4cam";

// A folder for the generated inputs, removed at exit.
struct WorkFolder {
  std::filesystem::path path =
      std::filesystem::temp_directory_path() / ("3dvo-texture-bench-" + std::to_string(::getpid()));
  ~WorkFolder() {
    std::error_code ec;
    std::filesystem::remove_all(path, ec);
  }
};
std::string workFolder(const std::string& name) {
  static WorkFolder folder;
  const std::filesystem::path p = folder.path / name;
  std::filesystem::create_directories(p);
  return p.string();
}

// A sequence with textures, coded once on first use.
struct TextureSequence {
  Dataset dataset;
  EncoderParams params;
  std::vector<Mesh> frames;
  Grid grid;
  std::vector<uint8_t> stream;                           // with textures
  std::vector<uint8_t> geometryStream;                   // the same geometry, no textures
  std::vector<IntMesh> firstGom;                         // the decoded meshes of GOM 0
  std::vector<CameraParameters> cameras;                 // with their texture boxes
  std::vector<std::vector<std::vector<uint8_t>>> units;  // GOM 0's access units [camera][frame]
  size_t pictures() const { return firstGom.size() * cameras.size(); }
};

EncoderParams codingParams(const Dataset& dataset, int frames, int gomSize) {
  EncoderParams p;  // defaults: d3dmc, lossless on a 12-bit grid
  p.dataset = dataset.folder;
  p.frameRate = dataset.frameRate;
  p.frameCount = frames;
  p.gomSize = gomSize;
  p.textureMode = TextureBoxMode::kBox;
  p.texturePadding = TexturePadding::kMb128;
  p.textureQp = 28;
  p.texturePreset = "medium";
  return p;
}

void code(TextureSequence& s) {
  s.grid = gridForSequence(s.frames, s.params.gridBits);
  TextureEncoder textures(s.params, s.dataset, s.frames);
  s.cameras = textures.cameras();
  s.units.resize(s.cameras.size());
  const size_t gomSize = static_cast<size_t>(s.params.gomSize);
  s.stream = encodeSequence(
                 s.params, s.grid, s.frames, {},
                 [&](int frame, const IntMesh& mesh) {
                   if (static_cast<size_t>(frame) < gomSize) s.firstGom.push_back(mesh);
                 },
                 &textures, [](int, int, const YuvPicture&, const Image&) {})
                 .stream;
  EncoderParams geometryOnly = s.params;
  geometryOnly.dataset.clear();
  s.geometryStream =
      encodeSequence(geometryOnly, s.grid, s.frames, {}, [](int, const IntMesh&) {}).stream;
  // GOM 0's access units, per camera, from the stream.
  UnitReader reader(s.stream.data(), s.stream.size(), "bench.3dvo");
  UnitView unit;
  while (reader.next(unit)) {
    if (unit.type != static_cast<uint8_t>(UnitType::kTexture)) continue;
    ByteReader payload(unit.payload, unit.size, "bench.3dvo", unit.payloadOffset);
    TextureUnit tx;
    transfer(payload, tx);
    if (tx.tx_frame < gomSize) s.units[tx.tx_camera].push_back(std::move(tx.tx_access_unit));
  }
}

const TextureSequence& rig() {
  static const std::unique_ptr<TextureSequence> s = [] {
    auto s = std::make_unique<TextureSequence>();
    SynthParams synth;  // 3dvo-synth's defaults
    synth.output = workFolder("rig");
    writeSyntheticDataset(synth);
    s->dataset = readDataset(synth.output);
    s->params = codingParams(s->dataset, synth.frameCount, 5);
    s->frames = readDatasetFrames(s->dataset, 0, synth.frameCount);
    code(*s);
    return s;
  }();
  return *s;
}

const TextureSequence& uu4Cam() {
  static const std::unique_ptr<TextureSequence> s = [] {
    auto s = std::make_unique<TextureSequence>();
    // The geometry: frame 0 reconstructed as 3dvo-recon -c cfg/recon/uu-4cam.cfg does it.
    ReconParams recon;
    OptionTable table("texture_bench", "");
    addReconOptions(table, recon);
    table.parseFile(std::string(TDVO_SOURCE_DIR) + "/cfg/recon/uu-4cam.cfg");
    recon.input = kUu4Cam;
    recon.output = workFolder("uu-4cam-recon");
    recon.frameCount = 1;
    runReconstruction(recon, nullptr);
    const Mesh mesh = readObj(recon.output + "/0000.obj");
    ImportOptions import;
    import.up = "0,0,-1";
    s->dataset = importAny(kUu4Cam, import);
    const int frames = 50;
    s->params = codingParams(s->dataset, frames, 25);
    s->frames.assign(frames, mesh);
    code(*s);
    return s;
  }();
  return *s;
}

using SequenceOf = const TextureSequence& (*)();

void textureShape(benchmark::State& state, SequenceOf sequence) {
  const TextureSequence& s = sequence();
  const Mesh mesh = s.grid.dequantise(s.firstGom[0]);
  std::vector<MaskRenderer> cameras;
  for (size_t c = 0; c < s.cameras.size(); ++c)
    cameras.emplace_back(toCamera(s.cameras[c], static_cast<int>(c)));
  for (auto _ : state)
    for (const MaskRenderer& camera : cameras)
      benchmark::DoNotOptimize(textureShape(mesh, camera).pixels.data());
  state.SetItemsProcessed(int64_t(state.iterations()) * int64_t(cameras.size()));
  state.SetLabel("camera-frames/s, " + std::to_string(s.firstGom[0].triangles.size()) +
                 " triangles");
}

void textureEncode(benchmark::State& state, SequenceOf sequence, int threads) {
  const TextureSequence& s = sequence();
  EncoderParams params = s.params;
  params.threads = threads;
  TextureEncoder encoder(params, s.dataset, s.frames);  // the boxes: not timed
  for (auto _ : state) {
    UnitWriter units;
    encoder.encodeGom(0, s.firstGom, s.grid, units,
                      [](int, int, const YuvPicture&, const Image&) {});
    benchmark::DoNotOptimize(units.bytes().data());
  }
  state.SetItemsProcessed(int64_t(state.iterations()) * int64_t(s.pictures()));
  state.SetLabel("camera-frames/s");
}

void textureDecode(benchmark::State& state, SequenceOf sequence) {
  const TextureSequence& s = sequence();
  for (auto _ : state)
    for (size_t c = 0; c < s.cameras.size(); ++c) {
      H264Decoder decoder("bench");
      const TextureBox box = textureBox(s.cameras[c]);
      for (const std::vector<uint8_t>& unit : s.units[c])
        benchmark::DoNotOptimize(decoder.decode(unit, box.width, box.height).y.data());
    }
  state.SetItemsProcessed(int64_t(state.iterations()) * int64_t(s.pictures()));
  state.SetLabel("camera-frames/s");
}

void streamDecode(benchmark::State& state, SequenceOf sequence, bool textures, int threads) {
  const TextureSequence& s = sequence();
  const std::vector<uint8_t>& stream = textures ? s.stream : s.geometryStream;
  for (auto _ : state) {
    StreamDecoder decoder(stream.data(), stream.size(), "bench.3dvo");
    decoder.setPictureDecoder(makeH264Decoder);
    decoder.setThreads(threads);
    decoder.decode([](int, const IntMesh& mesh) { benchmark::DoNotOptimize(geometryDigest(mesh)); },
                   [](int, int, const YuvPicture& picture, const Image&) {
                     benchmark::DoNotOptimize(pictureDigest(picture));
                   });
  }
  const double frames = double(state.iterations()) * double(s.frames.size());
  state.SetItemsProcessed(int64_t(frames));
  state.counters["realtime"] =
      benchmark::Counter(frames / s.params.frameRate, benchmark::Counter::kIsRate);
  state.SetLabel("frames/s; realtime = x real time at " + std::to_string(int(s.params.frameRate)) +
                 " fps");
}

void registerSequence(const std::string& name, SequenceOf sequence) {
  const std::string seq = "/" + name;
  benchmark::RegisterBenchmark(("TextureShape" + seq).c_str(), textureShape, sequence)
      ->Unit(benchmark::kMillisecond);
  // One thread: CPU time, as every single-core figure. More threads: wall time (the point of
  // threads; it depends on what else runs on the machine).
  benchmark::RegisterBenchmark(("TextureEncode" + seq + "/threads:1").c_str(), textureEncode,
                               sequence, 1)
      ->Unit(benchmark::kMillisecond);
  benchmark::RegisterBenchmark(("TextureEncode" + seq + "/threads:2").c_str(), textureEncode,
                               sequence, 2)
      ->Unit(benchmark::kMillisecond)
      ->UseRealTime();
  benchmark::RegisterBenchmark(("TextureDecode" + seq).c_str(), textureDecode, sequence)
      ->Unit(benchmark::kMillisecond);
  benchmark::RegisterBenchmark(("StreamDecode" + seq + "/geometry").c_str(), streamDecode, sequence,
                               false, 1)
      ->Unit(benchmark::kMillisecond);
  benchmark::RegisterBenchmark(("StreamDecode" + seq + "/textures/threads:1").c_str(), streamDecode,
                               sequence, true, 1)
      ->Unit(benchmark::kMillisecond);
  benchmark::RegisterBenchmark(("StreamDecode" + seq + "/textures/threads:2").c_str(), streamDecode,
                               sequence, true, 2)
      ->Unit(benchmark::kMillisecond)
      ->UseRealTime();
}

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  benchmark::AddCustomContext("sequence.rig",
                              "generated: 3dvo-synth defaults (8 cameras 320x240, 10 frames)");
  registerSequence("rig", rig);
  if (std::filesystem::exists(kUu4Cam + "/cam1/video.avi")) {
    benchmark::AddCustomContext(
        "sequence.uu-4cam",
        kUu4Cam + ": 4 cameras 644x486, 50 frames, geometry 3dvo-recon of frame 0");
    registerSequence("uu-4cam", uu4Cam);
  } else {
    benchmark::AddCustomContext("sequence.uu-4cam", "absent (" + kUu4Cam + "): skipped");
    std::fprintf(stderr, "texture_bench: %s is absent: the uu-4cam benchmarks are skipped\n",
                 kUu4Cam.c_str());
  }
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
