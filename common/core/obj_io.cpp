#include "common/core/obj_io.h"

#include <charconv>
#include <cmath>
#include <cstring>
#include <iterator>
#include <string_view>

#include "common/core/error.h"
#include "common/core/file_io.h"
#include "common/core/mesh_attributes.h"
#include "common/core/number_text.h"
#include "common/core/text_tokens.h"
#include "common/core/warnings.h"

namespace tdvo {

namespace {

class ObjParser {
 public:
  explicit ObjParser(const std::string& name) : name_(name) {}

  // Parses the next piece of the text; lines may be split between pieces. Only the unfinished
  // last line is kept, so memory does not grow with the file beyond the mesh itself.
  void feed(std::string_view text) {
    if (!pending_.empty()) {
      const size_t end = text.find('\n');
      if (end == std::string_view::npos) {
        appendPending(text);
        return;
      }
      appendPending(text.substr(0, end));
      line(pending_);
      pending_.clear();
      text.remove_prefix(end + 1);
    }
    size_t pos = 0;
    while (pos < text.size()) {
      const size_t end = text.find('\n', pos);
      if (end == std::string_view::npos) {
        appendPending(text.substr(pos));
        return;
      }
      line(text.substr(pos, end - pos));
      pos = end + 1;
    }
  }

  Mesh finish() {
    if (!pending_.empty()) line(pending_);
    pending_.clear();
    // Indices may refer to vertices defined later in the file, so they are checked at the end,
    // against the largest index seen and the line it was on.
    if (!mesh_.triangles.empty()) checkLargest(largest_, mesh_.positions.size(), "vertex");
    MeshAttributes& at = mesh_.attributes;
    if (!finishAttribute(uv_, at.uvs.size(), at.uvTriangles)) at.uvs.clear();
    if (!finishAttribute(normal_, at.normals.size(), at.normalTriangles)) at.normals.clear();
    const auto leftOut = [&](size_t line, const std::string& what) {
      if (line > 0)
        warnForFile(
            what, name_ + ":" + std::to_string(line) + ": " + what + " (this line and any other)");
    };
    leftOut(extraVertexValuesLine_,
            "values after x y z on 'v' lines (w, or vertex colours) are left out");
    leftOut(extraUvValuesLine_, "values after u v on 'vt' lines (w) are left out");
    leftOut(extraNormalValuesLine_, "values after x y z on 'vn' lines are left out");
    warnSkippedStatements();
    if (firstPolygonLine_ > 0)
      warnForFile(kPolygonsSplit, name_ + ":" + std::to_string(firstPolygonLine_) + ": " +
                                      kPolygonsSplit + " (first)");
    if (mesh_.positions.empty()) throw Error(name_ + ": no vertices");
    if (mesh_.triangles.empty()) throw Error(name_ + ": no faces");
    // Triangles with a repeated vertex are kept here (the encoder drops them, with a warning),
    // but a mesh made of nothing else has no surface at all.
    if (properTriangles_ == 0) {
      lineNumber_ = firstFaceLine_;
      fail("every face has a repeated vertex (degenerate): no triangle is left to code");
    }
    return std::move(mesh_);
  }

 private:
  // Statements read and left out (materials, names, groups, smoothing, free-form parameters):
  // 3DVO codes positions, texture coordinates and normals.
  static constexpr const char* kSkippedStatements[] = {"mtllib", "usemtl", "o", "g", "s", "vp"};
  static size_t skippedStatement(std::string_view keyword) {
    size_t k = 0;
    while (k < std::size(kSkippedStatements) && keyword != kSkippedStatements[k])
      ++k;
    return k;
  }

  // One warning for the statements left out, each with the first line that has it.
  void warnSkippedStatements() const {
    std::string kinds, lines;
    size_t first = 0;
    for (size_t k = 0; k < std::size(kSkippedStatements); ++k) {
      if (skippedLine_[k] == 0) continue;
      const std::string sep = kinds.empty() ? "" : ", ";
      kinds += sep + kSkippedStatements[k];
      lines += sep + "'" + kSkippedStatements[k] + "' line " + std::to_string(skippedLine_[k]);
      if (first == 0 || skippedLine_[k] < first) first = skippedLine_[k];
    }
    if (kinds.empty()) return;
    const std::string what = "statements 3DVO does not code (" + kinds +
                             ": materials, names, groups, smoothing) are left out of the "
                             "decoded frames";
    warnForFile(what,
                name_ + ":" + std::to_string(first) + ": " + what + " (first: " + lines + ")");
  }

  // The largest 0-based index of one kind (vertex, texture coordinate or normal) the faces
  // gave so far, and the line where it first appeared: checked against the number of values
  // of that kind once the whole file is read (values may come after the faces using them).
  struct LargestIndex {
    uint32_t value = 0;
    size_t line = 0;  // 0: no index yet

    void note(uint32_t index, size_t lineNumber) {
      if (index > value || line == 0) {
        value = index;
        line = lineNumber;
      }
    }
  };

  // A face attribute (texture coordinates or normals): its corner indices.
  struct Attribute {
    explicit Attribute(const char* name) : what(name) {}
    const char* what;
    int state = 0;  // 0: no face yet, 1: every corner gives it, 2: none does, 3: some do
    LargestIndex largest;
    std::vector<uint32_t> corners;    // of the current face
    std::vector<Triangle> triangles;  // one per triangle
  };

  void appendPending(std::string_view piece) {
    if (piece.size() > kMaxObjLineBytes - pending_.size()) {
      ++lineNumber_;
      fail("line longer than " + std::to_string(kMaxObjLineBytes) + " bytes");
    }
    pending_.append(piece);
  }

  void line(std::string_view line) {
    ++lineNumber_;
    if (lineNumber_ == 1) line = withoutUtf8Bom(line);
    if (line.size() > kMaxObjLineBytes)
      fail("line longer than " + std::to_string(kMaxObjLineBytes) + " bytes");
    size_t hash = line.find('#');
    if (hash != std::string_view::npos) line = line.substr(0, hash);
    tokenize(line, tokens_);
    if (tokens_.empty()) return;
    const std::vector<std::string_view>& tokens = tokens_;
    const std::string_view keyword = tokens[0];
    if (keyword == "v") {
      if (tokens.size() < 4) fail("vertex needs three coordinates");
      if (mesh_.positions.size() >= kMaxObjVertices)
        fail("more than " + std::to_string(kMaxObjVertices) + " vertices");
      // Extra values (w, or per-vertex colours) are allowed and left out, with a warning.
      if (tokens.size() > 4 && extraVertexValuesLine_ == 0) extraVertexValuesLine_ = lineNumber_;
      mesh_.positions.push_back({number(tokens[1]), number(tokens[2]), number(tokens[3])});
    } else if (keyword == "vt") {
      // u [v [w]]: v defaults to 0 (as OBJ says); w is left out, with a warning.
      if (tokens.size() < 2) fail("texture coordinate needs a value");
      if (tokens.size() > 3 && extraUvValuesLine_ == 0) extraUvValuesLine_ = lineNumber_;
      if (mesh_.attributes.uvs.size() >= kMaxObjVertices)
        fail("more than " + std::to_string(kMaxObjVertices) + " texture coordinates");
      mesh_.attributes.uvs.push_back(
          {floatNumber(tokens[1]), tokens.size() > 2 ? floatNumber(tokens[2]) : 0.0f});
    } else if (keyword == "vn") {
      if (tokens.size() < 4) fail("normal needs three values");
      if (tokens.size() > 4 && extraNormalValuesLine_ == 0) extraNormalValuesLine_ = lineNumber_;
      if (mesh_.attributes.normals.size() >= kMaxObjVertices)
        fail("more than " + std::to_string(kMaxObjVertices) + " normals");
      mesh_.attributes.normals.push_back(
          {floatNumber(tokens[1]), floatNumber(tokens[2]), floatNumber(tokens[3])});
    } else if (keyword == "f") {
      if (tokens.size() < 4) fail("face needs at least three corners");
      if (mesh_.triangles.size() + (tokens.size() - 3) > kMaxObjTriangles)
        fail("more than " + std::to_string(kMaxObjTriangles) + " triangles");
      corners_.clear();
      uv_.corners.clear();
      normal_.corners.clear();
      for (size_t i = 1; i < tokens.size(); ++i) {
        corners_.push_back(index(tokens[i]));
        // v, v/vt, v//vn or v/vt/vn: every face of a file gives the same parts.
        const size_t slash = tokens[i].find('/');
        std::string_view rest =
            slash == std::string_view::npos ? std::string_view() : tokens[i].substr(slash + 1);
        const size_t slash2 = rest.find('/');
        const std::string_view vt = rest.substr(0, slash2);
        const std::string_view vn =
            slash2 == std::string_view::npos ? std::string_view() : rest.substr(slash2 + 1);
        attributeIndex(uv_, vt, tokens[i], mesh_.attributes.uvs.size());
        attributeIndex(normal_, vn, tokens[i], mesh_.attributes.normals.size());
      }
      if (firstFaceLine_ == 0) firstFaceLine_ = lineNumber_;
      if (corners_.size() > 3 && firstPolygonLine_ == 0) firstPolygonLine_ = lineNumber_;
      for (size_t i = 1; i + 1 < corners_.size(); ++i) {
        mesh_.triangles.push_back({corners_[0], corners_[i], corners_[i + 1]});
        properTriangles_ += corners_[0] != corners_[i] && corners_[i] != corners_[i + 1] &&
                            corners_[0] != corners_[i + 1];
        for (Attribute* a : {&uv_, &normal_})
          if (a->state == 1)
            a->triangles.push_back({a->corners[0], a->corners[i], a->corners[i + 1]});
      }
    } else if (const size_t k = skippedStatement(keyword); k < std::size(kSkippedStatements)) {
      // Not geometry 3DVO codes: left out, and said (warnSkippedStatements); smoothing groups
      // switched off ("s off", "s 0", what Blender writes) leave nothing out.
      const bool off =
          keyword == "s" && tokens.size() == 2 && (tokens[1] == "off" || tokens[1] == "0");
      if (skippedLine_[k] == 0 && !off) skippedLine_[k] = lineNumber_;
    } else {
      fail("unsupported statement '" + std::string(keyword) + "'");
    }
  }

  [[noreturn]] void fail(const std::string& what) const {
    throw Error(name_ + ":" + std::to_string(lineNumber_) + ": " + what);
  }

  double number(std::string_view token) const {
    double value = 0;
    if (!parseNumber(token, value)) fail("bad number '" + std::string(token) + "'");
    // Digits too large for a double read as infinite: beyond the range, as 1e301 is.
    const bool digits = token.find_first_of("iInN") == std::string_view::npos;
    if (!std::isfinite(value) && !digits) fail("non-finite number '" + std::string(token) + "'");
    if (!std::isfinite(value) || isBeyondCoordinateRange(value))
      fail("number '" + std::string(token) + "'" + kBeyondCoordinateRange);
    return value;
  }

  float floatNumber(std::string_view token) const {
    float value = 0;
    if (!parseNumber(token, value)) fail("bad number '" + std::string(token) + "'");
    if (!std::isfinite(value)) fail("non-finite number '" + std::string(token) + "'");
    return value;
  }

  // The texture-coordinate or normal index `part` of face corner `token` (empty: none), with
  // `count` values read so far. A file's faces either all give the attribute or none does.
  void attributeIndex(Attribute& a, std::string_view part, std::string_view token, size_t count) {
    const bool given = !part.empty();
    if (a.state == 0) a.state = given ? 1 : 2;
    if (a.state != 3 && given != (a.state == 1)) {
      a.state = 3;  // some corners give it, some do not: the mesh cannot have it
      a.corners.clear();
      std::vector<Triangle>().swap(a.triangles);
    }
    if (!given) return;
    const uint32_t index = resolveIndex(part, token, count, a.what);
    if (a.state != 1) return;
    a.largest.note(index, lineNumber_);
    a.corners.push_back(index);
  }

  // The index triangles of an attribute, checked against its `count` values (which may come
  // later in the file); false when not every face corner gives it, or the file has no values
  // for it (what there is of it is then dropped: a mesh has it at every corner or not at all).
  bool finishAttribute(Attribute& a, size_t count, std::vector<Triangle>& triangles) {
    // What is dropped is said (common/core/warnings.h).
    const std::string kind = a.what;
    std::string what;
    if (a.state == 3)
      what = kind + "s given by only some face corners: left out (a mesh has them at every " +
             "corner or not at all)";
    else if (a.state == 1 && count == 0)
      what = "faces give " + kind + " indices, but the file has no " + kind + " values: left out";
    else if (a.state == 2 && count > 0)
      what = kind + "s used by no face: left out";
    if (!what.empty())
      warnForFile(what, name_ + ": " + what +
                            (a.state == 2 ? " (" + countOf(count, a.what) + ")" : std::string()));
    if (a.state != 1 || count == 0) return false;
    checkLargest(a.largest, count, a.what);
    triangles = std::move(a.triangles);
    return true;
  }

  // "1 vertex", "3 vertices", "2 normals" ...
  static std::string countOf(size_t count, const std::string& what) {
    return std::to_string(count) + " " +
           (what == "vertex" ? std::string(count == 1 ? "vertex" : "vertices")
                             : what + (count == 1 ? "" : "s"));
  }

  // Why a negative (relative) index is out of range: it counts back from the `count` values of
  // its kind read so far.
  static std::string relativeIndexNote(size_t count, const std::string& what) {
    return "a negative index counts back from the " + countOf(count, what) + " read so far";
  }

  // The largest index of a kind against the `count` values the whole file has of it.
  void checkLargest(const LargestIndex& largest, size_t count, const std::string& what) {
    if (largest.value < count) return;
    lineNumber_ = largest.line;
    fail(what + " index " + std::to_string(largest.value + 1ull) + " out of range (the file has " +
         countOf(count, what) + ")");
  }

  // The 0-based index that the 1-based OBJ index `part` of face corner `token` names, `what`
  // being "vertex", "texture coordinate" or "normal" and `count` the values of that kind read
  // so far (a negative index counts back from them). Its range against all the file's values is
  // checked at the end (LargestIndex). `what` is a C string, so that a corner builds no
  // std::string unless it is in error (this runs for every face corner).
  uint32_t resolveIndex(std::string_view part, std::string_view token, size_t count,
                        const char* what) const {
    // How the messages name the index: the vertex index is the corner's first part.
    const auto named = [&]() {
      const std::string kind = what;
      return kind + (kind == "vertex" ? " index '" : " index in '") + std::string(token) + "'";
    };
    long long value = 0;
    auto [ptr, ec] = std::from_chars(part.data(), part.data() + part.size(), value);
    if (ec != std::errc() || ptr != part.data() + part.size() || value == 0) fail("bad " + named());
    if (value < 0) {
      value += static_cast<long long>(count) + 1;
      if (value < 1) fail(named() + " out of range (" + relativeIndexNote(count, what) + ")");
    }
    if (value > 0xFFFFFFFFLL) fail(named() + " out of range (above 4294967295)");
    return static_cast<uint32_t>(value - 1);
  }

  uint32_t index(std::string_view token) {
    const uint32_t result =
        resolveIndex(token.substr(0, token.find('/')), token, mesh_.positions.size(), "vertex");
    largest_.note(result, lineNumber_);
    return result;
  }

  const std::string& name_;
  size_t lineNumber_ = 0;
  LargestIndex largest_;  // of the vertex indices
  size_t firstFaceLine_ = 0;
  size_t firstPolygonLine_ = 0;  // the first face with more than three corners
  size_t skippedLine_[std::size(kSkippedStatements)] = {};  // first line of each, 0: none
  size_t extraVertexValuesLine_ = 0;  // the first 'v' line with more than x y z
  size_t extraUvValuesLine_ = 0;      // the first 'vt' line with more than u v
  size_t extraNormalValuesLine_ = 0;  // the first 'vn' line with more than x y z
  size_t properTriangles_ = 0;        // triangles with three different vertices
  Attribute uv_ = Attribute("texture coordinate");
  Attribute normal_ = Attribute("normal");
  Mesh mesh_;
  std::string pending_;  // the unfinished last line of the text fed so far
  std::vector<std::string_view> tokens_;
  std::vector<uint32_t> corners_;
};

template <class T>
void appendNumber(std::string& out, T value) {
  char buffer[32];
  auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  out.append(buffer, result.ptr);
}

// "keyword x y ...\n", each number in its shortest exact form.
template <class Values>
void appendLine(std::string& out, const char* keyword, const Values& values) {
  out += keyword;
  for (auto c : values) {
    out += ' ';
    appendNumber(out, c);
  }
  out += '\n';
}

}  // namespace

Mesh parseObj(const std::string& text, const std::string& name) {
  ObjParser parser(name);
  parser.feed(text);
  return parser.finish();
}

Mesh readObj(const std::string& path) {
  ObjParser parser(path);
  readFileMaybeGzChunks(
      path, [&](const char* data, size_t size) { parser.feed(std::string_view(data, size)); });
  return parser.finish();
}

std::string formatObj(const Mesh& mesh) {
  const MeshAttributes& at = mesh.attributes;
  const bool uvs = at.hasUvs() && at.uvTriangles.size() == mesh.triangles.size();
  const bool normals = at.hasNormals() && at.normalTriangles.size() == mesh.triangles.size();
  std::string out;
  out.reserve(mesh.positions.size() * 40 + mesh.triangles.size() * (24 + 24 * (uvs + normals)));
  for (const Vec3d& p : mesh.positions)
    appendLine(out, "v", p);
  // Texture coordinates and normals in the shortest decimal form that reads back to the same
  // float.
  // OBJ's v = 0 is the image's bottom row.
  std::vector<Vec2f> converted;
  if (uvs && at.uvOrigin != UvOrigin::kBottom) converted = uvsFrom(at, UvOrigin::kBottom);
  if (uvs)
    for (const Vec2f& t : at.uvOrigin == UvOrigin::kBottom ? at.uvs : converted)
      appendLine(out, "vt", t);
  if (normals)
    for (const Vec3f& n : at.normals)
      appendLine(out, "vn", n);
  for (size_t t = 0; t < mesh.triangles.size(); ++t) {
    out += 'f';
    for (int c = 0; c < 3; ++c) {
      out += ' ';
      out += std::to_string(mesh.triangles[t][c] + 1);
      if (!uvs && !normals) continue;
      out += '/';
      if (uvs) out += std::to_string(at.uvTriangles[t][c] + 1);
      if (normals) {
        out += '/';
        out += std::to_string(at.normalTriangles[t][c] + 1);
      }
    }
    out += '\n';
  }
  return out;
}

void writeObj(const std::string& path, const Mesh& mesh) {
  writeFileAtomic(path, formatObj(mesh));
}

}  // namespace tdvo
