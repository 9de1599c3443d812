// Mesh file formats (issue 19, item 6): PLY and glTF reading and writing at library level, and
// through the apps: OBJ -> 3DVO -> glTF and PLY -> 3DVO -> PLY keep positions (within half a
// grid step), vertex order and triangles, on generated meshes and on a shared sequence.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "common/core/error.h"
#include "common/core/gltf_io.h"
#include "common/core/mesh_io.h"
#include "common/core/obj_io.h"
#include "common/core/ply_io.h"
#include "common/core/sequence.h"
#include "common/core/tiny_gltf_config.h"
#include "common/core/warnings.h"
#include "tests/test_support.h"

namespace tdvo {
namespace {

const std::string kBin = TDVO_BIN_DIR;

// Positions bit for bit and triangles by index.
void expectSame(const Mesh& a, const Mesh& b) {
  ASSERT_EQ(a.positions.size(), b.positions.size());
  EXPECT_EQ(std::memcmp(a.positions.data(), b.positions.data(), a.positions.size() * 24), 0);
  EXPECT_EQ(a.triangles, b.triangles);
}

// Positions within `tolerance` per coordinate, the same order, the same triangles.
void expectClose(const Mesh& in, const Mesh& out, double tolerance, const std::string& what) {
  ASSERT_EQ(in.positions.size(), out.positions.size()) << what;
  double worst = 0;
  for (size_t i = 0; i < in.positions.size(); ++i)
    for (int c = 0; c < 3; ++c)
      worst = std::max(worst, std::fabs(in.positions[i][c] - out.positions[i][c]));
  EXPECT_LE(worst, tolerance) << what;
  EXPECT_EQ(in.triangles, out.triangles) << what;
}

using test::errorOf;

// ---- PLY ----

TEST(Ply, BinaryAndAsciiRoundTripExactly) {
  Mesh m = test::wobblingSphere(2, 1)[0];
  m.triangles.push_back({0, 1, 1});  // a degenerate triangle is kept
  m.positions[3] = {0.1, -1e-300, 12345.678901234567};
  expectSame(parsePly(formatPly(m), "b.ply"), m);
  expectSame(parsePly(formatPly(m, PlyEncoding::kAscii), "a.ply"), m);
  // Through the file reader, chunk by chunk and gzip-compressed.
  test::TempDir dir("ply");
  writePly(dir.file("m.ply"), m);
  expectSame(readPly(dir.file("m.ply")), m);
  expectSame(readMesh(dir.file("m.ply")), m);
}

// Big-endian, float/int/uchar coordinates, skipped properties and elements, polygons, a face
// element before the vertices.
TEST(Ply, TypesEndiannessAndSkippedData) {
  std::string body;
  auto be32 = [&](uint32_t v) {
    for (int i = 3; i >= 0; --i)
      body += static_cast<char>((v >> (8 * i)) & 0xFF);
  };
  auto bef = [&](float f) {
    uint32_t v;
    std::memcpy(&v, &f, 4);
    be32(v);
  };
  // face first: a quad (fan: 0 1 2, 0 2 3) with a skipped list before and a float after
  body += static_cast<char>(2);
  be32(7);
  be32(8);
  body += static_cast<char>(4);
  for (uint32_t i : {0u, 1u, 2u, 3u})
    be32(i);
  bef(0.5f);
  // an element 'edge' (skipped)
  body += std::string(2, '\x01');
  // four vertices: float x, skipped uchar, int y, double-less float z
  const float xs[] = {0, 1, 1, 0};
  const int32_t ys[] = {0, 0, 1, 1};
  for (int v = 0; v < 4; ++v) {
    bef(xs[v]);
    body += static_cast<char>(200);
    be32(static_cast<uint32_t>(ys[v]));
    bef(-2.5f);
  }
  const std::string header =
      "ply\nformat binary_big_endian 1.0\ncomment made by hand\n"
      "element face 1\nproperty list uchar int flags\nproperty list uchar uint vertex_indices\n"
      "property float quality\nelement edge 1\nproperty uchar a\nproperty uchar b\n"
      "element vertex 4\nproperty float x\nproperty uchar red\nproperty int y\n"
      "property float z\nend_header\n";
  const Mesh m = parsePly(header + body, "be.ply");
  ASSERT_EQ(m.positions.size(), 4u);
  EXPECT_EQ(m.positions[2], (Vec3d{1, 1, -2.5}));
  EXPECT_EQ(m.triangles, (std::vector<Triangle>{{0, 1, 2}, {0, 2, 3}}));
  // The same as ascii.
  const std::string ascii =
      "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty uchar red\n"
      "property int y\nproperty float z\nelement face 1\nproperty list uchar int "
      "vertex_indices\nend_header\n0 200 0 -2.5\n1 200 0 -2.5\n\n1 200 1 -2.5\n0 200 1 -2.5\n"
      "4 0 1 2 3";
  const Mesh a = parsePly(ascii, "a.ply");
  EXPECT_EQ(a.positions, m.positions);
  EXPECT_EQ(a.triangles, m.triangles);
}

TEST(Ply, MalformedFilesNameTheirPlace) {
  const Mesh m = test::wobblingSphere(1, 1)[0];
  const std::string good = formatPly(m);
  const size_t headerEnd = good.find("end_header\n") + 11;
  auto err = [](const std::string& data) { return errorOf([&] { parsePly(data, "x.ply"); }); };
  EXPECT_NE(err(good.substr(0, good.size() - 5)).find("x.ply: byte "), std::string::npos);
  EXPECT_NE(err(good.substr(0, good.size() - 5)).find("truncated"), std::string::npos);
  EXPECT_NE(err(good + "xx").find("bytes after the last element"), std::string::npos);
  EXPECT_NE(err("v 0 0 0\n").find("x.ply:1: not a PLY file"), std::string::npos);
  EXPECT_NE(err(good.substr(0, headerEnd - 11)).find("no end_header"), std::string::npos);
  // an index beyond the vertices, at the byte of its face
  std::string bad = good;
  bad[bad.size() - 4] = 100;
  EXPECT_NE(err(bad).find("vertex index 100 out of range (the file has 42 vertices)"),
            std::string::npos)
      << err(bad);
  const std::string head =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
      "property float y\nproperty float z\nelement face 1\n"
      "property list uchar int vertex_indices\nend_header\n";
  EXPECT_NE(err(head + "0 0 0\n1 0 0\n0 1\n3 0 1 2\n").find("x.ply:12: "), std::string::npos);
  EXPECT_NE(err(head + "0 0 0\n1 0 0\n0 1 nan\n3 0 1 2\n").find("x.ply:12: non-finite"),
            std::string::npos);
  EXPECT_NE(err(head + "0 0 0\n1 0 0\n0 1 0\n3 0 1 1\n").find("x.ply:13: every face"),
            std::string::npos);
  EXPECT_NE(err(head + "0 0 0\n1 0 0\n0 1 0\n2 0 1\n").find("x.ply:13: face needs at least"),
            std::string::npos);
  EXPECT_NE(err(head + "0 0 0\n1 0 0\n0 1 0\n3 0 1 -1\n").find("out of range"), std::string::npos);
  EXPECT_NE(err(head + "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n9 9 9\n").find("x.ply:14: text after"),
            std::string::npos);
  // A list longer than the limit is refused at its count, before its entries are read.
  EXPECT_NE(err(head + "0 0 0\n1 0 0\n0 1 0\n256 0 1 2\n").find("out of its type's range"),
            std::string::npos);
  std::string wide = head;
  wide.replace(wide.find("list uchar"), 10, "list uint");
  EXPECT_NE(err(wide + "0 0 0\n1 0 0\n0 1 0\n70000 0 1 2\n").find("x.ply:13: list of 70000"),
            std::string::npos);
  // A header declaring more vertices than the limit.
  EXPECT_NE(err("ply\nformat ascii 1.0\nelement vertex 99999999999\n").find("x.ply:3: more than"),
            std::string::npos);
}

// What a PLY file holds beyond positions, texture coordinates, normals and vertex indices is
// said in one warning (properties of vertex and face, other elements with records); tiny and
// '+'-signed numbers are numbers.
TEST(Ply, WhatIsNotReadIsSaid) {
  std::vector<std::string> said;
  const WarningHandler before =
      setWarningHandler([&](const std::string& message) { said.push_back(message); });
  const std::string text =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
      "property float z\nproperty uchar red\nproperty uchar green\nproperty float nx\n"
      "property float ny\nproperty float nz\nelement face 1\n"
      "property list uchar int vertex_indices\nproperty list uchar float texcoord\n"
      "element edge 2\nproperty int vertex1\nproperty int vertex2\nelement material 0\n"
      "property float shine\nend_header\n"
      "0 0 0 255 0 0 0 1e-50\n+1 0 0 0 255 0 0 1\n0 1 0 0 0 0 0 1\n3 0 1 2 6 0 0 1 0 0 1\n"
      "0 1\n1 2\n";
  const Mesh m = parsePly(text, "c.ply");
  EXPECT_EQ(m.positions[1], (Vec3d{1, 0, 0}));
  EXPECT_EQ(m.attributes.normals[0], (Vec3f{0, 0, 0}));
  ASSERT_EQ(said.size(), 1u);
  EXPECT_EQ(said[0],
            "c.ply: left out (not read): vertex properties red, green; face property texcoord; "
            "element edge (2 records)");
  said.clear();
  // In a run, files that leave the same things out (in other amounts) are counted.
  {
    WarnOnceScope once;
    parsePly(text, "c0.ply");
    std::string three = text;
    three.replace(three.find("element edge 2"), 14, "element edge 3");
    parsePly(three + "2 0\n", "c1.ply");
  }
  EXPECT_EQ(said, (std::vector<std::string>{
                      "c0.ply: left out (not read): vertex properties red, green; face property "
                      "texcoord; element edge (2 records)",
                      "left out (not read): vertex properties red, green; face property texcoord; "
                      "element edge: the same in 1 more file or frame"}));
  said.clear();
  parsePly(formatPly(test::wobblingSphere(1, 1)[0], PlyEncoding::kAscii), "plain.ply");
  EXPECT_TRUE(said.empty());
  // Meshlab's texture link (a comment, the one listed) and a quad split into two triangles.
  const Mesh quad = parsePly(
      "ply\nformat ascii 1.0\ncomment VCGLIB generated\ncomment TextureFile skin.png\n"
      "element vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
      "element face 2\nproperty list uchar int vertex_indices\nend_header\n"
      "0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2\n4 0 1 2 3\n",
      "quad.ply");
  EXPECT_EQ(quad.triangles, (std::vector<Triangle>{{0, 1, 2}, {0, 1, 2}, {0, 2, 3}}));
  EXPECT_EQ(said, (std::vector<std::string>{
                      "quad.ply: left out (not read): the texture image's name (comment "
                      "TextureFile, header line 4)",
                      "quad.ply:17: faces with more than three corners are split into triangles "
                      "(a fan from each face's first corner) (first)"}));
  setWarningHandler(before);
}

// ---- glTF ----

// A glTF model made with tinygltf's own API and writer (not ours): `frames` frames as a base mesh
// plus one morph target per further frame, with a STEP weights animation (or none).
std::string tinygltfMorphFile(const std::vector<Mesh>& frames, bool binary, bool animate,
                              float rate = 25.0f) {
  tinygltf::Model model;
  model.asset.version = "2.0";
  model.buffers.resize(1);
  auto& bytes = model.buffers[0].data;
  auto view = [&](const void* data, size_t n) {
    while (bytes.size() % 4)
      bytes.push_back(0);
    tinygltf::BufferView bv;
    bv.buffer = 0;
    bv.byteOffset = bytes.size();
    bv.byteLength = n;
    bytes.insert(bytes.end(), static_cast<const uint8_t*>(data),
                 static_cast<const uint8_t*>(data) + n);
    model.bufferViews.push_back(bv);
    return static_cast<int>(model.bufferViews.size() - 1);
  };
  auto accessor = [&](const std::vector<float>& v, int type, size_t count) {
    tinygltf::Accessor a;
    a.bufferView = view(v.data(), v.size() * 4);
    a.componentType = TINYGLTF_COMPONENT_TYPE_FLOAT;
    a.type = type;
    a.count = count;
    if (type == TINYGLTF_TYPE_VEC3) {
      a.minValues = {-1e9, -1e9, -1e9};
      a.maxValues = {1e9, 1e9, 1e9};
    } else {
      a.minValues = {v.front()};
      a.maxValues = {v.back()};
    }
    model.accessors.push_back(a);
    return static_cast<int>(model.accessors.size() - 1);
  };
  const Mesh& base = frames[0];
  const size_t n = base.positions.size();
  auto floats = [&](const Mesh& m, const Mesh* minus) {
    std::vector<float> v;
    for (size_t i = 0; i < n; ++i)
      for (int c = 0; c < 3; ++c)
        v.push_back(static_cast<float>(m.positions[i][c] - (minus ? minus->positions[i][c] : 0)));
    return v;
  };
  tinygltf::Primitive prim;
  prim.mode = TINYGLTF_MODE_TRIANGLES;
  prim.attributes["POSITION"] = accessor(floats(base, nullptr), TINYGLTF_TYPE_VEC3, n);
  std::vector<uint16_t> indices;
  for (const Triangle& t : base.triangles)
    for (uint32_t v : t)
      indices.push_back(static_cast<uint16_t>(v));
  tinygltf::Accessor ia;
  ia.bufferView = view(indices.data(), indices.size() * 2);
  ia.componentType = TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT;
  ia.type = TINYGLTF_TYPE_SCALAR;
  ia.count = indices.size();
  model.accessors.push_back(ia);
  prim.indices = static_cast<int>(model.accessors.size() - 1);
  for (size_t f = 1; f < frames.size(); ++f)
    prim.targets.push_back(
        {{"POSITION", accessor(floats(frames[f], &base), TINYGLTF_TYPE_VEC3, n)}});
  tinygltf::Mesh mesh;
  mesh.primitives.push_back(prim);
  mesh.weights.assign(frames.size() - 1, 0.0);
  model.meshes.push_back(mesh);
  tinygltf::Node node;
  node.mesh = 0;
  model.nodes.push_back(node);
  tinygltf::Scene scene;
  scene.nodes.push_back(0);
  model.scenes.push_back(scene);
  if (animate) {
    const size_t t = frames.size() - 1;
    std::vector<float> times, weights(frames.size() * t, 0.0f);
    for (size_t f = 0; f < frames.size(); ++f) {
      times.push_back(static_cast<float>(f) / rate);
      if (f > 0) weights[f * t + f - 1] = 1.0f;
    }
    tinygltf::AnimationSampler s;
    s.input = accessor(times, TINYGLTF_TYPE_SCALAR, times.size());
    s.output = accessor(weights, TINYGLTF_TYPE_SCALAR, weights.size());
    s.interpolation = "STEP";
    tinygltf::AnimationChannel c;
    c.sampler = 0;
    c.target_node = 0;
    c.target_path = "weights";
    tinygltf::Animation anim;
    anim.samplers.push_back(s);
    anim.channels.push_back(c);
    model.animations.push_back(anim);
  }
  tinygltf::TinyGLTF writer;
  std::ostringstream out;
  EXPECT_TRUE(writer.WriteGltfSceneToStream(&model, out, false, binary));
  return out.str();
}

// A glTF from tinygltf's writer (made here from a known mesh) reads back with its positions,
// order and triangles; .gltf (data-URI buffer) and .glb alike.
TEST(Gltf, ReadsAFileMadeByTinygltf) {
  const Mesh m = test::wobblingSphere(2, 1)[0];
  for (bool binary : {false, true}) {
    test::TempDir dir("gltf");
    const std::string path = dir.file(binary ? "m.glb" : "m.gltf");
    test::writeText(path, tinygltfMorphFile({m}, binary, false));
    const Mesh back = readMesh(path);
    expectClose(m, back, 1e-6, path);
    for (size_t i = 0; i < m.positions.size(); ++i)
      for (int c = 0; c < 3; ++c)
        ASSERT_EQ(back.positions[i][c], static_cast<double>(static_cast<float>(m.positions[i][c])));
  }
}

// A .gltf whose buffer is an external file beside it (here the BIN chunk of a .glb, with the
// .glb's JSON naming it): read from the file's folder, whatever the working folder.
TEST(Gltf, ExternalBufferFile) {
  const Mesh m = test::wobblingSphere(2, 1)[0];
  const std::string glb = formatGltf(m, GltfContainer::kGlb);
  auto le32 = [&](size_t at) {
    return static_cast<uint32_t>(static_cast<uint8_t>(glb[at])) |
           static_cast<uint32_t>(static_cast<uint8_t>(glb[at + 1])) << 8 |
           static_cast<uint32_t>(static_cast<uint8_t>(glb[at + 2])) << 16 |
           static_cast<uint32_t>(static_cast<uint8_t>(glb[at + 3])) << 24;
  };
  const uint32_t jsonLength = le32(12);
  std::string json = glb.substr(20, jsonLength);
  const uint32_t binLength = le32(20 + jsonLength);
  const std::string bin = glb.substr(20 + jsonLength + 8, binLength);
  const std::string buffers = "\"buffers\":[{";
  const size_t at = json.find(buffers);
  ASSERT_NE(at, std::string::npos) << json;
  json.insert(at + buffers.size(), "\"uri\":\"data%20file.bin\",");
  test::TempDir dir("gltf-external");
  std::filesystem::create_directories(dir.path() / "sub");
  test::writeText(dir.file("sub/m.gltf"), json);
  test::writeText(dir.file("sub/data file.bin"), bin);
  expectClose(m, readMesh(dir.file("sub/m.gltf")), 1e-6, "external buffer");
  // A missing buffer file is an error naming it.
  std::filesystem::remove(dir.file("sub/data file.bin"));
  EXPECT_NE(errorOf([&] { readMesh(dir.file("sub/m.gltf")); }).find("data file.bin"),
            std::string::npos);
}

// One .glb whose animation is morph targets (a target per frame, STEP weights) is a frame
// sequence.
TEST(Gltf, MorphTargetAnimationIsReadAsFrames) {
  const std::vector<Mesh> frames = test::wobblingSphere(1, 6);
  const std::string glb = tinygltfMorphFile(frames, true, true);
  const GltfFile file(std::vector<uint8_t>(glb.begin(), glb.end()), "anim.glb");
  ASSERT_EQ(file.frameCount(), 6u);
  for (size_t f = 0; f < 6; ++f) {
    EXPECT_FLOAT_EQ(static_cast<float>(file.frameTime(f)), static_cast<float>(f) / 25.0f);
    expectClose(frames[f], file.frame(f), 1e-5, "frame " + std::to_string(f));
  }
  // Without the animation it is one frame: the base.
  const std::string still = tinygltfMorphFile(frames, false, false);
  const GltfFile one(std::vector<uint8_t>(still.begin(), still.end()), "still.gltf");
  ASSERT_EQ(one.frameCount(), 1u);
  expectClose(frames[0], one.frame(0), 1e-6, "still");
}

// Our writers: per-frame .gltf/.glb, and the animated .glb (runs of constant connectivity)
// read back as the same frames.
TEST(Gltf, WrittenFilesReadBack) {
  const Mesh m = test::wobblingSphere(2, 1)[0];
  for (GltfContainer c : {GltfContainer::kGltf, GltfContainer::kGlb}) {
    const std::string data = formatGltf(m, c);
    expectClose(m, GltfFile(std::vector<uint8_t>(data.begin(), data.end()), "w").frame(0), 1e-6,
                "per-frame");
  }
  // 5 frames of a sphere, then 3 of a sheet (another connectivity), then 2 of the sphere.
  std::vector<Mesh> frames = test::wobblingSphere(1, 5);
  for (const Mesh& s : test::waveSheet(4, 3, 3))
    frames.push_back(s);
  for (const Mesh& s : test::wobblingSphere(1, 2))
    frames.push_back(s);
  frames.push_back(test::waveSheet(5, 3, 1)[0]);  // a run of one frame (no morph targets)
  GltfAnimationWriter writer(30.0);
  for (const Mesh& f : frames)
    writer.add(f);
  const std::string glb = writer.finish();
  const GltfFile file(std::vector<uint8_t>(glb.begin(), glb.end()), "anim.glb");
  ASSERT_EQ(file.frameCount(), frames.size());
  for (size_t f = 0; f < frames.size(); ++f)
    expectClose(frames[f], file.frame(f), 1e-5, "frame " + std::to_string(f));
}

// The animation writer holds every frame until finish(): it takes at most
// kMaxGltfAnimationFrames frames and kMaxGltfAnimationVertexFrames vertices x frames, and only
// frames whose time (index / frame rate) is a float (a tiny frame rate made infinite key times,
// a file its own reader refused).
TEST(Gltf, AnimationWriterLimits) {
  const Mesh tri = test::waveSheet(2, 2, 1)[0];
  GltfAnimationWriter many(30.0);
  for (size_t k = 0; k < kMaxGltfAnimationFrames; ++k)
    many.add(tri);
  EXPECT_NE(
      errorOf([&] { many.add(tri); }).find("16385 frames, more than 16384 for one animation file"),
      std::string::npos);
  Mesh big = tri;
  big.positions.resize(kMaxGltfAnimationVertexFrames / 2 + 1, Vec3d{0, 0, 0});
  GltfAnimationWriter large(30.0);
  large.add(big);
  EXPECT_NE(errorOf([&] {
              large.add(big);
            }).find("more than 33554432 vertices x frames for one animation file"),
            std::string::npos);
  GltfAnimationWriter slow(1e-300);
  slow.add(tri);
  EXPECT_EQ(errorOf([&] { slow.add(tri); }),
            "its time in the animation, 1 / frame rate 1e-300, is beyond float32 (glTF's key "
            "times)");
}

TEST(Gltf, LimitsAndMalformedFiles) {
  auto err = [](const std::string& data) {
    return errorOf([&] { GltfFile(std::vector<uint8_t>(data.begin(), data.end()), "x.gltf"); });
  };
  EXPECT_NE(err("{").find("x.gltf: JSON byte"), std::string::npos) << err("{");
  std::string deep(100, '[');
  EXPECT_NE(err(deep).find("nested more than 64"), std::string::npos);
  std::string many = "{\"asset\":{\"version\":\"2.0\"},\"extras\":[";
  for (size_t i = 0; i < kMaxGltfJsonValues; ++i)
    many += "0,";
  many += "0]}";
  EXPECT_NE(err(many).find("more than 262144 JSON values"), std::string::npos);
  EXPECT_NE(err("{\"asset\":{}}").find("x.gltf: glTF: "), std::string::npos);
  // An external buffer is refused when reading from memory, and a missing one from a file.
  EXPECT_NE(err("{\"asset\":{\"version\":\"2.0\"},\"buffers\":[{\"uri\":\"b.bin\","
                "\"byteLength\":4}]}")
                .find("x.gltf: glTF: "),
            std::string::npos);
  // Two buffers naming one external file: each buffer file is read once.
  test::TempDir dir("gltf-limits");
  test::writeText(dir.file("b.bin"), "abcd");
  test::writeText(dir.file("two.gltf"),
                  "{\"asset\":{\"version\":\"2.0\"},\"buffers\":[{\"uri\":\"b.bin\",\"byteLength\":"
                  "4},{\"uri\":\"./b.bin\",\"byteLength\":4}]}");
  EXPECT_NE(errorOf([&] { GltfFile file(dir.file("two.gltf")); }).find("named by two buffers"),
            std::string::npos);
  // A mesh used by many nodes (or accessors sharing their data) cannot make a frame larger
  // than one vertex per byte of the file: 400 nodes showing one 42-vertex mesh.
  const Mesh m = test::wobblingSphere(1, 1)[0];
  nlohmann::json j = nlohmann::json::parse(formatGltf(m, GltfContainer::kGltf));
  for (int i = 0; i < 400; ++i) {
    j["nodes"][i] = {{"mesh", 0}};
    j["scenes"][0]["nodes"][i] = i;
  }
  const std::string shared = j.dump();
  const std::string sharedError = errorOf(
      [&] { GltfFile(std::vector<uint8_t>(shared.begin(), shared.end()), "x.gltf").frame(0); });
  EXPECT_NE(sharedError.find("x.gltf: 16800 vertices and 32000 triangles, more than one of each "
                             "per byte of the file and its buffers"),
            std::string::npos)
      << sharedError;
}

// ---- glTF scenes and node transforms ----

std::string base64(const std::string& bytes) {
  static const char* const kDigits =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  for (size_t i = 0; i < bytes.size(); i += 3) {
    uint32_t v = 0;
    for (size_t b = 0; b < 3; ++b)
      v = v << 8 | (i + b < bytes.size() ? static_cast<uint8_t>(bytes[i + b]) : 0u);
    for (size_t d = 0; d < 4; ++d)
      out += d <= bytes.size() - i ? kDigits[(v >> (18 - 6 * d)) & 63] : '=';
  }
  return out;
}

// Appends a buffer holding `values` (float) with one accessor of `type` over them; returns
// the accessor's index.
int addFloatAccessor(nlohmann::json& j, const std::vector<float>& values, const char* type,
                     size_t count) {
  const std::string bytes(reinterpret_cast<const char*>(values.data()), values.size() * 4);
  const size_t buffer = j["buffers"].size(), view = j["bufferViews"].size(),
               accessor = j["accessors"].size();
  j["buffers"][buffer] = {{"byteLength", bytes.size()},
                          {"uri", "data:application/octet-stream;base64," + base64(bytes)}};
  j["bufferViews"][view] = {{"buffer", buffer}, {"byteLength", bytes.size()}};
  j["accessors"][accessor] = {
      {"bufferView", view}, {"componentType", 5126}, {"count", count}, {"type", type}};
  if (std::string(type) == "SCALAR") {
    j["accessors"][accessor]["min"] = {values.front()};
    j["accessors"][accessor]["max"] = {values.back()};
  }
  return static_cast<int>(accessor);
}

// A tetrahedron with per-vertex normals (what formatGltf writes as node 0 of scene 0).
Mesh tetrahedron() {
  Mesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  m.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  m.attributes.normals = {{-0.57735f, -0.57735f, -0.57735f}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  m.attributes.normalTriangles = m.triangles;
  return m;
}

Mesh frameOf(const nlohmann::json& j, size_t k = 0) {
  const std::string text = j.dump();
  return GltfFile(std::vector<uint8_t>(text.begin(), text.end()), "t.gltf").frame(k);
}

// Rotation by `degrees` about z, then `scale`, then `offset`: what the nodes below express.
Vec3d rotateZ(const Vec3d& p, double degrees) {
  const double a = degrees * M_PI / 180;
  return {std::cos(a) * p[0] - std::sin(a) * p[1], std::sin(a) * p[0] + std::cos(a) * p[1], p[2]};
}

// A frame is what a viewer shows: each mesh node's mesh moved by its node's transform and its
// parents' (translation, rotation, scale or matrix), normals turned with it, front faces kept
// under a mirroring transform.
TEST(Gltf, NodeTransformsAreApplied) {
  const Mesh tet = tetrahedron();
  nlohmann::json j = nlohmann::json::parse(formatGltf(tet, GltfContainer::kGltf));
  const double h = std::sqrt(0.5);
  j["nodes"] = {{{"children", {1}},
                 {"translation", {1, 2, 3}},
                 {"rotation", {0, 0, h, h}},
                 {"scale", {2, 2, 2}}},
                {{"mesh", 0}, {"translation", {0, 0, 1}}}};
  j["scenes"] = {{{"nodes", {0}}}};
  const Mesh moved = frameOf(j);
  ASSERT_EQ(moved.positions.size(), 4u);
  for (size_t v = 0; v < 4; ++v) {
    const Vec3d p = tet.positions[v];
    const Vec3d r = rotateZ({2 * p[0], 2 * p[1], 2 * (p[2] + 1)}, 90);
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(moved.positions[v][c], r[c] + (c + 1.0), 1e-12) << v;
    const Vec3d n = rotateZ(
        {tet.attributes.normals[v][0], tet.attributes.normals[v][1], tet.attributes.normals[v][2]},
        90);
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(moved.attributes.normals[v][c], n[c], 1e-6) << v;
  }
  EXPECT_EQ(moved.triangles, tet.triangles);
  // The same as one matrix (column-major) gives the same frame.
  j["nodes"][0].erase("translation");
  j["nodes"][0].erase("rotation");
  j["nodes"][0].erase("scale");
  j["nodes"][0]["matrix"] = {0, 2, 0, 0, -2, 0, 0, 0, 0, 0, 2, 0, 1, 2, 3, 1};
  const Mesh matrix = frameOf(j);
  for (size_t v = 0; v < 4; ++v)
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(matrix.positions[v][c], moved.positions[v][c], 1e-12);
  // A mirror: x negated, each triangle's last two corners swapped (the side that faced the
  // viewer still does), normals mirrored.
  j["nodes"] = {{{"mesh", 0}, {"scale", {-1, 1, 1}}}};
  const Mesh mirrored = frameOf(j);
  for (size_t v = 0; v < 4; ++v) {
    EXPECT_EQ(mirrored.positions[v][0], -tet.positions[v][0]);
    EXPECT_FLOAT_EQ(mirrored.attributes.normals[v][0], -tet.attributes.normals[v][0]);
  }
  for (size_t i = 0; i < tet.triangles.size(); ++i)
    EXPECT_EQ(mirrored.triangles[i],
              (Triangle{tet.triangles[i][0], tet.triangles[i][2], tet.triangles[i][1]}));
  // Identity transforms leave the file's coordinates exactly as they are.
  j["nodes"] = {{{"mesh", 0}, {"translation", {0, 0, 0}}, {"rotation", {0, 0, 0, 1}}}};
  expectSame(tet, frameOf(j));
}

// The default scene's trees only: a node outside them is not shown, a mesh used by two nodes
// is shown twice, a node scaled to 0 0 0 hides its subtree; errors for what is not a tree, a
// skin, a projective matrix, a missing scene.
TEST(Gltf, SceneTreesAreWhatIsShown) {
  const Mesh tet = tetrahedron();
  nlohmann::json j = nlohmann::json::parse(formatGltf(tet, GltfContainer::kGltf));
  j["nodes"] = {{{"mesh", 0}, {"translation", {10, 0, 0}}},
                {{"mesh", 0}},
                {{"children", {3}}, {"scale", {0, 0, 0}}},
                {{"mesh", 0}},
                {{"mesh", 0}, {"translation", {5, 5, 5}}}};
  j["scenes"] = {{{"nodes", {4}}}, {{"nodes", {0, 1, 2}}}};
  j["scene"] = 1;
  const Mesh two = frameOf(j);
  ASSERT_EQ(two.positions.size(), 8u);
  for (size_t v = 0; v < 4; ++v) {
    EXPECT_EQ(two.positions[v][0], tet.positions[v][0] + 10);
    EXPECT_EQ(two.positions[4 + v], tet.positions[v]);
  }
  ASSERT_EQ(two.triangles.size(), 8u);
  EXPECT_EQ(two.triangles[4], (Triangle{4, 6, 5}));
  // Without scenes: the nodes that are no node's child (0, 1, 2, 4; 3 is hidden by 2).
  j.erase("scenes");
  j.erase("scene");
  EXPECT_EQ(frameOf(j).positions.size(), 12u);
  auto err = [](const nlohmann::json& bad) { return errorOf([&] { frameOf(bad); }); };
  nlohmann::json twice = j;
  twice["scenes"] = {{{"nodes", {0, 2}}}};
  twice["nodes"][2]["children"] = {3, 0};
  EXPECT_NE(
      err(twice).find("t.gltf: node 0 is reached twice from the scene (nodes must form trees)"),
      std::string::npos)
      << err(twice);
  nlohmann::json loop = j;
  loop["scenes"] = {{{"nodes", {2}}}};
  loop["nodes"][3]["children"] = {2};
  EXPECT_NE(err(loop).find("node 2 is reached twice"), std::string::npos) << err(loop);
  nlohmann::json skin = j;
  skin["nodes"][1]["skin"] = 0;
  skin["skins"] = {{{"joints", {0}}}};
  EXPECT_NE(err(skin).find("t.gltf: node 1: a skinned mesh (skin 0) is not read"),
            std::string::npos)
      << err(skin);
  nlohmann::json projective = j;
  projective["nodes"][1]["matrix"] = {1, 0, 0, 1, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  EXPECT_NE(err(projective).find("node 1: matrix is not affine"), std::string::npos)
      << err(projective);
  nlohmann::json noScene = j;
  noScene["scenes"] = {{{"nodes", {0}}}};
  noScene["scene"] = 3;
  EXPECT_NE(err(noScene).find("scene 3 (the default scene) does not exist"), std::string::npos)
      << err(noScene);
  nlohmann::json missing = j;
  missing["scenes"] = {{{"nodes", {0, 9}}}};
  EXPECT_NE(err(missing).find("the scene names node 9, which does not exist"), std::string::npos)
      << err(missing);
}

// Node animations are frames too: translation (LINEAR), rotation (LINEAR: spherical), at the
// merged key times; a node with a matrix cannot be animated.
TEST(Gltf, NodeAnimationsMoveTheFrames) {
  const Mesh tet = tetrahedron();
  nlohmann::json j = nlohmann::json::parse(formatGltf(tet, GltfContainer::kGltf));
  const double h = std::sqrt(0.5);
  const int t01 = addFloatAccessor(j, {0, 1}, "SCALAR", 2);
  const int moves = addFloatAccessor(j, {0, 0, 0, 2, 0, 0}, "VEC3", 2);
  const int t02 = addFloatAccessor(j, {0, 2}, "SCALAR", 2);
  const int turns = addFloatAccessor(
      j, {0, 0, 0, 1, 0, 0, static_cast<float>(h), static_cast<float>(h)}, "VEC4", 2);
  j["animations"] = {{{"samplers",
                       {{{"input", t01}, {"output", moves}, {"interpolation", "LINEAR"}},
                        {{"input", t02}, {"output", turns}, {"interpolation", "LINEAR"}}}},
                      {"channels",
                       {{{"sampler", 0}, {"target", {{"node", 0}, {"path", "translation"}}}},
                        {{"sampler", 1}, {"target", {{"node", 0}, {"path", "rotation"}}}}}}}};
  const std::string text = j.dump();
  const GltfFile file(std::vector<uint8_t>(text.begin(), text.end()), "a.gltf");
  ASSERT_EQ(file.frameCount(), 3u);  // t = 0, 1, 2
  const double degrees[3] = {0, 45, 90}, shift[3] = {0, 2, 2};
  for (size_t k = 0; k < 3; ++k) {
    const Mesh f = file.frame(k);
    for (size_t v = 0; v < 4; ++v) {
      const Vec3d r = rotateZ(tet.positions[v], degrees[k]);
      EXPECT_NEAR(f.positions[v][0], r[0] + shift[k], 1e-6) << k << " " << v;
      EXPECT_NEAR(f.positions[v][1], r[1], 1e-6) << k << " " << v;
      EXPECT_NEAR(f.positions[v][2], r[2], 1e-6) << k << " " << v;
    }
  }
  j["nodes"][0]["matrix"] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  EXPECT_NE(errorOf([&] { frameOf(j); })
                .find("animation 0 channel 0: node 0 has a matrix, and its translation cannot be "
                      "animated"),
            std::string::npos)
      << errorOf([&] { frameOf(j); });
}

// A frame's work counts every node and channel (F18): a chain of n nodes above a tetrahedron,
// its root's translation animated over n keys, is n^2 node visits from O(n) bytes. At n = 8000
// (about 400 KB) it is refused at once; it took 8 s when only vertices were counted.
TEST(Gltf, NodesAndChannelsCountInTheFrameWork) {
  auto chain = [](int n) {
    nlohmann::json j = nlohmann::json::parse(formatGltf(tetrahedron(), GltfContainer::kGltf));
    for (int k = 1; k <= n; ++k)
      j["nodes"][static_cast<size_t>(k)] = {{"children", {k - 1}}};
    j["scenes"][0]["nodes"] = {n};
    std::vector<float> times, moves;
    for (int k = 0; k < n; ++k) {
      times.push_back(static_cast<float>(k));
      moves.insert(moves.end(), {static_cast<float>(k % 7), 0, 0});
    }
    const int t = addFloatAccessor(j, times, "SCALAR", n);
    const int m = addFloatAccessor(j, moves, "VEC3", n);
    j["animations"] = {
        {{"samplers", {{{"input", t}, {"output", m}, {"interpolation", "STEP"}}}},
         {"channels", {{{"sampler", 0}, {"target", {{"node", n}, {"path", "translation"}}}}}}}};
    const std::string text = j.dump();
    return std::vector<uint8_t>(text.begin(), text.end());
  };
  const GltfFile small(chain(200), "chain.gltf");
  EXPECT_EQ(small.frameCount(), 200u);
  EXPECT_NEAR(small.frame(3).positions[1][0], 1 + 3, 1e-6);
  EXPECT_NE(errorOf([&] {
              GltfFile(chain(8000), "chain.gltf");
            }).find("vertex-frames per byte of the file and its buffers"),
            std::string::npos);
}

// What a glTF file holds that no frame takes is said in one warning per file (materials,
// textures and images, other vertex attributes, animations after the first, extensions used);
// an animated file read as one frame (a per-frame pattern) says its other keyframes are left.
TEST(Gltf, WhatIsNotReadIsSaid) {
  std::vector<std::string> said;
  const WarningHandler before =
      setWarningHandler([&](const std::string& message) { said.push_back(message); });
  nlohmann::json j = nlohmann::json::parse(formatGltf(tetrahedron(), GltfContainer::kGltf));
  frameOf(j);
  EXPECT_TRUE(said.empty()) << said[0];
  j["materials"] = {{{"name", "skin"}}, {{"name", "cloth"}}};
  j["images"] = {{{"uri", "skin.png"}}};
  j["textures"] = {{{"source", 0}}};
  j["meshes"][0]["primitives"][0]["material"] = 0;
  j["meshes"][0]["primitives"][0]["attributes"]["COLOR_0"] =
      addFloatAccessor(j, std::vector<float>(12, 0.5f), "VEC3", 4);
  j["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_1"] =
      addFloatAccessor(j, std::vector<float>(8, 0.5f), "VEC2", 4);
  j["extensionsUsed"] = {"KHR_materials_unlit"};
  j["nodes"].push_back({{"mesh", 0}, {"translation", {5, 0, 0}}});  // in the second scene
  j["scenes"].push_back({{"nodes", {1}}});
  frameOf(j);
  ASSERT_EQ(said.size(), 1u);
  EXPECT_EQ(said[0],
            "t.gltf: left out (3DVO codes positions, NORMAL and TEXCOORD_0): 2 materials; 1 "
            "texture; 1 image; vertex attributes COLOR_0, TEXCOORD_1; 1 scene other than the "
            "default; 1 node with a mesh outside the default scene; the extensions used "
            "KHR_materials_unlit");
  said.clear();
  // Two animations: the second is said; read as one frame of a pattern, the keyframes too.
  test::TempDir dir("gltf-left-out");
  const std::vector<Mesh> frames = test::wobblingSphere(1, 3);
  test::writeText(dir.file("a.glb"), tinygltfMorphFile(frames, true, true));
  expectClose(frames[0], readMesh(dir.file("a.glb")), 1e-5, "keyframe 0");
  EXPECT_EQ(said, (std::vector<std::string>{
                      dir.file("a.glb") +
                      ": an animated glTF file read as one frame: its first keyframe is read, "
                      "the others are left out (a pattern without %d reads one file's keyframes "
                      "as the frames) (3 keyframes)"}));
  said.clear();
  j = nlohmann::json::parse(formatGltf(tetrahedron(), GltfContainer::kGltf));
  const int times = addFloatAccessor(j, {0.0f, 1.0f}, "SCALAR", 2);
  const int moves = addFloatAccessor(j, {0, 0, 0, 1, 0, 0}, "VEC3", 2);
  const nlohmann::json animation = {
      {"samplers", {{{"input", times}, {"output", moves}}}},
      {"channels", {{{"sampler", 0}, {"target", {{"node", 0}, {"path", "translation"}}}}}}};
  j["animations"] = {animation, animation};
  const std::string text = j.dump();
  EXPECT_EQ(GltfFile(std::vector<uint8_t>(text.begin(), text.end()), "t.gltf").frameCount(), 2u);
  ASSERT_EQ(said.size(), 1u);
  EXPECT_EQ(said[0],
            "t.gltf: left out (3DVO codes positions, NORMAL and TEXCOORD_0): animations 1 .. 1 "
            "(animation 0 is read)");
  setWarningHandler(before);
}

// glTF output: normals not of unit length are scaled to it (glTF requires it), said once per
// run; length 0 and non-finite ones are kept and said.
TEST(Gltf, WrittenNormalsAreUnitLength) {
  std::vector<std::string> said;
  const WarningHandler before =
      setWarningHandler([&](const std::string& message) { said.push_back(message); });
  Mesh m = tetrahedron();
  m.attributes.normals = {{0, 0, 2}, {0.1f, 0.2f, 0.3f}, {0.57735f, 0.57735f, 0.57735f}, {0, 0, 0}};
  Mesh back;
  {
    WarnOnceScope once;
    const std::string text = formatGltf(m, GltfContainer::kGltf);
    formatGltf(m, GltfContainer::kGlb);
    back = GltfFile(std::vector<uint8_t>(text.begin(), text.end()), "n.gltf").frame(0);
  }
  ASSERT_EQ(back.attributes.normals.size(), 4u);
  EXPECT_EQ(back.attributes.normals[0], (Vec3f{0, 0, 1}));
  const double l = std::sqrt(0.01 + 0.04 + 0.09);
  for (int c = 0; c < 3; ++c)
    EXPECT_FLOAT_EQ(back.attributes.normals[1][c], static_cast<float>(0.1 * (c + 1) / l));
  EXPECT_EQ(back.attributes.normals[2], (Vec3f{0.57735f, 0.57735f, 0.57735f}));  // unit enough
  EXPECT_EQ(back.attributes.normals[3], (Vec3f{0, 0, 0}));
  EXPECT_EQ(said, (std::vector<std::string>{
                      "glTF output: normals not of unit length are scaled to it (glTF requires "
                      "unit NORMALs; OBJ and PLY output keep them as they are)",
                      "glTF output: normals of length 0 are written as they are (not valid "
                      "glTF)"}));
  said.clear();
  m.attributes.normals[3] = {std::numeric_limits<float>::infinity(), 0, 0};
  formatGltf(m, GltfContainer::kGlb);
  EXPECT_EQ(said.back(),
            "glTF output: normals that are not finite are written as they are (not valid glTF)");
  setWarningHandler(before);
}

// The key times' frame rate: evenly spaced keys give it (whole numbers and the NTSC rates as
// such, from float32 times), uneven ones or a single frame none.
TEST(Gltf, KeyRate) {
  const auto fileWithTimes = [](const std::vector<float>& t) {
    nlohmann::json j = nlohmann::json::parse(formatGltf(tetrahedron(), GltfContainer::kGltf));
    const int times = addFloatAccessor(j, t, "SCALAR", t.size());
    const int moves = addFloatAccessor(j, std::vector<float>(3 * t.size(), 0.0f), "VEC3", t.size());
    j["animations"] = {
        {{"samplers", {{{"input", times}, {"output", moves}}}},
         {"channels", {{{"sampler", 0}, {"target", {{"node", 0}, {"path", "translation"}}}}}}}};
    const std::string text = j.dump();
    return GltfFile(std::vector<uint8_t>(text.begin(), text.end()), "t.gltf");
  };
  std::vector<float> thirtieths, ntsc;
  for (int k = 0; k < 300; ++k) {
    thirtieths.push_back(static_cast<float>(k) / 30.0f);
    ntsc.push_back(static_cast<float>(k * 1001.0 / 30000.0));
  }
  EXPECT_EQ(fileWithTimes(thirtieths).keyRate(0, 300), 30.0);
  EXPECT_EQ(fileWithTimes(thirtieths).keyRate(100, 2), 30.0);
  EXPECT_EQ(fileWithTimes(ntsc).keyRate(0, 300), 30000.0 / 1001.0);
  // Two keys tell 29.97 from 30 (and 23.976 from 24) at the start; late, float32 cannot, and
  // the simpler rate is taken.
  EXPECT_EQ(fileWithTimes({0.0f, static_cast<float>(1001.0 / 30000.0)}).keyRate(0, 2),
            30000.0 / 1001.0);
  EXPECT_EQ(fileWithTimes({0.0f, static_cast<float>(1001.0 / 24000.0)}).keyRate(0, 2),
            24000.0 / 1001.0);
  EXPECT_EQ(fileWithTimes({0.0f, 1.0f / 30.0f}).keyRate(0, 2), 30.0);
  EXPECT_EQ(fileWithTimes({600.0f, static_cast<float>(600.0 + 1001.0 / 30000.0)}).keyRate(0, 2),
            30.0);
  EXPECT_EQ(fileWithTimes({0.0f, 2.0f, 4.0f}).keyRate(0, 3), 0.5);
  EXPECT_EQ(fileWithTimes({0.0f, 0.1f, 2.0f}).keyRate(0, 3), std::nullopt);
  EXPECT_EQ(fileWithTimes({0.0f, 0.1f, 2.0f}).keyRate(0, 2), 10.0);
  EXPECT_EQ(fileWithTimes({0.0f, 0.1f}).keyRate(0, 1), std::nullopt);
  EXPECT_EQ(fileWithTimes({0.0f, 0.1f}).keyRate(1, 2), std::nullopt);
  EXPECT_EQ(fileWithTimes({0.0f, 0.0001f}).keyRate(0, 2), 10000.0);  // out of FrameRate's range
  std::vector<float> halves, thousandths, tenMinutes;
  for (int k = 0; k < 100; ++k) {
    halves.push_back(static_cast<float>(k) / 12.5f);
    thousandths.push_back(static_cast<float>(k) / 1000.0f);
  }
  for (int k = 0; k <= 18000; ++k)
    tenMinutes.push_back(static_cast<float>(k) / 30.0f);
  EXPECT_EQ(fileWithTimes(halves).keyRate(0, 100), 12.5);
  EXPECT_EQ(fileWithTimes(thousandths).keyRate(0, 100), 1000.0);
  // Late in a long animation float32 key times are coarse (600 s: steps of 2^-17 s).
  EXPECT_EQ(fileWithTimes(tenMinutes).keyRate(0, 18001), 30.0);
  EXPECT_EQ(fileWithTimes(tenMinutes).keyRate(17999, 2), 30.0);
  EXPECT_EQ(fileWithTimes(tenMinutes).keyRate(9000, 3), 30.0);
  EXPECT_EQ(fileWithTimes(tenMinutes).keyRate(1, SIZE_MAX), std::nullopt);
}

// KHR_mesh_quantization positions (SHORT, 8-byte stride) without indices: 6 vertices in 48
// bytes are read (a bound of 12 bytes per vertex refused them).
TEST(Gltf, QuantizedPositionsWithoutIndices) {
  std::string bytes(48, '\0');
  const int16_t p[6][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}, {0, 1, 0}, {1, 0, 0}};
  for (int v = 0; v < 6; ++v)
    std::memcpy(&bytes[8 * v], p[v], 6);
  nlohmann::json j = {
      {"asset", {{"version", "2.0"}}},
      {"extensionsUsed", {"KHR_mesh_quantization"}},
      {"extensionsRequired", {"KHR_mesh_quantization"}},
      {"buffers",
       {{{"byteLength", 48}, {"uri", "data:application/octet-stream;base64," + base64(bytes)}}}},
      {"bufferViews", {{{"buffer", 0}, {"byteLength", 48}, {"byteStride", 8}}}},
      {"accessors",
       {{{"bufferView", 0},
         {"componentType", 5122},
         {"count", 6},
         {"type", "VEC3"},
         {"min", {0, 0, 0}},
         {"max", {1, 1, 0}}}}},
      {"meshes", {{{"primitives", {{{"attributes", {{"POSITION", 0}}}}}}}}},
      {"nodes", {{{"mesh", 0}}}},
      {"scenes", {{{"nodes", {0}}}}}};
  const Mesh m = frameOf(j);
  ASSERT_EQ(m.positions.size(), 6u);
  EXPECT_EQ(m.positions[3], (Vec3d{1, 1, 0}));
  EXPECT_EQ(m.triangles, (std::vector<Triangle>{{0, 1, 2}, {3, 4, 5}}));
}

// ---- Through the apps ----

// Encodes `frames` written in `inFormat` and decodes them with --MeshFormat=`outFormat`; checks
// every decoded frame against the input.
void roundTrip(const std::vector<Mesh>& frames, const std::string& inExt,
               const std::string& outFormat, const std::string& outExt, int bits = 16) {
  test::TempDir dir("formats-roundtrip");
  std::filesystem::create_directories(dir.path() / "in");
  for (size_t f = 0; f < frames.size(); ++f) {
    const std::string path = dir.file("in/" + framePath("%03d", static_cast<int>(f)) + inExt);
    if (inExt == ".obj") writeObj(path, frames[f]);
    if (inExt == ".ply") writePly(path, frames[f]);
    if (inExt == ".glb") writeGltf(path, frames[f], GltfContainer::kGlb);
  }
  const test::CommandResult enc = test::run(
      dir, kBin + "/3dvo-enc",
      {"--InputMeshPattern=in/%03d" + inExt, "--FrameCount=" + std::to_string(frames.size()),
       "--GridBits=" + std::to_string(bits), "--GOMSize=4", "-o", "x.3dvo"});
  ASSERT_EQ(enc.exitCode, 0) << enc.err;
  const test::CommandResult dec = test::run(
      dir, kBin + "/3dvo-dec", {"-i", "x.3dvo", "-o", "out", "--MeshFormat=" + outFormat});
  ASSERT_EQ(dec.exitCode, 0) << dec.err;
  // Half a grid step: the grid spans the extent with 2^bits - 1 steps at most.
  const double tolerance = 0.5 * test::extentOf(frames) / ((1 << bits) - 1) * 1.0001 + 1e-6;
  for (size_t f = 0; f < frames.size(); ++f) {
    const std::string path = dir.file("out/" + framePath("%04d", static_cast<int>(f)) + outExt);
    expectClose(frames[f], readMesh(path), tolerance, path);
  }
}

TEST(FormatsRoundTrip, ObjToGltfAndPlyToPly) {
  std::vector<Mesh> frames = test::wobblingSphere(2, 6, 1.0, {3, -2, 1});
  roundTrip(frames, ".obj", "gltf", ".gltf");
  roundTrip(frames, ".obj", "glb", ".glb");
  roundTrip(frames, ".ply", "ply", ".ply");
  roundTrip(frames, ".ply", "ply-ascii", ".ply");
  roundTrip(frames, ".glb", "obj", ".obj");
}

// The "MD5 ..." lines of an app's stdout.
std::vector<std::string> md5Lines(const std::string& out) {
  std::vector<std::string> lines;
  for (const std::string& l : test::lines(out))
    if (l.rfind("MD5 ", 0) == 0) lines.push_back(l);
  return lines;
}

// A few frames of horse-gallop (shared data): OBJ -> 3DVO -> glTF and, through PLY input,
// PLY -> 3DVO -> PLY.
TEST(FormatsRoundTrip, SharedSequenceHorseGallop) {
  std::string missing;
  std::vector<Mesh> frames = test::sharedHorseFrames(TDVO_SHARED_DATA_DIR, 1, 4, missing);
  if (frames.empty()) GTEST_SKIP() << missing;
  roundTrip(frames, ".obj", "glb", ".glb", 14);
  roundTrip(frames, ".ply", "ply", ".ply", 14);
}

// The per-frame MD5 lines hash the decoded integer geometry, not the files: every MeshFormat
// prints the same lines. --AnimationFile's .glb is read back (GltfFile) as the decoded frames,
// and as encoder input (InputMeshPattern without %d) it codes to the same MD5 lines.
TEST(FormatsApps, Md5LinesAndAnimationFile) {
  test::TempDir dir("formats-apps");
  std::filesystem::create_directories(dir.path() / "in");
  // Connectivity changes at frame 5 (intra GOMs of 5): two runs in the animation.
  std::vector<Mesh> frames = test::wobblingSphere(2, 5);
  for (const Mesh& m : test::waveSheet(6, 5, 4))
    frames.push_back(m);
  for (size_t f = 0; f < frames.size(); ++f)
    writeObj(dir.file("in/" + framePath("%03d.obj", static_cast<int>(f))), frames[f]);
  const test::CommandResult enc =
      test::run(dir, kBin + "/3dvo-enc",
                {"--InputMeshPattern=in/%03d.obj", "--FrameCount=9", "--GridBits=12", "--GOMSize=5",
                 "--FrameRate=30", "-o", "x.3dvo"});
  ASSERT_EQ(enc.exitCode, 0) << enc.err;
  std::vector<std::string> reference;
  for (const char* format : {"obj", "ply", "ply-ascii", "gltf", "glb", "none"}) {
    const test::CommandResult dec =
        test::run(dir, kBin + "/3dvo-dec",
                  {"-i", "x.3dvo", "-o", "out", "--Overwrite",
                   std::string("--MeshFormat=") + format, "--AnimationFile=all.glb"});
    ASSERT_EQ(dec.exitCode, 0) << format << ": " << dec.err;
    if (reference.empty()) reference = md5Lines(dec.out);
    EXPECT_EQ(md5Lines(dec.out), reference) << format;
    EXPECT_EQ(md5Lines(dec.out), md5Lines(enc.out)) << format;
    const bool none = std::string(format) == "none";
    EXPECT_EQ(std::filesystem::exists(dir.file("out/0000.obj")), std::string(format) == "obj");
    if (!none) {
      const std::string ext =
          meshOutputExtension(std::string(format) == "obj"    ? MeshOutputFormat::kObj
                              : std::string(format) == "gltf" ? MeshOutputFormat::kGltf
                              : std::string(format) == "glb"  ? MeshOutputFormat::kGlb
                                                              : MeshOutputFormat::kPly);
      EXPECT_TRUE(std::filesystem::exists(dir.file("out/0008" + ext))) << format;
    }
  }
  // Without MeshFormat, OutputMeshPattern's extension chooses the format.
  ASSERT_EQ(test::run(dir, kBin + "/3dvo-dec",
                      {"-i", "x.3dvo", "-o", "byname", "--OutputMeshPattern=f%03d.ply"})
                .exitCode,
            0);
  EXPECT_EQ(readPly(dir.file("byname/f008.ply")).triangles, frames[8].triangles);
  // The animation holds the decoded frames (as float).
  const GltfFile animation(dir.file("out/all.glb"));
  ASSERT_EQ(animation.frameCount(), frames.size());
  test::run(dir, kBin + "/3dvo-dec", {"-i", "x.3dvo", "-o", "objs"});
  for (size_t f = 0; f < frames.size(); ++f) {
    const Mesh decoded = readObj(dir.file("objs/" + framePath("%04d.obj", static_cast<int>(f))));
    expectClose(decoded, animation.frame(f), 1e-6, "animation frame " + std::to_string(f));
    EXPECT_NEAR(animation.frameTime(f), f / 30.0, 1e-6);
  }
  // The animation as encoder input: the same decoded geometry, so the same MD5 lines.
  const test::CommandResult again = test::run(dir, kBin + "/3dvo-enc",
                                              {"--InputMeshPattern=out/all.glb", "--GridBits=12",
                                               "--GOMSize=5", "--FrameRate=30", "-o", "y.3dvo"});
  ASSERT_EQ(again.exitCode, 0) << again.err;
  EXPECT_NE(again.out.find("# input frames: 9 of the 9 keyframes of out/all.glb"),
            std::string::npos)
      << again.out;
  // Decoded again: the first decode's frames, within half a step of the new grid, in order.
  const test::CommandResult redec =
      test::run(dir, kBin + "/3dvo-dec", {"-i", "y.3dvo", "-o", "again"});
  ASSERT_EQ(redec.exitCode, 0) << redec.err;
  std::vector<Mesh> decoded;
  for (size_t f = 0; f < frames.size(); ++f)
    decoded.push_back(readObj(dir.file("objs/" + framePath("%04d.obj", static_cast<int>(f)))));
  const double tolerance = 0.5 * test::extentOf(decoded) / ((1 << 12) - 1) * 1.0001 + 1e-6;
  for (size_t f = 0; f < frames.size(); ++f)
    expectClose(decoded[f],
                readObj(dir.file("again/" + framePath("%04d.obj", static_cast<int>(f)))), tolerance,
                "re-encoded frame " + std::to_string(f));
}

// A morph-target .glb made by tinygltf is encoder input: FirstFrame and FrameCount select
// keyframes, and the coded frames are the file's frames.
TEST(FormatsApps, MorphTargetGlbAsEncoderInput) {
  test::TempDir dir("formats-morph");
  const std::vector<Mesh> frames = test::wobblingSphere(2, 7);
  test::writeText(dir.file("seq.glb"), tinygltfMorphFile(frames, true, true));
  const test::CommandResult enc =
      test::run(dir, kBin + "/3dvo-enc",
                {"--InputMeshPattern=seq.glb", "--FirstFrame=2", "--GridBits=14",
                 "--ReconMeshPattern=r%04d.obj", "-o", "x.3dvo"});
  ASSERT_EQ(enc.exitCode, 0) << enc.err;
  EXPECT_NE(enc.out.find("# input frames: 5 of the 7 keyframes"), std::string::npos) << enc.out;
  const double tolerance = 0.5 * test::extentOf(frames) / ((1 << 14) - 1) * 1.0001 + 1e-5;
  for (int f = 2; f < 7; ++f)
    expectClose(frames[f], readObj(dir.file(framePath("r%04d.obj", f))), tolerance,
                "frame " + std::to_string(f));
  // ReconMeshPattern's extension chooses its format, as the decoder's OutputMeshPattern.
  ASSERT_EQ(test::run(dir, kBin + "/3dvo-enc",
                      {"--InputMeshPattern=seq.glb", "--FirstFrame=2", "--GridBits=14",
                       "--ReconMeshPattern=r%04d.ply", "-o", "y.3dvo"})
                .exitCode,
            0);
  EXPECT_EQ(readPly(dir.file("r0006.ply")).positions, readObj(dir.file("r0006.obj")).positions);
  // FrameRate not set: the key times' rate (25 above, the default's value; 30 here) is the
  // stream's; set, it is kept.
  EXPECT_NE(enc.out.find("# FrameRate: 25 (the key times of seq.glb)"), std::string::npos)
      << enc.out;
  test::writeText(dir.file("seq30.glb"), tinygltfMorphFile(frames, true, true, 30.0f));
  const test::CommandResult at30 =
      test::run(dir, kBin + "/3dvo-enc", {"--InputMeshPattern=seq30.glb", "-o", "z.3dvo"});
  ASSERT_EQ(at30.exitCode, 0) << at30.err;
  EXPECT_NE(at30.out.find("# FrameRate: 30 (the key times of seq30.glb)"), std::string::npos)
      << at30.out;
  EXPECT_NE(at30.out.find("frame rate          : 30\n"), std::string::npos) << at30.out;
  const test::CommandResult set = test::run(
      dir, kBin + "/3dvo-enc", {"--InputMeshPattern=seq30.glb", "--FrameRate=24", "-o", "w.3dvo"});
  ASSERT_EQ(set.exitCode, 0) << set.err;
  EXPECT_EQ(set.out.find("# FrameRate:"), std::string::npos) << set.out;
  EXPECT_NE(set.out.find("frame rate          : 24\n"), std::string::npos) << set.out;
}

// A sequence file's frames are named by their keyframe in the encoder's messages (one file
// holds them all): here a GOM whose frames change connectivity at keyframe 3 (FirstFrame 1).
TEST(FormatsApps, SequenceFileMessagesNameTheKeyframe) {
  test::TempDir dir("formats-keyframe-names");
  std::vector<Mesh> frames = test::wobblingSphere(1, 3);
  for (const Mesh& m : test::waveSheet(4, 3, 2))
    frames.push_back(m);
  GltfAnimationWriter writer(25.0);
  for (const Mesh& f : frames)
    writer.add(f);
  test::writeText(dir.file("seq.glb"), writer.finish());
  const test::CommandResult enc =
      test::run(dir, kBin + "/3dvo-enc",
                {"--InputMeshPattern=seq.glb", "--FirstFrame=1", "--PMeshMode=d3dmc", "--GOMSize=4",
                 "--GridBits=12", "-o", "x.3dvo"});
  EXPECT_EQ(enc.exitCode, 1);
  EXPECT_NE(enc.err.find("3dvo-enc: error: seq.glb keyframe 3: 12 vertices, but the GOM's first "
                         "frame (seq.glb keyframe 1) has 42"),
            std::string::npos)
      << enc.err;
}

// 3dvo-metrics reads PLY and glTF frames too: the decoded frames as binary PLY (double) against
// the same frames as glTF (float) differ by float rounding only.
TEST(FormatsApps, MetricsReadsPlyAndGltf) {
  test::TempDir dir("formats-metrics");
  std::filesystem::create_directories(dir.path() / "in");
  const std::vector<Mesh> frames = test::wobblingSphere(2, 3, 1.0, {2, 1, 0});
  for (size_t f = 0; f < frames.size(); ++f)
    writePly(dir.file("in/" + framePath("%03d.ply", static_cast<int>(f))), frames[f]);
  ASSERT_EQ(test::run(dir, kBin + "/3dvo-enc",
                      {"--InputMeshPattern=in/%03d.ply", "--FrameCount=3", "--GridBits=12", "-o",
                       "x.3dvo"})
                .exitCode,
            0);
  ASSERT_EQ(
      test::run(dir, kBin + "/3dvo-dec", {"-i", "x.3dvo", "-o", "p", "--MeshFormat=ply"}).exitCode,
      0);
  ASSERT_EQ(
      test::run(dir, kBin + "/3dvo-dec", {"-i", "x.3dvo", "-o", "g", "--MeshFormat=glb"}).exitCode,
      0);
  const test::CommandResult m =
      test::run(dir, kBin + "/3dvo-metrics",
                {"--ReferenceMeshes=p/%04d.ply", "--TestMeshes=g/%04d.glb", "--FrameCount=3"});
  ASSERT_EQ(m.exitCode, 0) << m.err;
  const size_t at = m.out.find("vertex RMSE           : ");
  ASSERT_NE(at, std::string::npos) << m.out;
  EXPECT_LT(std::stod(m.out.substr(at + 24)), 1e-6) << m.out;
}

// The same frames as OBJ and as binary PLY code to the same stream, byte for byte (PLY holds
// the positions as double, exactly as the OBJ text reads back).
TEST(FormatsApps, PlyAndObjInputCodeTheSameStream) {
  test::TempDir dir("formats-same");
  std::filesystem::create_directories(dir.path() / "in");
  const std::vector<Mesh> frames = test::wobblingSphere(2, 4, 0.7, {1, 2, 3});
  for (size_t f = 0; f < frames.size(); ++f) {
    writeObj(dir.file("in/" + framePath("%03d.obj", static_cast<int>(f))), frames[f]);
    writePly(dir.file("in/" + framePath("%03d.ply", static_cast<int>(f))), frames[f]);
  }
  for (const char* ext : {"obj", "ply"}) {
    const test::CommandResult r =
        test::run(dir, kBin + "/3dvo-enc",
                  {std::string("--InputMeshPattern=in/%03d.") + ext, "--FrameCount=4",
                   "--GridBits=14", "-o", std::string("x.") + ext + ".3dvo"});
    ASSERT_EQ(r.exitCode, 0) << r.err;
  }
  EXPECT_EQ(test::readText(dir.file("x.obj.3dvo")), test::readText(dir.file("x.ply.3dvo")));
}

}  // namespace
}  // namespace tdvo
