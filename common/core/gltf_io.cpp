#include "common/core/gltf_io.h"

#include <sys/stat.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <string_view>
#include <tuple>
#include <utility>

#include "common/core/error.h"
#include "common/core/file_io.h"
#include "common/core/mesh_attributes.h"
#include "common/core/number_text.h"
#include "common/core/tiny_gltf_config.h"
#include "common/core/warnings.h"

namespace tdvo {

namespace {

// ---- Limits checked before tinygltf sees the JSON ----

// Counts the JSON's values and depth without building it (nlohmann's SAX interface).
class JsonLimits : public nlohmann::json_sax<nlohmann::json> {
 public:
  std::string error;
  bool null() override { return value(); }
  bool boolean(bool) override { return value(); }
  bool number_integer(number_integer_t) override { return value(); }
  bool number_unsigned(number_unsigned_t) override { return value(); }
  bool number_float(number_float_t, const string_t&) override { return value(); }
  bool string(string_t&) override { return value(); }
  bool binary(binary_t&) override { return value(); }
  bool start_object(std::size_t) override { return open(); }
  bool key(string_t&) override { return true; }
  bool end_object() override { return close(); }
  bool start_array(std::size_t) override { return open(); }
  bool end_array() override { return close(); }
  bool parse_error(std::size_t position, const std::string&,
                   const nlohmann::detail::exception& e) override {
    error = "JSON byte " + std::to_string(position) + ": " + e.what();
    return false;
  }

 private:
  bool value() {
    if (++values_ > kMaxGltfJsonValues) {
      error = "more than " + std::to_string(kMaxGltfJsonValues) + " JSON values";
      return false;
    }
    return true;
  }
  bool open() {
    if (++depth_ > kMaxGltfJsonDepth) {
      error = "JSON nested more than " + std::to_string(kMaxGltfJsonDepth) + " levels deep";
      return false;
    }
    return value();
  }
  bool close() {
    --depth_;
    return true;
  }
  size_t values_ = 0, depth_ = 0;
};

uint32_t le32(const uint8_t* p) {
  return uint32_t{p[0]} | uint32_t{p[1]} << 8 | uint32_t{p[2]} << 16 | uint32_t{p[3]} << 24;
}

// ---- tinygltf's file access: ours, with limits ----

struct Files {
  std::string name;                        // the glTF file, for messages
  std::string folder;                      // where its external buffers are ("" = none may be read)
  std::string error;                       // our message, preferred to tinygltf's
  std::set<std::pair<dev_t, ino_t>> read;  // files read, each once
};

// Whether relative path `rel` stays in its folder: no ".." component leads above it.
bool staysInFolder(const std::string& rel) {
  long depth = 0;
  size_t begin = 0;
  while (begin <= rel.size()) {
    size_t end = rel.find('/', begin);
    if (end == std::string::npos) end = rel.size();
    const std::string_view part(rel.data() + begin, end - begin);
    if (part == "..") {
      if (--depth < 0) return false;
    } else if (!part.empty() && part != ".") {
      ++depth;
    }
    begin = end + 1;
  }
  return true;
}

bool fileExists(const std::string& path, void* user) {
  Files& files = *static_cast<Files*>(user);
  if (files.folder.empty()) return false;
  // Only files in the glTF file's folder or below it (tinygltf also tries the working
  // directory): a buffer uri such as "../../home/x" is refused, not read into the mesh.
  if (path.compare(0, files.folder.size() + 1, files.folder + "/") != 0) return false;
  if (!staysInFolder(path.substr(files.folder.size() + 1))) {
    if (files.error.empty())
      files.error = "'" + path.substr(files.folder.size() + 1) +
                    "' is outside the glTF file's folder (a buffer file must be in it or below it)";
    return false;
  }
  struct stat st;
  return ::stat(path.c_str(), &st) == 0;
}

std::string expandPath(const std::string& path, void*) {
  return path;
}

bool readWholeFile(std::vector<unsigned char>* out, std::string* err, const std::string& path,
                   void* user) {
  Files& files = *static_cast<Files*>(user);
  try {
    struct stat st;
    check(::stat(path.c_str(), &st) == 0, path + ": cannot open");
    check(files.read.insert({st.st_dev, st.st_ino}).second,
          path + ": named by two buffers (each buffer file is read once)");
    *out = readFileBytes(path, kMaxBinaryFileBytes, "a glTF buffer");
    return true;
  } catch (const Error& e) {
    files.error = e.what();
    if (err) *err = e.what();
    return false;
  }
}

bool writeWholeFile(std::string* err, const std::string&, const std::vector<unsigned char>&,
                    void*) {
  if (err) *err = "not written";
  return false;
}

// Images are not read (3DVO codes geometry).
bool ignoreImage(tinygltf::Image*, const int, std::string*, std::string*, int, int,
                 const unsigned char*, int, void*) {
  return true;
}

// The first line of a (multi-line) tinygltf message.
std::string firstLine(std::string s) {
  while (!s.empty() && (s.back() == '\n' || s.back() == '\r'))
    s.pop_back();
  const size_t nl = s.find('\n');
  if (nl != std::string::npos) s = s.substr(0, nl);
  return s;
}

// ---- Accessors, read with our own bounds checks ----

struct View {
  const uint8_t* data = nullptr;
  size_t count = 0, stride = 0, components = 0;
  int componentType = 0;
  bool normalized = false;

  double get(size_t i, size_t c) const {
    const uint8_t* p = data + i * stride;
    switch (componentType) {
      case TINYGLTF_COMPONENT_TYPE_FLOAT: {
        float v;
        std::memcpy(&v, p + 4 * c, 4);
        return v;
      }
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: {
        const double v = p[c];
        return normalized ? v / 255.0 : v;
      }
      case TINYGLTF_COMPONENT_TYPE_BYTE: {
        const double v = static_cast<int8_t>(p[c]);
        return normalized ? std::max(v / 127.0, -1.0) : v;
      }
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
        uint16_t v;
        std::memcpy(&v, p + 2 * c, 2);
        return normalized ? v / 65535.0 : v;
      }
      case TINYGLTF_COMPONENT_TYPE_SHORT: {
        int16_t v;
        std::memcpy(&v, p + 2 * c, 2);
        return normalized ? std::max(v / 32767.0, -1.0) : v;
      }
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: {
        uint32_t v;
        std::memcpy(&v, p + 4 * c, 4);
        return v;
      }
    }
    return 0;
  }
  // Value f of the accessor's values taken as one flat list.
  double flat(size_t f) const { return get(f / components, f % components); }
  uint32_t index(size_t i) const {
    const uint8_t* p = data + i * stride;
    if (componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE) return p[0];
    if (componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT) {
      uint16_t v;
      std::memcpy(&v, p, 2);
      return v;
    }
    uint32_t v;
    std::memcpy(&v, p, 4);
    return v;
  }
};

size_t componentBytes(int type) {
  switch (type) {
    case TINYGLTF_COMPONENT_TYPE_BYTE:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
      return 1;
    case TINYGLTF_COMPONENT_TYPE_SHORT:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
      return 2;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
    case TINYGLTF_COMPONENT_TYPE_FLOAT:
      return 4;
  }
  return 0;
}

size_t typeComponents(int type) {
  switch (type) {
    case TINYGLTF_TYPE_SCALAR:
      return 1;
    case TINYGLTF_TYPE_VEC2:
      return 2;
    case TINYGLTF_TYPE_VEC3:
      return 3;
    case TINYGLTF_TYPE_VEC4:
      return 4;
  }
  return 0;
}

float toFloat(double v) {
  return static_cast<float>(v);
}

// ---- Node transforms ----

// An affine transform: rows of [A | t], x' = A x + t.
struct Affine {
  double m[3][4] = {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}};

  bool identity() const {
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 4; ++c)
        if (m[r][c] != (r == c ? 1.0 : 0.0)) return false;
    return true;
  }
  Affine operator*(const Affine& b) const {
    Affine out;
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 4; ++c)
        out.m[r][c] = m[r][0] * b.m[0][c] + m[r][1] * b.m[1][c] + m[r][2] * b.m[2][c] +
                      (c == 3 ? m[r][3] : 0.0);
    return out;
  }
  Vec3d point(const Vec3d& p) const {
    Vec3d out;
    for (int r = 0; r < 3; ++r)
      out[r] = m[r][0] * p[0] + m[r][1] * p[1] + m[r][2] * p[2] + m[r][3];
    return out;
  }
  double determinant() const {
    return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
           m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
           m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
  }
  // A normal's direction after the transform: the inverse transpose of A, here its cofactor
  // matrix (det(A) times it) with det's sign, then normalised (a zero normal stays zero).
  Vec3f normal(const Vec3f& n) const {
    auto cof = [&](int r, int c) {
      const int r1 = (r + 1) % 3, r2 = (r + 2) % 3, c1 = (c + 1) % 3, c2 = (c + 2) % 3;
      return m[r1][c1] * m[r2][c2] - m[r1][c2] * m[r2][c1];
    };
    const double sign = determinant() < 0 ? -1.0 : 1.0;
    double out[3], length = 0;
    for (int r = 0; r < 3; ++r) {
      out[r] = sign * (cof(r, 0) * n[0] + cof(r, 1) * n[1] + cof(r, 2) * n[2]);
      length += out[r] * out[r];
    }
    length = std::sqrt(length);
    if (!(length > 0)) return {0, 0, 0};
    return {toFloat(out[0] / length), toFloat(out[1] / length), toFloat(out[2] / length)};
  }
};

// glTF's node transform: its matrix (column-major), else T * R * S (rotation a unit quaternion
// x, y, z, w).
Affine nodeTransform(const std::vector<double>& matrix, const std::vector<double>& t,
                     const std::vector<double>& q, const std::vector<double>& s) {
  Affine a;
  if (matrix.size() == 16) {
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 4; ++c)
        a.m[r][c] = matrix[static_cast<size_t>(4 * c + r)];
    return a;
  }
  if (q.size() == 4) {
    const double x = q[0], y = q[1], z = q[2], w = q[3];
    const double r[3][3] = {{1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)},
                            {2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)},
                            {2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)}};
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        a.m[i][j] = r[i][j];
  }
  if (s.size() == 3)
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        a.m[i][j] *= s[static_cast<size_t>(j)];
  if (t.size() == 3)
    for (int i = 0; i < 3; ++i)
      a.m[i][3] = t[static_cast<size_t>(i)];
  return a;
}

// q scaled to unit length (quaternions are normalised before use, as glTF viewers do).
std::vector<double> unitQuaternion(std::vector<double> q) {
  const double length = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  for (double& c : q)
    c /= length;
  return q;
}

}  // namespace

struct GltfFile::Impl {
  std::string name;
  tinygltf::Model model;
  uint64_t inputBytes = 0;   // the file's bytes
  uint64_t bufferBytes = 0;  // all buffers' bytes
  // The scene's nodes, depth first from its root nodes in the order listed (children in
  // order): each node once, its parent instance before it (-1 for a root).
  struct Instance {
    int node;
    int parent;
  };
  std::vector<Instance> instances;
  std::vector<int> meshNodes;  // instances with a mesh; without nodes, -1 - mesh index
  bool animated = false;
  std::vector<float> times;
  std::map<int, std::vector<float>> inputs;  // sampler input accessor -> key times
  // node -> sampler of animation 0, per animated property
  std::map<int, int> weightsSampler, scaleSampler, translationSampler, rotationSampler;

  // A primitive's TEXCOORD_0 (float, or normalized unsigned byte or short) for its `count`
  // vertices, appended to `uvs`.
  void readUvs(const tinygltf::Primitive& prim, size_t count, const std::string& what,
               std::vector<Vec2f>& uvs) const {
    const View t = view(prim.attributes.at("TEXCOORD_0"), what + " TEXCOORD_0");
    if (t.components != 2 || t.count != count)
      fail(what + " TEXCOORD_0: " + std::to_string(t.count) + " VEC" +
           std::to_string(t.components) + " elements, expected " + std::to_string(count) + " VEC2");
    for (size_t i = 0; i < count; ++i) {
      const Vec2f uv{toFloat(t.get(i, 0)), toFloat(t.get(i, 1))};
      if (!std::isfinite(uv[0]) || !std::isfinite(uv[1]))
        fail(what + " TEXCOORD_0: element " + std::to_string(i) + " is not finite");
      uvs.push_back(uv);
    }
  }

  // A primitive's NORMAL (float VEC3) for its `count` vertices, with its morph targets' NORMAL
  // displacements at `weights` (as the positions'), appended to `normals`.
  void readNormals(const tinygltf::Primitive& prim, size_t count,
                   const std::vector<double>& weights, const std::string& what,
                   std::vector<Vec3f>& normals) const {
    const View n = view(prim.attributes.at("NORMAL"), what + " NORMAL");
    if (n.components != 3 || n.count != count)
      fail(what + " NORMAL: " + std::to_string(n.count) + " VEC" + std::to_string(n.components) +
           " elements, expected " + std::to_string(count) + " VEC3");
    const size_t base = normals.size();
    for (size_t i = 0; i < count; ++i)
      normals.push_back({toFloat(n.get(i, 0)), toFloat(n.get(i, 1)), toFloat(n.get(i, 2))});
    for (size_t j = 0; j < prim.targets.size(); ++j) {
      const double w = j < weights.size() ? weights[j] : 0.0;
      const auto tn = prim.targets[j].find("NORMAL");
      if (w == 0 || tn == prim.targets[j].end()) continue;
      const std::string twhat = what + " target " + std::to_string(j) + " NORMAL";
      const View d = view(tn->second, twhat);
      if (d.components != 3 || d.count != count)
        fail(twhat + ": " + std::to_string(d.count) + " elements, the base has " +
             std::to_string(count));
      for (size_t i = 0; i < count; ++i)
        for (size_t c = 0; c < 3; ++c)
          normals[base + i][c] = toFloat(normals[base + i][c] + w * d.get(i, c));
    }
    for (size_t i = base; i < normals.size(); ++i)
      for (float c : normals[i])
        if (!std::isfinite(c))
          fail(what + " NORMAL: element " + std::to_string(i - base) + " is not finite");
  }

  [[noreturn]] void fail(const std::string& what) const { throw Error(name + ": " + what); }
  // "frame k: " in a sequence file's messages, nothing in a still file's.
  std::string frameLabel(size_t k) const {
    return animated ? "frame " + std::to_string(k) + ": " : std::string();
  }

  View view(int index, const std::string& what) const {
    if (index < 0 || static_cast<size_t>(index) >= model.accessors.size())
      fail(what + ": accessor " + std::to_string(index) + " does not exist");
    const tinygltf::Accessor& a = model.accessors[static_cast<size_t>(index)];
    const std::string where = what + " (accessor " + std::to_string(index) + ")";
    if (a.sparse.isSparse) fail(where + ": sparse accessors are not read");
    View v;
    v.count = a.count;
    v.components = typeComponents(a.type);
    v.componentType = a.componentType;
    v.normalized = a.normalized;
    const size_t bytes = componentBytes(a.componentType);
    if (v.components == 0 || bytes == 0) fail(where + ": unsupported type");
    if (a.count == 0) return v;
    if (a.bufferView < 0 || static_cast<size_t>(a.bufferView) >= model.bufferViews.size())
      fail(where + ": no bufferView (only accessors with data are read)");
    const tinygltf::BufferView& bv = model.bufferViews[static_cast<size_t>(a.bufferView)];
    if (bv.buffer < 0 || static_cast<size_t>(bv.buffer) >= model.buffers.size())
      fail(where + ": bufferView " + std::to_string(a.bufferView) + " names no buffer");
    const std::vector<unsigned char>& data = model.buffers[static_cast<size_t>(bv.buffer)].data;
    if (bv.byteOffset > data.size() || bv.byteLength > data.size() - bv.byteOffset)
      fail(where + ": bufferView " + std::to_string(a.bufferView) + " runs past its buffer");
    const size_t element = v.components * bytes;
    v.stride = bv.byteStride ? bv.byteStride : element;
    if (v.stride < element) fail(where + ": byteStride smaller than an element");
    // byteOffset + stride * (count - 1) + element <= byteLength, without overflow.
    const uint64_t length = bv.byteLength;
    if (a.byteOffset > length || element > length - a.byteOffset ||
        (a.count - 1) > (length - a.byteOffset - element) / v.stride)
      fail(where + ": " + std::to_string(a.count) + " elements run past bufferView " +
           std::to_string(a.bufferView));
    v.data = data.data() + bv.byteOffset + a.byteOffset;
    return v;
  }

  // The mesh of meshNodes' entry n.
  int meshOf(int n) const {
    return n < 0 ? -1 - n : model.nodes[static_cast<size_t>(instances[size_t(n)].node)].mesh;
  }

  // instances and meshNodes: the default scene's node trees (scene 0 when the file names none;
  // without scenes, every node that is no node's child, in node order).
  void loadScene() {
    const size_t numNodes = model.nodes.size();
    if (numNodes == 0) return;
    std::vector<int> roots;
    if (!model.scenes.empty()) {
      const int scene = model.defaultScene < 0 ? 0 : model.defaultScene;
      if (static_cast<size_t>(scene) >= model.scenes.size())
        fail("scene " + std::to_string(scene) + " (the default scene) does not exist");
      roots = model.scenes[static_cast<size_t>(scene)].nodes;
    } else {
      std::vector<uint8_t> child(numNodes, 0);
      for (const tinygltf::Node& node : model.nodes)
        for (int c : node.children)
          if (c >= 0 && static_cast<size_t>(c) < numNodes) child[static_cast<size_t>(c)] = 1;
      for (size_t n = 0; n < numNodes; ++n)
        if (!child[n]) roots.push_back(static_cast<int>(n));
    }
    // Depth first without recursion (a chain of nodes may be as long as the file allows).
    std::vector<uint8_t> reached(numNodes, 0);
    std::vector<Instance> stack;
    for (auto it = roots.rbegin(); it != roots.rend(); ++it)
      stack.push_back({*it, -1});
    while (!stack.empty()) {
      const Instance at = stack.back();
      stack.pop_back();
      if (at.node < 0 || static_cast<size_t>(at.node) >= numNodes)
        fail((at.parent < 0 ? std::string("the scene")
                            : "node " + std::to_string(instances[size_t(at.parent)].node)) +
             " names node " + std::to_string(at.node) + ", which does not exist");
      if (reached[static_cast<size_t>(at.node)])
        fail("node " + std::to_string(at.node) +
             " is reached twice from the scene (nodes must form trees)");
      reached[static_cast<size_t>(at.node)] = 1;
      const tinygltf::Node& node = model.nodes[static_cast<size_t>(at.node)];
      checkTransform(node, at.node);
      const int index = static_cast<int>(instances.size());
      instances.push_back(at);
      if (node.mesh >= 0) {
        if (static_cast<size_t>(node.mesh) >= model.meshes.size())
          fail("node " + std::to_string(at.node) + ": mesh " + std::to_string(node.mesh) +
               " does not exist");
        if (node.skin >= 0)
          fail("node " + std::to_string(at.node) + ": a skinned mesh (skin " +
               std::to_string(node.skin) + ") is not read");
        meshNodes.push_back(index);
      }
      for (auto it = node.children.rbegin(); it != node.children.rend(); ++it)
        stack.push_back({*it, index});
    }
  }

  // A node's matrix or translation, rotation and scale: as many finite values as glTF says.
  void checkTransform(const tinygltf::Node& node, int n) const {
    const std::string what = "node " + std::to_string(n);
    auto values = [&](const std::vector<double>& v, size_t count, const char* name) {
      if (!v.empty() && v.size() != count)
        fail(what + ": " + name + " has " + std::to_string(v.size()) + " values, not " +
             std::to_string(count));
      for (double x : v)
        if (!std::isfinite(x)) fail(what + ": " + name + " is not finite");
    };
    values(node.matrix, 16, "matrix");
    values(node.translation, 3, "translation");
    values(node.rotation, 4, "rotation");
    values(node.scale, 3, "scale");
    if (!node.matrix.empty() && (node.matrix[3] != 0 || node.matrix[7] != 0 ||
                                 node.matrix[11] != 0 || node.matrix[15] != 1))
      fail(what + ": matrix is not affine (its last row is not 0 0 0 1)");
  }

  // What the file holds that no frame takes (materials and images, vertex attributes other than
  // POSITION, NORMAL and TEXCOORD_0, animations after the first and channels of the first on
  // other properties, extensions used), in one warning (common/core/warnings.h). Names, cameras,
  // lights and extras are not listed.
  void warnLeftOut() const {
    std::vector<std::string> parts;
    const auto count = [&](size_t n, const char* what) {
      if (n > 0) parts.push_back(std::to_string(n) + " " + what);
    };
    count(model.materials.size(), model.materials.size() == 1 ? "material" : "materials");
    count(model.textures.size(), model.textures.size() == 1 ? "texture" : "textures");
    count(model.images.size(), model.images.size() == 1 ? "image" : "images");
    std::set<std::string> attributes;
    for (int n : meshNodes)
      for (const tinygltf::Primitive& prim :
           model.meshes[static_cast<size_t>(meshOf(n))].primitives) {
        for (const auto& [attribute, accessor] : prim.attributes)
          if (attribute != "POSITION" && attribute != "NORMAL" && attribute != "TEXCOORD_0")
            attributes.insert(attribute);
        for (const auto& target : prim.targets)
          for (const auto& [attribute, accessor] : target)
            if (attribute != "POSITION" && attribute != "NORMAL")
              attributes.insert("morph target " + attribute);
      }
    if (!attributes.empty()) {
      std::string list;
      for (const std::string& a : attributes)
        list += (list.empty() ? "" : ", ") + a;
      parts.push_back("vertex attributes " + list);
    }
    // What a viewer of the default scene does not show either.
    if (model.scenes.size() > 1)
      parts.push_back(std::to_string(model.scenes.size() - 1) + " scene" +
                      (model.scenes.size() == 2 ? "" : "s") + " other than the default");
    if (!model.scenes.empty() && !model.nodes.empty()) {  // (without scenes every root shows)
      std::vector<uint8_t> shownNode(model.nodes.size(), 0), shownMesh(model.meshes.size(), 0);
      for (const Instance& i : instances)
        shownNode[static_cast<size_t>(i.node)] = 1;
      for (int n : meshNodes)
        shownMesh[static_cast<size_t>(meshOf(n))] = 1;
      size_t hiddenNodes = 0, unusedMeshes = 0;
      for (size_t n = 0; n < model.nodes.size(); ++n)
        hiddenNodes += !shownNode[n] && model.nodes[n].mesh >= 0;
      for (uint8_t shown : shownMesh)
        unusedMeshes += !shown;
      if (hiddenNodes > 0)
        parts.push_back(std::to_string(hiddenNodes) + " node" + (hiddenNodes == 1 ? "" : "s") +
                        " with a mesh outside the default scene");
      if (unusedMeshes > 0)
        parts.push_back(std::to_string(unusedMeshes) + " mesh" + (unusedMeshes == 1 ? "" : "es") +
                        " no node of the default scene shows");
    }
    if (model.animations.size() > 1)
      parts.push_back("animations 1 .. " + std::to_string(model.animations.size() - 1) +
                      " (animation 0 is read)");
    std::set<std::string> paths;  // animation 0's channels on what no frame shows
    if (!model.animations.empty())
      for (const tinygltf::AnimationChannel& ch : model.animations[0].channels)
        if (ch.target_path != "weights" && ch.target_path != "translation" &&
            ch.target_path != "rotation" && ch.target_path != "scale")
          paths.insert(ch.target_path.empty() ? "(none)" : ch.target_path);
    if (!paths.empty()) {
      std::string list;
      for (const std::string& path : paths)
        list += (list.empty() ? "" : ", ") + path;
      parts.push_back("animation 0's channels on " + list);
    }
    std::string extensions;
    for (const std::string& e : model.extensionsUsed)
      if (e != "KHR_mesh_quantization") extensions += (extensions.empty() ? "" : ", ") + e;
    if (!extensions.empty()) parts.push_back("the extensions used " + extensions);
    if (parts.empty()) return;
    std::string what = "left out (3DVO codes positions, NORMAL and TEXCOORD_0): ";
    for (size_t i = 0; i < parts.size(); ++i)
      what += (i == 0 ? "" : "; ") + parts[i];
    warnForFile(what, name + ": " + what);
  }

  void load() {
    // Extensions that change what accessors hold (Draco or meshopt compression) are not read;
    // quantized positions (KHR_mesh_quantization) are plain accessors of integer types.
    for (const std::string& e : model.extensionsRequired)
      if (e != "KHR_mesh_quantization")
        fail("the file requires the extension " + e + ", which is not read");
    for (const tinygltf::Buffer& b : model.buffers)
      bufferBytes += b.data.size();
    loadScene();
    if (model.nodes.empty())
      for (size_t m = 0; m < model.meshes.size(); ++m)
        meshNodes.push_back(-1 - static_cast<int>(m));
    if (meshNodes.empty()) fail("no meshes");
    warnLeftOut();
    if (model.animations.empty()) return;
    animated = true;
    const tinygltf::Animation& anim = model.animations[0];
    uint64_t keys = 0;
    for (size_t c = 0; c < anim.channels.size(); ++c) {
      const tinygltf::AnimationChannel& ch = anim.channels[c];
      const std::string what = "animation 0 channel " + std::to_string(c);
      if (ch.sampler < 0 || static_cast<size_t>(ch.sampler) >= anim.samplers.size())
        fail(what + ": sampler " + std::to_string(ch.sampler) + " does not exist");
      const tinygltf::AnimationSampler& s = anim.samplers[static_cast<size_t>(ch.sampler)];
      if (s.interpolation != "STEP" && s.interpolation != "LINEAR" &&
          s.interpolation != "CUBICSPLINE")
        fail(what + ": unknown interpolation '" + s.interpolation + "'");
      if (!inputs.count(s.input)) {
        const View in = view(s.input, what + " input");
        if (in.components != 1 || in.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT)
          fail(what + " input: key times must be float scalars");
        // Inputs sharing their data cannot make more keys than the buffers hold.
        keys += in.count;
        if (keys * 4 > bufferBytes) fail(what + ": key times share their data");
        if (in.count == 0) fail(what + " input: no key times");
        std::vector<float> t(in.count);
        for (size_t i = 0; i < in.count; ++i) {
          t[i] = toFloat(in.get(i, 0));
          if (!std::isfinite(t[i]) || (i > 0 && !(t[i] > t[i - 1])))
            fail(what + " input: key times must be finite and increasing (key " +
                 std::to_string(i) + ")");
        }
        inputs.emplace(s.input, std::move(t));
      }
      std::map<int, int>* samplers = ch.target_path == "weights"       ? &weightsSampler
                                     : ch.target_path == "scale"       ? &scaleSampler
                                     : ch.target_path == "translation" ? &translationSampler
                                     : ch.target_path == "rotation"    ? &rotationSampler
                                                                       : nullptr;
      if (samplers == nullptr) continue;  // a property no frame shows (e.g. an extension's)
      if (ch.target_node < 0 || static_cast<size_t>(ch.target_node) >= model.nodes.size())
        fail(what + ": node " + std::to_string(ch.target_node) + " does not exist");
      if (ch.target_path != "weights" &&
          !model.nodes[static_cast<size_t>(ch.target_node)].matrix.empty())
        fail(what + ": node " + std::to_string(ch.target_node) + " has a matrix, and its " +
             ch.target_path + " cannot be animated");
      (*samplers)[ch.target_node] = ch.sampler;
    }
    for (const auto& [index, t] : inputs)
      times.insert(times.end(), t.begin(), t.end());
    std::sort(times.begin(), times.end());
    times.erase(std::unique(times.begin(), times.end()), times.end());
    if (times.empty()) fail("animation 0 has no channels");
    // The work of the frames: keyframes x the vertices a frame can have and what each frame
    // visits besides (its mesh nodes even when empty; every node of the model and every
    // channel, each costing about as much as kGltfNodeVertices vertices: a node's transform is
    // composed and its channels sampled), bounded by the input. Before nodes and channels were
    // counted, a chain of 8000 nodes animated over 8000 keys (a 304 KB file, 3 vertices) took
    // 8 s, 60,000 x 65,535 (2.4 MB) about 500 s.
    constexpr uint64_t kGltfNodeVertices = 32;
    uint64_t vertices = meshNodes.size() + instances.size() +
                        kGltfNodeVertices * (model.nodes.size() + anim.channels.size());
    for (int n : meshNodes) {
      const int m = meshOf(n);
      for (const tinygltf::Primitive& prim : model.meshes[static_cast<size_t>(m)].primitives) {
        const auto pos = prim.attributes.find("POSITION");
        if (pos != prim.attributes.end() && pos->second >= 0 &&
            static_cast<size_t>(pos->second) < model.accessors.size())
          vertices += model.accessors[static_cast<size_t>(pos->second)].count;
      }
    }
    const uint64_t budget = kMaxGltfVertexFramesPerByte * (inputBytes + bufferBytes);
    if (vertices > 0 && times.size() > budget / vertices)
      fail(std::to_string(times.size()) + " keyframes x " + std::to_string(vertices) +
           " vertices: more than " + std::to_string(kMaxGltfVertexFramesPerByte) +
           " vertex-frames per byte of the file and its buffers");
  }

  // The value of sampler `s` of animation 0 at time t: `width` values per key.
  // A rotation (`rotation`) is interpolated spherically (LINEAR: slerp along the shorter arc;
  // CUBICSPLINE: the spline, normalised).
  std::vector<double> sample(int s, float t, size_t width, const std::string& what,
                             bool rotation = false) const {
    const tinygltf::AnimationSampler& sampler =
        model.animations[0].samplers[static_cast<size_t>(s)];
    const std::vector<float>& keys = inputs.at(sampler.input);
    const bool cubic = sampler.interpolation == "CUBICSPLINE";
    const View out = view(sampler.output, what + " output");
    if (width == 0 || out.count * out.components != keys.size() * width * (cubic ? 3 : 1))
      fail(what + " output: " + std::to_string(out.count) + " values of " +
           std::to_string(out.components) + " components for " + std::to_string(keys.size()) +
           " keys of " + std::to_string(width));
    auto value = [&](size_t key, size_t c) {
      return out.flat((cubic ? key * 3 + 1 : key) * width + c);
    };
    std::vector<double> v(width);
    size_t i = static_cast<size_t>(std::upper_bound(keys.begin(), keys.end(), t) - keys.begin());
    if (i == 0 || i == keys.size() || keys[i - 1] == t || sampler.interpolation == "STEP") {
      const size_t key = i == 0 ? 0 : i - 1;
      for (size_t c = 0; c < width; ++c)
        v[c] = value(key, c);
      return v;
    }
    const size_t k = i - 1;
    const double dt = double{keys[k + 1]} - keys[k];
    const double u = (t - keys[k]) / dt;
    if (rotation && !cubic) {
      double a[4], b[4], dot = 0;
      for (size_t c = 0; c < 4; ++c) {
        a[c] = value(k, c);
        b[c] = value(k + 1, c);
        dot += a[c] * b[c];
      }
      const double flip = dot < 0 ? -1.0 : 1.0;
      dot *= flip;
      const double theta = std::acos(std::min(dot, 1.0));
      double wa = 1 - u, wb = u;
      if (theta > 1e-6) {
        wa = std::sin((1 - u) * theta) / std::sin(theta);
        wb = std::sin(u * theta) / std::sin(theta);
      }
      for (size_t c = 0; c < 4; ++c)
        v[c] = wa * a[c] + flip * wb * b[c];
      return v;
    }
    for (size_t c = 0; c < width; ++c) {
      if (!cubic) {
        v[c] = value(k, c) * (1 - u) + value(k + 1, c) * u;
        continue;
      }
      const double p0 = value(k, c), p1 = value(k + 1, c);
      const double m0 = dt * out.flat((k * 3 + 2) * width + c);
      const double m1 = dt * out.flat(((k + 1) * 3) * width + c);
      const double u2 = u * u, u3 = u2 * u;
      v[c] = (2 * u3 - 3 * u2 + 1) * p0 + (u3 - 2 * u2 + u) * m0 + (-2 * u3 + 3 * u2) * p1 +
             (u3 - u2) * m1;
    }
    return v;
  }

  Mesh frame(size_t k) const {
    const float t = animated ? times.at(k) : 0.0f;
    // Every instance's transform at time t, parents first (the scene's order has them first),
    // and whether it is hidden: a node whose scale is 0 0 0 hides its subtree.
    std::vector<Affine> world(instances.size());
    std::vector<uint8_t> hidden(instances.size(), 0);
    for (size_t i = 0; i < instances.size(); ++i) {
      const int n = instances[i].node, parent = instances[i].parent;
      const tinygltf::Node& node = model.nodes[static_cast<size_t>(n)];
      const std::string what = "node " + std::to_string(n);
      auto animatedOr = [&](const std::map<int, int>& samplers, const std::vector<double>& still,
                            size_t width, const char* name) {
        const auto it = animated ? samplers.find(n) : samplers.end();
        if (it == samplers.end()) return still;
        return sample(it->second, t, width, what + " " + name, width == 4);
      };
      const std::vector<double> scale = animatedOr(scaleSampler, node.scale, 3, "scale");
      std::vector<double> rotation = animatedOr(rotationSampler, node.rotation, 4, "rotation");
      const std::vector<double> translation =
          animatedOr(translationSampler, node.translation, 3, "translation");
      if (rotation.size() == 4) {
        const double length2 = rotation[0] * rotation[0] + rotation[1] * rotation[1] +
                               rotation[2] * rotation[2] + rotation[3] * rotation[3];
        if (!(length2 > 0) || !std::isfinite(length2))
          fail(frameLabel(k) + what + ": rotation is not a quaternion of finite, nonzero length");
        rotation = unitQuaternion(std::move(rotation));
      }
      hidden[i] = (parent >= 0 && hidden[static_cast<size_t>(parent)]) ||
                  (scale.size() == 3 && scale[0] == 0 && scale[1] == 0 && scale[2] == 0);
      const Affine local = nodeTransform(node.matrix, translation, rotation, scale);
      world[i] = parent < 0 ? local : world[static_cast<size_t>(parent)] * local;
    }
    struct Shown {
      int mesh;
      std::vector<double> weights;
      Affine transform;
    };
    std::vector<Shown> shown;
    for (int n : meshNodes) {
      if (n < 0) {
        const tinygltf::Mesh& m = model.meshes[static_cast<size_t>(-1 - n)];
        shown.push_back({-1 - n, m.weights, Affine()});
        continue;
      }
      if (hidden[static_cast<size_t>(n)]) continue;
      const int nodeIndex = instances[static_cast<size_t>(n)].node;
      const tinygltf::Node& node = model.nodes[static_cast<size_t>(nodeIndex)];
      const std::string what = "node " + std::to_string(nodeIndex);
      const tinygltf::Mesh& m = model.meshes[static_cast<size_t>(node.mesh)];
      const size_t targets = m.primitives.empty() ? 0 : m.primitives[0].targets.size();
      std::vector<double> weights = !node.weights.empty() ? node.weights : m.weights;
      if (animated && weightsSampler.count(nodeIndex))
        weights = sample(weightsSampler.at(nodeIndex), t, targets, what + " weights");
      shown.push_back({node.mesh, std::move(weights), world[static_cast<size_t>(n)]});
    }
    // The frame's size first, bounded by the buffers' bytes (shared data cannot inflate it).
    uint64_t vertices = 0, corners = 0;
    for (const Shown& s : shown) {
      const tinygltf::Mesh& m = model.meshes[static_cast<size_t>(s.mesh)];
      for (size_t p = 0; p < m.primitives.size(); ++p) {
        const tinygltf::Primitive& prim = m.primitives[p];
        const std::string what =
            "mesh " + std::to_string(s.mesh) + " primitive " + std::to_string(p);
        if (prim.mode != -1 && prim.mode != TINYGLTF_MODE_TRIANGLES)
          fail(what + ": mode " + std::to_string(prim.mode) + " (only triangles are read)");
        const auto pos = prim.attributes.find("POSITION");
        if (pos == prim.attributes.end()) fail(what + ": no POSITION");
        const View v = view(pos->second, what + " POSITION");
        vertices += v.count;
        corners += prim.indices >= 0 ? view(prim.indices, what + " indices").count : v.count;
        if (prim.targets.size() != m.primitives[0].targets.size())
          fail(what + ": " + std::to_string(prim.targets.size()) +
               " morph targets, primitive 0 has " + std::to_string(m.primitives[0].targets.size()));
      }
    }
    // Morph-target vertices added, likewise (targets sharing their data cannot multiply the work).
    uint64_t moved = 0;
    for (const Shown& s : shown) {
      const tinygltf::Mesh& m = model.meshes[static_cast<size_t>(s.mesh)];
      for (const tinygltf::Primitive& prim : m.primitives)
        for (size_t j = 0; j < prim.targets.size() && j < s.weights.size(); ++j) {
          const auto tp = prim.targets[j].find("POSITION");
          if (s.weights[j] != 0 && tp != prim.targets[j].end() && tp->second >= 0 &&
              static_cast<size_t>(tp->second) < model.accessors.size())
            moved += model.accessors[static_cast<size_t>(tp->second)].count;
        }
    }
    const uint64_t fileBytes = inputBytes + bufferBytes;
    if (moved > fileBytes)
      fail(frameLabel(k) + "its morph targets move " + std::to_string(moved) +
           " vertices, more than one per byte of the file and its buffers (" +
           std::to_string(fileBytes) + " bytes; targets sharing their data)");
    if (vertices > fileBytes || corners > 3 * fileBytes)
      fail(frameLabel(k) + std::to_string(vertices) + " vertices and " +
           std::to_string(corners / 3) +
           " triangles, more than one of each per byte of the file and its buffers (" +
           std::to_string(fileBytes) + " bytes; meshes used by many nodes, or sharing their data)");
    Mesh mesh;
    mesh.positions.reserve(vertices);
    mesh.triangles.reserve(corners / 3);
    // Texture coordinates (TEXCOORD_0) and normals (NORMAL) are the frame's when every primitive
    // shown has them (docs/user-guide.md, "Texture coordinates and normals").
    bool uvs = true, normals = true, someUvs = false, someNormals = false;
    for (const Shown& s : shown)
      for (const tinygltf::Primitive& prim : model.meshes[static_cast<size_t>(s.mesh)].primitives) {
        uvs &= prim.attributes.count("TEXCOORD_0") > 0;
        normals &= prim.attributes.count("NORMAL") > 0;
        someUvs |= prim.attributes.count("TEXCOORD_0") > 0;
        someNormals |= prim.attributes.count("NORMAL") > 0;
      }
    // What is dropped is said (common/core/warnings.h).
    for (const auto& [some, all, attribute] :
         {std::tuple{someUvs, uvs, "TEXCOORD_0"}, std::tuple{someNormals, normals, "NORMAL"}})
      if (some && !all) {
        const std::string what =
            std::string(attribute) + " given by only some primitives: left out";
        warnForFile(what, name + ": frame " + std::to_string(k) + ": " + what);
      }
    for (const Shown& s : shown) {
      const tinygltf::Mesh& m = model.meshes[static_cast<size_t>(s.mesh)];
      for (size_t p = 0; p < m.primitives.size(); ++p) {
        const tinygltf::Primitive& prim = m.primitives[p];
        const std::string what =
            "mesh " + std::to_string(s.mesh) + " primitive " + std::to_string(p);
        const View v = view(prim.attributes.at("POSITION"), what + " POSITION");
        if (v.components != 3) fail(what + " POSITION: not VEC3");
        const size_t base = mesh.positions.size();
        for (size_t i = 0; i < v.count; ++i)
          mesh.positions.push_back({v.get(i, 0), v.get(i, 1), v.get(i, 2)});
        for (size_t j = 0; j < prim.targets.size(); ++j) {
          const double w = j < s.weights.size() ? s.weights[j] : 0.0;
          const auto tp = prim.targets[j].find("POSITION");
          if (w == 0 || tp == prim.targets[j].end()) continue;
          const std::string twhat = what + " target " + std::to_string(j);
          const View d = view(tp->second, twhat + " POSITION");
          if (d.components != 3 || d.count != v.count)
            fail(twhat + " POSITION: " + std::to_string(d.count) + " elements, the base has " +
                 std::to_string(v.count));
          for (size_t i = 0; i < v.count; ++i)
            for (size_t c = 0; c < 3; ++c)
              mesh.positions[base + i][c] += w * d.get(i, c);
        }
        const bool moves = !s.transform.identity();
        if (moves)
          for (size_t i = base; i < mesh.positions.size(); ++i)
            mesh.positions[i] = s.transform.point(mesh.positions[i]);
        for (size_t i = base; i < mesh.positions.size(); ++i)
          for (double c : mesh.positions[i])
            if (!std::isfinite(c))
              fail(what + ": vertex " + std::to_string(i - base) + " is not finite");
            else if (isBeyondCoordinateRange(c))
              fail(what + ": vertex " + std::to_string(i - base) + ": coordinate " +
                   coordinateText(c) + kBeyondCoordinateRange);
        if (uvs) readUvs(prim, v.count, what, mesh.attributes.uvs);
        if (normals) {
          const size_t first = mesh.attributes.normals.size();
          readNormals(prim, v.count, s.weights, what, mesh.attributes.normals);
          if (moves)
            for (size_t i = first; i < mesh.attributes.normals.size(); ++i)
              mesh.attributes.normals[i] = s.transform.normal(mesh.attributes.normals[i]);
        }
        // A mirroring transform turns the triangles' front faces round (glTF: the winding
        // order follows the determinant's sign); two corners are swapped to keep the side
        // that faces the viewer.
        const bool mirrored = moves && s.transform.determinant() < 0;
        const size_t firstTriangle = mesh.triangles.size();
        if (prim.indices >= 0) {
          const View ix = view(prim.indices, what + " indices");
          if (ix.components != 1 || ix.componentType == TINYGLTF_COMPONENT_TYPE_FLOAT ||
              ix.componentType == TINYGLTF_COMPONENT_TYPE_BYTE ||
              ix.componentType == TINYGLTF_COMPONENT_TYPE_SHORT)
            fail(what + " indices: not unsigned integer scalars");
          if (ix.count % 3 != 0)
            fail(what + " indices: " + std::to_string(ix.count) + " is not a multiple of 3");
          for (size_t i = 0; i < ix.count; i += 3) {
            Triangle tri;
            for (size_t c = 0; c < 3; ++c) {
              const uint32_t index = ix.index(i + c);
              if (index >= v.count)
                fail(what + " indices: index " + std::to_string(index) + " at " +
                     std::to_string(i + c) + " out of range (the primitive has " +
                     std::to_string(v.count) + " vertices)");
              tri[c] = static_cast<uint32_t>(base + index);
            }
            mesh.triangles.push_back(tri);
          }
        } else {
          if (v.count % 3 != 0)
            fail(what + ": " + std::to_string(v.count) +
                 " vertices without indices is not a multiple of 3");
          for (size_t i = 0; i < v.count; i += 3)
            mesh.triangles.push_back({static_cast<uint32_t>(base + i),
                                      static_cast<uint32_t>(base + i + 1),
                                      static_cast<uint32_t>(base + i + 2)});
        }
        if (mirrored)
          for (size_t i = firstTriangle; i < mesh.triangles.size(); ++i)
            std::swap(mesh.triangles[i][1], mesh.triangles[i][2]);
      }
    }
    if (uvs) mesh.attributes.uvTriangles = mesh.triangles;  // per vertex
    if (uvs) mesh.attributes.uvOrigin = UvOrigin::kTop;     // glTF's v = 0: the top row
    if (normals) mesh.attributes.normalTriangles = mesh.triangles;
    const std::string frameName = frameLabel(k);
    if (mesh.positions.empty()) fail(frameName + "no vertices");
    if (mesh.triangles.empty()) fail(frameName + "no faces");
    bool proper = false;
    for (const Triangle& tri : mesh.triangles)
      proper |= tri[0] != tri[1] && tri[1] != tri[2] && tri[0] != tri[2];
    if (!proper)
      fail(frameName +
           "every face has a repeated vertex (degenerate): no triangle is left to code");
    return mesh;
  }
};

namespace {

std::unique_ptr<GltfFile::Impl> parseGltf(const std::vector<uint8_t>& bytes,
                                          const std::string& name, const std::string& folder) {
  auto impl = std::make_unique<GltfFile::Impl>();
  impl->name = name;
  // The JSON: the whole file, or a GLB's first chunk.
  const bool glb = bytes.size() >= 4 && std::memcmp(bytes.data(), "glTF", 4) == 0;
  const uint8_t* json = bytes.data();
  size_t jsonSize = bytes.size();
  if (glb) {
    if (bytes.size() < 20 || le32(bytes.data() + 4) != 2 || le32(bytes.data() + 16) != 0x4E4F534A ||
        le32(bytes.data() + 12) > bytes.size() - 20)
      throw Error(name + ": not a glTF 2.0 binary file (bad GLB header or JSON chunk)");
    json = bytes.data() + 20;
    jsonSize = le32(bytes.data() + 12);
  }
  if (jsonSize > kMaxGltfJsonBytes)
    throw Error(name + ": JSON of " + std::to_string(jsonSize) + " bytes (more than " +
                std::to_string(kMaxGltfJsonBytes) + ")");
  {
    JsonLimits limits;
    nlohmann::json::sax_parse(json, json + jsonSize, &limits);
    if (!limits.error.empty()) throw Error(name + ": " + limits.error);
  }
  if (glb) {
    // The BIN chunk is copied into every buffer without a uri: only one may have none.
    const nlohmann::json doc = nlohmann::json::parse(json, json + jsonSize);
    const auto buffers = doc.find("buffers");
    if (buffers != doc.end() && buffers->is_array()) {
      size_t embedded = 0;
      for (const auto& b : *buffers)
        embedded += b.is_object() && !b.contains("uri");
      if (embedded > 1)
        throw Error(name + ": " + std::to_string(embedded) +
                    " buffers use the GLB's BIN chunk (one may)");
    }
  }
  Files files{name, folder, "", {}};
  tinygltf::TinyGLTF loader;
  loader.SetFsCallbacks({&fileExists, &expandPath, &readWholeFile, &writeWholeFile, &files});
  loader.SetImageLoader(&ignoreImage, nullptr);
  std::string err, warn;
  const std::string base = folder.empty() ? std::string("/nonexistent") : folder;
  const bool ok = glb ? loader.LoadBinaryFromMemory(&impl->model, &err, &warn, bytes.data(),
                                                    static_cast<unsigned int>(bytes.size()), base)
                      : loader.LoadASCIIFromString(&impl->model, &err, &warn,
                                                   reinterpret_cast<const char*>(bytes.data()),
                                                   static_cast<unsigned int>(bytes.size()), base);
  if (!ok) {
    if (!files.error.empty()) throw Error(name + ": buffer: " + files.error);
    throw Error(name + ": glTF: " + firstLine(err.empty() ? "cannot be read" : err));
  }
  impl->inputBytes = bytes.size();
  impl->load();
  return impl;
}

std::string folderOf(const std::string& path) {
  const size_t slash = path.rfind('/');
  if (slash == std::string::npos) return ".";
  if (slash == 0) return "/";
  return path.substr(0, slash);
}

}  // namespace

namespace {

// A .glb is read up to the binary-file limit; any other name is JSON (.gltf), at most
// kMaxGltfJsonBytes, so that a .gltf that never ends (/dev/zero) stops there.
std::vector<uint8_t> readGltfBytes(const std::string& path) {
  std::string lower = path.size() >= 4 ? path.substr(path.size() - 4) : path;
  for (char& c : lower)
    c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (lower == ".glb") return readFileBytes(path, kMaxBinaryFileBytes, "a glTF binary file");
  return readFileBytes(path, kMaxGltfJsonBytes, "a glTF JSON file");
}

}  // namespace

GltfFile::GltfFile(const std::string& path)
    : impl_(parseGltf(readGltfBytes(path), path, folderOf(path))) {}

GltfFile::GltfFile(const std::vector<uint8_t>& bytes, const std::string& name)
    : impl_(parseGltf(bytes, name, "")) {}

GltfFile::~GltfFile() = default;
GltfFile::GltfFile(GltfFile&&) noexcept = default;
GltfFile& GltfFile::operator=(GltfFile&&) noexcept = default;

size_t GltfFile::frameCount() const {
  return impl_->animated ? impl_->times.size() : 1;
}

double GltfFile::frameTime(size_t k) const {
  return impl_->animated ? impl_->times.at(k) : 0.0;
}

std::optional<double> GltfFile::keyRate(size_t first, size_t count) const {
  const size_t n = frameCount();
  if (count < 2 || first >= n || count > n - first) return std::nullopt;
  const auto t = [&](size_t k) { return frameTime(first + k); };
  const double t0 = t(0), span = t(count - 1) - t0;
  if (!(span > 0)) return std::nullopt;
  // The float32 rounding of a key time.
  const auto ulp = [](double x) {
    const float f = static_cast<float>(std::abs(x));
    return static_cast<double>(std::nextafter(f, std::numeric_limits<float>::infinity()) - f);
  };
  // How far the keys are from t0 + k / rate beyond the float32 rounding of both times (at most
  // 0: exactly at it, as far as float32 tells), over all keys.
  const auto excess = [&](double rate) {
    double worst = -std::numeric_limits<double>::infinity();
    for (size_t k = 1; k < count; ++k)
      worst = std::max(
          worst, std::abs(t(k) - (t0 + static_cast<double>(k) / rate)) - 2 * (ulp(t(k)) + ulp(t0)));
    return worst;
  };
  const double raw = static_cast<double>(count - 1) / span;
  // Simple rates p / q (q up to 12: 25, 12.5, 7.5, ...) and p / (1.001 q) (29.97 = 30000 / 1001,
  // 23.976, ...), simplest first: the first that the keys are exactly at, else the one they are
  // nearest, when within a thousandth of its spacing (evenly spaced); else the mean spacing's.
  std::vector<double> tried;
  std::optional<double> best;
  double bestExcess = std::numeric_limits<double>::infinity();
  for (int q = 1; q <= 12; ++q)
    for (const bool ntsc : {false, true}) {
      const double p = std::round(raw * q * (ntsc ? 1.001 : 1.0));
      if (p < 1) continue;
      const double rate = ntsc ? p * 1000 / (q * 1001.0) : p / q;
      if (std::find(tried.begin(), tried.end(), rate) != tried.end()) continue;
      tried.push_back(rate);
      const double e = excess(rate);
      if (e <= 0) return rate;
      if (e <= 1e-3 / rate && e < bestExcess) best = rate, bestExcess = e;
    }
  if (best) return best;
  if (excess(raw) <= 1e-3 / raw) return raw;
  return std::nullopt;
}

Mesh GltfFile::frame(size_t k) const {
  if (k >= frameCount())
    throw Error(impl_->name + ": frame " + std::to_string(k) + " is not in the file (" +
                std::to_string(frameCount()) + " frames)");
  return impl_->frame(k);
}

Mesh readGltf(const std::string& path) {
  const GltfFile file(path);
  Mesh first = file.frame(0);  // its errors before the warning
  if (file.frameCount() > 1) {
    const std::string what =
        "an animated glTF file read as one frame: its first keyframe is "
        "read, the others are left out (a pattern without %d reads one "
        "file's keyframes as the frames)";
    warnForFile(what,
                path + ": " + what + " (" + std::to_string(file.frameCount()) + " keyframes)");
  }
  return first;
}

// ---- Writing ----

namespace {

// Appends raw bytes to buffer 0 (4-byte aligned) and returns a bufferView over them.
int addView(tinygltf::Model& model, const void* data, size_t bytes, int target) {
  std::vector<unsigned char>& buffer = model.buffers[0].data;
  while (buffer.size() % 4 != 0)
    buffer.push_back(0);
  tinygltf::BufferView bv;
  bv.buffer = 0;
  bv.byteOffset = buffer.size();
  bv.byteLength = bytes;
  bv.target = target;
  const auto* p = static_cast<const unsigned char*>(data);
  buffer.insert(buffer.end(), p, p + bytes);
  model.bufferViews.push_back(bv);
  return static_cast<int>(model.bufferViews.size() - 1);
}

int addAccessor(tinygltf::Model& model, int view, int componentType, int type, size_t count,
                std::vector<double> min = {}, std::vector<double> max = {}) {
  tinygltf::Accessor a;
  a.bufferView = view;
  a.byteOffset = 0;
  a.componentType = componentType;
  a.type = type;
  a.count = count;
  a.minValues = std::move(min);
  a.maxValues = std::move(max);
  model.accessors.push_back(a);
  return static_cast<int>(model.accessors.size() - 1);
}

// float positions (x y z per vertex) as a POSITION accessor with its bounds.
int addPositions(tinygltf::Model& model, const float* xyz, size_t vertices) {
  std::vector<double> lo(3, 0.0), hi(3, 0.0);
  for (size_t i = 0; i < vertices; ++i)
    for (size_t c = 0; c < 3; ++c) {
      const double v = xyz[i * 3 + c];
      if (i == 0 || v < lo[c]) lo[c] = v;
      if (i == 0 || v > hi[c]) hi[c] = v;
    }
  const int view = addView(model, xyz, vertices * 3 * sizeof(float), TINYGLTF_TARGET_ARRAY_BUFFER);
  return addAccessor(model, view, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, vertices, lo,
                     hi);
}

// Float vectors of `components` values per vertex (TEXCOORD_0: 2, NORMAL: 3), no bounds.
int addVectors(tinygltf::Model& model, const float* values, size_t vertices, int components) {
  const int view =
      addView(model, values, vertices * components * sizeof(float), TINYGLTF_TARGET_ARRAY_BUFFER);
  return addAccessor(model, view, TINYGLTF_COMPONENT_TYPE_FLOAT,
                     components == 2 ? TINYGLTF_TYPE_VEC2 : TINYGLTF_TYPE_VEC3, vertices);
}

int addIndices(tinygltf::Model& model, const std::vector<Triangle>& triangles) {
  std::vector<uint32_t> indices;
  indices.reserve(triangles.size() * 3);
  for (const Triangle& t : triangles)
    indices.insert(indices.end(), t.begin(), t.end());
  const int view =
      addView(model, indices.data(), indices.size() * 4, TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER);
  return addAccessor(model, view, TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT, TINYGLTF_TYPE_SCALAR,
                     indices.size());
}

int addScalars(tinygltf::Model& model, const std::vector<float>& values, bool bounds) {
  const int view = addView(model, values.data(), values.size() * 4, 0);
  std::vector<double> lo, hi;
  if (bounds && !values.empty()) {
    lo = {*std::min_element(values.begin(), values.end())};
    hi = {*std::max_element(values.begin(), values.end())};
  }
  return addAccessor(model, view, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_SCALAR,
                     values.size(), lo, hi);
}

tinygltf::Model newModel() {
  tinygltf::Model model;
  model.asset.version = "2.0";
  model.asset.generator = "3DVO";
  model.buffers.resize(1);
  model.scenes.resize(1);
  model.defaultScene = 0;
  return model;
}

std::string serialise(tinygltf::Model& model, bool binary) {
  tinygltf::TinyGLTF writer;
  std::ostringstream out;
  if (!writer.WriteGltfSceneToStream(&model, out, false, binary))
    throw Error("glTF: cannot serialise the model");
  return out.str();
}

// glTF positions are float32: a coordinate beyond its range (about 3.4e38, which OBJ and PLY
// hold) cannot be written, and is an error rather than an infinity in the file.
float checkedFloat(double value, size_t vertex) {
  const float f = static_cast<float>(value);
  if (!std::isfinite(f))
    throw Error("glTF: vertex " + std::to_string(vertex) + " has a coordinate (" +
                formatDouble(value) +
                ") beyond the range of the float32 that glTF positions are; write OBJ or PLY "
                "(--MeshFormat=obj or ply)");
  return f;
}

std::vector<float> toFloats(const Mesh& mesh) {
  std::vector<float> xyz;
  xyz.reserve(mesh.positions.size() * 3);
  for (size_t v = 0; v < mesh.positions.size(); ++v)
    for (double c : mesh.positions[v])
      xyz.push_back(checkedFloat(c, v));
  return xyz;
}

// glTF requires NORMAL to be of unit length: a normal whose length differs from 1 by more than
// 5e-4 is scaled to it (one of length 0 cannot be, and is written as it is), and that is said
// (what is changed is said, common/core/warnings.h). OBJ and PLY keep such normals exactly.
void unitNormals(Mesh& mesh) {
  size_t scaled = 0, zero = 0, infinite = 0;
  for (Vec3f& n : mesh.attributes.normals) {
    const double length =
        std::sqrt(double{n[0]} * n[0] + double{n[1]} * n[1] + double{n[2]} * n[2]);
    if (std::abs(length - 1) <= 5e-4) continue;
    if (!std::isfinite(length)) {
      ++infinite;
      continue;
    }
    if (!(length > 0)) {
      ++zero;
      continue;
    }
    for (float& c : n)
      c = static_cast<float>(c / length);
    ++scaled;
  }
  // Once per run (WarnOnceScope): the frames of a sequence repeat it.
  if (scaled > 0)
    warn(
        "glTF output: normals not of unit length are scaled to it (glTF requires unit NORMALs; "
        "OBJ and PLY output keep them as they are)");
  if (zero > 0) warn("glTF output: normals of length 0 are written as they are (not valid glTF)");
  if (infinite > 0)
    warn("glTF output: normals that are not finite are written as they are (not valid glTF)");
}

}  // namespace

std::string formatGltf(const Mesh& input, GltfContainer container) {
  tinygltf::Model model = newModel();
  // glTF attributes are per vertex: seams are split into appended vertex copies.
  Mesh mesh = splitAttributeSeams(input);
  setUvOrigin(mesh.attributes, UvOrigin::kTop);  // glTF's v = 0: the image's top row
  unitNormals(mesh);
  const std::vector<float> xyz = toFloats(mesh);
  tinygltf::Primitive prim;
  prim.mode = TINYGLTF_MODE_TRIANGLES;
  prim.attributes["POSITION"] = addPositions(model, xyz.data(), mesh.positions.size());
  if (mesh.attributes.hasUvs())
    prim.attributes["TEXCOORD_0"] =
        addVectors(model, mesh.attributes.uvs[0].data(), mesh.positions.size(), 2);
  if (mesh.attributes.hasNormals())
    prim.attributes["NORMAL"] =
        addVectors(model, mesh.attributes.normals[0].data(), mesh.positions.size(), 3);
  prim.indices = addIndices(model, mesh.triangles);
  tinygltf::Mesh m;
  m.primitives.push_back(prim);
  model.meshes.push_back(m);
  tinygltf::Node node;
  node.mesh = 0;
  model.nodes.push_back(node);
  model.scenes[0].nodes.push_back(0);
  return serialise(model, container == GltfContainer::kGlb);
}

void writeGltf(const std::string& path, const Mesh& mesh, GltfContainer container) {
  writeFileAtomic(path, formatGltf(mesh, container));
}

GltfAnimationWriter::GltfAnimationWriter(double frameRate) : frameRate_(frameRate) {}
GltfAnimationWriter::~GltfAnimationWriter() = default;

void checkGltfAnimationFrames(uint64_t frames) {
  if (frames > kMaxGltfAnimationFrames)
    throw Error(std::to_string(frames) + " frames, more than " +
                std::to_string(kMaxGltfAnimationFrames) +
                " for one animation file (it is made in memory): write per-frame files "
                "(MeshFormat) or fewer frames (FrameCount)");
}

void GltfAnimationWriter::add(const Mesh& input) {
  checkGltfAnimationFrames(frames_ + 1);
  if (input.positions.size() > kMaxGltfAnimationVertexFrames - vertexFrames_)
    throw Error("more than " + std::to_string(kMaxGltfAnimationVertexFrames) +
                " vertices x frames for one animation file (it is made in memory): write "
                "per-frame files (MeshFormat) or fewer frames (FrameCount)");
  const float time = static_cast<float>(static_cast<double>(frames_) / frameRate_);
  if (!std::isfinite(time))
    throw Error("its time in the animation, " + std::to_string(frames_) + " / frame rate " +
                formatDouble(frameRate_) + ", is beyond float32 (glTF's key times)");
  vertexFrames_ += input.positions.size();
  Mesh frame = splitAttributeSeams(input);  // per-vertex attributes, as formatGltf
  setUvOrigin(frame.attributes, UvOrigin::kTop);
  unitNormals(frame);
  const size_t inRun = runs_.empty() ? 0 : frames_ - runs_.back().first;
  const bool normals = frame.attributes.hasNormals();
  if (runs_.empty() || inRun == kMaxGltfRunFrames ||
      runs_.back().vertices != frame.positions.size() ||
      runs_.back().triangles != frame.triangles || runs_.back().uvs != frame.attributes.uvs ||
      runs_.back().normals.empty() == normals) {
    Run run;
    run.first = frames_;
    run.vertices = frame.positions.size();
    run.triangles = frame.triangles;
    run.uvs = frame.attributes.uvs;
    runs_.push_back(std::move(run));
  }
  const std::vector<float> xyz = toFloats(frame);
  runs_.back().positions.insert(runs_.back().positions.end(), xyz.begin(), xyz.end());
  for (const Vec3f& n : frame.attributes.normals)
    runs_.back().normals.insert(runs_.back().normals.end(), n.begin(), n.end());
  ++frames_;
}

std::string GltfAnimationWriter::finish() {
  tinygltf::Model model = newModel();
  tinygltf::Animation animation;
  animation.name = "frames";
  auto time = [this](size_t frame) { return static_cast<float>(frame / frameRate_); };
  for (size_t r = 0; r < runs_.size(); ++r) {
    const Run& run = runs_[r];
    const size_t n = run.positions.size() / (run.vertices * 3);  // frames in the run
    tinygltf::Primitive prim;
    prim.mode = TINYGLTF_MODE_TRIANGLES;
    prim.attributes["POSITION"] = addPositions(model, run.positions.data(), run.vertices);
    if (!run.uvs.empty())
      prim.attributes["TEXCOORD_0"] = addVectors(model, run.uvs[0].data(), run.vertices, 2);
    if (!run.normals.empty())
      prim.attributes["NORMAL"] = addVectors(model, run.normals.data(), run.vertices, 3);
    prim.indices = addIndices(model, run.triangles);
    // Target j - 1 moves the base (frame 0 of the run) to frame j (and turns its normals into
    // frame j's, when they differ).
    std::vector<float> delta(run.vertices * 3);
    for (size_t j = 1; j < n; ++j) {
      for (size_t i = 0; i < delta.size(); ++i)  // (float positions; the difference may not be)
        delta[i] =
            checkedFloat(double(run.positions[j * delta.size() + i]) - run.positions[i], i / 3);
      std::map<std::string, int> target{
          {"POSITION", addPositions(model, delta.data(), run.vertices)}};
      if (!run.normals.empty()) {
        bool same = true;
        for (size_t i = 0; i < delta.size(); ++i) {
          delta[i] = run.normals[j * delta.size() + i] - run.normals[i];
          same &= delta[i] == 0;
        }
        if (!same) target["NORMAL"] = addVectors(model, delta.data(), run.vertices, 3);
      }
      prim.targets.push_back(std::move(target));
    }
    tinygltf::Mesh mesh;
    mesh.name = "frames " + std::to_string(run.first) + "-" + std::to_string(run.first + n - 1);
    mesh.primitives.push_back(prim);
    mesh.weights.assign(n - 1, 0.0);
    model.meshes.push_back(mesh);
    tinygltf::Node node;
    node.name = mesh.name;
    node.mesh = static_cast<int>(r);
    if (r > 0) node.scale = {0, 0, 0};  // a viewer without animation shows the first run
    model.nodes.push_back(node);
    model.scenes[0].nodes.push_back(static_cast<int>(r));
    const int nodeIndex = static_cast<int>(r);
    auto channel = [&](const std::vector<float>& times, const std::vector<float>& values,
                       const char* path) {
      tinygltf::AnimationSampler s;
      s.input = addScalars(model, times, true);
      s.output = addScalars(model, values, false);
      if (std::string(path) == "scale") {
        model.accessors[static_cast<size_t>(s.output)].type = TINYGLTF_TYPE_VEC3;
        model.accessors[static_cast<size_t>(s.output)].count = values.size() / 3;
      }
      s.interpolation = "STEP";
      animation.samplers.push_back(s);
      tinygltf::AnimationChannel c;
      c.sampler = static_cast<int>(animation.samplers.size() - 1);
      c.target_node = nodeIndex;
      c.target_path = path;
      animation.channels.push_back(c);
    };
    if (n > 1) {
      std::vector<float> times(n), weights(n * (n - 1), 0.0f);
      for (size_t j = 0; j < n; ++j) {
        times[j] = time(run.first + j);
        if (j > 0) weights[j * (n - 1) + (j - 1)] = 1.0f;
      }
      channel(times, weights, "weights");
    }
    // Visible from the run's first frame to the next run's.
    std::vector<float> times, scales;
    if (run.first > 0) {
      times.push_back(0.0f);
      scales.insert(scales.end(), {0, 0, 0});
    }
    times.push_back(time(run.first));
    scales.insert(scales.end(), {1, 1, 1});
    if (r + 1 < runs_.size()) {
      times.push_back(time(runs_[r + 1].first));
      scales.insert(scales.end(), {0, 0, 0});
    }
    channel(times, scales, "scale");
  }
  model.animations.push_back(animation);
  return serialise(model, true);
}

}  // namespace tdvo
