// The WebAssembly module's JavaScript interface (docs/wasm.md): tdvo::Decoder through embind:
// geometry, and the texture access units for the browser's own H.264 decoder (WebCodecs). A
// stream is given whole or as it arrives (Decoder.growing). Frame data are views into the
// module's memory, valid until the next call that decodes (next, seek), appends, or the
// decoder's delete(); errors are JavaScript Errors whose message is tdvo::Error's, the message
// 3dvo-dec prints after "3dvo-dec: error: ".
#include <emscripten/bind.h>
#include <emscripten/val.h>

#include <exception>
#include <string>
#include <utility>

#include "common/core/error.h"
#include "common/core/md5.h"
#include "common/views/yuv_picture.h"
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

template <class T>
emscripten::val array(const T* values, size_t count) {
  emscripten::val out = emscripten::val::array();
  for (size_t k = 0; k < count; ++k)
    out.call<void>("push", static_cast<double>(values[k]));
  return out;
}

// A byte string of JavaScript (Uint8Array or ArrayBuffer; embind copies it) as bytes.
const uint8_t* bytesOf(const std::string& bytes) {
  return reinterpret_cast<const uint8_t*>(bytes.data());
}

emscripten::val cameraObject(const CameraParameters& c) {
  emscripten::val out = emscripten::val::object();
  out.set("name", c.cam_name);
  out.set("width", c.cam_width);
  out.set("height", c.cam_height);
  out.set("fx", c.cam_fx);
  out.set("fy", c.cam_fy);
  out.set("cx", c.cam_cx);
  out.set("cy", c.cam_cy);
  const double distortion[5] = {c.cam_k1, c.cam_k2, c.cam_p1, c.cam_p2, c.cam_k3};
  out.set("distortion", array(distortion, 5));
  out.set("R", array(c.cam_rotation, 9));
  out.set("t", array(c.cam_translation, 3));
  emscripten::val box = emscripten::val::object();
  box.set("x", c.tx_box_x);
  box.set("y", c.tx_box_y);
  box.set("width", c.tx_box_width);
  box.set("height", c.tx_box_height);
  out.set("box", box);
  return out;
}

class WasmDecoder {
 public:
  // `bytes`: the whole stream (a Uint8Array or ArrayBuffer from JavaScript); `name` prefixes
  // errors.
  WasmDecoder(const std::string& bytes, const std::string& name)
      : decoder_(rethrowAsJs(
            [&] { return Decoder::openMemory(bytesOf(bytes), bytes.size(), name, true); })) {}
  explicit WasmDecoder(Decoder decoder) : decoder_(std::move(decoder)) {}

  // Decoder.growing(name): a stream whose bytes arrive by append() and end with finish()
  // (tdvo::Decoder::openArriving). The caller delete()s it.
  static WasmDecoder* growing(const std::string& name) {
    return new WasmDecoder(Decoder::openArriving(name));
  }
  void append(const std::string& bytes) {
    rethrowAsJs([&] { decoder_.append(bytesOf(bytes), bytes.size()); });
  }
  void finish() {
    rethrowAsJs([&] { decoder_.finish(); });
  }
  double bytesReceived() const { return static_cast<double>(decoder_.bytesArrived()); }
  bool headerReady() {
    return rethrowAsJs([&] { return decoder_.headerArrived(); });
  }
  bool canDecodeNext() {
    return rethrowAsJs([&] { return decoder_.canDecodeNext(); });
  }

  // {syntaxVersion, firstFrame, frameCount, frameRate, cameraCount, grid: {origin, step, bits},
  //  cameras: [{name, width, height, fx, fy, cx, cy, distortion, R, t, box}], description, up}
  emscripten::val info() const {
    const StreamInfo& i = rethrowAsJs([&]() -> const StreamInfo& { return decoder_.info(); });
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
    emscripten::val cameras = emscripten::val::array();
    for (const CameraParameters& c : i.cameras)
      cameras.call<void>("push", cameraObject(c));
    out.set("cameras", cameras);
    out.set("description", i.description);
    out.set("up", i.upPresent ? array(i.up.data(), 3) : emscripten::val::null());
    return out;
  }

  // Frames then carry their texture access units (textureUnits); before the first next().
  void setTextureUnits(bool keep) { decoder_.setTextureAccessUnits(keep); }

  // Decodes the next frame; false after the last one.
  bool next() {
    return rethrowAsJs([&] {
      if (!decoder_.next(frame_)) return false;
      // WebGL takes float32 vertices: the frame's double positions, rounded once here.
      positions32_.resize(frame_.positions.size() * 3);
      for (size_t v = 0; v < frame_.positions.size(); ++v)
        for (size_t c = 0; c < 3; ++c)
          positions32_[3 * v + c] = static_cast<float>(frame_.positions[v][c]);
      return true;
    });
  }

  double frameNumber() const { return static_cast<double>(frame_.number); }
  unsigned frameIndex() const { return frame_.index; }
  unsigned vertexCount() const { return static_cast<unsigned>(frame_.mesh.positions.size()); }
  unsigned triangleCount() const { return static_cast<unsigned>(frame_.mesh.triangles.size()); }

  // Float32Array, x y z per vertex: the positions (origin + q * step, computed in double and
  // rounded to float for WebGL; gridPositions() and the grid give them exactly).
  emscripten::val positions() const {
    return emscripten::val(emscripten::typed_memory_view(
        positions32_.size(), positions32_.empty() ? nullptr : positions32_.data()));
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

  // With setTextureUnits(true): camera c's H.264 access units (Annex B) to decode before this
  // frame is shown, an Array of Uint8Array views: the frame's own, last (after a seek into a
  // GOM, the GOM's earlier ones before it, from its IDR picture on).
  emscripten::val textureUnits(unsigned camera) const {
    emscripten::val out = emscripten::val::array();
    if (camera < frame_.textures.size())
      for (const std::vector<uint8_t>& unit : frame_.textures[camera].accessUnits)
        out.call<void>("push", emscripten::val(emscripten::typed_memory_view(
                                   unit.size(), unit.empty() ? nullptr : unit.data())));
    return out;
  }
  // The frame's own access unit of camera c (the last of textureUnits(c)), a Uint8Array view.
  emscripten::val textureUnit(unsigned camera) const {
    if (camera >= frame_.textures.size() || frame_.textures[camera].accessUnits.empty())
      return emscripten::val::null();
    const std::vector<uint8_t>& unit = frame_.textures[camera].accessUnits.back();
    return emscripten::val(emscripten::typed_memory_view(unit.size(), unit.data()));
  }
  // "MD5 frame=<n> texture cam=<c> <hex>", the line 3dvo-dec prints, for camera c's picture of
  // frame n (an input frame number) decoded elsewhere: `i420` its Y, U and V planes, tightly
  // packed (the texture box's size).
  std::string textureHashLine(double frameNumber, unsigned camera, const std::string& i420) const {
    return rethrowAsJs([&] {
      const StreamInfo& i = decoder_.info();
      if (camera >= i.cameras.size())
        throw Error("textureHashLine: no camera " + std::to_string(camera));
      const CameraParameters& c = i.cameras[camera];
      YuvPicture picture(c.tx_box_width, c.tx_box_height);
      const size_t luma = picture.y.size(), chroma = picture.u.size();
      if (i420.size() != luma + 2 * chroma)
        throw Error("textureHashLine: " + std::to_string(i420.size()) + " bytes for a " +
                    std::to_string(c.tx_box_width) + "x" + std::to_string(c.tx_box_height) +
                    " picture of " + std::to_string(luma + 2 * chroma));
      const uint8_t* p = bytesOf(i420);
      picture.y.assign(p, p + luma);
      picture.u.assign(p + luma, p + luma + chroma);
      picture.v.assign(p + luma + chroma, p + luma + 2 * chroma);
      return tdvo::textureHashLine(static_cast<int>(frameNumber), static_cast<int>(camera),
                                   picture);
    });
  }
  // "MD5 header=<hex>", the line 3dvo-dec prints after the frames.
  std::string headerHashLine() const {
    return rethrowAsJs([&] { return decoder_.headerHashLine(); });
  }

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
  std::vector<float> positions32_;  // frame_.positions as float32, x y z per vertex
};

// md5Hex(bytes): the MD5 of a byte string, 32 lowercase hex digits.
std::string md5Hex(const std::string& bytes) {
  Md5 md5;
  md5.update(bytes.data(), bytes.size());
  return toHex(md5.finish());
}

EMSCRIPTEN_BINDINGS(tdvo) {
  emscripten::function("md5Hex", &md5Hex);
  emscripten::class_<WasmDecoder>("Decoder")
      .constructor<const std::string&, const std::string&>()
      .class_function("growing", &WasmDecoder::growing, emscripten::allow_raw_pointers())
      .function("append", &WasmDecoder::append)
      .function("finish", &WasmDecoder::finish)
      .function("bytesReceived", &WasmDecoder::bytesReceived)
      .function("headerReady", &WasmDecoder::headerReady)
      .function("canDecodeNext", &WasmDecoder::canDecodeNext)
      .function("setTextureUnits", &WasmDecoder::setTextureUnits)
      .function("textureUnits", &WasmDecoder::textureUnits)
      .function("textureUnit", &WasmDecoder::textureUnit)
      .function("textureHashLine", &WasmDecoder::textureHashLine)
      .function("headerHashLine", &WasmDecoder::headerHashLine)
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
