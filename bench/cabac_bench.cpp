// Throughput of the CABAC engine (common/entropy/cabac.h) in bins per second (items_per_second).
//   Regular/<p%>: context-coded i.i.d. bins with P(1) = p% through one adaptive context;
//                 10% is the skewed case that matters, 50% is the branch-predictor worst case.
//   Bypass:       one encodeBypass/decodeBypass call per bin.
//   BypassBits8:  8 bypass bins per encodeBypassBits/decodeBypassBits call.
// Each iteration codes or decodes a whole payload of kBins bins, including construction and
// finish(), so the numbers include per-payload overhead the way a codec would see it.
#include <benchmark/benchmark.h>

#include <cstdint>
#include <random>
#include <vector>

#include "common/entropy/cabac.h"

namespace {

constexpr int kBins = 1 << 20;

std::vector<uint8_t> randomBins(double pOne, uint32_t seed) {
  std::mt19937 rng(seed);
  std::bernoulli_distribution source(pOne);
  std::vector<uint8_t> bins(kBins);
  for (auto& b : bins)
    b = source(rng) ? 1 : 0;
  return bins;
}

std::vector<uint8_t> encodeRegular(const std::vector<uint8_t>& bins) {
  tdvo::CabacEncoder enc;
  tdvo::ContextModel ctx;
  for (uint8_t b : bins)
    enc.encodeBin(ctx, b);
  return enc.finish();
}

void BM_EncodeRegular(benchmark::State& state) {
  const std::vector<uint8_t> bins = randomBins(state.range(0) / 100.0, 1);
  for (auto _ : state) {
    std::vector<uint8_t> payload = encodeRegular(bins);
    benchmark::DoNotOptimize(payload.data());
  }
  state.SetItemsProcessed(int64_t(state.iterations()) * kBins);
}

void BM_DecodeRegular(benchmark::State& state) {
  const std::vector<uint8_t> payload = encodeRegular(randomBins(state.range(0) / 100.0, 1));
  for (auto _ : state) {
    tdvo::CabacDecoder dec(payload.data(), payload.size());
    tdvo::ContextModel ctx;
    unsigned ones = 0;
    for (int i = 0; i < kBins; ++i)
      ones += dec.decodeBin(ctx);
    benchmark::DoNotOptimize(ones);
  }
  state.SetItemsProcessed(int64_t(state.iterations()) * kBins);
}

void BM_EncodeBypass(benchmark::State& state) {
  const std::vector<uint8_t> bins = randomBins(0.5, 2);
  for (auto _ : state) {
    tdvo::CabacEncoder enc;
    for (uint8_t b : bins)
      enc.encodeBypass(b);
    std::vector<uint8_t> payload = enc.finish();
    benchmark::DoNotOptimize(payload.data());
  }
  state.SetItemsProcessed(int64_t(state.iterations()) * kBins);
}

void BM_DecodeBypass(benchmark::State& state) {
  tdvo::CabacEncoder enc;
  for (uint8_t b : randomBins(0.5, 2))
    enc.encodeBypass(b);
  const std::vector<uint8_t> payload = enc.finish();
  for (auto _ : state) {
    tdvo::CabacDecoder dec(payload.data(), payload.size());
    unsigned ones = 0;
    for (int i = 0; i < kBins; ++i)
      ones += dec.decodeBypass();
    benchmark::DoNotOptimize(ones);
  }
  state.SetItemsProcessed(int64_t(state.iterations()) * kBins);
}

void BM_EncodeBypassBits8(benchmark::State& state) {
  std::vector<uint32_t> values(kBins / 8);
  for (size_t i = 0; i < values.size(); ++i)
    values[i] = uint32_t(i * 2654435761u) >> 24;
  for (auto _ : state) {
    tdvo::CabacEncoder enc;
    for (uint32_t v : values)
      enc.encodeBypassBits(v, 8);
    std::vector<uint8_t> payload = enc.finish();
    benchmark::DoNotOptimize(payload.data());
  }
  state.SetItemsProcessed(int64_t(state.iterations()) * kBins);
}

void BM_DecodeBypassBits8(benchmark::State& state) {
  tdvo::CabacEncoder enc;
  for (int i = 0; i < kBins / 8; ++i)
    enc.encodeBypassBits(uint32_t(i * 2654435761u) >> 24, 8);
  const std::vector<uint8_t> payload = enc.finish();
  for (auto _ : state) {
    tdvo::CabacDecoder dec(payload.data(), payload.size());
    uint32_t sum = 0;
    for (int i = 0; i < kBins / 8; ++i)
      sum += dec.decodeBypassBits(8);
    benchmark::DoNotOptimize(sum);
  }
  state.SetItemsProcessed(int64_t(state.iterations()) * kBins);
}

BENCHMARK(BM_EncodeRegular)->Name("Encode/Regular")->Arg(10)->Arg(50);
BENCHMARK(BM_DecodeRegular)->Name("Decode/Regular")->Arg(10)->Arg(50);
BENCHMARK(BM_EncodeBypass)->Name("Encode/Bypass");
BENCHMARK(BM_DecodeBypass)->Name("Decode/Bypass");
BENCHMARK(BM_EncodeBypassBits8)->Name("Encode/BypassBits8");
BENCHMARK(BM_DecodeBypassBits8)->Name("Decode/BypassBits8");

}  // namespace

BENCHMARK_MAIN();
