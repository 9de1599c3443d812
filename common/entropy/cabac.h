// CABAC: the context-adaptive binary arithmetic coder of H.264/AVC (ITU-T H.264 clause 9.3),
// used by 3DVO for all entropy-coded syntax, plus the binarisations built on top of it.
//
// Engine. A 9-bit range register (initially 510) and a low/offset register, the 64-state
// probability tables of clause 9.3.3.2 (common/entropy/cabac_tables.h) and three kinds of bins:
//   * regular bins (encodeBin/decodeBin) are coded with an adaptive ContextModel, which the
//     call updates (clause 9.3.3.2.1);
//   * bypass bins (encodeBypass/decodeBypass) are coded with probability 1/2 and cost exactly
//     one bit (clause 9.3.3.2.3);
//   * terminate bins (encodeTerminate/decodeTerminate) use the fixed LPS width 2 (clause
//     9.3.3.2.2.3). Bin 0 costs almost nothing and means "not finished"; bin 1 ends the
//     arithmetic codeword.
// The encoder writes exactly the bit string that the standard's encoder (clause 9.3.4, with
// PutBit/bitsOutstanding) writes; carries are resolved on whole bytes instead of single bits.
//
// Termination and flushing. encodeTerminate(1) performs the standard's EncodeFlush (clause
// 9.3.4.5): the last bit it writes is a 1 (it doubles as H.264's rbsp_stop_one_bit), after which
// the encoder pads with zero bits to the next byte boundary, so each codeword is a
// self-contained, byte-aligned run of bytes. The encoder then restarts (range 510, low 0, as
// clause 9.3.1.2 does after I_PCM samples) and further bins start a new codeword in the next
// byte. Contexts are owned by the caller and are not touched by termination.
// finish() ends the current codeword with encodeTerminate(1) (skipped when the current codeword
// is empty because the last call already was encodeTerminate(1)) and returns all bytes written.
//
// The decoder mirrors this: when decodeTerminate() returns 1 it has consumed exactly the
// codeword; it skips the zero padding and, if payload bytes remain, starts decoding the next
// codeword there (which loads that codeword's first 9 bits). codewordEnd() then gives the byte
// offset where the closed codeword ended; after the final one it equals the payload size.
//
// Overrun. The decoder never reads outside [data, data + size). Bits past the end read as
// zeros and set the sticky overrun() flag once such a bit has actually been used (the decoder's
// internal read-ahead does not count). Decoding a well-formed payload up to and including its
// final terminate bin never sets the flag; decoding any bin after that final bin always does.
// Callers check overrun() once per unit instead of after every bin. Garbage input never causes
// undefined behaviour or unbounded loops: it just decodes to garbage bins. The binarisation
// decoders below throw tdvo::Error where a corrupt stream would otherwise produce an
// out-of-range value or a very long loop.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <vector>

#include "common/entropy/cabac_tables.h"

namespace tdvo {

// One adaptive binary context: a 6-bit probability state index (0..62 usable; 63 is reserved
// for the terminate bin and never adapts) and the value of the most probable symbol.
struct ContextModel {
  uint8_t state = 0;
  uint8_t mps = 0;

  // The state/MPS pair whose probability is closest (in the log domain) to P(bin == 1) = pOne.
  // pOne is clamped to [0, 1]; probabilities beyond the table's range saturate at state 62.
  static ContextModel fromProbability(double pOne);
  // State 0, MPS 0: P(1) = 0.5, the usual starting point for contexts without a trained prior.
  static ContextModel equiprobable() { return ContextModel{}; }

  // P(LPS) represented by a state: 0.5 * alpha^state with alpha = (0.01875 / 0.5)^(1/63).
  static double lpsProbability(int state);
  // P(bin == 1) represented by this context.
  double probabilityOne() const;
};

class CabacEncoder {
 public:
  CabacEncoder();

  // Codes one regular bin (any nonzero value is a 1) and adapts ctx.
  inline void encodeBin(ContextModel& ctx, unsigned bin);
  // Codes one bin with probability 1/2 (any nonzero value is a 1); costs one bit.
  inline void encodeBypass(unsigned bin);
  // Codes the low numBits bits of value as bypass bins, most significant first. 0 <= numBits
  // <= 32; higher bits of value are ignored.
  void encodeBypassBits(uint32_t value, int numBits);
  // Codes a terminate bin. 0: continue; 1: end the codeword (flush, pad, restart; see above).
  void encodeTerminate(unsigned bin);
  // Ends the current codeword as described above and returns the payload: every byte written
  // since construction or the previous finish(). The encoder is then empty and ready for a new
  // payload; binCount() keeps counting.
  std::vector<uint8_t> finish();

  // Bins coded so far over the encoder's lifetime: regular, bypass (one per bit) and terminate,
  // including the terminate bin added by finish().
  uint64_t binCount() const { return bins_; }
  // Bytes already final in the output (excluding up to a few bytes held for carry resolution
  // and the bits still in the low register): a cheap lower bound of the payload size.
  size_t bytesWritten() const { return out_.size(); }

 private:
  void drain();
  void putByte(uint32_t byte);
  void restart();

  std::vector<uint8_t> out_;
  // Interval base. Bits [0, 9) are the current range window; the pend_ bits above it are code
  // bits not yet moved to out_; one more bit above those catches a carry into earlier bytes.
  uint64_t low_ = 0;
  uint32_t range_ = 510;
  int pend_ = 0;
  // Carry resolution: the last byte that is not 0xFF and the run of 0xFF bytes after it are
  // held back, because a carry out of low_ increments that byte and turns the run into 0x00s.
  uint32_t held_ = 0;
  bool hasHeld_ = false;
  size_t numFF_ = 0;
  bool codewordEmpty_ = true;  // nothing coded since the last restart
  bool anyCodeword_ = false;   // a codeword was terminated since the last finish()
  uint64_t bins_ = 0;
};

class CabacDecoder {
 public:
  // The decoder reads from data; the buffer must outlive the decoder.
  CabacDecoder(const uint8_t* data, size_t size);

  inline unsigned decodeBin(ContextModel& ctx);
  inline unsigned decodeBypass();
  // Decodes numBits (0..32) bypass bins, the first one becoming the most significant bit.
  uint32_t decodeBypassBits(int numBits);
  // Decodes a terminate bin; on 1 moves to the next codeword (see above).
  unsigned decodeTerminate();

  // Sticky: some decoded bin depended on bits beyond the end of the payload. (Only bytes
  // supplied past the end can make it true, so the common case is one comparison.)
  bool overrun() const { return pastEnd_ != 0 && consumedBits() > uint64_t(size_) * 8; }
  // Bytes of the payload used so far, i.e. loaded into the 9-bit offset register (rounded up;
  // > size only after overrun). After the final terminate bin this is the payload size.
  size_t bytesConsumed() const { return size_t((consumedBits() + 7) / 8); }
  // Byte offset just past the codeword most recently closed by decodeTerminate() == 1 (0 if
  // none yet): where a following codeword, or data the caller placed after the payload, starts.
  size_t codewordEnd() const { return codewordEnd_; }

  class LocalEngine;

 private:
  // The read-ahead window: value_, ptr_ and bits_ below.
  struct Window {
    uint64_t value;
    const uint8_t* ptr;
    int bits;
  };
  uint64_t consumedBits() const {
    return (uint64_t(ptr_ - data_) + pastEnd_) * 8 - uint64_t(int64_t(bits_));
  }
  void refill();
  // Tops a window up to 48..55 bits byte by byte (bytes past the end of the payload read as
  // zeros and are counted in pastEnd_): the start of the payload and its last 7 bytes.
  Window refillTail(Window w) noexcept;
  void startCodeword();
  void endCodeword();

  const uint8_t* data_;
  const uint8_t* ptr_;
  const uint8_t* end_;
  size_t size_;
  uint64_t pastEnd_ = 0;  // zero bytes supplied beyond the end of the payload
  size_t codewordEnd_ = 0;
  // value_ holds the 9-bit offset register at bits [bits_, bits_ + 9) and bits_ read-ahead
  // bits below it, so a bin is decoded by comparing value_ with range_ << bits_, and consuming
  // a bit is just --bits_. Kept at bits_ >= 8 between steps: a renormalisation takes at most
  // 7 bits and decodeBypassBits refills after every 8.
  uint64_t value_ = 0;
  int bits_ = 0;
  uint32_t range_ = 510;
};

// The decoding engine with its registers (value, read position, bits, range) copied into local
// variables, for a run of bins such as one syntax element's binarisation: construct it on the
// stack, decode, and its destructor writes the registers back (also when an error is thrown,
// so error messages see the right byte offset). Why: a context is two uint8_t, and a store to
// a uint8_t may alias any object, so after every context update the compiler would have to
// write the decoder's members back to memory and reload them for the next bin. Locals whose
// address never escapes cannot be aliased, and stay in CPU registers from bin to bin.
// Only one LocalEngine per decoder may exist at a time, and the decoder's own decode calls must
// not be used while it does. Decoding is exactly that of CabacDecoder's members.
class CabacDecoder::LocalEngine {
 public:
  explicit LocalEngine(CabacDecoder& dec)
      : dec_(dec), value_(dec.value_), ptr_(dec.ptr_), bits_(dec.bits_), range_(dec.range_) {}
  __attribute__((always_inline)) ~LocalEngine() { sync(); }
  LocalEngine(const LocalEngine&) = delete;
  LocalEngine& operator=(const LocalEngine&) = delete;
  // Writes the registers back now (for reading the decoder's position while the engine lives).
  // Always inlined, also on cold paths: a call would take the engine's address, and an engine
  // whose address escapes lives in memory, not in registers.
  __attribute__((always_inline)) void sync() const {
    dec_.value_ = value_;
    dec_.ptr_ = ptr_;
    dec_.bits_ = bits_;
    dec_.range_ = range_;
  }

  inline unsigned decodeBin(ContextModel& ctx);
  inline unsigned decodeBypass();
  // numBits in [0, 32] (not checked here).
  inline uint32_t decodeBypassBits(int numBits);
  // As CabacDecoder::overrun().
  bool overrun() const {
    return dec_.pastEnd_ != 0 &&
           (uint64_t(ptr_ - dec_.data_) + dec_.pastEnd_) * 8 - uint64_t(int64_t(bits_)) >
               uint64_t(dec_.size_) * 8;
  }

 private:
  inline void refill();

  CabacDecoder& dec_;
  uint64_t value_;
  const uint8_t* ptr_;
  int bits_;
  uint32_t range_;
};

// ---- Binarisations (clause 9.3.2). Bin i of a context-coded prefix uses
// ctxs[min(i, numCtx - 1)]; numCtx must be >= 1 whenever such a bin is coded.
// Caller mistakes (missing contexts, value > cMax, k or numBits out of range) throw
// std::invalid_argument; tdvo::Error is reserved for what comes from the stream.

// Unary: value ones, then a zero.
void encodeUnary(CabacEncoder& enc, ContextModel* ctxs, int numCtx, uint32_t value);
// Throws Error if more than maxValue ones are read (corrupt stream).
uint32_t decodeUnary(CabacDecoder& dec, ContextModel* ctxs, int numCtx, uint32_t maxValue);

// Truncated unary with maximum cMax: as unary, but the zero is omitted when value == cMax.
// Requires value <= cMax.
inline void encodeTruncatedUnary(CabacEncoder& enc, ContextModel* ctxs, int numCtx, uint32_t value,
                                 uint32_t cMax);
inline uint32_t decodeTruncatedUnary(CabacDecoder& dec, ContextModel* ctxs, int numCtx,
                                     uint32_t cMax);

// k-th order Exp-Golomb in bypass bins, in the form of the UEGk suffix (clause 9.3.2.3): while
// value >= 2^k, a 1 and value -= 2^k, k++; then a 0 and value in k bits. 0 <= k <= 31.
void encodeExpGolombBypass(CabacEncoder& enc, uint32_t value, int k);
// Throws Error when the prefix is longer than any 32-bit value needs or the value overflows.
uint32_t decodeExpGolombBypass(CabacDecoder& dec, int k);

// UEGk (clause 9.3.2.3, as used for mvd with k = 3, uCoff = 9): a truncated-unary prefix
// min(value, uCoff) with contexts and, when value >= uCoff, an Exp-Golomb suffix of
// value - uCoff in bypass bins. The signed variant codes |value| and then, when value != 0, a
// bypass sign bin (1 = negative).
inline void encodeUEGk(CabacEncoder& enc, ContextModel* ctxs, int numCtx, uint32_t value, int k,
                       uint32_t uCoff);
inline uint32_t decodeUEGk(CabacDecoder& dec, ContextModel* ctxs, int numCtx, int k,
                           uint32_t uCoff);
inline void encodeSignedUEGk(CabacEncoder& enc, ContextModel* ctxs, int numCtx, int32_t value,
                             int k, uint32_t uCoff);
inline int32_t decodeSignedUEGk(CabacDecoder& dec, ContextModel* ctxs, int numCtx, int k,
                                uint32_t uCoff);

// ---- Inline hot paths. Everything rare (byte output, the refill of the payload's last bytes,
// termination, errors) is in cabac.cpp. The UEGk binarisations are inline because P meshes
// code three of them per vertex: a call per bin costs more than the bin.

namespace cabac {
// Left shift that brings a range in [2, 511] back to [256, 511] (renormalisation).
inline int renormShift(uint32_t range) {
  return __builtin_clz(range) - 23;
}
// Cold error paths of the inline decoders (they throw what the checks in cabac.cpp throw).
[[noreturn]] void throwNoContexts(const char* what);
[[noreturn]] void throwAboveMax(const char* what);
[[noreturn]] void throwBadK(const char* what);
[[noreturn]] void throwLoopOverrun(const char* what);
[[noreturn]] void throwCorrupt(const char* message);
}  // namespace cabac

inline void CabacEncoder::encodeBin(ContextModel& ctx, unsigned bin) {
  ++bins_;
  codewordEmpty_ = false;
  const unsigned s = ctx.state & 63u;
  const uint32_t lps = cabac::kRangeTabLPS[s][(range_ >> 6) & 3];
  range_ -= lps;
  if (unsigned(bin != 0) != ctx.mps) {
    low_ += range_;  // the LPS sub-interval is the upper one
    range_ = lps;
    ctx.mps ^= unsigned(s == 0);  // clause 9.3.3.2.1.1: LPS in state 0 swaps MPS and LPS
    ctx.state = cabac::kTransIdxLPS[s];
  } else {
    ctx.state = cabac::kTransIdxMPS[s];
  }
  const int shift = cabac::renormShift(range_);
  low_ <<= shift;
  range_ <<= shift;
  pend_ += shift;
  if (pend_ >= 32) drain();
}

inline void CabacEncoder::encodeBypass(unsigned bin) {
  ++bins_;
  codewordEmpty_ = false;
  low_ = (low_ << 1) + (range_ & (0u - unsigned(bin != 0)));
  if (++pend_ >= 32) drain();
}

inline unsigned CabacDecoder::LocalEngine::decodeBin(ContextModel& ctx) {
  const unsigned s = ctx.state & 63u;
  const unsigned mps = ctx.mps;
  // The row of rangeTabLPS is loaded before the range is known, and the range then only picks a
  // byte of it: shorter than indexing the table with the range (the chain from one bin's range
  // to the next is what limits decoding speed).
  const uint32_t lps = (cabac::kRangeTabLPSRows[s] >> ((range_ >> 3) & 24)) & 0xFFu;
  const uint32_t mpsRange = range_ - lps;
  const uint64_t scaled = uint64_t(mpsRange) << bits_;
  unsigned bin;
  if (value_ < scaled) {
    bin = mps;
    ctx.state = cabac::kTransIdxMPS[s];
    // An MPS leaves at least 128 of the range (Table 9-44), so at most one bit is renormalised.
    const bool renormalise = mpsRange < 256;
    range_ = renormalise ? 2 * mpsRange : mpsRange;
    bits_ -= int(renormalise);
  } else {
    value_ -= scaled;
    bin = mps ^ 1u;
    ctx.mps = uint8_t(mps ^ unsigned(s == 0));  // clause 9.3.3.2.1.1: LPS in state 0 swaps
    ctx.state = cabac::kTransIdxLPS[s];
    const int shift = cabac::renormShift(lps);
    range_ = lps << shift;
    bits_ -= shift;
  }
  if (bits_ < 8) refill();
  return bin;
}

inline unsigned CabacDecoder::LocalEngine::decodeBypass() {
  --bits_;  // shift the next bit into the offset window
  const uint64_t scaled = uint64_t(range_) << bits_;
  const unsigned bin = value_ >= scaled;
  value_ -= scaled & (0 - uint64_t(bin));
  if (bits_ < 8) refill();
  return bin;
}

inline uint32_t CabacDecoder::LocalEngine::decodeBypassBits(int numBits) {
  uint32_t value = 0;
  while (numBits > 0) {
    const int n = numBits < 8 ? numBits : 8;  // bits_ >= 8 on entry covers one chunk
    numBits -= n;
    for (int i = 0; i < n; ++i) {
      --bits_;
      const uint64_t scaled = uint64_t(range_) << bits_;
      const uint32_t bin = value_ >= scaled;
      value_ -= scaled & (0 - uint64_t(bin));
      value = (value << 1) | bin;
    }
    if (bits_ < 8) refill();
  }
  return value;
}

// Called with 0 <= bits_ < 8: six more bytes make 48..55 bits of read-ahead.
inline void CabacDecoder::LocalEngine::refill() {
  if (dec_.end_ - ptr_ >= 8) {
    uint64_t word;
    std::memcpy(&word, ptr_, 8);
#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__
    word = __builtin_bswap64(word);
#endif
    value_ = (value_ << 48) | (word >> 16);
    ptr_ += 6;
    bits_ += 48;
    return;
  }
  const Window w = dec_.refillTail({value_, ptr_, bits_});
  value_ = w.value;
  ptr_ = w.ptr;
  bits_ = w.bits;
}

inline unsigned CabacDecoder::decodeBin(ContextModel& ctx) {
  LocalEngine engine(*this);
  return engine.decodeBin(ctx);
}

inline unsigned CabacDecoder::decodeBypass() {
  LocalEngine engine(*this);
  return engine.decodeBypass();
}

inline void encodeTruncatedUnary(CabacEncoder& enc, ContextModel* ctxs, int numCtx, uint32_t value,
                                 uint32_t cMax) {
  if (value > cMax) cabac::throwAboveMax("encodeTruncatedUnary");
  if (cMax == 0) return;
  if (ctxs == nullptr || numCtx < 1) cabac::throwNoContexts("encodeTruncatedUnary");
  const uint32_t lastCtx = uint32_t(numCtx - 1);
  for (uint32_t i = 0; i < value; ++i)
    enc.encodeBin(ctxs[i < lastCtx ? i : lastCtx], 1);
  if (value < cMax) enc.encodeBin(ctxs[value < lastCtx ? value : lastCtx], 0);
}

inline void encodeUEGk(CabacEncoder& enc, ContextModel* ctxs, int numCtx, uint32_t value, int k,
                       uint32_t uCoff) {
  if (k < 0 || k > 31) cabac::throwBadK("encodeUEGk");
  encodeTruncatedUnary(enc, ctxs, numCtx, value < uCoff ? value : uCoff, uCoff);
  if (value >= uCoff) encodeExpGolombBypass(enc, value - uCoff, k);
}

inline void encodeSignedUEGk(CabacEncoder& enc, ContextModel* ctxs, int numCtx, int32_t value,
                             int k, uint32_t uCoff) {
  const uint32_t magnitude = value < 0 ? 0u - uint32_t(value) : uint32_t(value);
  encodeUEGk(enc, ctxs, numCtx, magnitude, k, uCoff);
  if (magnitude != 0) enc.encodeBypass(value < 0 ? 1 : 0);
}

// The decoding binarisations run on one LocalEngine: cabac::decode* below do the work, the
// public decode* functions check their arguments and hold the engine.
namespace cabac {

inline uint32_t decodeTruncatedUnary(CabacDecoder::LocalEngine& engine, ContextModel* ctxs,
                                     uint32_t lastCtx, uint32_t cMax) {
  uint32_t n = 0;
  while (n < cMax && engine.decodeBin(ctxs[n < lastCtx ? n : lastCtx])) {
    ++n;
    // Stop a long run of ones read past the end of the payload (checked every 64 bins).
    if ((n & 63) == 0 && engine.overrun()) throwLoopOverrun("truncated unary value");
  }
  return n;
}

inline uint32_t decodeExpGolombBypass(CabacDecoder::LocalEngine& engine, int k) {
  uint64_t value = 0;
  while (engine.decodeBypass()) {
    // A 32-bit value ends its prefix by the time k reaches 32; a longer one is corrupt.
    if (k >= 32) throwCorrupt("CABAC: Exp-Golomb prefix too long (corrupt stream)");
    value += uint64_t(1) << k;
    ++k;
  }
  value += engine.decodeBypassBits(k);
  if (value > UINT32_MAX) throwCorrupt("CABAC: Exp-Golomb value exceeds 32 bits (corrupt stream)");
  return uint32_t(value);
}

inline uint32_t decodeUEGk(CabacDecoder::LocalEngine& engine, ContextModel* ctxs, int numCtx, int k,
                           uint32_t uCoff) {
  const uint32_t prefix = decodeTruncatedUnary(engine, ctxs, uint32_t(numCtx - 1), uCoff);
  if (prefix < uCoff) return prefix;
  const uint64_t value = uint64_t(uCoff) + decodeExpGolombBypass(engine, k);
  if (value > UINT32_MAX) throwCorrupt("CABAC: UEGk value exceeds 32 bits (corrupt stream)");
  return uint32_t(value);
}

// As decodeSignedUEGk below, without its argument checks.
inline int32_t decodeSignedUEGk(CabacDecoder::LocalEngine& engine, ContextModel* ctxs, int numCtx,
                                int k, uint32_t uCoff) {
  const uint32_t magnitude = decodeUEGk(engine, ctxs, numCtx, k, uCoff);
  if (magnitude == 0) return 0;
  // The sign is a fair coin: no branch on it.
  const uint32_t negative = engine.decodeBypass();
  if (magnitude > 0x7FFFFFFFu + negative)
    throwCorrupt("CABAC: signed UEGk value exceeds 32 bits (corrupt stream)");
  return int32_t((magnitude ^ (0u - negative)) + negative);  // two's complement negation
}

}  // namespace cabac

inline uint32_t decodeTruncatedUnary(CabacDecoder& dec, ContextModel* ctxs, int numCtx,
                                     uint32_t cMax) {
  if (cMax == 0) return 0;
  if (ctxs == nullptr || numCtx < 1) cabac::throwNoContexts("decodeTruncatedUnary");
  CabacDecoder::LocalEngine engine(dec);
  return cabac::decodeTruncatedUnary(engine, ctxs, uint32_t(numCtx - 1), cMax);
}

namespace cabac {

// The arguments of decodeUEGk and decodeSignedUEGk: k in [0, 31], contexts when a prefix is
// coded.
inline void checkUegkArguments(const ContextModel* ctxs, int numCtx, int k, uint32_t uCoff) {
  if (k < 0 || k > 31) throwBadK("decodeUEGk");
  if (uCoff > 0 && (ctxs == nullptr || numCtx < 1)) throwNoContexts("decodeTruncatedUnary");
}

}  // namespace cabac

inline uint32_t decodeUEGk(CabacDecoder& dec, ContextModel* ctxs, int numCtx, int k,
                           uint32_t uCoff) {
  cabac::checkUegkArguments(ctxs, numCtx, k, uCoff);
  CabacDecoder::LocalEngine engine(dec);
  return cabac::decodeUEGk(engine, ctxs, numCtx, k, uCoff);
}

inline int32_t decodeSignedUEGk(CabacDecoder& dec, ContextModel* ctxs, int numCtx, int k,
                                uint32_t uCoff) {
  cabac::checkUegkArguments(ctxs, numCtx, k, uCoff);
  CabacDecoder::LocalEngine engine(dec);
  return cabac::decodeSignedUEGk(engine, ctxs, numCtx, k, uCoff);
}

}  // namespace tdvo
