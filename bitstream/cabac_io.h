// CABAC-coded syntax I/O: the entropy-coded counterpart of byte_io.h. Syntax code is written
// once, as a template over CabacWriterIo / CabacReaderIo; every call names its syntax element,
// which gives a trace (--trace) and error messages that name the element.
#pragma once

#include <cstdint>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <vector>

#include "common/core/error.h"
#include "common/entropy/cabac.h"

namespace tdvo {

class CabacWriterIo {
 public:
  static constexpr bool kReading = false;
  explicit CabacWriterIo(std::FILE* trace = nullptr) : trace_(trace) {}

  // A regular bin; `value` is coded (0 or 1).
  void bin(const char* name, ContextModel& ctx, unsigned& value) {
    if (trace_) std::fprintf(trace_, "  %-32s = %u\n", name, value);
    encoder_.encodeBin(ctx, value);
  }
  // A signed value as UEGk (cabac.h), |value| <= maxAbs.
  void signedUeg(const char* name, ContextModel* ctxs, int numCtx, int k, uint32_t uCoff,
                 int32_t& value, int32_t maxAbs) {
    if (value < -maxAbs || value > maxAbs) require(false, std::string(name) + " out of range");
    if (trace_) std::fprintf(trace_, "  %-32s = %d\n", name, value);
    encodeSignedUEGk(encoder_, ctxs, numCtx, value, k, uCoff);
  }
  // Three signed values with one binarisation, each with its own contexts (a vector's
  // components), coded one after the other as by three signedUeg calls.
  void signedUeg3(const char* const names[3], ContextModel* const ctxs[3], int numCtx, int k,
                  uint32_t uCoff, int32_t (&values)[3], int32_t maxAbs) {
    for (int c = 0; c < 3; ++c)
      signedUeg(names[c], ctxs[c], numCtx, k, uCoff, values[c], maxAbs);
  }
  void require(bool condition, const char* what) const {
    if (!condition) throw std::logic_error(std::string("writing: ") + what);
  }
  void require(bool condition, const std::string& what) const { require(condition, what.c_str()); }
  // Ends the payload (terminate bin 1, flush) and returns it.
  std::vector<uint8_t> finish() { return encoder_.finish(); }
  uint64_t binCount() const { return encoder_.binCount(); }

 private:
  CabacEncoder encoder_;
  std::FILE* trace_;
};

class CabacReaderIo {
 public:
  static constexpr bool kReading = true;
  // `context` names the unit in error messages.
  CabacReaderIo(const uint8_t* data, size_t size, std::string context, std::FILE* trace = nullptr)
      : decoder_(data, size), size_(size), context_(std::move(context)), trace_(trace) {}

  void bin(const char* name, ContextModel& ctx, unsigned& value) {
    value = decoder_.decodeBin(ctx);
    if (trace_) std::fprintf(trace_, "  %-32s = %u\n", name, value);
  }
  // Runs three times per coded vertex: always inlined (a call costs as much as the bins), with
  // the error paths out of line, building their messages only when taken.
  __attribute__((always_inline)) void signedUeg(const char* name, ContextModel* ctxs, int numCtx,
                                                int k, uint32_t uCoff, int32_t& value,
                                                int32_t maxAbs) {
    try {
      value = decodeSignedUEGk(decoder_, ctxs, numCtx, k, uCoff);
    } catch (const Error& e) {
      failElement(name, e.what());
    }
    if (trace_) std::fprintf(trace_, "  %-32s = %d\n", name, value);
    if (value < -maxAbs || value > maxAbs) failRange(name, value, maxAbs);
    // A payload read past its end decodes to zeros forever; stop as soon as that happens.
    if (decoder_.overrun()) failElement(name, "payload ends early (truncated)");
  }
  // As three signedUeg calls (a vector's components, each with its own contexts), on one
  // engine: its registers stay in CPU registers from the first bin to the last. The cold paths
  // write them back before they report the byte offset.
  __attribute__((always_inline)) void signedUeg3(const char* const names[3],
                                                 ContextModel* const ctxs[3], int numCtx, int k,
                                                 uint32_t uCoff, int32_t (&values)[3],
                                                 int32_t maxAbs) {
    for (int c = 0; c < 3; ++c)
      cabac::checkUegkArguments(ctxs[c], numCtx, k, uCoff);
    CabacDecoder::LocalEngine engine(decoder_);
    for (int c = 0; c < 3; ++c) {
      int32_t& value = values[c];
      try {
        value = cabac::decodeSignedUEGk(engine, ctxs[c], numCtx, k, uCoff);
      } catch (const Error& e) {
        engine.sync();
        failElement(names[c], e.what());
      }
      if (trace_) std::fprintf(trace_, "  %-32s = %d\n", names[c], value);
      if (value < -maxAbs || value > maxAbs) {
        engine.sync();
        failRange(names[c], value, maxAbs);
      }
      if (engine.overrun()) {
        engine.sync();
        failElement(names[c], "payload ends early (truncated)");
      }
    }
  }
  void require(bool condition, const char* what) const {
    if (!condition) fail(what);
  }
  void require(bool condition, const std::string& what) const {
    if (!condition) fail(what);
  }
  [[noreturn]] void fail(const std::string& what) const {
    throw Error(context_ + ", payload byte " + std::to_string(decoder_.bytesConsumed()) + ": " +
                what);
  }
  [[noreturn]] __attribute__((noinline, cold)) void failElement(const char* name,
                                                                const char* what) const {
    fail(std::string(name) + ": " + what);
  }
  [[noreturn]] __attribute__((noinline, cold)) void failRange(const char* name, int32_t value,
                                                              int32_t maxAbs) const {
    fail(std::string(name) + " = " + std::to_string(value) + " out of range [" +
         std::to_string(-maxAbs) + ", " + std::to_string(maxAbs) + "]");
  }
  // Reads the final terminate bin and checks that the payload was used exactly.
  void finish() {
    require(decoder_.decodeTerminate() == 1, "missing end of payload (terminate bin)");
    // Bytes after the codeword first: the decoder starts a next codeword on them, and one byte
    // is too short for one (it would read as a truncation).
    if (decoder_.codewordEnd() < size_)
      fail(std::to_string(size_ - decoder_.codewordEnd()) +
           " unexpected bytes after the payload's end");
    require(!decoder_.overrun(), "payload ends early (truncated)");
  }

 private:
  CabacDecoder decoder_;
  size_t size_;
  std::string context_;
  std::FILE* trace_;
};

}  // namespace tdvo
