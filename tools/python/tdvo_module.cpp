// The Python module's extension, tdvo._tdvo (docs/python.md): the public decoding and encoding
// API (decoder/decoder.h, encoder/encoder.h) for Python, frames as numpy arrays.
//
// Decoded frames are handed out without copying: a Frame owns its tdvo::DecodedFrame, and its
// arrays are read-only views of the frame's vectors that keep the Frame alive (numpy's base).
// Frames given to encode() are Python input like an OBJ file: every array is checked (shape,
// dtype, finite coordinates, indices in range, the OBJ reader's size limits) before anything
// is encoded, and what is wrong is named with the frame's index in the sequence. Every
// tdvo::Error becomes tdvo.Error with the message the apps print after "<app>: error: ".
// Decoding and encoding run with the GIL released.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <iterator>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "bitstream/byte_io.h"
#include "bitstream/header_hash.h"
#include "bitstream/units.h"
#include "common/core/error.h"
#include "common/core/md5.h"
#include "common/core/obj_io.h"
#include "decoder/decoder.h"
#include "decoder/stream_decoder.h"
#include "decoder/texture/h264_decoder.h"
#include "encoder/encoder.h"
#include "tools/python/frame_arrays.h"

namespace py = pybind11;

namespace tdvo::python {
namespace {

static_assert(sizeof(std::array<float, 3>) == 3 * sizeof(float), "positions are N x 3 floats");
static_assert(sizeof(Vec3i) == 3 * sizeof(int32_t), "grid positions are N x 3 int32");
static_assert(sizeof(Triangle) == 3 * sizeof(uint32_t), "triangles are M x 3 uint32");

// A read-only numpy view of `data` (rows x columns of T, C order) that keeps `owner` alive.
template <class T>
py::array view(const py::handle owner, const T* data, size_t rows, size_t columns) {
  py::array_t<T> array({static_cast<py::ssize_t>(rows), static_cast<py::ssize_t>(columns)}, data,
                       owner);
  array.attr("flags").attr("writeable") = false;
  return std::move(array);
}

template <class T>
py::array view(const py::handle owner, const std::vector<T>& data, size_t rows, size_t columns) {
  return view(owner, data.empty() ? nullptr : data.data(), rows, columns);
}

// The same for rows held as std::array<T, N>.
template <class T, size_t N>
py::array view(const py::handle owner, const std::vector<std::array<T, N>>& rows) {
  static_assert(sizeof(std::array<T, N>) == N * sizeof(T), "rows are packed");
  return view(owner, rows.empty() ? nullptr : rows[0].data(), rows.size(), N);
}

// An attribute's rows (texture coordinates, normals or their index triangles) as a view, or
// None when the frame has none.
template <class T, size_t N>
py::object viewOrNone(const py::handle owner, const std::vector<std::array<T, N>>& rows) {
  if (rows.empty()) return py::none();
  return view(owner, rows);
}

// The name of an object's type, for messages.
std::string typeName(const py::handle object) {
  return py::str(py::type::of(object).attr("__name__")).cast<std::string>();
}

// ---- Decoding ----

// Where a stream comes from: a file, or bytes in memory (kept alive here; other buffers are
// copied by the decoder, since they may change).
struct Source {
  std::optional<std::string> path;
  py::object bytes;  // a bytes object, when not copied
  py::buffer_info buffer;
  bool copy = true;
  std::string name;
};

Source sourceOf(const py::object& source, const std::optional<std::string>& name) {
  Source s;
  if (py::isinstance<py::str>(source) || py::hasattr(source, "__fspath__")) {
    s.path = py::str(py::module_::import("os").attr("fspath")(source)).cast<std::string>();
    s.name = name ? *name : *s.path;
    return s;
  }
  if (!PyObject_CheckBuffer(source.ptr()))
    throw Error("Decoder: expected a file path or a bytes-like object, got " + typeName(source));
  s.buffer = py::reinterpret_borrow<py::buffer>(source).request();
  if (s.buffer.ndim != 1 || s.buffer.itemsize != 1 || s.buffer.strides[0] != 1)
    throw Error("Decoder: the stream must be a contiguous buffer of bytes");
  s.copy = !py::isinstance<py::bytes>(source);  // bytes cannot change: no copy needed
  if (!s.copy) s.bytes = source;
  s.name = name ? *name : "stream";
  return s;
}

// The stream's "MD5 header=..." line, from its first unit.
std::string headerHashLine(const Source& source) {
  std::unique_ptr<UnitSource> units;
  if (source.path)
    units = std::make_unique<UnitFileReader>(*source.path, source.name);
  else
    units = std::make_unique<UnitReader>(static_cast<const uint8_t*>(source.buffer.ptr),
                                         static_cast<size_t>(source.buffer.size), source.name);
  UnitView unit;
  check(units->next(unit) && unit.type == static_cast<uint8_t>(UnitType::kSequenceHeader),
        source.name + ": the stream does not start with a SEQUENCE_HEADER unit");
  ByteReader bytes(unit.payload, unit.size, source.name, unit.payloadOffset);
  SequenceHeader sh;
  transfer(bytes, sh);
  return sequenceHeaderHashLine(sh);
}

// One decoded frame, owned by its Python object.
struct Frame {
  DecodedFrame frame;
  std::vector<std::string> textureLines() const {
    std::vector<std::string> lines;
    for (const DecodedTexture& t : frame.textures)
      lines.push_back(textureHashLine(static_cast<int>(frame.number), t.camera, t.picture));
    return lines;
  }
};

class PyDecoder {
 public:
  PyDecoder(const py::object& source, bool textures, const std::optional<std::string>& name,
            std::optional<uint64_t> maxVertexFramesPerByte,
            std::optional<uint64_t> maxMeshMemoryPerByte,
            std::optional<uint64_t> maxTexturePixelsPerByte)
      : source_(sourceOf(source, name)) {
    py::gil_scoped_release unlocked;
    if (source_.path)
      decoder_ = std::make_unique<Decoder>(Decoder::openFile(*source_.path, source_.name));
    else
      decoder_ = std::make_unique<Decoder>(Decoder::openMemory(
          static_cast<const uint8_t*>(source_.buffer.ptr), static_cast<size_t>(source_.buffer.size),
          source_.name, source_.copy));
    if (textures) decoder_->setPictureDecoder(makeH264Decoder);
    if (maxVertexFramesPerByte) decoder_->setMaxVertexFramesPerByte(*maxVertexFramesPerByte);
    if (maxMeshMemoryPerByte) decoder_->setMaxMeshMemoryPerByte(*maxMeshMemoryPerByte);
    if (maxTexturePixelsPerByte) decoder_->setMaxTexturePixelsPerByte(*maxTexturePixelsPerByte);
  }

  const StreamInfo& info() const { return decoder_->info(); }

  // The next frame, or nullptr after the last one.
  std::unique_ptr<Frame> next() {
    auto frame = std::make_unique<Frame>();
    bool more;
    {
      py::gil_scoped_release unlocked;
      const std::lock_guard<std::mutex> lock(busy_);
      more = decoder_->next(frame->frame);
    }
    if (!more) return nullptr;
    return frame;
  }

  std::vector<int64_t> gomStarts() {
    py::gil_scoped_release unlocked;
    const std::lock_guard<std::mutex> lock(busy_);
    return decoder_->gomStarts();
  }

  void seek(int64_t frameNumber) {
    py::gil_scoped_release unlocked;
    const std::lock_guard<std::mutex> lock(busy_);
    decoder_->seek(frameNumber);
  }

  const std::string& headerLine() {
    if (headerLine_.empty()) headerLine_ = headerHashLine(source_);
    return headerLine_;
  }

 private:
  Source source_;
  std::unique_ptr<Decoder> decoder_;
  std::string headerLine_;
  // Held while the decoder works without the GIL: two Python threads sharing one Decoder take
  // turns instead of racing.
  std::mutex busy_;
};

// Every MD5 line 3dvo-dec prints for a stream, in its order (a GOM's geometry lines, then its
// texture lines; the header line last), from the push decoder 3dvo-dec runs.
std::vector<std::string> md5Lines(const py::object& source, bool textures,
                                  const std::optional<std::string>& name) {
  const Source s = sourceOf(source, name);
  std::vector<std::string> lines;
  py::gil_scoped_release unlocked;
  std::unique_ptr<UnitFileReader> units;
  std::unique_ptr<StreamDecoder> decoder;
  if (s.path) {
    units = std::make_unique<UnitFileReader>(*s.path, s.name);
    decoder = std::make_unique<StreamDecoder>(*units, s.name);
  } else {
    decoder = std::make_unique<StreamDecoder>(static_cast<const uint8_t*>(s.buffer.ptr),
                                              static_cast<size_t>(s.buffer.size), s.name);
  }
  if (textures) decoder->setPictureDecoder(makeH264Decoder);
  auto number = [&](int k) {
    return static_cast<int>(decoder->sequenceHeader().sh_first_frame + static_cast<uint32_t>(k));
  };
  decoder->decode(
      [&](int frame, const IntMesh& mesh) {
        lines.push_back(geometryHashLine(number(frame), mesh));
      },
      textures
          ? TextureCallback([&](int frame, int camera, const YuvPicture& picture, const Image&) {
              lines.push_back(textureHashLine(number(frame), camera, picture));
            })
          : TextureCallback());
  lines.push_back(sequenceHeaderHashLine(decoder->sequenceHeader()));
  return lines;
}

// ---- Encoding ----

// Python's text for a cfg value: str as it is, bool as true/false, numbers as Python prints
// them (the shortest text that reads back to the same double).
std::string cfgValue(const std::string& key, const py::handle value) {
  if (py::isinstance<py::str>(value)) return value.cast<std::string>();
  if (py::isinstance<py::bool_>(value)) return value.cast<bool>() ? "true" : "false";
  if (py::isinstance<py::int_>(value) || py::isinstance<py::float_>(value) ||
      py::hasattr(value, "__index__") || py::hasattr(value, "__float__"))
    return py::str(value).cast<std::string>();
  if (py::hasattr(value, "__fspath__"))
    return py::str(py::module_::import("os").attr("fspath")(value)).cast<std::string>();
  throw Error("cfg: " + key + ": a " + typeName(value) +
              " is not a cfg value (str, int, float, bool or a path)");
}

// One input frame's arrays: positions and triangles, from a pair or an object with those
// attributes (e.g. a decoded tdvo.Frame).
// item.name, or None when item has no such attribute. An exception the attribute itself raises
// (a property that fails) is the caller's to see: py::hasattr would swallow it, and the frame
// would be refused for a reason that is not the user's.
py::object attributeOrNone(const py::handle item, const char* name) {
  PyObject* value = PyObject_GetAttrString(item.ptr(), name);
  if (value) return py::reinterpret_steal<py::object>(value);
  if (!PyErr_ExceptionMatches(PyExc_AttributeError)) throw py::error_already_set();
  PyErr_Clear();
  return py::none();
}

std::pair<py::object, py::object> frameArrays(const py::handle item, const std::string& frame) {
  if (py::isinstance<py::tuple>(item) || py::isinstance<py::list>(item)) {
    const py::sequence pair = py::reinterpret_borrow<py::sequence>(item);
    if (pair.size() != 2)
      throw Error(frame + ": expected (positions, triangles), got a sequence of " +
                  std::to_string(pair.size()) + " items");
    return {pair[0], pair[1]};
  }
  // Never dropped silently: an object carrying texture coordinates or normals is refused.
  for (const char* attribute : {"uvs", "normals"})
    if (!attributeOrNone(item, attribute).is_none())
      throw Error(frame + ": has " +
                  (std::string(attribute) == "uvs" ? "texture coordinates" : "normals") +
                  ", which tdvo.encode does not take yet (docs/python.md); pass (positions, "
                  "triangles) to code the geometry alone");
  py::object positions = attributeOrNone(item, "positions");
  py::object triangles = attributeOrNone(item, "triangles");
  if (!positions.is_none() && !triangles.is_none()) return {positions, triangles};
  throw Error(frame +
              ": expected (positions, triangles) or an object with .positions and .triangles, "
              "got " +
              typeName(item));
}

// `object` as a numpy array whose memory frameMesh reads: numpy's own where it can (no copy),
// else converted (nested lists; float16, long double or another byte order to 64 bits).
py::array readableArray(const py::object& object, const std::string& where) {
  py::array a = py::array::ensure(object);
  if (!a) throw Error(where + ": not an array (" + typeName(object) + ")");
  const char kind = a.dtype().kind();
  const bool native = a.dtype().attr("isnative").cast<bool>();
  if ((kind == 'f' || kind == 'i' || kind == 'u') &&
      (!native || !readableElement(kind, static_cast<int>(a.itemsize()))))
    a = a.attr("astype")(kind == 'f' ? "float64" : kind == 'i' ? "int64" : "uint64");
  return a;
}

ArrayView arrayView(const py::array& a) {
  ArrayView v;
  v.kind = a.dtype().kind();
  v.itemSize = static_cast<int>(a.itemsize());
  v.dtypeName = py::str(a.dtype()).cast<std::string>();
  for (py::ssize_t d = 0; d < a.ndim(); ++d) {
    v.shape.push_back(a.shape(d));
    v.strides.push_back(a.strides(d));
  }
  v.data = static_cast<const uint8_t*>(a.data());
  return v;
}

Mesh toMesh(const py::handle item, size_t k) {
  const std::string frame = "frame " + std::to_string(k);
  const auto [positionsObject, trianglesObject] = frameArrays(item, frame);
  const py::array positions = readableArray(positionsObject, frame + ": positions");
  const py::array triangles = readableArray(trianglesObject, frame + ": triangles");
  const ArrayView p = arrayView(positions), t = arrayView(triangles);
  py::gil_scoped_release unlocked;  // the arrays stay referenced above
  return frameMesh(p, t, frame);
}

struct Encoded {
  py::bytes stream;
  std::vector<std::string> md5Lines;
  py::dict stats;
  std::string effectiveConfig;
};

Encoded encode(const py::object& frames, const std::optional<py::dict>& cfg,
               const std::vector<std::string>& cfgFiles) {
  Encoder encoder;
  for (const std::string& file : cfgFiles)
    encoder.readConfig(file);
  if (cfg)
    for (const auto& [key, value] : *cfg) {
      if (!py::isinstance<py::str>(key)) throw Error("cfg: keys must be str, got " + typeName(key));
      const std::string name = key.cast<std::string>();
      encoder.set(name, cfgValue(name, value));
    }

  if (!py::isinstance<py::sequence>(frames) || py::isinstance<py::str>(frames))
    throw Error("frames: expected a sequence of frames (a list or tuple), got " + typeName(frames));
  const py::sequence sequence = py::reinterpret_borrow<py::sequence>(frames);
  const size_t count = sequence.size();
  if (count == 0) throw Error("frames: no frames to encode");
  if (count > kMaxFrames)
    throw Error("frames: " + std::to_string(count) + " frames, more than " +
                std::to_string(kMaxFrames));
  std::vector<Mesh> meshes;
  meshes.reserve(count);
  for (size_t k = 0; k < count; ++k)
    meshes.push_back(toMesh(sequence[k], k));

  EncodedSequence coded;
  {
    py::gil_scoped_release unlocked;
    coded = encoder.encode(meshes);
  }
  Encoded out;
  out.stream = py::bytes(reinterpret_cast<const char*>(coded.stream.data()), coded.stream.size());
  out.md5Lines = std::move(coded.md5Lines);
  out.stats["header_bytes"] = coded.headerBytes;
  out.stats["i_mesh_bytes"] = coded.iMeshBytes;
  out.stats["p_mesh_bytes"] = coded.pMeshBytes;
  out.stats["texture_bytes"] = coded.textureBytes;
  out.stats["order_bytes"] = coded.orderBytes;
  out.stats["vertex_frames"] = coded.vertexFrames;
  out.stats["sum_squared_error"] = coded.sumSquaredError;
  out.stats["max_abs_error"] = coded.maxAbsError;
  out.effectiveConfig = encoder.effectiveConfig();
  return out;
}

}  // namespace
}  // namespace tdvo::python

PYBIND11_MODULE(_tdvo, m) {
  using namespace tdvo;
  using namespace tdvo::python;
  m.doc() = "3DVO: decoding and encoding of 3D video object streams (docs/python.md)";
#ifdef TDVO_VERSION
  m.attr("__version__") = TDVO_VERSION;
#endif
  py::register_exception<Error>(m, "Error", PyExc_RuntimeError);

  py::class_<Grid>(m, "Grid", "The stream's integer grid: position = origin + q * step")
      .def_property_readonly(
          "origin",
          [](const Grid& g) { return py::make_tuple(g.origin[0], g.origin[1], g.origin[2]); })
      .def_readonly("step", &Grid::step)
      .def_readonly("bits", &Grid::bits)
      .def("__repr__", [](const Grid& g) {
        return "Grid(origin=" +
               py::repr(py::make_tuple(g.origin[0], g.origin[1], g.origin[2])).cast<std::string>() +
               ", step=" + py::repr(py::float_(g.step)).cast<std::string>() +
               ", bits=" + std::to_string(g.bits) + ")";
      });

  py::class_<CameraParameters>(m, "Camera", "A camera of the stream (docs/cameras.md)")
      .def_readonly("name", &CameraParameters::cam_name)
      .def_property_readonly("width", [](const CameraParameters& c) { return c.cam_width; })
      .def_property_readonly("height", [](const CameraParameters& c) { return c.cam_height; })
      .def_property_readonly("K",
                             [](const CameraParameters& c) {
                               py::array_t<double> k({3, 3});
                               auto r = k.mutable_unchecked<2>();
                               const double v[9] = {c.cam_fx, 0, c.cam_cx, 0, c.cam_fy,
                                                    c.cam_cy, 0, 0,        1};
                               for (int i = 0; i < 9; ++i)
                                 r(i / 3, i % 3) = v[i];
                               return k;
                             })
      .def_property_readonly("R",
                             [](const CameraParameters& c) {
                               py::array_t<double> rotation({3, 3});
                               std::copy(std::begin(c.cam_rotation), std::end(c.cam_rotation),
                                         rotation.mutable_data());
                               return rotation;
                             })
      .def_property_readonly("t",
                             [](const CameraParameters& c) {
                               py::array_t<double> t(3);
                               std::copy(std::begin(c.cam_translation), std::end(c.cam_translation),
                                         t.mutable_data());
                               return t;
                             })
      .def_property_readonly("distortion",
                             [](const CameraParameters& c) {
                               return py::make_tuple(c.cam_k1, c.cam_k2, c.cam_p1, c.cam_p2,
                                                     c.cam_k3);
                             })
      .def_property_readonly("texture_box",
                             [](const CameraParameters& c) {
                               return py::make_tuple(c.tx_box_x, c.tx_box_y, c.tx_box_width,
                                                     c.tx_box_height);
                             })
      .def("__repr__", [](const CameraParameters& c) {
        return "Camera(" + py::repr(py::str(c.cam_name)).cast<std::string>() + ", " +
               std::to_string(c.cam_width) + "x" + std::to_string(c.cam_height) + ")";
      });

  py::class_<StreamInfo>(m, "StreamInfo", "What the sequence header says")
      .def_readonly("syntax_version", &StreamInfo::syntaxVersion)
      .def_readonly("first_frame", &StreamInfo::firstFrame)
      .def_readonly("frame_count", &StreamInfo::frameCount)
      .def_readonly("frame_rate", &StreamInfo::frameRate)
      .def_readonly("grid", &StreamInfo::grid)
      .def_readonly("cameras", &StreamInfo::cameras)
      .def_readonly("description", &StreamInfo::description)
      .def_property_readonly("up",
                             [](const StreamInfo& i) -> py::object {
                               if (!i.upPresent) return py::none();
                               return py::make_tuple(i.up[0], i.up[1], i.up[2]);
                             })
      .def_property_readonly("frame_numbers", [](const StreamInfo& i) {
        return py::module_::import("builtins")
            .attr("range")(i.firstFrame, i.firstFrame + static_cast<int64_t>(i.frameCount));
      });

  py::class_<DecodedTexture>(m, "Texture", "One camera's decoded texture picture of a frame")
      .def_readonly("camera", &DecodedTexture::camera)
      .def_property_readonly("box",
                             [](const DecodedTexture& t) {
                               return py::make_tuple(t.box.x, t.box.y, t.box.width, t.box.height);
                             })
      .def_property_readonly("y",
                             [](py::handle self) {
                               const auto& p = self.cast<const DecodedTexture&>().picture;
                               return view(self, p.y, p.height, p.width);
                             })
      .def_property_readonly("u",
                             [](py::handle self) {
                               const auto& p = self.cast<const DecodedTexture&>().picture;
                               return view(self, p.u, p.chromaHeight(), p.chromaWidth());
                             })
      .def_property_readonly("v",
                             [](py::handle self) {
                               const auto& p = self.cast<const DecodedTexture&>().picture;
                               return view(self, p.v, p.chromaHeight(), p.chromaWidth());
                             })
      .def_property_readonly("shape", [](py::handle self) {
        const Image& s = self.cast<const DecodedTexture&>().shape;
        return view(self, s.pixels, s.height, static_cast<size_t>(s.width) * s.channels);
      });

  py::class_<Frame>(m, "Frame", "One decoded frame; its arrays are read-only views")
      .def_property_readonly("number", [](const Frame& f) { return f.frame.number; })
      .def_property_readonly("index", [](const Frame& f) { return f.frame.index; })
      .def_property_readonly("positions",
                             [](py::handle self) {
                               const auto& f = self.cast<const Frame&>().frame;
                               return view(self, f.positions);
                             })
      .def_property_readonly("grid_positions",
                             [](py::handle self) {
                               const auto& f = self.cast<const Frame&>().frame;
                               return view(self, f.mesh.positions);
                             })
      .def_property_readonly("triangles",
                             [](py::handle self) {
                               const auto& f = self.cast<const Frame&>().frame;
                               return view(self, f.mesh.triangles);
                             })
      // Texture coordinates and normals (docs/user-guide.md): per corner, as OBJ's f v/vt/vn:
      // triangle t's corner c has uvs[uv_triangles[t, c]]; None when the stream has none.
      .def_property_readonly("uvs",
                             [](py::handle self) {
                               const auto& f = self.cast<const Frame&>().frame;
                               return viewOrNone(self, f.mesh.attributes.uvs);
                             })
      // Where v = 0 lies in the texture image, as the input gave it: "bottom" (OBJ, PLY) or
      // "top" (glTF); None without texture coordinates.
      .def_property_readonly("uv_origin",
                             [](py::handle self) -> py::object {
                               const auto& a = self.cast<const Frame&>().frame.mesh.attributes;
                               if (!a.hasUvs()) return py::none();
                               return py::str(a.uvOrigin == UvOrigin::kTop ? "top" : "bottom");
                             })
      .def_property_readonly("uv_triangles",
                             [](py::handle self) {
                               const auto& f = self.cast<const Frame&>().frame;
                               return viewOrNone(self, f.mesh.attributes.uvTriangles);
                             })
      .def_property_readonly("normals",
                             [](py::handle self) {
                               const auto& f = self.cast<const Frame&>().frame;
                               return viewOrNone(self, f.mesh.attributes.normals);
                             })
      .def_property_readonly("normal_triangles",
                             [](py::handle self) {
                               const auto& f = self.cast<const Frame&>().frame;
                               return viewOrNone(self, f.mesh.attributes.normalTriangles);
                             })
      .def_property_readonly(
          "textures",
          [](py::handle self) {
            auto& f = self.cast<Frame&>().frame;
            py::list list;
            for (DecodedTexture& t : f.textures)
              list.append(py::cast(&t, py::return_value_policy::reference_internal, self));
            return list;
          })
      .def_property_readonly("md5_line", [](const Frame& f) { return f.frame.geometryHashLine(); })
      .def_property_readonly("texture_md5_lines", &Frame::textureLines)
      .def("__repr__", [](const Frame& f) {
        return "Frame(number=" + std::to_string(f.frame.number) + ", " +
               std::to_string(f.frame.mesh.positions.size()) + " vertices, " +
               std::to_string(f.frame.mesh.triangles.size()) + " triangles, " +
               std::to_string(f.frame.textures.size()) + " textures)";
      });

  py::class_<PyDecoder>(m, "Decoder", "A .3dvo stream, frame by frame (docs/python.md)")
      .def(py::init<const py::object&, bool, const std::optional<std::string>&,
                    std::optional<uint64_t>, std::optional<uint64_t>, std::optional<uint64_t>>(),
           py::arg("source"), py::kw_only(), py::arg("textures") = true,
           py::arg("name") = py::none(), py::arg("max_vertex_frames_per_byte") = py::none(),
           py::arg("max_mesh_memory_per_byte") = py::none(),
           py::arg("max_texture_pixels_per_byte") = py::none())
      .def_property_readonly("info", &PyDecoder::info, py::return_value_policy::reference_internal)
      .def_property_readonly("gom_starts", &PyDecoder::gomStarts)
      .def_property_readonly("header_md5_line", &PyDecoder::headerLine)
      .def("seek", &PyDecoder::seek, py::arg("frame_number"))
      .def("__iter__", [](py::handle self) { return self; })
      .def("__next__",
           [](PyDecoder& d) {
             std::unique_ptr<Frame> frame = d.next();
             if (!frame) throw py::stop_iteration();
             return frame;
           })
      .def("read", &PyDecoder::next, "The next frame, or None after the last one");

  m.def("md5_lines", &md5Lines, py::arg("source"), py::kw_only(), py::arg("textures") = true,
        py::arg("name") = py::none(),
        "Every MD5 line 3dvo-dec prints for the stream, in its order");

  py::class_<Encoded>(m, "Encoded", "An encoded stream and what the encoder reports about it")
      .def_readonly("stream", &Encoded::stream)
      .def_readonly("md5_lines", &Encoded::md5Lines)
      .def_readonly("stats", &Encoded::stats)
      .def_readonly("effective_config", &Encoded::effectiveConfig);

  m.def("encode", &encode, py::arg("frames"), py::arg("cfg") = py::none(), py::kw_only(),
        py::arg("cfg_files") = std::vector<std::string>(),
        "Encodes frames (pairs of positions N x 3 and triangles M x 3) with 3dvo-enc's cfg keys");
}
