// Texture coordinates and normals (issue 19, point 6): read from OBJ (vt, vn), PLY (u/v or s/t,
// nx/ny/nz) and glTF (TEXCOORD_0, NORMAL), written back (seams split into appended vertex
// copies in PLY and glTF), and carried through the stream (ATTRIBUTES units): OBJ -> 3DVO ->
// glTF and PLY -> 3DVO -> PLY keep positions within the grid, vertex order, triangles, and the
// texture coordinates and normals bit for bit.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "bitstream/units.h"
#include "common/core/error.h"
#include "common/core/gltf_io.h"
#include "common/core/md5.h"
#include "common/core/mesh_attributes.h"
#include "common/core/mesh_io.h"
#include "common/core/obj_io.h"
#include "common/core/ply_io.h"
#include "common/core/sequence.h"
#include "common/core/tiny_gltf_config.h"
#include "common/core/warnings.h"
#include "decoder/stream_decoder.h"
#include "encoder/sequence_encoder.h"
#include "tests/stream_units.h"
#include "tests/test_support.h"

namespace tdvo {
namespace {

const std::string kBin = TDVO_BIN_DIR;

using test::errorOf;

// The value at every triangle corner: what a file keeps whether or not it splits seams.
template <class T>
std::vector<T> perCorner(const std::vector<T>& values, const std::vector<Triangle>& indices) {
  std::vector<T> out;
  for (const Triangle& t : indices)
    for (uint32_t i : t)
      out.push_back(values.at(i));
  return out;
}

// Bit for bit (also tells -0 from 0).
template <class T>
bool sameBits(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0;
}

// `out` is `in` with its attributes made per vertex (or as they were): the first vertices are
// in's within `tolerance`, in order; further ones are copies at seams; every triangle corner
// uses in's vertex or a copy of it; and every corner's texture coordinate and normal is in's,
// bit for bit (normals only when `normals`; texture coordinates in out's convention).
void expectSameSurface(const Mesh& in, const Mesh& out, double tolerance, const std::string& what,
                       bool normals = true) {
  ASSERT_GE(out.positions.size(), in.positions.size()) << what;
  ASSERT_EQ(out.triangles.size(), in.triangles.size()) << what;
  double worst = 0;
  for (size_t i = 0; i < in.positions.size(); ++i)
    for (int c = 0; c < 3; ++c)
      worst = std::max(worst, std::fabs(in.positions[i][c] - out.positions[i][c]));
  EXPECT_LE(worst, tolerance) << what;
  for (size_t t = 0; t < in.triangles.size(); ++t)
    for (int c = 0; c < 3; ++c) {
      const uint32_t o = out.triangles[t][c], v = in.triangles[t][c];
      if (o == v) continue;
      ASSERT_GE(o, in.positions.size()) << what << ": triangle " << t;
      ASSERT_EQ(out.positions[o], out.positions[v]) << what << ": triangle " << t;
    }
  const MeshAttributes &a = in.attributes, &b = out.attributes;
  ASSERT_EQ(a.hasUvs(), b.hasUvs()) << what;
  if (a.hasUvs()) {
    // In out's convention (v = 0 at the image's bottom or top row): exactly 1 - v when the
    // formats differ, as the writers convert.
    EXPECT_TRUE(
        sameBits(perCorner(uvsFrom(a, b.uvOrigin), a.uvTriangles), perCorner(b.uvs, b.uvTriangles)))
        << what << ": texture coordinates";
  }
  if (!normals) return;
  ASSERT_EQ(a.hasNormals(), b.hasNormals()) << what;
  if (a.hasNormals()) {
    EXPECT_TRUE(
        sameBits(perCorner(a.normals, a.normalTriangles), perCorner(b.normals, b.normalTriangles)))
        << what << ": normals";
  }
}

// Positions as float (what glTF stores), the rest unchanged.
Mesh asFloat(Mesh m) {
  for (Vec3d& p : m.positions)
    for (double& c : p)
      c = static_cast<float>(c);
  return m;
}

Mesh sphereWithAttributes(bool perCornerUvs) {
  std::vector<Mesh> frames = test::wobblingSphere(2, 1);
  test::addAttributes(frames, perCornerUvs);
  return frames[0];
}

// ---- Files ----

TEST(AttributeFiles, ObjReadsAndWritesTextureCoordinatesAndNormals) {
  const std::string text =
      "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
      "vt 0 0\nvt 1 0\nvt 1 1 0.5\nvt 0 1\n"
      "vn 0 0 1\nvn 0 0 -0\n"
      "f 1/1/1 2/2/1 3/3/1 4/4/2\n"      // a quad: a fan of two triangles
      "f -4/-1/-1 -2/-3/-2 -1/-2/-1\n";  // negative indices count back
  const Mesh m = parseObj(text, "m.obj");
  ASSERT_EQ(m.triangles.size(), 3u);
  const MeshAttributes& a = m.attributes;
  EXPECT_EQ(a.uvs, (std::vector<Vec2f>{{0, 0}, {1, 0}, {1, 1}, {0, 1}}));
  EXPECT_EQ(a.uvTriangles, (std::vector<Triangle>{{0, 1, 2}, {0, 2, 3}, {3, 1, 2}}));
  EXPECT_EQ(a.normalTriangles, (std::vector<Triangle>{{0, 0, 0}, {0, 0, 1}, {1, 0, 1}}));
  EXPECT_TRUE(std::signbit(a.normals[1][2]));
  // Written and read again: the same, bit for bit.
  const Mesh back = parseObj(formatObj(m), "back.obj");
  EXPECT_EQ(back.attributes, m.attributes);
  EXPECT_TRUE(sameBits(back.attributes.normals, m.attributes.normals));
  // v/vt and v//vn alone, and values no face uses (dropped).
  const Mesh uvOnly =
      parseObj("v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0.25 0.5\nvn 0 0 1\nf 1/1 2/1 3/1\n", "uv.obj");
  EXPECT_TRUE(uvOnly.attributes.hasUvs());
  EXPECT_FALSE(uvOnly.attributes.hasNormals());
  EXPECT_NE(formatObj(uvOnly).find("f 1/1 2/1 3/1"), std::string::npos) << formatObj(uvOnly);
  const Mesh nOnly = parseObj("v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1//1 2//1 3//1\n", "n.obj");
  EXPECT_FALSE(nOnly.attributes.hasUvs());
  EXPECT_NE(formatObj(nOnly).find("f 1//1 2//1 3//1"), std::string::npos) << formatObj(nOnly);
  // Shortest float text that reads back to the same float.
  Mesh odd = nOnly;
  odd.attributes.normals[0] = {0.1f, 1e-30f, -3.4028235e38f};
  EXPECT_TRUE(
      sameBits(parseObj(formatObj(odd), "odd.obj").attributes.normals, odd.attributes.normals));
}

// OBJ's 'vt u [v [w]]': v defaults to 0; w, and values after a normal's x y z, are left out with
// one warning per file naming the first such line.
TEST(AttributeFiles, ObjOptionalAndExtraAttributeValues) {
  const std::string tri = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
  std::vector<std::string> said;
  const WarningHandler before =
      setWarningHandler([&](const std::string& message) { said.push_back(message); });
  const Mesh m = parseObj(
      tri + "vt 0.25\nvt 0.5 0.75 0.5\nvt 1 1 2\nvn 0 0 1 9\nf 1/1/1 2/2/1 3/3/1\n", "w.obj");
  setWarningHandler(before);
  ASSERT_EQ(m.attributes.uvs.size(), 3u);
  EXPECT_EQ(m.attributes.uvs[0], (Vec2f{0.25f, 0.0f}));
  EXPECT_EQ(m.attributes.uvs[1], (Vec2f{0.5f, 0.75f}));
  ASSERT_EQ(m.attributes.normals.size(), 1u);
  ASSERT_EQ(said.size(), 2u);
  EXPECT_EQ(said[0],
            "w.obj:5: values after u v on 'vt' lines (w) are left out (this line and any "
            "other)");
  EXPECT_EQ(said[1],
            "w.obj:7: values after x y z on 'vn' lines are left out (this line and any "
            "other)");
}

TEST(AttributeFiles, ObjErrorsNameTheLine) {
  const std::string tri = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
  EXPECT_NE(errorOf([&] { parseObj(tri + "vt 0 0\nf 1/1 2/2 3/1\n", "a.obj"); })
                .find("a.obj:5: texture coordinate index 2 out of range (the file has 1 "
                      "texture coordinate)"),
            std::string::npos);
  // Corners without the index, or indices without values: the attribute is left out.
  const Mesh mixed = parseObj(tri + "vn 0 0 1\nvt 0 0\nf 1//1 2//1 3//1\nf 1/1 2/1 3\n", "b.obj");
  EXPECT_TRUE(mixed.attributes.empty());
  EXPECT_EQ(mixed.triangles.size(), 2u);
  EXPECT_TRUE(parseObj(tri + "f 1/7/2 2/7/2 3/7/2\n", "b.obj").attributes.empty());
  EXPECT_NE(errorOf([&] {
              parseObj(tri + "vt\nf 1 2 3\n", "c.obj");
            }).find("c.obj:4: texture coordinate needs a value"),
            std::string::npos);
  EXPECT_NE(errorOf([&] {
              parseObj(tri + "vn 0 0 nan\nf 1 2 3\n", "d.obj");
            }).find("d.obj:4: non-finite number 'nan'"),
            std::string::npos);
  EXPECT_NE(errorOf([&] {
              parseObj(tri + "vt 0 0\nf 1/x 2/1 3/1\n", "e.obj");
            }).find("e.obj:5: bad texture coordinate index in '1/x'"),
            std::string::npos);
}

TEST(AttributeFiles, PlyPerVertexExactlyAndSeamsSplit) {
  const Mesh m = sphereWithAttributes(false);
  ASSERT_TRUE(attributesPerVertex(m));
  for (PlyEncoding e : {PlyEncoding::kBinaryLittleEndian, PlyEncoding::kAscii}) {
    const Mesh back = parsePly(formatPly(m, e), "m.ply");
    EXPECT_EQ(back.positions, m.positions);
    EXPECT_EQ(back.triangles, m.triangles);
    EXPECT_EQ(back.attributes, m.attributes);
  }
  // Per-corner texture coordinates: vertex copies at the seams, listed after the others.
  const Mesh seams = sphereWithAttributes(true);
  ASSERT_FALSE(attributesPerVertex(seams));
  size_t copies = 0;
  const Mesh split = splitAttributeSeams(seams, &copies);
  EXPECT_GT(copies, 0u);
  EXPECT_EQ(split.positions.size(), seams.positions.size() + copies);
  for (PlyEncoding e : {PlyEncoding::kBinaryLittleEndian, PlyEncoding::kAscii}) {
    const std::string data = formatPly(seams, e);
    EXPECT_NE(data.find("comment 3DVO: the last " + std::to_string(copies) + " of "),
              std::string::npos);
    expectSameSurface(seams, parsePly(data, "seams.ply"), 0, "seams.ply");
  }
  // Other property names for texture coordinates; an incomplete normal is an error.
  const std::string st =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty "
      "float z\nproperty float texture_s\nproperty float texture_t\nelement face 1\nproperty "
      "list uchar int vertex_indices\nend_header\n0 0 0 0.5 0.25\n1 0 0 1 0\n0 1 0 0 1\n3 0 1 2\n";
  const Mesh stMesh = parsePly(st, "st.ply");
  EXPECT_EQ(stMesh.attributes.uvs, (std::vector<Vec2f>{{0.5f, 0.25f}, {1, 0}, {0, 1}}));
  EXPECT_EQ(stMesh.attributes.uvTriangles, stMesh.triangles);
  std::string partial = st;
  partial.replace(partial.find("texture_s"), 9, "nx");
  partial.replace(partial.find("texture_t"), 9, "ny");
  EXPECT_NE(errorOf([&] { parsePly(partial, "p.ply"); })
                .find("p.ply:3: the vertex element has part of a normal (nx, ny and nz go "
                      "together)"),
            std::string::npos);
}

TEST(AttributeFiles, GltfWrittenFilesReadBack) {
  for (bool corners : {false, true}) {
    const Mesh m = sphereWithAttributes(corners);
    for (GltfContainer c : {GltfContainer::kGltf, GltfContainer::kGlb}) {
      const std::string data = formatGltf(m, c);
      const GltfFile file(std::vector<uint8_t>(data.begin(), data.end()), "m.gltf");
      expectSameSurface(asFloat(m), file.frame(0), 1e-6, "glTF");
    }
  }
  // The animated .glb: texture coordinates of each run, the normals of every frame.
  std::vector<Mesh> frames = test::wobblingSphere(1, 5);
  test::addAttributes(frames, true);
  GltfAnimationWriter writer(25);
  for (const Mesh& f : frames)
    writer.add(f);
  const std::string glb = writer.finish();
  const GltfFile file(std::vector<uint8_t>(glb.begin(), glb.end()), "anim.glb");
  ASSERT_EQ(file.frameCount(), frames.size());
  for (size_t k = 0; k < frames.size(); ++k) {
    const Mesh back = file.frame(k);
    expectSameSurface(frames[k], back, 1e-5, "frame " + std::to_string(k), false);
    const std::vector<Vec3f> a = perCorner(frames[k].attributes.normals, frames[k].triangles);
    const std::vector<Vec3f> b = perCorner(back.attributes.normals, back.triangles);
    ASSERT_EQ(a.size(), b.size());
    for (size_t i = 0; i < a.size(); ++i)
      for (int c = 0; c < 3; ++c)
        ASSERT_NEAR(a[i][c], b[i][c], 1e-6) << "frame " << k;
  }
}

// A glTF made by tinygltf's writer (another tool than ours: its own layout, 16-bit indices, an
// interleaved vertex buffer with a stride, texture coordinates as normalized unsigned shorts)
// from a known mesh reads back with its texture coordinates and normals.
TEST(AttributeFiles, GltfMadeByTinygltfIsRead) {
  const Mesh m = sphereWithAttributes(false);
  const size_t n = m.positions.size();
  tinygltf::Model model;
  model.asset.version = "2.0";
  model.buffers.resize(1);
  std::vector<unsigned char>& bytes = model.buffers[0].data;
  auto append = [&](const void* p, size_t size) {
    const size_t at = bytes.size();
    bytes.insert(bytes.end(), static_cast<const unsigned char*>(p),
                 static_cast<const unsigned char*>(p) + size);
    return at;
  };
  // Interleaved: position (3 float), normal (3 float), uv (2 ushort, normalized) = 28 bytes.
  std::vector<Vec2f> expectedUvs;
  for (size_t i = 0; i < n; ++i) {
    const float p[3] = {float(m.positions[i][0]), float(m.positions[i][1]),
                        float(m.positions[i][2])};
    append(p, 12);
    append(m.attributes.normals[i].data(), 12);
    uint16_t uv[2];
    for (int c = 0; c < 2; ++c) {
      const float clamped = std::min(1.0f, std::max(0.0f, m.attributes.uvs[i][c]));
      uv[c] = static_cast<uint16_t>(std::lround(clamped * 65535.0f));
    }
    append(uv, 4);
    expectedUvs.push_back({float(uv[0] / 65535.0), float(uv[1] / 65535.0)});
  }
  tinygltf::BufferView vertexView;
  vertexView.buffer = 0;
  vertexView.byteOffset = 0;
  vertexView.byteLength = bytes.size();
  vertexView.byteStride = 28;
  vertexView.target = TINYGLTF_TARGET_ARRAY_BUFFER;
  model.bufferViews.push_back(vertexView);
  std::vector<uint16_t> indices;
  for (const Triangle& t : m.triangles)
    for (uint32_t v : t)
      indices.push_back(static_cast<uint16_t>(v));
  tinygltf::BufferView indexView;
  indexView.buffer = 0;
  indexView.byteOffset = append(indices.data(), indices.size() * 2);
  indexView.byteLength = indices.size() * 2;
  indexView.target = TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER;
  model.bufferViews.push_back(indexView);
  auto accessor = [&](int view, size_t offset, int componentType, int type, size_t count,
                      bool normalized) {
    tinygltf::Accessor a;
    a.bufferView = view;
    a.byteOffset = offset;
    a.componentType = componentType;
    a.type = type;
    a.count = count;
    a.normalized = normalized;
    if (type == TINYGLTF_TYPE_VEC3) {
      a.minValues = {-1e9, -1e9, -1e9};
      a.maxValues = {1e9, 1e9, 1e9};
    }
    model.accessors.push_back(a);
    return static_cast<int>(model.accessors.size() - 1);
  };
  tinygltf::Primitive prim;
  prim.mode = TINYGLTF_MODE_TRIANGLES;
  prim.attributes["POSITION"] =
      accessor(0, 0, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, n, false);
  prim.attributes["NORMAL"] =
      accessor(0, 12, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, n, false);
  prim.attributes["TEXCOORD_0"] =
      accessor(0, 24, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT, TINYGLTF_TYPE_VEC2, n, true);
  prim.indices = accessor(1, 0, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT, TINYGLTF_TYPE_SCALAR,
                          indices.size(), false);
  tinygltf::Mesh mesh;
  mesh.primitives.push_back(prim);
  model.meshes.push_back(mesh);
  tinygltf::Node node;
  node.mesh = 0;
  model.nodes.push_back(node);
  tinygltf::Scene scene;
  scene.nodes.push_back(0);
  model.scenes.push_back(scene);
  for (bool binary : {false, true}) {
    tinygltf::TinyGLTF writer;
    std::ostringstream out;
    ASSERT_TRUE(writer.WriteGltfSceneToStream(&model, out, false, binary));
    test::TempDir dir("gltf-attributes");
    const std::string path = dir.file(binary ? "m.glb" : "m.gltf");
    test::writeText(path, out.str());
    const Mesh back = readMesh(path);
    EXPECT_EQ(back.triangles, m.triangles);
    EXPECT_TRUE(sameBits(back.attributes.normals, m.attributes.normals)) << path;
    EXPECT_TRUE(sameBits(back.attributes.uvs, expectedUvs)) << path;
    EXPECT_EQ(back.attributes.uvTriangles, m.triangles);
    EXPECT_EQ(back.attributes.normalTriangles, m.triangles);
  }
}

// ---- Through the apps ----

struct Coded {
  std::string encoderErr;
  std::string encoderBytes;  // the summary's "bytes" line
  std::vector<Mesh> decoded;
};

// Encodes `frames` written as `inExt` with `options`, decodes with --MeshFormat=`outFormat`.
// Normals are compared unless `normalsKept` is false (computed or dropped).
Coded roundTrip(const std::vector<Mesh>& given, const std::string& inExt,
                const std::string& outFormat, const std::string& outExt,
                const std::vector<std::string>& options, int bits = 16, bool normalsKept = true) {
  test::TempDir dir("attributes-roundtrip");
  std::filesystem::create_directories(dir.path() / "in");
  // The input files; the frames compared with the output are what they hold (a glTF file's
  // seams split and v measured from the top row).
  std::vector<Mesh> frames;
  for (size_t f = 0; f < given.size(); ++f) {
    const std::string path = dir.file("in/" + framePath("%03d", static_cast<int>(f)) + inExt);
    if (inExt == ".obj") writeObj(path, given[f]);
    if (inExt == ".ply") writePly(path, given[f]);
    if (inExt == ".gltf") writeGltf(path, given[f], GltfContainer::kGltf);
    frames.push_back(inExt == ".gltf" ? readMesh(path) : given[f]);
  }
  std::vector<std::string> args = {"--InputMeshPattern=in/%03d" + inExt,
                                   "--FrameCount=" + std::to_string(frames.size()),
                                   "--GridBits=" + std::to_string(bits), "-o", "x.3dvo"};
  args.insert(args.end(), options.begin(), options.end());
  const test::CommandResult enc = test::run(dir, kBin + "/3dvo-enc", args);
  Coded out;
  out.encoderErr = enc.err;
  for (const std::string& line : test::lines(enc.out))
    if (line.rfind("bytes ", 0) == 0) out.encoderBytes = line;
  EXPECT_EQ(enc.exitCode, 0) << enc.err;
  if (enc.exitCode != 0) return out;
  // The decoder reproduces the encoder's MD5 lines (attributes included).
  test::writeText(dir.file("enc.log"), enc.out);
  const test::CommandResult verified =
      test::run(dir, kBin + "/3dvo-dec",
                {"-i", "x.3dvo", "-o", "out", "--MeshFormat=" + outFormat, "--verify", "enc.log"});
  EXPECT_EQ(verified.exitCode, 0) << verified.err;
  const double tolerance = 0.5 * test::extentOf(frames) / ((1 << bits) - 1) * 1.0001 + 1e-6;
  for (size_t f = 0; f < frames.size(); ++f) {
    const std::string path = dir.file("out/" + framePath("%04d", static_cast<int>(f)) + outExt);
    out.decoded.push_back(readMesh(path));
    // glTF holds positions as float: add their rounding.
    const double slack = outExt == ".obj" || outExt == ".ply" ? 0 : 1e-6 * test::extentOf(frames);
    expectSameSurface(frames[f], out.decoded.back(), tolerance + slack, path, normalsKept);
  }
  return out;
}

// OBJ with per-corner texture coordinates (seams) and normals constant over the GOM: coded
// once per I mesh; out as glTF (seams split), .glb and OBJ (the same indices, exactly).
TEST(AttributesRoundTrip, ObjToGltfWithPMeshes) {
  std::vector<Mesh> frames = test::wobblingSphere(2, 6, 1.0, {3, -2, 1});
  test::addAttributes(frames, true, true);
  const Coded gltf = roundTrip(frames, ".obj", "gltf", ".gltf", {"--GOMSize=4"});
  EXPECT_NE(gltf.encoderErr.find("normals from frame 0 on: coded exactly, once per I mesh"),
            std::string::npos)
      << gltf.encoderErr;
  roundTrip(frames, ".obj", "glb", ".glb", {"--GOMSize=4", "--PMeshMode=afxic"});
  const Coded obj = roundTrip(frames, ".obj", "obj", ".obj", {"--GOMSize=3"});
  for (size_t f = 0; f < frames.size(); ++f)
    EXPECT_EQ(obj.decoded[f].attributes, frames[f].attributes) << "frame " << f;
}

// glTF input: texture coordinates whose v = 0 is the image's top row (at_uv_origin 1) come out
// of a glTF exactly and of an OBJ or PLY as 1 - v (expectSameSurface compares in the output's
// convention), so a texture image shows the same way through every format.
TEST(AttributesRoundTrip, GltfTextureCoordinatesKeepTheirImage) {
  std::vector<Mesh> frames = test::wobblingSphere(2, 4, 1.0, {3, -2, 1});
  test::addAttributes(frames, true, true);
  const Coded gltf = roundTrip(frames, ".gltf", "gltf", ".gltf", {"--GOMSize=4"});
  ASSERT_EQ(gltf.decoded.size(), frames.size());
  EXPECT_EQ(gltf.decoded[0].attributes.uvOrigin, UvOrigin::kTop);
  const Coded obj = roundTrip(frames, ".gltf", "obj", ".obj", {"--GOMSize=4"});
  ASSERT_EQ(obj.decoded.size(), frames.size());
  EXPECT_EQ(obj.decoded[0].attributes.uvOrigin, UvOrigin::kBottom);
  roundTrip(frames, ".gltf", "ply", ".ply", {"--PMeshMode=intra"});
  // Within a float32 rounding (of values below 2 here) of those the glTF was made from:
  // 1 - (1 - v).
  const MeshAttributes &in = frames[0].attributes, &out = obj.decoded[0].attributes;
  ASSERT_EQ(out.uvTriangles.size(), in.uvTriangles.size());
  for (size_t t = 0; t < in.uvTriangles.size(); ++t)
    for (int c = 0; c < 3; ++c)
      for (int k = 0; k < 2; ++k)
        ASSERT_NEAR(out.uvs[out.uvTriangles[t][c]][k], in.uvs[in.uvTriangles[t][c]][k], 2.5e-7)
            << "triangle " << t;
}

// PLY with per-vertex attributes, normals changing every frame: intra GOMs code every frame's
// exactly; out as PLY.
TEST(AttributesRoundTrip, PlyToPlyIntra) {
  std::vector<Mesh> frames = test::wobblingSphere(2, 5, 1.0, {3, -2, 1});
  test::addAttributes(frames, false);
  const Coded ply = roundTrip(frames, ".ply", "ply", ".ply", {"--PMeshMode=intra"});
  for (size_t f = 0; f < frames.size(); ++f)
    EXPECT_EQ(ply.decoded[f].attributes, frames[f].attributes) << "frame " << f;
  roundTrip(frames, ".ply", "ply-ascii", ".ply", {"--PMeshMode=intra"});
}

// Normals changing within a GOM of P meshes: the decoder computes them (Normals auto says so),
// per vertex from the decoded frame; texture coordinates still exact.
TEST(AttributesRoundTrip, ChangingNormalsAreComputed) {
  std::vector<Mesh> frames = test::wobblingSphere(2, 4, 1.0);
  test::addAttributes(frames, false);
  const Coded c = roundTrip(frames, ".ply", "ply", ".ply", {"--GOMSize=4"}, 16, false);
  EXPECT_NE(c.encoderErr.find("normals from frame 0 on: computed by the decoder from each decoded "
                              "frame (they change within the GOM)"),
            std::string::npos)
      << c.encoderErr;
  for (size_t f = 0; f < frames.size(); ++f) {
    const std::vector<Vec3f>& n = c.decoded[f].attributes.normals;
    ASSERT_EQ(n.size(), frames[f].positions.size());
    for (size_t v = 0; v < n.size(); ++v)
      for (int k = 0; k < 3; ++k)
        ASSERT_NEAR(n[v][k], frames[f].attributes.normals[v][k], 0.01) << "frame " << f;
  }
  // Normals none drops them; coded refuses (they change).
  const Coded none =
      roundTrip(frames, ".ply", "ply", ".ply", {"--GOMSize=4", "--Normals=none"}, 16, false);
  EXPECT_FALSE(none.decoded[0].attributes.hasNormals());
  EXPECT_TRUE(none.decoded[0].attributes.hasUvs());
}

// The same normal at every corner, listed in another order from frame 1 on (another `vn`
// order): coded once, exact per corner, and the list order said; not computed.
TEST(AttributesRoundTrip, ReorderedNormalsAreCodedExactlyPerCorner) {
  std::vector<Mesh> frames = test::wobblingSphere(2, 4, 1.0);
  test::addAttributes(frames, true, true);
  const auto reverse = [](auto& values, std::vector<Triangle>& indices) {
    const uint32_t last = static_cast<uint32_t>(values.size() - 1);
    std::reverse(values.begin(), values.end());
    for (Triangle& t : indices)
      for (uint32_t& i : t)
        i = last - i;
  };
  for (size_t f = 1; f < frames.size(); ++f)
    reverse(frames[f].attributes.normals, frames[f].attributes.normalTriangles);
  reverse(frames[2].attributes.uvs, frames[2].attributes.uvTriangles);
  // (roundTrip compares every corner's texture coordinate, bit for bit.)
  const Coded c = roundTrip(frames, ".obj", "obj", ".obj", {"--GOMSize=4"}, 16, false);
  EXPECT_NE(c.encoderErr.find("in/001.obj and 2 more frames of its GOM list the normals of the "
                              "GOM's first frame (in/000.obj) in another order"),
            std::string::npos)
      << c.encoderErr;
  EXPECT_NE(c.encoderErr.find("in/002.obj lists the texture coordinates of the GOM's first frame "
                              "(in/000.obj) in another order"),
            std::string::npos)
      << c.encoderErr;
  EXPECT_NE(c.encoderErr.find("normals from frame 0 on: coded exactly, once per I mesh"),
            std::string::npos)
      << c.encoderErr;
  ASSERT_EQ(c.decoded.size(), frames.size());
  for (size_t f = 0; f < frames.size(); ++f) {
    const MeshAttributes &in = frames[f].attributes, &out = c.decoded[f].attributes;
    ASSERT_EQ(out.normalTriangles.size(), in.normalTriangles.size()) << "frame " << f;
    for (size_t t = 0; t < in.normalTriangles.size(); ++t)
      for (int k = 0; k < 3; ++k)
        ASSERT_EQ(out.normals[out.normalTriangles[t][k]], in.normals[in.normalTriangles[t][k]])
            << "frame " << f << " triangle " << t;
  }
  // Normals coded accepts them too (nothing changes but the order).
  roundTrip(frames, ".obj", "obj", ".obj", {"--GOMSize=4", "--Normals=coded"}, 16, false);
  // Values are compared bit for bit: -0 where the first frame has 0 is a change (the normals
  // are then computed), not the first frame's value.
  std::vector<Mesh> zero = test::wobblingSphere(2, 4, 1.0);
  test::addAttributes(zero, false, true);
  for (Mesh& m : zero)
    m.attributes.normals[0] = {0.0f, 1.0f, 0.0f};
  EXPECT_NE(roundTrip(zero, ".obj", "obj", ".obj", {"--GOMSize=4"})
                .encoderErr.find("normals from frame 0 on: coded exactly, once per I mesh"),
            std::string::npos);
  zero[3].attributes.normals[0][0] = -0.0f;
  const Coded signedZero = roundTrip(zero, ".obj", "obj", ".obj", {"--GOMSize=4"}, 16, false);
  EXPECT_NE(signedZero.encoderErr.find("(they change within the GOM)"), std::string::npos)
      << signedZero.encoderErr;
}

TEST(AttributesRoundTrip, EncoderRefusesWhatItWouldLose) {
  std::vector<Mesh> frames = test::wobblingSphere(1, 4);
  test::addAttributes(frames, true);
  for (size_t f : {2, 3})  // new texture coordinates from frame 2 on
    frames[f].attributes.uvs[5][0] += 0.5f;
  test::TempDir dir("attributes-errors");
  std::filesystem::create_directories(dir.path() / "in");
  for (size_t f = 0; f < frames.size(); ++f)
    writeObj(dir.file("in/" + framePath("%03d", static_cast<int>(f)) + ".obj"), frames[f]);
  auto encode = [&](const std::vector<std::string>& options) {
    std::vector<std::string> args = {"--InputMeshPattern=in/%03d.obj", "--FrameCount=4", "-o",
                                     "x.3dvo"};
    args.insert(args.end(), options.begin(), options.end());
    return test::run(dir, kBin + "/3dvo-enc", args);
  };
  const test::CommandResult changed = encode({"--GOMSize=4"});
  EXPECT_EQ(changed.exitCode, 1);
  EXPECT_NE(changed.err.find("in/002.obj: texture coordinates differ from those of the GOM's "
                             "first frame (in/000.obj)"),
            std::string::npos)
      << changed.err;
  EXPECT_NE(changed.err.find("use shorter GOMs (GOMSize, GOMListFile) or PMeshMode intra"),
            std::string::npos);
  EXPECT_FALSE(std::filesystem::exists(dir.file("x.3dvo")));
  // The remedies work.
  EXPECT_EQ(encode({"--GOMSize=2"}).exitCode, 0);
  EXPECT_EQ(encode({"--PMeshMode=intra"}).exitCode, 0);
  EXPECT_EQ(encode({"--GOMSize=4", "--TextureCoordinates=0"}).exitCode, 0);
  // Normals coded while they change.
  const test::CommandResult coded = encode({"--GOMSize=2", "--Normals=coded"});
  EXPECT_EQ(coded.exitCode, 1);
  EXPECT_NE(coded.err.find("normals change within the GOM, and Normals coded"), std::string::npos)
      << coded.err;
  // A later frame with attributes when the first has none.
  Mesh bare = frames[0];
  bare.attributes = MeshAttributes();
  writeObj(dir.file("in/000.obj"), bare);
  const test::CommandResult late = encode({"--PMeshMode=intra"});
  EXPECT_EQ(late.exitCode, 1);
  EXPECT_NE(late.err.find("in/001.obj: has texture coordinates or normals, but the sequence's "
                          "first frame has none"),
            std::string::npos)
      << late.err;
}

// How normals are carried is said once, as a warning (Quality's trial codings repeated it, on
// stderr past the warning handler), and Normals none says it left them out.
TEST(AttributesRoundTrip, TheNormalsLineIsSaidOnce) {
  test::TempDir dir("attributes-normals");
  std::filesystem::create_directories(dir.path() / "in");
  for (const char* frame : {"in/000.obj", "in/001.obj"})
    test::writeText(dir.file(frame),
                    "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nvn 0 0 1\n"
                    "f 1/1/1 2/2/1 3/3/1\n");
  for (const bool none : {false, true}) {
    std::vector<std::string> args = {"--InputMeshPattern=in/%03d.obj", "-o", "x.3dvo"};
    if (none) args.push_back("--Normals=none");
    const test::CommandResult enc = test::run(dir, kBin + "/3dvo-enc", args);  // Quality 50
    ASSERT_EQ(enc.exitCode, 0) << enc.err;
    const std::string line = std::string("3dvo-enc: warning: normals from frame 0 on: ") +
                             (none ? "none (Normals none: left out)" : "coded exactly");
    EXPECT_EQ(test::linesStartingWith(enc.err, line).size(), 1u) << enc.err;
    EXPECT_EQ(enc.err.find("normals from frame 0 on:"), enc.err.rfind("normals from frame 0 on:"))
        << enc.err;
  }
}

// An OBJ file with more texture coordinates than face corners (values no corner refers to): those
// are left out with a warning, and every corner keeps its value. (The encoder refused the file.)
TEST(AttributesRoundTrip, ValuesNoCornerRefersToAreLeftOut) {
  test::TempDir dir("attributes-unused");
  std::filesystem::create_directories(dir.path() / "in");
  for (const char* frame : {"in/000.obj", "in/001.obj"})
    test::writeText(dir.file(frame),
                    "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 0.5 0.5\nvt 1 0\nvt 0.25 0.75\n"
                    "f 1/1 2/3 3/4\n");
  const test::CommandResult enc =
      test::run(dir, kBin + "/3dvo-enc", {"--InputMeshPattern=in/%03d.obj", "-o", "x.3dvo"});
  ASSERT_EQ(enc.exitCode, 0) << enc.err;
  EXPECT_NE(enc.err.find("in/000.obj: 1 texture coordinate that no face corner refers to: left "
                         "out"),
            std::string::npos)
      << enc.err;
  ASSERT_EQ(test::run(dir, kBin + "/3dvo-dec", {"-i", "x.3dvo", "-o", "out"}).exitCode, 0);
  const Mesh decoded = readMesh(dir.file("out/0000.obj"));
  const MeshAttributes& a = decoded.attributes;
  ASSERT_EQ(a.uvs.size(), 3u);
  ASSERT_EQ(a.uvTriangles.size(), 1u);
  ASSERT_EQ(decoded.triangles.size(), 1u);
  const std::map<uint32_t, std::array<float, 2>> expected = {
      {0, {0.0f, 0.0f}}, {1, {1.0f, 0.0f}}, {2, {0.25f, 0.75f}}};
  for (int k = 0; k < 3; ++k)
    EXPECT_EQ(a.uvs[a.uvTriangles[0][k]], expected.at(decoded.triangles[0][k])) << "corner " << k;
}

// Per-vertex OBJ values (the indices are the vertex indices) with a vertex no triangle uses: the
// encoder drops the vertex (with a warning) but not its values: the file comes back with the
// input's texture coordinate and normal lists and corner indices (coded per corner).
TEST(AttributesRoundTrip, ADroppedVertexKeepsTheLists) {
  test::TempDir dir("attributes-dropped-vertex");
  std::filesystem::create_directories(dir.path() / "in");
  const std::string lists =
      "vt 0 0\nvt 0.125 0\nvt 0.875 0.875\nvt 0 0.125\nvt 0.125 0.125\n"
      "vn 0 0 1\nvn 0 0.6 0.8\nvn 1 0 0\nvn 0 1 0\nvn 0.6 0 0.8\n"
      "f 1/1/1 2/2/2 5/5/5\nf 1/1/1 5/5/5 4/4/4\n";
  test::writeText(dir.file("in/000.obj"), "v 0 0 0\nv 1 0 0\nv 7 7 7\nv 0 1 0\nv 1 1 0\n" + lists);
  test::writeText(dir.file("in/001.obj"),
                  "v 0 0 0\nv 1 0 0\nv 7 7 7\nv 0 1 0\nv 1 1 0.5\n" + lists);
  const test::CommandResult enc =
      test::run(dir, kBin + "/3dvo-enc",
                {"-c", TDVO_SOURCE_DIR "/cfg/d3dmc-lossless.cfg", "--InputMeshPattern=in/%03d.obj",
                 "--Normals=coded", "-o", "x.3dvo"});
  ASSERT_EQ(enc.exitCode, 0) << enc.err;
  ASSERT_EQ(test::run(dir, kBin + "/3dvo-dec", {"-i", "x.3dvo", "-o", "out"}).exitCode, 0);
  for (const char* frame : {"000", "001"}) {
    const Mesh in = readMesh(dir.file(std::string("in/") + frame + ".obj"));
    const Mesh out = readMesh(dir.file(std::string("out/0") + frame + ".obj"));
    EXPECT_EQ(out.attributes, in.attributes) << frame;
    EXPECT_EQ(out.positions.size(), 4u) << frame;
  }
}

// A few frames of horse-gallop (shared data) given texture coordinates and normals: OBJ ->
// 3DVO -> glTF (per-corner texture coordinates) and PLY -> 3DVO -> PLY (per vertex).
TEST(AttributesRoundTrip, SharedSequenceHorseGallop) {
  std::string missing;
  std::vector<Mesh> frames = test::sharedHorseFrames(TDVO_SHARED_DATA_DIR, 1, 4, missing);
  if (frames.empty()) GTEST_SKIP() << missing;
  std::vector<Mesh> corners = frames;
  test::addAttributes(corners, true, true);
  const Coded obj = roundTrip(corners, ".obj", "glb", ".glb", {"--GOMSize=4"}, 14);
  std::printf(
      "horse-gallop frames 1-4, per-corner texture coordinates (%zu) and per-vertex "
      "normals (%zu): %s\n",
      corners[0].attributes.uvs.size(), corners[0].attributes.normals.size(),
      obj.encoderBytes.c_str());
  test::addAttributes(frames, false, true);
  const Coded ply = roundTrip(frames, ".ply", "ply", ".ply", {"--GOMSize=4"}, 14);
  std::printf("horse-gallop frames 1-4, per-vertex texture coordinates and normals: %s\n",
              ply.encoderBytes.c_str());
}

// ---- The stream ----

// The decoder's frames equal the encoder's reconstruction, attributes included; the MD5 lines
// cover the attributes; GOMs that continue an I mesh carry its attributes without a unit.
TEST(AttributesStream, DecoderEqualsEncoderAndHashesCoverAttributes) {
  std::vector<Mesh> frames = test::wobblingSphere(2, 8);
  const std::vector<Mesh> bare = frames;
  test::addAttributes(frames, true, true);
  EncoderParams params;
  params.gridBits = 12;
  params.gomSize = 4;
  params.keyframeCount = 2;       // interpolated frames too
  params.randomAccessPeriod = 0;  // one I mesh: the GOMs after it continue it
  const Grid grid = gridForSequence(frames, params.gridBits);
  std::vector<IntMesh> recon;
  const EncodedSequence coded =
      encodeSequence(params, grid, frames, {}, [&](int, const IntMesh& m) { recon.push_back(m); });
  EXPECT_EQ(test::countUnits(coded.stream, UnitType::kAttributes), 1u);
  EXPECT_GT(coded.attributeBytes, 0u);
  StreamDecoder decoder(coded.stream.data(), coded.stream.size(), "x.3dvo");
  std::vector<IntMesh> decoded;
  decoder.decode([&](int, const IntMesh& m) { decoded.push_back(m); });
  ASSERT_EQ(decoded.size(), frames.size());
  for (size_t f = 0; f < frames.size(); ++f) {
    EXPECT_EQ(decoded[f].positions, recon[f].positions);
    EXPECT_EQ(decoded[f].attributes, recon[f].attributes);
    EXPECT_EQ(decoded[f].attributes, frames[f].attributes) << "frame " << f;
  }
  // Without attributes the same geometry hashes differently (and as before: no attributes,
  // no extra bytes).
  IntMesh plain = decoded[0];
  plain.attributes = MeshAttributes();
  EXPECT_NE(geometryHashLine(0, plain), geometryHashLine(0, decoded[0]));
  std::vector<IntMesh> bareRecon;
  encodeSequence(params, grid, bare, {}, [&](int, const IntMesh& m) { bareRecon.push_back(m); });
  EXPECT_EQ(geometryHashLine(0, plain), geometryHashLine(0, bareRecon[0]));
  // One changed texture coordinate changes the hash.
  IntMesh changed = decoded[0];
  changed.attributes.uvs[0][0] = std::nextafter(changed.attributes.uvs[0][0], 2.0f);
  EXPECT_NE(geometryHashLine(0, changed), geometryHashLine(0, decoded[0]));
}

// What texture coordinates and normals cost: printed (and recorded) for the report.
TEST(AttributesStream, BytesOfAttributes) {
  std::vector<Mesh> frames = test::wobblingSphere(3, 8);
  test::addAttributes(frames, true, true);
  EncoderParams params;
  params.gomSize = 8;
  const EncodedSequence coded = encodeSequence(params, gridForSequence(frames, params.gridBits),
                                               frames, {}, [](int, const IntMesh&) {});
  const size_t uvs = frames[0].attributes.uvs.size(), normals = frames[0].attributes.normals.size();
  std::printf(
      "ATTRIBUTES: %llu bytes for %zu texture coordinates, %zu corners and %zu normals "
      "(per vertex) of one I mesh; I mesh %llu, vertex order %llu bytes\n",
      static_cast<unsigned long long>(coded.attributeBytes), uvs, 3 * frames[0].triangles.size(),
      normals, static_cast<unsigned long long>(coded.iMeshBytes),
      static_cast<unsigned long long>(coded.orderBytes));
  // Lossless floats: less than their raw 32 bits each plus a 32-bit index per corner.
  EXPECT_LT(coded.attributeBytes, 4 * (2 * uvs + 3 * normals + 3 * frames[0].triangles.size()));
  // Quantised (UVQuantBits 12, NormalQuantBits 10): values are multiples of 2^-bits, nearest.
  params.uvQuantBits = 12;
  params.normalQuantBits = 10;
  std::vector<IntMesh> decoded;
  const EncodedSequence quantised =
      encodeSequence(params, gridForSequence(frames, params.gridBits), frames, {},
                     [&](int, const IntMesh& m) { decoded.push_back(m); });
  std::printf("quantised (UVQuantBits 12, NormalQuantBits 10): %llu bytes\n",
              static_cast<unsigned long long>(quantised.attributeBytes));
  EXPECT_LT(quantised.attributeBytes, coded.attributeBytes / 2);
  const MeshAttributes& in = frames[0].attributes;
  const MeshAttributes& out = decoded[0].attributes;
  ASSERT_EQ(out.uvs.size(), in.uvs.size());
  EXPECT_EQ(out.uvTriangles, in.uvTriangles);
  for (size_t i = 0; i < in.uvs.size(); ++i)
    for (int c = 0; c < 2; ++c)
      ASSERT_EQ(out.uvs[i][c], std::round(in.uvs[i][c] * 4096.0f) / 4096.0f);
  for (size_t i = 0; i < in.normals.size(); ++i)
    for (int c = 0; c < 3; ++c)
      ASSERT_EQ(out.normals[i][c], std::round(in.normals[i][c] * 1024.0f) / 1024.0f);
  // Values too large for the quantisation are an error naming the frame.
  std::vector<Mesh> large = frames;
  for (Mesh& m : large)
    m.attributes.uvs[3][1] = 5000.0f;  // 5000 * 2^12 > 2^24
  EXPECT_NE(errorOf([&] {
              encodeSequence(params, gridForSequence(large, params.gridBits), large, {},
                             [](int, const IntMesh&) {});
            })
                .find("texture coordinate 3 has a component (5000.000000) too large for "
                      "UVQuantBits 12 (magnitudes below 2^12)"),
            std::string::npos);
}

}  // namespace
}  // namespace tdvo
