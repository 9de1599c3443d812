// OBJ reading and writing (common/core/obj_io.h): accepted forms, exact round trips, gzip input and
// an error naming file and line for every malformed input.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include "common/core/error.h"
#include "common/core/obj_io.h"
#include "common/core/warnings.h"
#include "tests/test_support.h"

namespace tdvo {
namespace {

using test::TempDir;

// Parses `text` and returns the error message; fails the test when no Error is thrown.
std::string parseError(const std::string& text, const std::string& name = "mesh.obj") {
  try {
    parseObj(text, name);
  } catch (const Error& e) {
    return e.what();
  }
  ADD_FAILURE() << "no error for:\n" << text;
  return "";
}

const char* const kTetrahedron =
    "v 0 0 0\n"
    "v 1 0 0\n"
    "v 0 1 0\n"
    "v 0 0 1\n"
    "f 1 3 2\n"
    "f 1 2 4\n"
    "f 1 4 3\n"
    "f 2 3 4\n";

TEST(ObjIo, ParsesVerticesAndTriangles) {
  const Mesh m = parseObj(kTetrahedron, "t.obj");
  ASSERT_EQ(m.positions.size(), 4u);
  EXPECT_EQ(m.positions[0], (Vec3d{0, 0, 0}));
  EXPECT_EQ(m.positions[1], (Vec3d{1, 0, 0}));
  EXPECT_EQ(m.positions[2], (Vec3d{0, 1, 0}));
  EXPECT_EQ(m.positions[3], (Vec3d{0, 0, 1}));
  ASSERT_EQ(m.triangles.size(), 4u);
  EXPECT_EQ(m.triangles[0], (Triangle{0, 2, 1}));
  EXPECT_EQ(m.triangles[1], (Triangle{0, 1, 3}));
  EXPECT_EQ(m.triangles[2], (Triangle{0, 3, 2}));
  EXPECT_EQ(m.triangles[3], (Triangle{1, 2, 3}));
}

// A UTF-8 byte-order mark (as Windows editors write) is no part of the first statement: the file
// reads as without it (it was "unsupported statement 'v'", the mark invisible in the message),
// plain and gzip-compressed. Elsewhere the bytes are an error as before.
TEST(ObjIo, ByteOrderMarkAtTheStartIsSkipped) {
  const std::string bom = "\xEF\xBB\xBF";
  const Mesh m = parseObj(bom + kTetrahedron, "t.obj");
  EXPECT_EQ(m.positions, parseObj(kTetrahedron, "t.obj").positions);
  EXPECT_EQ(m.triangles, parseObj(kTetrahedron, "t.obj").triangles);
  test::TempDir dir("obj-bom");
  test::writeGz(dir.file("t.obj.gz"), bom + kTetrahedron);
  EXPECT_EQ(readObj(dir.file("t.obj.gz")).triangles, m.triangles);
  try {
    parseObj(std::string(kTetrahedron) + bom + "v 0 0 0\n", "t.obj");
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("unsupported statement"), std::string::npos) << e.what();
  }
}

TEST(ObjIo, ParsesNumberForms) {
  const Mesh m = parseObj("v -1.5 2e3 .25\nv 1E-2 -0 7\nv 3 4 5 1.0\nf 1 2 3\n", "n.obj");
  ASSERT_EQ(m.positions.size(), 3u);
  EXPECT_EQ(m.positions[0], (Vec3d{-1.5, 2000, 0.25}));
  EXPECT_EQ(m.positions[1], (Vec3d{0.01, 0, 7}));
  EXPECT_TRUE(std::signbit(m.positions[1][1]));
  EXPECT_EQ(m.positions[2], (Vec3d{3, 4, 5}));  // the w component is ignored
}

TEST(ObjIo, SlashIndexForms) {
  const Mesh m = parseObj(
      "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\n"
      "vt 0 0\nvt 1 0\nvt 0 1\nvn 0 0 1\n"
      "f 1/1/1 2/2/1 3/3/1\n"
      "f 2//1 4//1 3//1\n"
      "f 4/3 3/2 2/1\n",
      "s.obj");
  ASSERT_EQ(m.triangles.size(), 3u);
  EXPECT_EQ(m.triangles[0], (Triangle{0, 1, 2}));
  EXPECT_EQ(m.triangles[1], (Triangle{1, 3, 2}));
  EXPECT_EQ(m.triangles[2], (Triangle{3, 2, 1}));
}

TEST(ObjIo, NegativeIndicesCountBackFromVerticesReadSoFar) {
  const Mesh m = parseObj(
      "v 0 0 0\nv 1 0 0\nv 0 1 0\n"
      "f -3 -2 -1\n"
      "v 5 5 5\n"
      "f -1 -2/7/1 -4\n",
      "neg.obj");
  ASSERT_EQ(m.triangles.size(), 2u);
  EXPECT_EQ(m.triangles[0], (Triangle{0, 1, 2}));
  EXPECT_EQ(m.triangles[1], (Triangle{3, 2, 0}));
}

TEST(ObjIo, PolygonsAreFannedAroundTheirFirstCorner) {
  const Mesh m = parseObj(
      "v 0 0 0\nv 1 0 0\nv 2 1 0\nv 1 2 0\nv 0 1 0\n"
      "f 1 2 3 4 5\n"
      "f 5 4 3 2\n",
      "poly.obj");
  ASSERT_EQ(m.triangles.size(), 5u);
  EXPECT_EQ(m.triangles[0], (Triangle{0, 1, 2}));
  EXPECT_EQ(m.triangles[1], (Triangle{0, 2, 3}));
  EXPECT_EQ(m.triangles[2], (Triangle{0, 3, 4}));
  EXPECT_EQ(m.triangles[3], (Triangle{4, 3, 2}));
  EXPECT_EQ(m.triangles[4], (Triangle{4, 2, 1}));
}

TEST(ObjIo, CommentsBlankLinesAndIgnoredStatements) {
  const Mesh m = parseObj(
      "# a comment line\r\n"
      "mtllib x.mtl\r\n"
      "o object\n"
      "\n"
      "   \t \n"
      "g group\n"
      "v 1 2 3 # trailing comment\r\n"
      "  v\t4 5 6\n"
      "vn 0 0 1\n"
      "vp 0.5\n"
      "v 7 8 9\n"
      "usemtl m\n"
      "s off\n"
      "f 1 2 3 # 4 5 6\n"
      "#f 3 2 1\n",
      "c.obj");
  ASSERT_EQ(m.positions.size(), 3u);
  EXPECT_EQ(m.positions[0], (Vec3d{1, 2, 3}));
  EXPECT_EQ(m.positions[1], (Vec3d{4, 5, 6}));
  EXPECT_EQ(m.positions[2], (Vec3d{7, 8, 9}));
  ASSERT_EQ(m.triangles.size(), 1u);
  EXPECT_EQ(m.triangles[0], (Triangle{0, 1, 2}));
}

TEST(ObjIo, FacesMayReferToVerticesDefinedLater) {
  const Mesh m = parseObj("f 1 2 3\nv 0 0 0\nv 1 0 0\nv 0 1 0\n", "late.obj");
  ASSERT_EQ(m.triangles.size(), 1u);
  EXPECT_EQ(m.triangles[0], (Triangle{0, 1, 2}));
}

TEST(ObjIo, FormatThenParseIsExact) {
  Mesh m;
  const double awkward[] = {0.1,
                            1.0 / 3.0,
                            -2.0 / 7.0,
                            1e-300,
                            -0.0,
                            123456789.123456789,
                            std::numeric_limits<double>::denorm_min(),
                            std::nextafter(1.0, 2.0),
                            -1e300,
                            0.30000000000000004};
  const size_t n = sizeof awkward / sizeof awkward[0];
  for (size_t i = 0; i < n; ++i)
    m.positions.push_back({awkward[i], awkward[(i + 3) % n], awkward[(i + 7) % n]});
  for (uint32_t i = 0; i + 2 < n; ++i)
    m.triangles.push_back({i, i + 2, i + 1});
  const Mesh back = parseObj(formatObj(m), "rt.obj");
  ASSERT_EQ(back.positions.size(), m.positions.size());
  ASSERT_EQ(back.triangles, m.triangles);
  for (size_t i = 0; i < n; ++i)
    for (int a = 0; a < 3; ++a)
      EXPECT_EQ(std::memcmp(&back.positions[i][a], &m.positions[i][a], sizeof(double)), 0)
          << "vertex " << i << " axis " << a << ": " << m.positions[i][a] << " read back as "
          << back.positions[i][a];
}

TEST(ObjIo, FormatObjText) {
  Mesh m;
  m.positions = {{0.5, -1, 2}, {3, 4, 5}, {6, 7, 8.25}};
  m.triangles = {{0, 2, 1}};
  EXPECT_EQ(formatObj(m), "v 0.5 -1 2\nv 3 4 5\nv 6 7 8.25\nf 1 3 2\n");
}

TEST(ObjIo, WriteObjThenReadObj) {
  TempDir dir("obj");
  Mesh m = parseObj(kTetrahedron, "t.obj");
  m.positions[2] = {1.0 / 3.0, -0.1, 1e10};
  const std::string path = dir.file("t.obj");
  writeObj(path, m);
  const Mesh back = readObj(path);
  EXPECT_EQ(back.positions, m.positions);
  EXPECT_EQ(back.triangles, m.triangles);
  // writeObj leaves only the final file behind (no temporary).
  EXPECT_EQ(test::listFolder(dir.path()), std::vector<std::string>{"t.obj"});
}

TEST(ObjIo, ReadsGzipCompressedFiles) {
  TempDir dir("objgz");
  const std::string path = dir.file("t.obj.gz");
  test::writeGz(path, kTetrahedron);
  // The file really is compressed (not the plain text).
  EXPECT_NE(test::readText(path), kTetrahedron);
  const Mesh fromGz = readObj(path);
  const Mesh fromText = parseObj(kTetrahedron, "t.obj");
  EXPECT_EQ(fromGz.positions, fromText.positions);
  EXPECT_EQ(fromGz.triangles, fromText.triangles);

  // Gzip content is recognised by its bytes, whatever the name.
  const std::string disguised = dir.file("plain-name.obj");
  test::writeGz(disguised, kTetrahedron);
  EXPECT_EQ(readObj(disguised).triangles, fromText.triangles);
}

TEST(ObjIo, ErrorsInGzipFilesNameTheLine) {
  TempDir dir("objgzerr");
  const std::string path = dir.file("bad.obj.gz");
  test::writeGz(path, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nv 1 2 oops\n");
  try {
    readObj(path);
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()), path + ":5: bad number 'oops'");
  }
}

TEST(ObjIo, CorruptGzipIsAnError) {
  TempDir dir("objgzbad");
  const std::string path = dir.file("t.obj.gz");
  test::writeGz(path, std::string(kTetrahedron) + std::string(4000, '#') + "\n");
  std::string bytes = test::readText(path);
  bytes.resize(bytes.size() / 2);  // truncated gzip stream
  test::writeText(path, bytes);
  try {
    readObj(path);
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()).rfind(path + ":", 0), 0u) << e.what();
  }
}

TEST(ObjIo, MissingFile) {
  TempDir dir("objmissing");
  const std::string path = dir.file("nothing-here.obj");
  try {
    readObj(path);
    FAIL() << "no error";
  } catch (const Error& e) {
    const std::string message = e.what();
    EXPECT_EQ(message.rfind(path + ": cannot open", 0), 0u) << message;
  }
}

// ---- Malformed input: every error names the file and the line. ----

TEST(ObjIoErrors, BadNumber) {
  EXPECT_EQ(parseError("v 0 0 0\nv 1 0 0\nv 0 1.5.2 0\nf 1 2 3\n"),
            "mesh.obj:3: bad number '1.5.2'");
  EXPECT_EQ(parseError("v 0 0 0\nv x 0 0\n"), "mesh.obj:2: bad number 'x'");
  EXPECT_EQ(parseError("v 0 0 1e999\n"),
            "mesh.obj:1: number '1e999' is beyond ±1e300, 3DVO's coordinate range");
  EXPECT_EQ(parseError("v 0 0 ++1\n"), "mesh.obj:1: bad number '++1'");
  EXPECT_EQ(parseError("v 0 0 +-1\n"), "mesh.obj:1: bad number '+-1'");
}

// Numbers as the C library reads them: a leading '+', and values too small for their type
// (float texture coordinates and normals, double positions) rounded to 0 or a subnormal.
TEST(ObjIo, PlusSignsAndTinyNumbersAreNumbers) {
  const Mesh m = parseObj(
      "v +1 0 1e-400\nv 1 +1.5e+0 0\nv 0 1 0\nvt 1e-46 +0.5\nvt 0 0\nvt 1 1\n"
      "f 1/1 2/2 3/3\n",
      "mesh.obj");
  EXPECT_EQ(m.positions[0], (Vec3d{1, 0, 0}));
  EXPECT_EQ(m.positions[1], (Vec3d{1, 1.5, 0}));
  EXPECT_EQ(m.attributes.uvs[0], (Vec2f{0, 0.5f}));
}

TEST(ObjIoErrors, NonFiniteNumber) {
  EXPECT_EQ(parseError("v 0 0 0\nv nan 0 0\n"), "mesh.obj:2: non-finite number 'nan'");
  EXPECT_EQ(parseError("v 0 0 0\n\nv 0 inf 0\n"), "mesh.obj:3: non-finite number 'inf'");
  // Finite, but beyond the range every reader takes (mesh.h, kMaxCoordinate).
  EXPECT_EQ(parseError("v 0 0 -1e301\n"),
            "mesh.obj:1: number '-1e301' is beyond ±1e300, 3DVO's coordinate range");
  EXPECT_NO_THROW(parseObj("v 0 0 1e300\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "mesh.obj"));
}

TEST(ObjIoErrors, MissingCoordinates) {
  EXPECT_EQ(parseError("v 0 0 0\nv 1 0\nv 0 1 0\nf 1 2 3\n"),
            "mesh.obj:2: vertex needs three coordinates");
  EXPECT_EQ(parseError("v\n"), "mesh.obj:1: vertex needs three coordinates");
}

TEST(ObjIoErrors, FaceWithTooFewCorners) {
  EXPECT_EQ(parseError("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2\n"),
            "mesh.obj:4: face needs at least three corners");
}

TEST(ObjIoErrors, FaceIndexZero) {
  EXPECT_EQ(parseError("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 0 1 2\n"),
            "mesh.obj:5: bad vertex index '0'");
  EXPECT_EQ(parseError("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 0/1/1 2\n"),
            "mesh.obj:4: bad vertex index '0/1/1'");
}

TEST(ObjIoErrors, BadFaceIndexToken) {
  EXPECT_EQ(parseError("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 two 3\n"),
            "mesh.obj:4: bad vertex index 'two'");
  EXPECT_EQ(parseError("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 /2 3\n"),
            "mesh.obj:4: bad vertex index '/2'");
}

TEST(ObjIoErrors, FaceIndexOutOfRange) {
  // Positive indices are checked once all vertices are known; the line of the offending face
  // is still named.
  EXPECT_EQ(parseError("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 4\nf 3 2 1\n"),
            "mesh.obj:5: vertex index 4 out of range (the file has 3 vertices)");
  EXPECT_EQ(parseError("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 9\nf 1 99 2\n"),
            "mesh.obj:6: vertex index 99 out of range (the file has 3 vertices)");
  // Negative indices are resolved (and checked) where they stand.
  EXPECT_EQ(parseError("v 0 0 0\nv 1 0 0\nv 0 1 0\nf -1 -2 -4\n"),
            "mesh.obj:4: vertex index '-4' out of range (a negative index counts back from the "
            "3 vertices read so far)");
  EXPECT_EQ(parseError("v 0 0 0\nf 1 2 99999999999\n"),
            "mesh.obj:2: vertex index '99999999999' out of range (above 4294967295)");
  EXPECT_EQ(parseError("v 0 0 0\nvt 0 0\nf 1/-2 1/1 1/1\n"),
            "mesh.obj:3: texture coordinate index in '1/-2' out of range (a negative index counts "
            "back from the 1 texture coordinate read so far)");
}

TEST(ObjIoErrors, UnknownStatement) {
  EXPECT_EQ(parseError("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\ncurv 0 1 2\n"),
            "mesh.obj:5: unsupported statement 'curv'");
  EXPECT_EQ(parseError("V 0 0 0\n"), "mesh.obj:1: unsupported statement 'V'");
}

TEST(ObjIoErrors, NoFaces) {
  EXPECT_EQ(parseError("v 0 0 0\nv 1 0 0\nv 0 1 0\n", "pts.obj"), "pts.obj: no faces");
}

TEST(ObjIoErrors, EmptyFile) {
  EXPECT_EQ(parseError("", "empty.obj"), "empty.obj: no vertices");
  EXPECT_EQ(parseError("# only a comment\n\n", "empty.obj"), "empty.obj: no vertices");
}

TEST(ObjIoErrors, ReadObjNamesThePath) {
  TempDir dir("objerr");
  const std::string path = dir.file("broken.obj");
  test::writeText(path, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3 x\n");
  try {
    readObj(path);
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()), path + ":4: bad vertex index 'x'");
  }
}

// What the reader leaves out of a file it says (common/core/warnings.h), once per attribute.
TEST(ObjIo, AttributesLeftOutAreSaid) {
  std::vector<std::string> said;
  const WarningHandler before =
      setWarningHandler([&](const std::string& message) { said.push_back(message); });
  const Mesh some = parseObj(
      "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nvt 0 0\nvt 1 0\nvt 0 1\n"
      "f 1/1 2/2 3/3\nf 1 2 4\n",
      "some.obj");
  EXPECT_TRUE(some.attributes.uvs.empty());
  ASSERT_EQ(said.size(), 1u);
  EXPECT_EQ(said[0],
            "some.obj: texture coordinates given by only some face corners: left out (a mesh has "
            "them at every corner or not at all)");
  said.clear();
  const Mesh unused = parseObj("v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1 2 3\n", "unused.obj");
  EXPECT_TRUE(unused.attributes.normals.empty());
  ASSERT_EQ(said.size(), 1u);
  EXPECT_EQ(said[0], "unused.obj: normals used by no face: left out (1 normal)");
  said.clear();
  const Mesh full = parseObj("v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2/1 3/1\n", "full.obj");
  EXPECT_EQ(full.attributes.uvs.size(), 1u);
  EXPECT_TRUE(said.empty());
  // Vertex colours (or w) after x y z: one warning naming the first such line.
  const Mesh coloured =
      parseObj("v 0 0 0\nv 1 0 0 1 0.5 0\nv 0 1 0 0 0 1\nf 1 2 3\n", "coloured.obj");
  EXPECT_EQ(coloured.positions[1], (Vec3d{1, 0, 0}));
  ASSERT_EQ(said.size(), 1u);
  EXPECT_EQ(said[0],
            "coloured.obj:2: values after x y z on 'v' lines (w, or vertex colours) are left out "
            "(this line and any other)");
  said.clear();
  // Statements 3DVO does not code (a Blender export's materials, object name and smoothing):
  // one warning naming each with the first line that has it.
  const Mesh blender = parseObj(
      "# Blender\nmtllib cube.mtl\no Cube\nv 0 0 0\nv 1 0 0\nv 0 1 0\ns 1\nusemtl Mat\n"
      "f 1 2 3\no Other\ng part\nf 1 3 2\n",
      "blender.obj");
  EXPECT_EQ(blender.triangles.size(), 2u);
  ASSERT_EQ(said.size(), 1u);
  EXPECT_EQ(said[0],
            "blender.obj:2: statements 3DVO does not code (mtllib, usemtl, o, g, s: materials, "
            "names, groups, smoothing) are left out of the decoded frames (first: 'mtllib' line "
            "2, 'usemtl' line 8, 'o' line 3, 'g' line 11, 's' line 7)");
  said.clear();
  // Smoothing switched off leaves nothing out.
  parseObj("v 0 0 0\nv 1 0 0\nv 0 1 0\ns off\nf 1 2 3\ns 0\n", "off.obj");
  EXPECT_TRUE(said.empty()) << said[0];
  // Polygons are split into fans, said once with the first one's line.
  const Mesh quads =
      parseObj("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3\nf 1 2 3 4\nf 4 3 2 1\n", "q.obj");
  EXPECT_EQ(quads.triangles.size(), 5u);
  EXPECT_EQ(said, (std::vector<std::string>{"q.obj:6: faces with more than three corners are "
                                            "split into triangles (a fan from each face's first "
                                            "corner) (first)"}));
  setWarningHandler(before);
}

}  // namespace
}  // namespace tdvo
