// Tests of the CABAC engine and binarisations (common/entropy/cabac.h).
#include "common/entropy/cabac.h"

#include <gtest/gtest.h>

#include <climits>
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include "common/core/error.h"

namespace tdvo {
namespace {

// ---- A bit-serial encoder written straight from the flowcharts of clause 9.3.4 (PutBit with
// firstBitFlag and bitsOutstanding). The real encoder must produce the same bytes.
class ReferenceEncoder {
 public:
  void bin(ContextModel& ctx, unsigned b) {
    const uint32_t lps = cabac::kRangeTabLPS[ctx.state][(range_ >> 6) & 3];
    range_ -= lps;
    if (b != ctx.mps) {
      low_ += range_;
      range_ = lps;
      if (ctx.state == 0) ctx.mps = 1 - ctx.mps;
      ctx.state = cabac::kTransIdxLPS[ctx.state];
    } else {
      ctx.state = cabac::kTransIdxMPS[ctx.state];
    }
    renorm();
  }
  void bypass(unsigned b) {
    low_ <<= 1;
    if (b) low_ += range_;
    if (low_ >= 1024) {
      putBit(1);
      low_ -= 1024;
    } else if (low_ < 512) {
      putBit(0);
    } else {
      low_ -= 512;
      ++outstanding_;
    }
  }
  void terminate(unsigned b) {
    range_ -= 2;
    if (!b) {
      renorm();
      return;
    }
    low_ += range_;
    range_ = 2;  // EncodeFlush
    renorm();
    putBit((low_ >> 9) & 1);
    bits_.push_back((low_ >> 8) & 1);
    bits_.push_back(1);
    while (bits_.size() % 8)
      bits_.push_back(0);
    low_ = 0;  // restart, as the coder under test does
    range_ = 510;
    first_ = true;
  }
  std::vector<uint8_t> bytes() const {
    std::vector<uint8_t> out(bits_.size() / 8, 0);
    for (size_t i = 0; i < bits_.size(); ++i)
      out[i / 8] |= uint8_t(bits_[i] << (7 - i % 8));
    return out;
  }

 private:
  void renorm() {
    while (range_ < 256) {
      if (low_ < 256) {
        putBit(0);
      } else if (low_ >= 512) {
        low_ -= 512;
        putBit(1);
      } else {
        low_ -= 256;
        ++outstanding_;
      }
      range_ <<= 1;
      low_ <<= 1;
    }
  }
  void putBit(int b) {
    if (first_) {
      first_ = false;
    } else {
      bits_.push_back(b);
    }
    for (; outstanding_ > 0; --outstanding_)
      bits_.push_back(1 - b);
  }
  uint32_t low_ = 0, range_ = 510;
  int outstanding_ = 0;
  bool first_ = true;
  std::vector<int> bits_;
};

// One coded symbol of a mixed test stream.
struct Op {
  enum Kind { kRegular, kBypass, kBypassBits, kTerminate } kind;
  int ctx;         // regular: context index; bypass bits: number of bits
  uint32_t value;  // the bin or bits
};

// 10^6 bins: mostly regular bins over 32 contexts with their own probabilities, plus bypass
// bins, multi-bit bypass, terminate 0 bins and three mid-stream terminate 1 bins.
std::vector<Op> makeMixedStream(std::mt19937& rng, std::vector<ContextModel>& initial) {
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  std::vector<double> p(32);
  initial.assign(32, ContextModel{});
  for (int i = 0; i < 32; ++i) {
    p[i] = uni(rng);
    if (i % 2) initial[i] = ContextModel::fromProbability(uni(rng));
  }
  std::vector<Op> ops;
  uint64_t bins = 0;
  while (bins < 1000000) {
    const uint32_t r = rng() % 1000;
    if (r < 800) {
      const int c = int(rng() % 32);
      ops.push_back({Op::kRegular, c, uni(rng) < p[c] ? 1u : 0u});
      bins += 1;
    } else if (r < 980) {
      ops.push_back({Op::kBypass, 0, uint32_t(rng() & 1)});
      bins += 1;
    } else if (r < 998) {
      const int n = int(rng() % 33);
      ops.push_back({Op::kBypassBits, n, n ? uint32_t(rng()) >> (32 - n) : 0});
      bins += uint64_t(n);
    } else {
      ops.push_back({Op::kTerminate, 0, 0});
      bins += 1;
    }
  }
  for (size_t at : {ops.size() / 4, ops.size() / 2, ops.size() * 3 / 4})
    ops.insert(ops.begin() + long(at), Op{Op::kTerminate, 0, 1});
  return ops;
}

std::vector<uint8_t> encodeOps(const std::vector<Op>& ops, std::vector<ContextModel> ctxs) {
  CabacEncoder enc;
  for (const Op& op : ops) {
    switch (op.kind) {
      case Op::kRegular:
        enc.encodeBin(ctxs[op.ctx], op.value);
        break;
      case Op::kBypass:
        enc.encodeBypass(op.value);
        break;
      case Op::kBypassBits:
        enc.encodeBypassBits(op.value, op.ctx);
        break;
      case Op::kTerminate:
        enc.encodeTerminate(op.value);
        break;
    }
  }
  return enc.finish();
}

TEST(Cabac, MixedRoundTrip) {
  std::mt19937 rng(12345);
  std::vector<ContextModel> initial;
  const std::vector<Op> ops = makeMixedStream(rng, initial);
  const std::vector<uint8_t> payload = encodeOps(ops, initial);

  std::vector<ContextModel> ctxs = initial;
  CabacDecoder dec(payload.data(), payload.size());
  size_t mismatches = 0;
  for (const Op& op : ops) {
    uint32_t got = 0;
    switch (op.kind) {
      case Op::kRegular:
        got = dec.decodeBin(ctxs[op.ctx]);
        break;
      case Op::kBypass:
        got = dec.decodeBypass();
        break;
      case Op::kBypassBits:
        got = dec.decodeBypassBits(op.ctx);
        break;
      case Op::kTerminate:
        got = dec.decodeTerminate();
        break;
    }
    mismatches += got != op.value;
  }
  EXPECT_EQ(mismatches, 0u);
  EXPECT_EQ(dec.decodeTerminate(), 1u);  // the bin added by finish()
  EXPECT_FALSE(dec.overrun());
  EXPECT_EQ(dec.bytesConsumed(), payload.size());
}

TEST(Cabac, MatchesBitSerialReferenceEncoder) {
  std::mt19937 rng(777);
  std::vector<ContextModel> initial;
  std::vector<Op> ops = makeMixedStream(rng, initial);
  ops.resize(200000);
  std::vector<ContextModel> ctxs = initial;
  ReferenceEncoder ref;
  for (const Op& op : ops) {
    switch (op.kind) {
      case Op::kRegular:
        ref.bin(ctxs[op.ctx], op.value);
        break;
      case Op::kBypass:
        ref.bypass(op.value);
        break;
      case Op::kBypassBits:
        for (int i = op.ctx - 1; i >= 0; --i)
          ref.bypass((op.value >> i) & 1);
        break;
      case Op::kTerminate:
        ref.terminate(op.value);
        break;
    }
  }
  ref.terminate(1);
  EXPECT_EQ(encodeOps(ops, initial), ref.bytes());
}

// Coding efficiency on an i.i.d. source, p(1) = 0.05, one adaptive context.
// Two separate costs: (1) the arithmetic coder itself, measured against the ideal code length
// of the probabilities it was given (sum of -log2 p over the context's state sequence), must be
// within 0.5%; (2) the overall ratio to n * H(p). One might expect (2) within 3%, but the
// H.264 state machine adapts with a memory of only 1 / (1 - alpha) ~ 20 bins, so its estimate
// of p = 0.05 fluctuates by about p itself, and that costs ~5% at this p even for an ideal
// coder (a non-adapting context at the nearest state costs 0.2%). (2) is therefore checked
// against 1.065, which a wrong state transition or a coder leak would still exceed.
TEST(Cabac, CompressesNearEntropy) {
  const int n = 1000000;
  const double p = 0.05;
  std::mt19937 rng(2024);
  std::bernoulli_distribution source(p);
  std::vector<uint8_t> bins(n);
  for (auto& b : bins)
    b = source(rng);

  CabacEncoder enc;
  ContextModel ctx = ContextModel::equiprobable();
  double idealBits = 0;
  for (uint8_t b : bins) {
    const double p1 = ctx.probabilityOne();
    idealBits -= std::log2(b ? p1 : 1 - p1);
    enc.encodeBin(ctx, b);
  }
  const std::vector<uint8_t> payload = enc.finish();

  const double entropy = -p * std::log2(p) - (1 - p) * std::log2(1 - p);
  const double bits = double(payload.size()) * 8;
  const double ratio = bits / (n * entropy);
  std::printf("p=%.2f: %zu bytes; bits / (n*H) = %.4f; bits / ideal(state sequence) = %.4f\n", p,
              payload.size(), ratio, bits / idealBits);
  EXPECT_LT(bits / idealBits, 1.005);
  EXPECT_GT(bits / idealBits, 0.995);
  EXPECT_LT(ratio, 1.065);
  EXPECT_GT(ratio, 1.0);

  CabacDecoder dec(payload.data(), payload.size());
  ContextModel dctx = ContextModel::equiprobable();
  int mismatches = 0;
  for (uint8_t b : bins)
    mismatches += dec.decodeBin(dctx) != b;
  EXPECT_EQ(mismatches, 0);
  EXPECT_EQ(dec.decodeTerminate(), 1u);
  EXPECT_FALSE(dec.overrun());
}

// Issue 3, acceptance 1: an i.i.d. source with p(1) = 0.05 coded within 3% of its binary
// entropy. This is the engine's own efficiency: the context is held at the state that
// represents p (ContextModel::fromProbability), i.e. re-armed before every bin, so the only
// costs are the 64-state quantisation of p and the 9-bit range arithmetic. The adaptive
// estimator's extra cost is measured separately above (CompressesNearEntropy).
TEST(Cabac, KnownProbabilityCodesWithinThreePercentOfEntropy) {
  const int n = 1000000;
  const double p = 0.05;
  std::mt19937 rng(77);
  std::bernoulli_distribution source(p);
  std::vector<uint8_t> bins(n);
  for (auto& b : bins)
    b = source(rng);
  const ContextModel known = ContextModel::fromProbability(p);
  CabacEncoder enc;
  for (uint8_t b : bins) {
    ContextModel ctx = known;
    enc.encodeBin(ctx, b);
  }
  const std::vector<uint8_t> payload = enc.finish();
  const double entropy = -p * std::log2(p) - (1 - p) * std::log2(1 - p);
  const double ratio = double(payload.size()) * 8 / (n * entropy);
  std::printf("p=%.2f, context at state %d: bits / (n*H) = %.4f\n", p, known.state, ratio);
  EXPECT_NEAR(ratio, 1.0, 0.03);  // the sample's own ones may fall below n * p

  CabacDecoder dec(payload.data(), payload.size());
  int mismatches = 0;
  for (uint8_t b : bins) {
    ContextModel ctx = known;
    mismatches += dec.decodeBin(ctx) != b;
  }
  EXPECT_EQ(mismatches, 0);
  EXPECT_EQ(dec.decodeTerminate(), 1u);
}

// Values to try for a binarisation with a cutoff: small, around the cutoff, around powers of
// two, and random large values up to 2^24.
std::vector<uint32_t> testValues(uint32_t cutoff, std::mt19937& rng) {
  std::vector<uint32_t> v = {0, 1, 2, 3, 7, 8, 9, 15, 16, 17, 1u << 24};
  for (int d = -2; d <= 2; ++d)
    if (int64_t(cutoff) + d >= 0) v.push_back(uint32_t(int64_t(cutoff) + d));
  for (int b = 2; b <= 24; ++b) {
    v.push_back((1u << b) - 1);
    v.push_back(1u << b);
  }
  for (int i = 0; i < 200; ++i)
    v.push_back(rng() % (1u << 24));
  return v;
}

TEST(Cabac, BinarisationsRoundTrip) {
  std::mt19937 rng(99);
  struct Ueg {
    int k;
    uint32_t uCoff;
  };
  const Ueg uegs[] = {{3, 9}, {0, 14}, {0, 0}, {5, 1}};
  const int egOrders[] = {0, 1, 3, 7, 31};
  const uint32_t tuMax[] = {1, 2, 14, 100};

  CabacEncoder enc;
  ContextModel ectx[8];
  std::vector<uint32_t> unaryVals, egVals, uegVals;
  std::vector<int32_t> signedVals = {0, -1, 1, -9, 9, -10, 10, INT32_MIN, INT32_MAX, -(1 << 24)};
  for (uint32_t v = 0; v < 40; ++v)
    unaryVals.push_back(v);
  unaryVals.push_back(300);
  for (uint32_t v : testValues(9, rng))
    signedVals.push_back(rng() & 1 ? -int32_t(v) : int32_t(v));
  egVals = testValues(14, rng);
  egVals.push_back(UINT32_MAX);
  egVals.push_back(UINT32_MAX - 1);

  for (uint32_t v : unaryVals)
    encodeUnary(enc, ectx, 3, v);
  for (uint32_t cMax : tuMax)
    for (uint32_t v = 0; v <= cMax; ++v)
      encodeTruncatedUnary(enc, ectx + 3, 2, v, cMax);
  for (int k : egOrders)
    for (uint32_t v : egVals)
      encodeExpGolombBypass(enc, v, k);
  for (const Ueg& u : uegs)
    for (uint32_t v : egVals)
      encodeUEGk(enc, ectx + 5, 2, v, u.k, u.uCoff);
  for (int32_t v : signedVals)
    encodeSignedUEGk(enc, ectx + 7, 1, v, 3, 9);
  const std::vector<uint8_t> payload = enc.finish();

  CabacDecoder dec(payload.data(), payload.size());
  ContextModel dctx[8];
  for (uint32_t v : unaryVals)
    ASSERT_EQ(decodeUnary(dec, dctx, 3, 1000), v);
  for (uint32_t cMax : tuMax)
    for (uint32_t v = 0; v <= cMax; ++v)
      ASSERT_EQ(decodeTruncatedUnary(dec, dctx + 3, 2, cMax), v);
  for (int k : egOrders)
    for (uint32_t v : egVals)
      ASSERT_EQ(decodeExpGolombBypass(dec, k), v) << "k=" << k;
  for (const Ueg& u : uegs)
    for (uint32_t v : egVals)
      ASSERT_EQ(decodeUEGk(dec, dctx + 5, 2, u.k, u.uCoff), v);
  for (int32_t v : signedVals)
    ASSERT_EQ(decodeSignedUEGk(dec, dctx + 7, 1, 3, 9), v);
  EXPECT_EQ(dec.decodeTerminate(), 1u);
  EXPECT_FALSE(dec.overrun());
}

TEST(Cabac, UnaryAboveMaximumThrows) {
  CabacEncoder enc;
  ContextModel ctx;
  encodeUnary(enc, &ctx, 1, 10);
  const std::vector<uint8_t> payload = enc.finish();
  CabacDecoder dec(payload.data(), payload.size());
  ContextModel dctx;
  EXPECT_THROW(decodeUnary(dec, &dctx, 1, 5), Error);
}

// Decodes a bit of everything; corrupt data may throw Error but must not hang or crash.
void decodeEverything(const std::vector<uint8_t>& data) {
  CabacDecoder dec(data.data(), data.size());
  ContextModel ctxs[4];
  try {
    for (int i = 0; i < 200; ++i) {
      dec.decodeBin(ctxs[i % 4]);
      dec.decodeBypass();
      dec.decodeBypassBits(i % 33);
      decodeUnary(dec, ctxs, 2, UINT32_MAX);
      decodeTruncatedUnary(dec, ctxs + 2, 2, UINT32_MAX);
      decodeExpGolombBypass(dec, i % 8);
      decodeSignedUEGk(dec, ctxs, 4, 3, 9);
      dec.decodeTerminate();
    }
  } catch (const Error&) {
  }
}

// ---- A bit-serial decoder written straight from the flowcharts of clause 9.3.3.2
// (DecodeDecision, RenormD, DecodeBypass, DecodeTerminate) reading one bit at a time, zeros past
// the end. The real decoder (registers in local variables, several bytes per refill, the LPS
// range picked from a packed row) must decode the same bins from any bytes.
class ReferenceDecoder {
 public:
  explicit ReferenceDecoder(const std::vector<uint8_t>& data) : data_(data) {
    offset_ = readBits(9);
  }
  unsigned bin(ContextModel& ctx) {
    const uint32_t lps = cabac::kRangeTabLPS[ctx.state][(range_ >> 6) & 3];
    range_ -= lps;
    unsigned b;
    if (offset_ >= range_) {
      b = 1u - ctx.mps;
      offset_ -= range_;
      range_ = lps;
      if (ctx.state == 0) ctx.mps = uint8_t(1 - ctx.mps);
      ctx.state = cabac::kTransIdxLPS[ctx.state];
    } else {
      b = ctx.mps;
      ctx.state = cabac::kTransIdxMPS[ctx.state];
    }
    while (range_ < 256) {
      range_ <<= 1;
      offset_ = (offset_ << 1) | readBits(1);
    }
    return b;
  }
  unsigned bypass() {
    offset_ = (offset_ << 1) | readBits(1);
    if (offset_ >= range_) {
      offset_ -= range_;
      return 1;
    }
    return 0;
  }
  unsigned terminate() {
    range_ -= 2;
    if (offset_ >= range_) return 1;  // the caller stops comparing here
    while (range_ < 256) {
      range_ <<= 1;
      offset_ = (offset_ << 1) | readBits(1);
    }
    return 0;
  }
  bool overrun() const { return bitsRead_ > 8 * data_.size(); }

 private:
  uint32_t readBits(int n) {
    uint32_t v = 0;
    for (int i = 0; i < n; ++i, ++bitsRead_) {
      const size_t byte = bitsRead_ / 8;
      const uint32_t bit = byte < data_.size() ? (data_[byte] >> (7 - bitsRead_ % 8)) & 1 : 0;
      v = (v << 1) | bit;
    }
    return v;
  }
  const std::vector<uint8_t>& data_;
  uint32_t range_ = 510, offset_ = 0;
  size_t bitsRead_ = 0;
};

TEST(Cabac, DecoderMatchesBitSerialReferenceDecoder) {
  std::mt19937 rng(2024);
  for (int trial = 0; trial < 3000; ++trial) {
    // Random bytes of every kind and length, from shorter than the decoder's 8-byte reads.
    std::vector<uint8_t> data(trial < 100 ? trial % 20 : rng() % 400);
    const int fill = trial % 4;
    for (auto& b : data)
      b = fill == 0 ? uint8_t(rng()) : fill == 1 ? 0 : fill == 2 ? 0xFF : uint8_t(rng() % 3);
    // A first 9 bits of 510 or 511 would start the offset at or above the range, which no
    // encoder makes and where the standard's 9-bit register and the decoder's wider one part
    // (both without undefined behaviour); from below the range, it stays below.
    if (!data.empty()) data[0] &= 0xFE;
    ContextModel real[6], ref[6];
    for (int i = 0; i < 6; ++i)
      real[i] = ref[i] = ContextModel::fromProbability(double(rng() % 101) / 100.0);
    CabacDecoder dec(data.data(), data.size());
    ReferenceDecoder reference(data);
    const int ops = 50 + int(rng() % 3000);
    for (int op = 0; op < ops; ++op) {
      const uint32_t kind = rng() % 100;
      if (kind < 70) {
        const int c = int(rng() % 6);
        ASSERT_EQ(dec.decodeBin(real[c]), reference.bin(ref[c])) << "trial " << trial;
        ASSERT_EQ(real[c].state, ref[c].state);
        ASSERT_EQ(real[c].mps, ref[c].mps);
      } else if (kind < 90) {
        ASSERT_EQ(dec.decodeBypass(), reference.bypass()) << "trial " << trial;
      } else if (kind < 99) {
        const int n = int(rng() % 33);
        uint32_t expected = 0;
        for (int i = 0; i < n; ++i)
          expected = (expected << 1) | reference.bypass();
        ASSERT_EQ(dec.decodeBypassBits(n), expected) << "trial " << trial;
      } else {
        const unsigned t = reference.terminate();
        ASSERT_EQ(dec.decodeTerminate(), t) << "trial " << trial;
        if (t) break;  // the reference does not model the next codeword
      }
      ASSERT_EQ(dec.overrun(), reference.overrun()) << "trial " << trial << ", op " << op;
    }
  }
}

TEST(Cabac, GarbageAndTruncatedInputTerminate) {
  std::mt19937 rng(4242);
  for (int trial = 0; trial < 2000; ++trial) {
    std::vector<uint8_t> data(rng() % 80);
    const int fill = trial % 4;  // random, all zeros, all ones, sparse
    for (auto& b : data)
      b = fill == 0 ? uint8_t(rng()) : fill == 1 ? 0 : fill == 2 ? 0xFF : uint8_t(rng() % 3);
    decodeEverything(data);
  }
  std::vector<ContextModel> initial;
  std::vector<Op> ops = makeMixedStream(rng, initial);
  ops.resize(3000);
  const std::vector<uint8_t> payload = encodeOps(ops, initial);
  for (size_t len = 0; len < payload.size(); ++len)
    decodeEverything(std::vector<uint8_t>(payload.begin(), payload.begin() + long(len)));
}

TEST(Cabac, ExpGolombOnAllOnesThrows) {
  const std::vector<uint8_t> ones(64, 0xFF);
  for (int k : {0, 3, 31}) {
    CabacDecoder dec(ones.data(), ones.size());
    EXPECT_THROW(decodeExpGolombBypass(dec, k), Error) << "k=" << k;
  }
}

TEST(Cabac, LongUnaryRunOnZerosStopsAtEnd) {
  // A context confident in 1 decodes ones from zero bytes; the loop must stop at the end of
  // the payload instead of running to maxValue = 2^32 - 1.
  const std::vector<uint8_t> zeros(16, 0);
  CabacDecoder dec(zeros.data(), zeros.size());
  ContextModel ctx = ContextModel::fromProbability(0.999);
  EXPECT_THROW(decodeUnary(dec, &ctx, 1, UINT32_MAX), Error);
  EXPECT_TRUE(dec.overrun());
  EXPECT_LT(dec.bytesConsumed(), zeros.size() + 16);  // stopped soon after the end
}

TEST(Cabac, OverrunIsReportedAndSticky) {
  CabacEncoder enc;
  for (int i = 0; i < 1000; ++i)
    enc.encodeBypass(i % 3 == 0);
  const std::vector<uint8_t> payload = enc.finish();

  {  // Complete payload: no overrun up to the final terminate bin, overrun after it.
    CabacDecoder dec(payload.data(), payload.size());
    for (int i = 0; i < 1000; ++i)
      ASSERT_EQ(dec.decodeBypass(), unsigned(i % 3 == 0));
    EXPECT_EQ(dec.decodeTerminate(), 1u);
    EXPECT_FALSE(dec.overrun());
    EXPECT_EQ(dec.bytesConsumed(), payload.size());
    ContextModel ctx;
    dec.decodeBin(ctx);
    EXPECT_TRUE(dec.overrun());
  }
  {  // Truncated by one byte: bypass bins use one bit each, so the end is crossed for sure.
    CabacDecoder dec(payload.data(), payload.size() - 1);
    for (int i = 0; i < 1000; ++i)
      dec.decodeBypass();
    dec.decodeTerminate();
    EXPECT_TRUE(dec.overrun());
    dec.decodeBypassBits(0);
    EXPECT_TRUE(dec.overrun());  // sticky
  }
  {  // Empty payload: the initial 9 bits already lie beyond the end once used.
    CabacDecoder dec(nullptr, 0);
    EXPECT_EQ(dec.decodeBypass(), 0u);
    EXPECT_TRUE(dec.overrun());
  }
}

TEST(Cabac, EmptyAndConcatenatedCodewords) {
  CabacEncoder enc;
  const std::vector<uint8_t> empty = enc.finish();
  EXPECT_EQ(empty.size(), 2u);  // a lone terminate bin: 9 bits, padded
  CabacDecoder dec0(empty.data(), empty.size());
  EXPECT_EQ(dec0.decodeTerminate(), 1u);
  EXPECT_FALSE(dec0.overrun());

  // encodeTerminate(1) followed by finish() must not append an empty codeword.
  ContextModel ctx;
  enc.encodeBin(ctx, 1);
  enc.encodeTerminate(1);
  const size_t firstLength = enc.bytesWritten();
  enc.encodeBin(ctx, 0);
  enc.encodeTerminate(1);
  const std::vector<uint8_t> two = enc.finish();
  ContextModel dctx;
  CabacDecoder dec(two.data(), two.size());
  EXPECT_EQ(dec.decodeBin(dctx), 1u);
  EXPECT_EQ(dec.decodeTerminate(), 1u);
  EXPECT_EQ(dec.codewordEnd(), firstLength);
  EXPECT_EQ(dec.decodeBin(dctx), 0u);
  EXPECT_EQ(dec.decodeTerminate(), 1u);
  EXPECT_EQ(dec.codewordEnd(), two.size());
  EXPECT_EQ(dec.bytesConsumed(), two.size());
  EXPECT_FALSE(dec.overrun());
}

TEST(Cabac, Deterministic) {
  std::mt19937 rng(5);
  std::vector<ContextModel> initial;
  std::vector<Op> ops = makeMixedStream(rng, initial);
  ops.resize(100000);
  const std::vector<uint8_t> a = encodeOps(ops, initial);
  const std::vector<uint8_t> b = encodeOps(ops, initial);
  EXPECT_FALSE(a.empty());
  EXPECT_EQ(a, b);
  // The same encoder gives the same bytes again after finish().
  CabacEncoder enc;
  ContextModel c1, c2;
  for (int i = 0; i < 5000; ++i)
    enc.encodeBin(c1, i % 7 == 0);
  const std::vector<uint8_t> first = enc.finish();
  for (int i = 0; i < 5000; ++i)
    enc.encodeBin(c2, i % 7 == 0);
  EXPECT_EQ(enc.finish(), first);
}

TEST(Cabac, ContextFromProbability) {
  EXPECT_EQ(ContextModel::fromProbability(0.5).state, 0);
  const ContextModel high = ContextModel::fromProbability(0.95);
  EXPECT_EQ(high.mps, 1);
  EXPECT_NEAR(high.probabilityOne(), 0.95, 0.005);
  const ContextModel low = ContextModel::fromProbability(0.0);
  EXPECT_EQ(low.state, 62);
  EXPECT_EQ(low.mps, 0);
  EXPECT_EQ(ContextModel::fromProbability(1.0).mps, 1);
  EXPECT_EQ(ContextModel::fromProbability(std::nan("")).state, 0);
  for (int s = 0; s < 63; ++s) {
    ContextModel c;
    c.state = uint8_t(s);
    EXPECT_EQ(ContextModel::fromProbability(c.probabilityOne()).state, s);
  }
}

// Guards against a typo in the transcribed tables. The standard derived them from the state
// model: rangeTabLPS[s][q] ~ p(s) * (middle of range quarter q), capped at 128 so that the LPS
// never gets more than half of the smallest range; transIdxLPS[s] ~ the state nearest to
// alpha * p(s) + (1 - alpha). Every entry is within 1 of that, so any wrong digit shows.
TEST(Cabac, TablesAreConsistentWithTheStateModel) {
  const double alpha = std::exp(std::log(0.01875 / 0.5) / 63);
  for (int s = 0; s < 63; ++s) {
    const double p = ContextModel::lpsProbability(s);
    for (int q = 0; q < 4; ++q) {
      double predicted = p * (288 + 64 * q);
      if (q == 0 && predicted > 128) predicted = 128;
      EXPECT_NEAR(cabac::kRangeTabLPS[s][q], predicted, 1.0) << "state " << s << ", q " << q;
    }
    EXPECT_EQ(cabac::kTransIdxMPS[s], s < 62 ? s + 1 : 62);
    const double after = alpha * p + (1 - alpha);
    EXPECT_NEAR(cabac::kTransIdxLPS[s], std::log(after / 0.5) / std::log(alpha), 1.0) << s;
  }
  for (int q = 0; q < 4; ++q)
    EXPECT_EQ(cabac::kRangeTabLPS[63][q], 2);
  EXPECT_EQ(cabac::kTransIdxLPS[63], 63);
  EXPECT_EQ(cabac::kTransIdxMPS[63], 63);
  // Off-by-one slips fit within the tolerance above; these position-weighted sums (taken from
  // the tables after checking them against two independent H.264 implementations) do not.
  uint64_t rangeSum = 0, lpsSum = 0;
  for (int i = 0; i < 256; ++i)
    rangeSum += uint64_t(i + 1) * cabac::kRangeTabLPS[i / 4][i % 4];
  for (int i = 0; i < 64; ++i)
    lpsSum += uint64_t(i + 1) * cabac::kTransIdxLPS[i];
  EXPECT_EQ(rangeSum, 985645u);
  EXPECT_EQ(lpsSum, 61354u);
}

}  // namespace
}  // namespace tdvo
