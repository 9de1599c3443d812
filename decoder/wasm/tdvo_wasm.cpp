// The WebAssembly module's JavaScript interface (docs/wasm.md): tdvo::Decoder through embind,
// geometry only. Frame data are views into the module's memory, valid until the next call that
// decodes (next, seek) or the decoder's delete(); errors are JavaScript Errors whose message is
// tdvo::Error's, the message 3dvo-dec prints after "3dvo-dec: error: ".
#include <emscripten/bind.h>
#include <emscripten/val.h>

#include <exception>
#include <string>
#include <utility>

#include "common/core/error.h"
#include "decoder/decoder.h"

namespace tdvo {
namespace {

// Runs `f`, turning a C++ exception into a thrown JavaScript Error with the same message. The
// JavaScript exception unwinds the C++ frames without destructors: the message is kept in a
// static buffer (the module is single-threaded) and the Error made from a C string, so that
// nothing is left allocated.
template <class F>
auto rethrowAsJs(F&& f) -> decltype(f()) {
  static std::string message;
  try {
    return f();
  } catch (const std::exception& e) {
    message = e.what();
  }
  emscripten::val::global("Error").new_(emscripten::val(message.c_str())).throw_();
}

class WasmDecoder {
 public:
  // `bytes`: the stream (a Uint8Array or ArrayBuffer from JavaScript); `name` prefixes errors.
  WasmDecoder(const std::string& bytes, const std::string& name)
      : decoder_(rethrowAsJs([&] {
          return Decoder::openMemory(reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size(),
                                     name, true);
        })) {}

  // {syntaxVersion, firstFrame, frameCount, frameRate, cameraCount, grid: {origin, step, bits}}
  emscripten::val info() const {
    const StreamInfo& i = decoder_.info();
    emscripten::val grid = emscripten::val::object();
    emscripten::val origin = emscripten::val::array();
    for (double o : i.grid.origin)
      origin.call<void>("push", o);
    grid.set("origin", origin);
    grid.set("step", i.grid.step);
    grid.set("bits", i.grid.bits);
    emscripten::val out = emscripten::val::object();
    out.set("syntaxVersion", i.syntaxVersion);
    out.set("firstFrame", static_cast<double>(i.firstFrame));
    out.set("frameCount", i.frameCount);
    out.set("frameRate", i.frameRate);
    out.set("cameraCount", static_cast<unsigned>(i.cameras.size()));
    out.set("grid", grid);
    return out;
  }

  // Decodes the next frame; false after the last one.
  bool next() {
    return rethrowAsJs([&] { return decoder_.next(frame_); });
  }

  double frameNumber() const { return static_cast<double>(frame_.number); }
  unsigned frameIndex() const { return frame_.index; }
  unsigned vertexCount() const { return static_cast<unsigned>(frame_.mesh.positions.size()); }
  unsigned triangleCount() const { return static_cast<unsigned>(frame_.mesh.triangles.size()); }

  // Float32Array, x y z per vertex: the positions (origin + q * step).
  emscripten::val positions() const {
    return emscripten::val(emscripten::typed_memory_view(
        frame_.positions.size() * 3,
        frame_.positions.empty() ? nullptr : frame_.positions[0].data()));
  }
  // Int32Array, x y z per vertex: the grid integers.
  emscripten::val gridPositions() const {
    const auto& p = frame_.mesh.positions;
    return emscripten::val(
        emscripten::typed_memory_view(p.size() * 3, p.empty() ? nullptr : p[0].data()));
  }
  // Uint32Array, three vertex indices per triangle.
  emscripten::val triangles() const {
    const auto& t = frame_.mesh.triangles;
    return emscripten::val(
        emscripten::typed_memory_view(t.size() * 3, t.empty() ? nullptr : t[0].data()));
  }
  // "MD5 frame=<n> geometry=<hex>", the line 3dvo-dec prints.
  std::string geometryHashLine() const { return frame_.geometryHashLine(); }

  // The random access points (input frame numbers), an Array of numbers.
  emscripten::val gomStarts() {
    return rethrowAsJs([&] {
      emscripten::val out = emscripten::val::array();
      for (int64_t s : decoder_.gomStarts())
        out.call<void>("push", static_cast<double>(s));
      return out;
    });
  }

  void seek(double frameNumber) {
    rethrowAsJs([&] { decoder_.seek(static_cast<int64_t>(frameNumber)); });
  }

 private:
  Decoder decoder_;
  DecodedFrame frame_;
};

EMSCRIPTEN_BINDINGS(tdvo) {
  emscripten::class_<WasmDecoder>("Decoder")
      .constructor<const std::string&, const std::string&>()
      .function("info", &WasmDecoder::info)
      .function("next", &WasmDecoder::next)
      .function("frameNumber", &WasmDecoder::frameNumber)
      .function("frameIndex", &WasmDecoder::frameIndex)
      .function("vertexCount", &WasmDecoder::vertexCount)
      .function("triangleCount", &WasmDecoder::triangleCount)
      .function("positions", &WasmDecoder::positions)
      .function("gridPositions", &WasmDecoder::gridPositions)
      .function("triangles", &WasmDecoder::triangles)
      .function("geometryHashLine", &WasmDecoder::geometryHashLine)
      .function("gomStarts", &WasmDecoder::gomStarts)
      .function("seek", &WasmDecoder::seek);
}

}  // namespace
}  // namespace tdvo
