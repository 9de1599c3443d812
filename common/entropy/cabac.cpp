// CABAC engine and binarisations; see common/entropy/cabac.h for the coding conventions.
#include "common/entropy/cabac.h"

#include <cmath>
#include <cstring>
#include <stdexcept>
#include <string>

#include "common/core/error.h"

namespace tdvo {

namespace {

// alpha of the state machine: p(state) = 0.5 * alpha^state, p(62) ~= 0.01875 (clause 9.3.3.2).
const double kLogAlpha = std::log(0.01875 / 0.5) / 63.0;

void requireBits(int numBits, const char* what) {
  if (numBits < 0 || numBits > 32) throw std::invalid_argument(std::string(what) + ": numBits");
}

void requireK(int k, const char* what) {
  if (k < 0 || k > 31) throw std::invalid_argument(std::string(what) + ": k out of [0, 31]");
}

void requireContexts(const ContextModel* ctxs, int numCtx, const char* what) {
  if (ctxs == nullptr || numCtx < 1) throw std::invalid_argument(std::string(what) + ": no ctxs");
}

// Context of prefix bin i: the last context is shared by all later bins.
inline ContextModel& binContext(ContextModel* ctxs, int numCtx, uint32_t i) {
  return ctxs[i < uint32_t(numCtx - 1) ? i : uint32_t(numCtx - 1)];
}

// Loops whose length comes from the stream stop once the payload is used up: past the end
// every bin reads zeros, and a context whose MPS is 1 would keep decoding ones until the
// caller's maximum (up to 2^32). Checking every 64 bins keeps the check off the common path.
inline void guardLoop(const CabacDecoder::LocalEngine& dec, uint32_t i, const char* what) {
  if ((i & 63) == 0 && dec.overrun())
    throw Error(std::string("CABAC: ") + what + " runs past the end of the payload");
}

}  // namespace

// ---- Error paths of the inline binarisation decoders (cabac.h)

namespace cabac {

void throwNoContexts(const char* what) {
  throw std::invalid_argument(std::string(what) + ": no ctxs");
}

void throwAboveMax(const char* what) {
  throw std::invalid_argument(std::string(what) + ": value > cMax");
}

void throwBadK(const char* what) {
  throw std::invalid_argument(std::string(what) + ": k out of [0, 31]");
}

void throwLoopOverrun(const char* what) {
  throw Error(std::string("CABAC: ") + what + " runs past the end of the payload");
}

void throwCorrupt(const char* message) {
  throw Error(message);
}

}  // namespace cabac

// ---- ContextModel

double ContextModel::lpsProbability(int state) {
  return 0.5 * std::exp(kLogAlpha * state);
}

double ContextModel::probabilityOne() const {
  const double lps = lpsProbability(state & 63);
  return mps ? 1.0 - lps : lps;
}

ContextModel ContextModel::fromProbability(double pOne) {
  if (!(pOne == pOne)) return equiprobable();  // NaN
  pOne = pOne < 0.0 ? 0.0 : (pOne > 1.0 ? 1.0 : pOne);
  ContextModel ctx;
  ctx.mps = pOne > 0.5 ? 1 : 0;
  const double lps = ctx.mps ? 1.0 - pOne : pOne;
  // States are evenly spaced in log(p), so the nearest state is a rounded logarithm.
  double s = lps > 0.0 ? std::log(lps / 0.5) / kLogAlpha : 62.0;
  s = s < 0.0 ? 0.0 : (s > 62.0 ? 62.0 : s);
  ctx.state = uint8_t(std::lround(s));
  return ctx;
}

// ---- Encoder

CabacEncoder::CabacEncoder() {
  restart();
}

void CabacEncoder::restart() {
  // Clause 9.3.1.2 (initialisation of the encoding engine). The standard's extra leading bit of
  // codILow (always 0, dropped by firstBitFlag) is simply not represented here.
  low_ = 0;
  range_ = 510;
  pend_ = 0;
  codewordEmpty_ = true;
}

void CabacEncoder::drain() {
  while (pend_ >= 8) {
    pend_ -= 8;
    putByte(uint32_t(low_ >> (pend_ + 9)));  // 8 code bits plus the carry bit above them
    low_ &= (uint64_t(1) << (pend_ + 9)) - 1;
  }
}

// Byte-wise equivalent of the standard's PutBit/bitsOutstanding: a carry out of low_ can only
// change the held byte (incremented) and the 0xFF run after it (which becomes 0x00s). Once a
// carry has happened, no second carry can reach those bytes (codILow never exceeds its 10 bits
// in the standard), so they are final; and a carry never reaches bytes already in out_.
void CabacEncoder::putByte(uint32_t byte) {
  if (byte > 0xFF) {
    if (hasHeld_) out_.push_back(uint8_t(held_ + 1));  // held_ != 0xFF, so no overflow
    out_.insert(out_.end(), numFF_, uint8_t(0x00));
    hasHeld_ = false;
    numFF_ = 0;
    byte &= 0xFF;
  }
  if (byte == 0xFF) {
    ++numFF_;  // may still become 0x00 through a later carry
    return;
  }
  if (hasHeld_) out_.push_back(uint8_t(held_));
  out_.insert(out_.end(), numFF_, uint8_t(0xFF));
  numFF_ = 0;
  held_ = byte;
  hasHeld_ = true;
}

void CabacEncoder::encodeBypassBits(uint32_t value, int numBits) {
  requireBits(numBits, "encodeBypassBits");
  bins_ += uint64_t(numBits);
  if (numBits > 0) codewordEmpty_ = false;
  while (numBits > 0) {
    // n bypass bins at once: low = low * 2^n + range * bits (clause 9.3.4.4, unrolled).
    const int n = numBits < 8 ? numBits : 8;
    numBits -= n;
    const uint32_t chunk = (value >> numBits) & ((1u << n) - 1);
    low_ = (low_ << n) + uint64_t(range_) * chunk;
    pend_ += n;
    if (pend_ >= 32) drain();
  }
}

void CabacEncoder::encodeTerminate(unsigned bin) {
  ++bins_;
  codewordEmpty_ = false;
  range_ -= 2;
  if (bin == 0) {
    const int shift = cabac::renormShift(range_);  // 0 or 1
    low_ <<= shift;
    range_ <<= shift;
    pend_ += shift;
    if (pend_ >= 32) drain();
    return;
  }
  // Clause 9.3.4.5: the terminate sub-interval is the top 2 of the range; EncodeFlush sets the
  // range to 2 and renormalises by 7, then writes bit 9 of codILow (our top pending bit was
  // already counted), bit 8, and a 1 in place of bit 7 (the stop bit). Any value in the final
  // interval decodes correctly, and this one needs no further bits.
  low_ += range_;
  low_ <<= 7;
  pend_ += 7;
  const int numBits = pend_ + 2;
  const int pad = (8 - numBits % 8) % 8;  // zero bits up to the byte boundary
  const uint64_t bits = ((low_ >> 7) | 1) << pad;
  const int numBytes = (numBits + pad) / 8;
  putByte(uint32_t(bits >> (8 * (numBytes - 1))));  // includes the carry bit
  for (int i = numBytes - 2; i >= 0; --i)
    putByte(uint32_t(bits >> (8 * i)) & 0xFF);
  if (hasHeld_) out_.push_back(uint8_t(held_));
  out_.insert(out_.end(), numFF_, uint8_t(0xFF));
  hasHeld_ = false;
  numFF_ = 0;
  anyCodeword_ = true;
  restart();
}

std::vector<uint8_t> CabacEncoder::finish() {
  if (!codewordEmpty_ || !anyCodeword_) encodeTerminate(1);
  anyCodeword_ = false;
  std::vector<uint8_t> payload;
  payload.swap(out_);
  return payload;
}

// ---- Decoder

CabacDecoder::CabacDecoder(const uint8_t* data, size_t size)
    : data_(data), ptr_(data), end_(data + size), size_(size) {
  // Clause 9.3.1.2: codIRange = 510, codIOffset = the first 9 bits. Read bytewise from an
  // empty window (bits_ = -9) so the same code handles payloads shorter than 8 bytes.
  const Window w = refillTail({0, data, -9});
  value_ = w.value;
  ptr_ = w.ptr;
  bits_ = w.bits;
  range_ = 510;
}

// Tops the read-ahead up to 48..55 bits. Called with 0 <= bits_ < 48.
void CabacDecoder::refill() {
  if (end_ - ptr_ >= 8) {
    uint64_t word;
    std::memcpy(&word, ptr_, 8);
#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__
    word = __builtin_bswap64(word);
#endif
    const int n = (55 - bits_) >> 3;  // whole bytes that fit: value_ stays below 2^64
    value_ = (value_ << (8 * n)) | (word >> (64 - 8 * n));
    ptr_ += n;
    bits_ += 8 * n;
    return;
  }
  const Window w = refillTail({value_, ptr_, bits_});
  value_ = w.value;
  ptr_ = w.ptr;
  bits_ = w.bits;
}

CabacDecoder::Window CabacDecoder::refillTail(Window w) noexcept {
  while (w.bits < 48) {
    uint64_t byte = 0;
    if (w.ptr < end_) {
      byte = *w.ptr++;
    } else {
      ++pastEnd_;
    }
    w.value = (w.value << 8) | byte;
    w.bits += 8;
  }
  return w;
}

uint32_t CabacDecoder::decodeBypassBits(int numBits) {
  requireBits(numBits, "decodeBypassBits");
  LocalEngine engine(*this);
  return engine.decodeBypassBits(numBits);
}

unsigned CabacDecoder::decodeTerminate() {
  range_ -= 2;
  const uint64_t scaled = uint64_t(range_) << bits_;
  if (value_ >= scaled) {
    endCodeword();  // clause 9.3.3.2.2.3: binVal 1, no renormalisation
    return 1;
  }
  const int shift = cabac::renormShift(range_);
  range_ <<= shift;
  bits_ -= shift;
  if (bits_ < 8) refill();
  return 0;
}

// After a terminate bin of 1 the decoder has consumed exactly the encoder's codeword up to its
// stop bit; skip the zero padding and start on the next codeword, if there is one.
void CabacDecoder::endCodeword() {
  if (bits_ < 24) refill();
  bits_ -= int((8 - consumedBits() % 8) % 8);
  codewordEnd_ = size_t(consumedBits() / 8);
  if (consumedBits() < uint64_t(size_) * 8) {
    startCodeword();
    return;
  }
  // Nothing follows. A zero offset with the smallest range makes every further bin renormalise
  // at least one bit, i.e. read past the end, so overrun() reports any use of the decoder now.
  value_ &= (uint64_t(1) << bits_) - 1;
  range_ = 256;
}

void CabacDecoder::startCodeword() {
  if (bits_ < 24) refill();
  value_ &= (uint64_t(1) << bits_) - 1;  // drop the old offset window
  bits_ -= 9;                            // the next 9 bits are the new codIOffset
  range_ = 510;
}

// ---- Binarisations

void encodeUnary(CabacEncoder& enc, ContextModel* ctxs, int numCtx, uint32_t value) {
  requireContexts(ctxs, numCtx, "encodeUnary");
  for (uint32_t i = 0; i < value; ++i)
    enc.encodeBin(binContext(ctxs, numCtx, i), 1);
  enc.encodeBin(binContext(ctxs, numCtx, value), 0);
}

uint32_t decodeUnary(CabacDecoder& dec, ContextModel* ctxs, int numCtx, uint32_t maxValue) {
  requireContexts(ctxs, numCtx, "decodeUnary");
  CabacDecoder::LocalEngine engine(dec);
  uint32_t n = 0;
  while (engine.decodeBin(binContext(ctxs, numCtx, n))) {
    if (n == maxValue)
      throw Error("CABAC: unary value above its maximum " + std::to_string(maxValue));
    ++n;
    guardLoop(engine, n, "unary value");
  }
  return n;
}

void encodeExpGolombBypass(CabacEncoder& enc, uint32_t value, int k) {
  requireK(k, "encodeExpGolombBypass");
  uint64_t rest = value;
  while (rest >= (uint64_t(1) << k)) {
    enc.encodeBypass(1);
    rest -= uint64_t(1) << k;
    ++k;
  }
  enc.encodeBypass(0);
  enc.encodeBypassBits(uint32_t(rest), k);  // k <= 32 because value < 2^32
}

uint32_t decodeExpGolombBypass(CabacDecoder& dec, int k) {
  requireK(k, "decodeExpGolombBypass");
  CabacDecoder::LocalEngine engine(dec);
  return cabac::decodeExpGolombBypass(engine, k);
}

}  // namespace tdvo
