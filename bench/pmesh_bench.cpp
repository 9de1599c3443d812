// Speed of geometry coding on a shared sequence (bench_sequences.h says which one ran):
//
//   PMeshDecode/<condition>/<seq>   decoding every P mesh of the sequence, chained frame after
//                                   frame from the decoded I mesh (one GOM over all frames);
//                                   items_per_second = vertex-frames/s (issue 10 target:
//                                   >= 20 M for d3dmc on one core)
//   PMeshEncode/<condition>/<seq>   the encoder's RD search and CABAC writing for the same
//                                   P meshes (encodePMesh; no closed-loop check)
//   GomTopologyBuild/<seq>          the per-GOM connectivity tables (rings, wings, BFS order)
//   IMeshEncode/<seq>, IMeshDecode  frame 0 as an I mesh (Draco, DracoSpeed 0, lossless on the
//                                   12-bit grid); IMeshEncode includes the encoder's own decode
//                                   and vertex-order recovery; items = vertices
//   StreamDecode/<condition>/<seq>  a whole stream (GOMSize of cfg/per-sequence) through
//                                   StreamDecoder: I meshes, P meshes, interpolation;
//                                   items_per_second = frames/s; ...Md5 adds the per-frame MD5
//                                   that 3dvo-dec prints
//   StreamEncode/<condition>/<seq>/threads:<n>  encodeSequence with Threads = n (frames/s)
//   GomDecode/quality-50[-noB]/<seq> the GOMs of the default Quality (with B meshes; -noB
//                                   without) through the GOM loop, from each GOM's decoded I
//                                   mesh: P meshes, B meshes, interpolation (vertex-frames/s)
//   PMeshBinsOnly/<condition>/<seq> the arithmetic decoding alone of PMeshDecode's payloads:
//                                   every bin, each with the context the P-mesh decoding used
//                                   for it (recorded once), decoded in a plain loop; no
//                                   octree, prediction or binarisation logic. What the bins
//                                   cost on this machine: a floor for PMeshDecode
//
// Conditions: d3dmc-lossless (MotionQuantStep 1, Lambda 0), d3dmc-lossy (MotionQuantStep 8,
// automatic Lambda), afxic (AFX-IC-style reference, MotionQuantStep 1), all on the sequence's
// 12-bit grid; and for PMeshDecode quality-50: the grid (fitted to the object), quantiser, Lambda
// and I-mesh step (IMeshQuantStep) that the default Quality (50) chooses for the sequence.
//
//   build/bin/pmesh_bench --benchmark_filter=PMeshDecode
#include <benchmark/benchmark.h>

#include <cstring>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "bench/bench_sequences.h"
#include "bitstream/pmesh_syntax.h"
#include "common/core/md5.h"
#include "decoder/gom_decoder.h"
#include "decoder/imesh_decoder.h"
#include "decoder/pmesh_decoder.h"
#include "decoder/stream_decoder.h"
#include "encoder/gom_coder.h"
#include "encoder/imesh_encoder.h"
#include "encoder/pmesh_encoder.h"
#include "encoder/quality.h"
#include "encoder/sequence_encoder.h"

using namespace tdvo;
using tdvo::bench::BenchSequence;

namespace {

constexpr int kGridBits = 12;

// A coding condition: its grid (GridBits, GridFit) and its P-mesh coding.
struct Condition {
  const char* name;
  PMeshMode mode;
  int gridBits;
  GridFit fit;
  int quantStep;
  double lambda;           // -1: automatic
  int iMeshQuantStep = 1;  // the I meshes' im_quant_step (IMeshQuantStep)
};
const Condition kConditions[] = {
    {"d3dmc-lossless", PMeshMode::kD3dmc, kGridBits, GridFit::kSequence, 1, 0},
    {"d3dmc-lossy", PMeshMode::kD3dmc, kGridBits, GridFit::kSequence, 8, -1},
    {"afxic", PMeshMode::kAfxic, kGridBits, GridFit::kSequence, 1, 0},
};

EncoderParams encoderParams(const Condition& c, const BenchSequence& s) {
  EncoderParams p;
  p.gridBits = c.gridBits;
  p.gridFit = c.fit;
  p.gomSize = s.gomSize;
  p.pmeshMode = c.mode;
  p.motionQuantStep = c.quantStep;
  p.lambda = c.lambda;
  p.iMeshQuantStep = c.iMeshQuantStep;
  return p;
}

// The frames of a sequence, loaded once on first use.
const std::vector<Mesh>& framesOf(const BenchSequence& s) {
  static std::map<std::string, std::vector<Mesh>> cache;
  std::vector<Mesh>& frames = cache[s.name];
  if (frames.empty()) frames = bench::loadFrames(s);
  return frames;
}

// A sequence quantised to a condition's grid, its frame 0 coded as an I mesh, and the other
// frames as targets in the I mesh's (decoded) vertex order. Built once per sequence and grid, on
// first use.
struct Gom {
  Grid grid;
  IMeshEncoding iMesh;
  GomTopology topology;
  std::vector<std::vector<Vec3i>> targets;  // frame f in GOM order; [0] is the decoded I mesh
  uint64_t vertices() const { return topology.numVertices; }
};

const Gom& gomOf(const BenchSequence& s, const Condition& c) {
  static std::map<std::string, std::unique_ptr<Gom>> cache;
  std::unique_ptr<Gom>& g = cache[s.name + "/" + std::to_string(c.gridBits) +
                                  (c.fit == GridFit::kObject ? "/object" : "/sequence") + "/" +
                                  std::to_string(c.iMeshQuantStep)];
  if (g) return *g;
  g = std::make_unique<Gom>();
  const std::vector<Mesh>& frames = framesOf(s);
  g->grid = gridForSequence(frames, c.gridBits, c.fit);
  const IntMesh first = g->grid.quantise(frames[0]);
  g->iMesh = encodeIMesh(first, g->grid.bits, 0, true, c.iMeshQuantStep);
  g->topology = GomTopology::build(g->iMesh.decoded);
  g->targets.push_back(g->iMesh.decoded.positions);
  for (size_t f = 1; f < frames.size(); ++f) {
    const IntMesh q = g->grid.quantise(frames[f]);
    std::vector<Vec3i> t(g->iMesh.inputIndex.size());
    for (size_t j = 0; j < t.size(); ++j)
      t[j] = q.positions[g->iMesh.inputIndex[j]];
    g->targets.push_back(std::move(t));
  }
  return *g;
}

// The sequence on the 12-bit grid, for the benchmarks that have no condition.
const Gom& gomOf(const BenchSequence& s) {
  return gomOf(s, kConditions[0]);
}

// The P-mesh coding of a condition on its grid (which may have more bits than GridBits).
PMeshParams pmeshParams(const Gom& g, const Condition& c) {
  PMeshParams p;
  p.gridBits = g.grid.bits;
  p.quantStep = c.quantStep;
  p.maxDepth = g.grid.bits;
  return p;
}

double lambdaOf(const Condition& c) {
  EncoderParams p;
  p.motionQuantStep = c.quantStep;
  p.lambda = c.lambda;
  return p.effectiveLambda();
}

// The P meshes of a sequence under a condition (closed loop), coded once on first use.
struct Coded {
  std::vector<std::vector<uint8_t>> payloads;  // [f] codes frame f from frame f - 1 (f >= 1)
  std::vector<std::vector<Vec3i>> previous;    // [f] the decoded frame f - 1
  uint64_t bins = 0;                           // CABAC bins of all payloads
};

const Coded& codedOf(const BenchSequence& s, const Condition& c) {
  static std::map<std::string, std::unique_ptr<Coded>> cache;
  std::unique_ptr<Coded>& coded = cache[s.name + "/" + c.name];
  if (coded) return *coded;
  coded = std::make_unique<Coded>();
  const Gom& g = gomOf(s, c);
  const PMeshParams params = pmeshParams(g, c);
  std::vector<Vec3i> previous = g.targets[0];
  coded->payloads.emplace_back();
  coded->previous.emplace_back();
  for (size_t f = 1; f < g.targets.size(); ++f) {
    PMeshEncoding e = c.mode == PMeshMode::kD3dmc
                          ? encodePMesh(g.topology, previous, g.targets[f], params, lambdaOf(c))
                          : encodeTemporalDpcm(previous, g.targets[f], params);
    coded->payloads.push_back(std::move(e.payload));
    coded->bins += e.bins;
    coded->previous.push_back(previous);
    previous = std::move(e.reconstruction);
  }
  return *coded;
}

void pmeshDecode(benchmark::State& state, const BenchSequence& s, const Condition& c) {
  const Gom& g = gomOf(s, c);
  const Coded& coded = codedOf(s, c);
  const PMeshParams params = pmeshParams(g, c);
  const std::string context = "bench";
  PMeshWorkspace work;
  std::vector<Vec3i> previous, current;
  uint64_t bytes = 0;
  for (const auto& p : coded.payloads)
    bytes += p.size();
  for (auto _ : state) {
    previous = g.targets[0];
    for (size_t f = 1; f < coded.payloads.size(); ++f) {
      const std::vector<uint8_t>& p = coded.payloads[f];
      if (c.mode == PMeshMode::kD3dmc)
        decodePMesh(p.data(), p.size(), g.topology, previous, params, context, work, current);
      else
        decodeTemporalDpcm(p.data(), p.size(), previous, params, context, current);
      previous.swap(current);
    }
    benchmark::DoNotOptimize(previous.data());
  }
  const int64_t vertexFrames = int64_t(g.vertices()) * int64_t(coded.payloads.size() - 1);
  state.SetItemsProcessed(int64_t(state.iterations()) * vertexFrames);
  state.counters["bits/vertex"] = 8.0 * double(bytes) / double(vertexFrames);
  state.counters["bins/vertex"] = double(coded.bins) / double(vertexFrames);
  state.counters["bins/s"] = benchmark::Counter(double(coded.bins) * double(state.iterations()),
                                                benchmark::Counter::kIsRate);
  state.SetLabel("vertex-frames/s");
}

// The Io of codePMesh / codeTemporalDpcm as CabacReaderIo reads, recording every bin it
// decodes: the context's offset from the payload's first context (the first context of
// PMeshContexts or TemporalDpcmContexts, which the first element of either payload uses),
// kBypass for a bypass bin, and the bin's value in bit 7. signedUeg is the UEGk binarisation of
// common/entropy/cabac.h bin by bin; the recorded decoding is checked against decodePMesh's output.
class RecordingReaderIo {
 public:
  static constexpr bool kReading = true;
  static constexpr uint8_t kBypass = 127;
  RecordingReaderIo(const std::vector<uint8_t>& payload, std::vector<uint8_t>& ops)
      : decoder_(payload.data(), payload.size()), ops_(ops) {}

  void bin(const char*, ContextModel& ctx, unsigned& value) { value = regular(ctx); }
  void signedUeg(const char*, ContextModel* ctxs, int numCtx, int k, uint32_t uCoff, int32_t& value,
                 int32_t) {
    uint32_t magnitude = 0;
    while (magnitude < uCoff && regular(ctxs[std::min<uint32_t>(magnitude, numCtx - 1)]))
      ++magnitude;
    if (magnitude == uCoff) {
      while (bypass()) {
        magnitude += 1u << k;
        ++k;
      }
      uint32_t suffix = 0;
      for (int i = 0; i < k; ++i)
        suffix = suffix << 1 | bypass();
      magnitude += suffix;
    }
    value = magnitude != 0 && bypass() ? -int32_t(magnitude) : int32_t(magnitude);
  }
  void signedUeg3(const char* const names[3], ContextModel* const ctxs[3], int numCtx, int k,
                  uint32_t uCoff, int32_t (&values)[3], int32_t maxAbs) {
    for (int c = 0; c < 3; ++c)
      signedUeg(names[c], ctxs[c], numCtx, k, uCoff, values[c], maxAbs);
  }
  void require(bool condition, const char* what) const {
    if (!condition) throw Error(std::string("bench recording: ") + what);
  }
  void require(bool condition, const std::string& what) const { require(condition, what.c_str()); }

 private:
  unsigned regular(ContextModel& ctx) {
    if (!base_) base_ = &ctx;
    const ptrdiff_t offset = &ctx - base_;
    require(offset >= 0 && offset < kBypass, "a context before the first or too far from it");
    const unsigned b = decoder_.decodeBin(ctx);
    ops_.push_back(uint8_t(offset | b << 7));
    return b;
  }
  unsigned bypass() {
    const unsigned b = decoder_.decodeBypass();
    ops_.push_back(uint8_t(kBypass | b << 7));
    return b;
  }

  CabacDecoder decoder_;
  std::vector<uint8_t>& ops_;
  const ContextModel* base_ = nullptr;
};

// Every bin of the P meshes of a sequence under a condition, recorded once on first use.
const std::vector<std::vector<uint8_t>>& binsOf(const BenchSequence& s, const Condition& c) {
  static std::map<std::string, std::vector<std::vector<uint8_t>>> cache;
  std::vector<std::vector<uint8_t>>& ops = cache[s.name + "/" + c.name];
  if (!ops.empty()) return ops;
  const Gom& g = gomOf(s, c);
  const Coded& coded = codedOf(s, c);
  const PMeshParams params = pmeshParams(g, c);
  ops.resize(coded.payloads.size());
  std::vector<Vec3i> previous = g.targets[0];
  for (size_t f = 1; f < coded.payloads.size(); ++f) {
    RecordingReaderIo io(coded.payloads[f], ops[f]);
    NoDecisions none;
    std::vector<Vec3i> recorded;
    if (c.mode == PMeshMode::kD3dmc) {
      PMeshWorkspace work;
      codePMesh(io, none, g.topology, previous, params, work, recorded);
    } else {
      codeTemporalDpcm(io, none, previous, params, recorded);
    }
    const std::vector<Vec3i> decoded =
        c.mode == PMeshMode::kD3dmc
            ? decodePMesh(coded.payloads[f], g.topology, previous, params, "bench")
            : decodeTemporalDpcm(coded.payloads[f], previous, params, "bench");
    if (recorded != decoded) throw Error("bench: the recording decoder disagrees with the decoder");
    previous = decoded;
  }
  return ops;
}

void pmeshBinsOnly(benchmark::State& state, const BenchSequence& s, const Condition& c) {
  const Gom& g = gomOf(s, c);
  const Coded& coded = codedOf(s, c);
  const std::vector<std::vector<uint8_t>>& ops = binsOf(s, c);
  uint64_t bins = 0;
  for (const auto& o : ops)
    bins += o.size();
  unsigned mismatch = 0;
  for (auto _ : state) {
    for (size_t f = 1; f < coded.payloads.size(); ++f) {
      ContextModel contexts[RecordingReaderIo::kBypass] = {};  // every context starts at state 0
      CabacDecoder decoder(coded.payloads[f].data(), coded.payloads[f].size());
      CabacDecoder::LocalEngine engine(decoder);
      for (const uint8_t op : ops[f]) {
        const unsigned slot = op & 127u;
        const unsigned bin = slot == RecordingReaderIo::kBypass ? engine.decodeBypass()
                                                                : engine.decodeBin(contexts[slot]);
        mismatch |= bin ^ (op >> 7);
      }
    }
    benchmark::DoNotOptimize(mismatch);
  }
  if (mismatch != 0) state.SkipWithError("the replayed bins differ from the recorded ones");
  const int64_t vertexFrames = int64_t(g.vertices()) * int64_t(coded.payloads.size() - 1);
  state.SetItemsProcessed(int64_t(state.iterations()) * vertexFrames);
  state.counters["bins/vertex"] = double(bins) / double(vertexFrames);
  state.counters["bins/s"] =
      benchmark::Counter(double(bins) * double(state.iterations()), benchmark::Counter::kIsRate);
  state.SetLabel("vertex-frames/s");
}

void pmeshEncode(benchmark::State& state, const BenchSequence& s, const Condition& c) {
  const Gom& g = gomOf(s, c);
  const Coded& coded = codedOf(s, c);
  const PMeshParams params = pmeshParams(g, c);
  const double lambda = lambdaOf(c);
  for (auto _ : state)
    for (size_t f = 1; f < coded.payloads.size(); ++f) {
      PMeshEncoding e =
          c.mode == PMeshMode::kD3dmc
              ? encodePMesh(g.topology, coded.previous[f], g.targets[f], params, lambda)
              : encodeTemporalDpcm(coded.previous[f], g.targets[f], params);
      benchmark::DoNotOptimize(e.payload.data());
    }
  state.SetItemsProcessed(int64_t(state.iterations()) * int64_t(g.vertices()) *
                          int64_t(coded.payloads.size() - 1));
  state.SetLabel("vertex-frames/s");
}

void topologyBuild(benchmark::State& state, const BenchSequence& s) {
  const Gom& g = gomOf(s);
  for (auto _ : state) {
    GomTopology t = GomTopology::build(g.iMesh.decoded);
    benchmark::DoNotOptimize(t.order.data());
  }
  state.SetItemsProcessed(int64_t(state.iterations()) * int64_t(g.vertices()));
  state.SetLabel("vertices/s");
}

void iMeshEncode(benchmark::State& state, const BenchSequence& s) {
  const Gom& g = gomOf(s);
  const IntMesh input = g.grid.quantise(framesOf(s)[0]);
  size_t bytes = 0;
  for (auto _ : state) {
    IMeshEncoding e = encodeIMesh(input, g.grid.bits, 0);
    bytes = e.payload.size();
    benchmark::DoNotOptimize(e.payload.data());
  }
  state.SetItemsProcessed(int64_t(state.iterations()) * int64_t(input.positions.size()));
  state.counters["bytes"] = double(bytes);
  state.SetLabel("vertices/s");
}

void iMeshDecode(benchmark::State& state, const BenchSequence& s) {
  const Gom& g = gomOf(s);
  for (auto _ : state) {
    IntMesh m = decodeIMesh(g.iMesh.payload, g.grid.bits, "bench");
    benchmark::DoNotOptimize(m.positions.data());
  }
  state.SetItemsProcessed(int64_t(state.iterations()) * int64_t(g.vertices()));
  state.counters["bytes"] = double(g.iMesh.payload.size());
  state.SetLabel("vertices/s");
}

// The whole stream of a sequence under a condition, encoded once on first use.
const std::vector<uint8_t>& streamOf(const BenchSequence& s, const Condition& c) {
  static std::map<std::string, std::vector<uint8_t>> cache;
  std::vector<uint8_t>& stream = cache[s.name + "/" + c.name];
  if (!stream.empty()) return stream;
  const Gom& g = gomOf(s, c);
  const std::vector<Mesh>& frames = framesOf(s);
  stream =
      encodeSequence(encoderParams(c, s), g.grid, frames, {}, [](int, const IntMesh&) {}).stream;
  return stream;
}

void streamDecode(benchmark::State& state, const BenchSequence& s, const Condition& c, bool md5) {
  const std::vector<uint8_t>& stream = streamOf(s, c);
  int64_t frames = 0, vertexFrames = 0;
  for (auto _ : state) {
    frames = vertexFrames = 0;
    StreamDecoder decoder(stream.data(), stream.size(), "bench.3dvo");
    decoder.decode([&](int frame, const IntMesh& mesh) {
      if (md5) benchmark::DoNotOptimize(geometryDigest(mesh));
      benchmark::DoNotOptimize(frame);
      ++frames;
      vertexFrames += int64_t(mesh.positions.size());
    });
  }
  state.SetItemsProcessed(int64_t(state.iterations()) * frames);
  state.counters["vertex-frames/s"] = benchmark::Counter(
      double(vertexFrames) * double(state.iterations()), benchmark::Counter::kIsRate);
  state.SetLabel("frames/s");
}

void streamEncode(benchmark::State& state, const BenchSequence& s, const Condition& c,
                  int threads) {
  const Gom& g = gomOf(s, c);
  EncoderParams params = encoderParams(c, s);
  params.threads = threads;
  for (auto _ : state) {
    EncodedSequence e = encodeSequence(params, g.grid, framesOf(s), {}, [](int, const IntMesh&) {});
    benchmark::DoNotOptimize(e.stream.data());
  }
  state.SetItemsProcessed(int64_t(state.iterations()) * int64_t(framesOf(s).size()));
  state.SetLabel("frames/s");
}

// The condition the default Quality (50) chooses for a sequence: the grid (fitted to the
// object), quantiser, Lambda and I-mesh step of resolveQuality(), found once per sequence on first
// use (its trial codes a few windows of the frames). Its P meshes are coded as every condition's
// are: every frame a P mesh of the one before (a keyframe subset only skips frames), closed loop.
const Condition& qualityCondition(const BenchSequence& s) {
  static std::map<std::string, Condition> cache;
  const auto found = cache.find(s.name);
  if (found != cache.end()) return found->second;
  const std::vector<Mesh>& frames = framesOf(s);
  FrameSource source;
  source.count = frames.size();
  source.read = [&frames](size_t k) { return frames[k]; };
  EncoderParams defaults;
  defaults.gomSize = s.gomSize;
  const EncoderParams p = resolveQuality(defaults, boundsOfSequence(frames), source,
                                         [](const std::string&) { return false; });
  const Condition c{"quality-50",      p.pmeshMode, p.gridBits,      p.gridFit,
                    p.motionQuantStep, p.lambda,    p.iMeshQuantStep};
  return cache.emplace(s.name, c).first->second;
}

void pmeshDecodeQuality(benchmark::State& state, const BenchSequence& s) {
  const Condition& c = qualityCondition(s);
  pmeshDecode(state, s, c);
  state.SetLabel("vertex-frames/s, GridBits " + std::to_string(c.gridBits) + " MotionQuantStep " +
                 std::to_string(c.quantStep) + " IMeshQuantStep " +
                 std::to_string(c.iMeshQuantStep));
}

// GomDecode/<variant>/<seq>: the geometry of every GOM (GOMSize of cfg/per-sequence) as the
// default Quality (50) codes it, decoded by the GOM loop (GomDecoder) from its first reference
// (the decoded I mesh, not timed): its P meshes and, with B meshes (the default), its B meshes.
// items_per_second = vertex-frames/s of the frames after each GOM's first. Variants: quality-50
// (the default: B meshes, BMeshGap 8), quality-50-noB (BMeshGap 0, every frame a keyframe).
struct CodedGoms {
  int gridBits = 0;
  std::vector<GomHeader> headers;
  std::vector<GomReference> firsts;
  std::vector<std::vector<std::vector<uint8_t>>> payloads;  // per GOM, in stream order
  int64_t vertexFrames = 0;
  uint64_t bytes = 0;
};

class ReplayUnits : public GomUnits {
 public:
  explicit ReplayUnits(const std::vector<std::vector<uint8_t>>& payloads) : payloads_(payloads) {}
  void iMesh(uint32_t, IntMesh&, std::string&) override {
    throw std::logic_error("bench: the GOM's I mesh is given");
  }
  PMeshPayload pMesh(uint32_t) override {
    const std::vector<uint8_t>& p = payloads_.at(next_++);
    return {p.data(), p.size(), "bench", nullptr};
  }

 private:
  const std::vector<std::vector<uint8_t>>& payloads_;
  size_t next_ = 0;
};

const CodedGoms& codedGomsOf(const BenchSequence& s, bool bMeshes) {
  static std::map<std::string, std::unique_ptr<CodedGoms>> cache;
  std::unique_ptr<CodedGoms>& coded = cache[s.name + (bMeshes ? "/b" : "/p")];
  if (coded) return *coded;
  coded = std::make_unique<CodedGoms>();
  const Condition& c = qualityCondition(s);
  EncoderParams params = encoderParams(c, s);
  params.bMeshGap = bMeshes ? kQualityBMeshGap : 0;
  const std::vector<Mesh>& frames = framesOf(s);
  const Grid grid = gridForSequence(frames, c.gridBits, c.fit);
  coded->gridBits = grid.bits;
  params.gridBits = grid.bits;
  for (size_t first = 0; first < frames.size(); first += size_t(s.gomSize)) {
    const size_t count = std::min(frames.size() - first, size_t(s.gomSize));
    const GomGeometry g =
        encodeGomGeometry(params, grid, first,
                          std::vector<Mesh>(frames.begin() + std::ptrdiff_t(first),
                                            frames.begin() + std::ptrdiff_t(first + count)),
                          [](size_t k) { return std::to_string(k); });
    std::vector<std::vector<uint8_t>> payloads;
    for (const GomGeometry::Unit& u : g.units) {
      ByteReader reader(u.payload.data(), u.payload.size(), "bench", 0);
      if (u.type == UnitType::kGomHeader) {
        GomHeader gh;
        transfer(reader, gh);
        coded->headers.push_back(gh);
      } else if (u.type == UnitType::kPMesh) {
        PMeshUnit pm;
        transfer(reader, pm);
        coded->bytes += pm.pm_cabac_payload.size();
        payloads.push_back(std::move(pm.pm_cabac_payload));
      }
    }
    const IntMesh& i = g.iMeshes[0].decoded;
    coded->firsts.push_back({i, std::make_shared<const GomTopology>(GomTopology::build(i))});
    coded->payloads.push_back(std::move(payloads));
    coded->vertexFrames += int64_t(i.positions.size()) * int64_t(count - 1);
  }
  return *coded;
}

void gomDecode(benchmark::State& state, const BenchSequence& s, bool bMeshes) {
  const CodedGoms& coded = codedGomsOf(s, bMeshes);
  GomDecoder decoder;
  for (auto _ : state) {
    for (size_t g = 0; g < coded.headers.size(); ++g) {
      ReplayUnits units(coded.payloads[g]);
      decoder.start(coded.headers[g], coded.gridBits, "bench", &coded.firsts[g]);
      while (!decoder.done())
        benchmark::DoNotOptimize(decoder.next(units).data());
    }
  }
  state.SetItemsProcessed(int64_t(state.iterations()) * coded.vertexFrames);
  state.counters["bits/vertex"] = 8.0 * double(coded.bytes) / double(coded.vertexFrames);
  const Condition& c = qualityCondition(s);
  state.SetLabel("vertex-frames/s, GridBits " + std::to_string(c.gridBits) + " MotionQuantStep " +
                 std::to_string(c.quantStep) + " IMeshQuantStep " +
                 std::to_string(c.iMeshQuantStep) +
                 (bMeshes ? ", B meshes: BMeshGap " + std::to_string(kQualityBMeshGap) +
                                " BMeshQuantStep " + std::to_string(2 * c.quantStep)
                          : ", every frame a keyframe"));
}

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  for (const BenchSequence& s : bench::benchSequences()) {
    const std::string seq = "/" + s.name;
    for (const Condition& c : kConditions)
      benchmark::RegisterBenchmark(("PMeshDecode/" + std::string(c.name) + seq).c_str(),
                                   pmeshDecode, s, c)
          ->Unit(benchmark::kMillisecond);
    benchmark::RegisterBenchmark(("PMeshDecode/quality-50" + seq).c_str(), pmeshDecodeQuality, s)
        ->Unit(benchmark::kMillisecond);
    benchmark::RegisterBenchmark(("GomDecode/quality-50" + seq).c_str(), gomDecode, s, true)
        ->Unit(benchmark::kMillisecond);
    benchmark::RegisterBenchmark(("GomDecode/quality-50-noB" + seq).c_str(), gomDecode, s, false)
        ->Unit(benchmark::kMillisecond);
    for (const Condition& c : kConditions)
      benchmark::RegisterBenchmark(("PMeshBinsOnly/" + std::string(c.name) + seq).c_str(),
                                   pmeshBinsOnly, s, c)
          ->Unit(benchmark::kMillisecond);
    for (const Condition& c : kConditions)
      benchmark::RegisterBenchmark(("PMeshEncode/" + std::string(c.name) + seq).c_str(),
                                   pmeshEncode, s, c)
          ->Unit(benchmark::kMillisecond);
    benchmark::RegisterBenchmark(("GomTopologyBuild" + seq).c_str(), topologyBuild, s)
        ->Unit(benchmark::kMillisecond);
    benchmark::RegisterBenchmark(("IMeshEncode" + seq).c_str(), iMeshEncode, s)
        ->Unit(benchmark::kMillisecond);
    benchmark::RegisterBenchmark(("IMeshDecode" + seq).c_str(), iMeshDecode, s)
        ->Unit(benchmark::kMillisecond);
    for (const Condition& c : kConditions) {
      benchmark::RegisterBenchmark(("StreamDecode/" + std::string(c.name) + seq).c_str(),
                                   streamDecode, s, c, false)
          ->Unit(benchmark::kMillisecond);
      benchmark::RegisterBenchmark(("StreamDecodeMd5/" + std::string(c.name) + seq).c_str(),
                                   streamDecode, s, c, true)
          ->Unit(benchmark::kMillisecond);
    }
    for (const Condition& c : kConditions)
      for (int threads : {1, 2})
        benchmark::RegisterBenchmark(
            ("StreamEncode/" + std::string(c.name) + seq + "/threads:" + std::to_string(threads))
                .c_str(),
            streamEncode, s, c, threads)
            ->Unit(benchmark::kMillisecond)
            ->UseRealTime();  // wall time: the point of threads
  }
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
