#include "common/core/obj_io.h"

#include <charconv>
#include <cstring>
#include <string_view>

#include "common/core/error.h"
#include "common/core/file_io.h"
#include "common/core/text_tokens.h"

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
    if (!mesh_.triangles.empty() && maxIndex_ >= mesh_.positions.size()) {
      lineNumber_ = maxIndexLine_;
      fail("vertex index " + std::to_string(maxIndex_ + 1ull) + " out of range (the file has " +
           std::to_string(mesh_.positions.size()) + " vertices)");
    }
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
  void appendPending(std::string_view piece) {
    if (piece.size() > kMaxObjLineBytes - pending_.size()) {
      ++lineNumber_;
      fail("line longer than " + std::to_string(kMaxObjLineBytes) + " bytes");
    }
    pending_.append(piece);
  }

  void line(std::string_view line) {
    ++lineNumber_;
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
      // Extra values (w, or per-vertex colours) are allowed and ignored.
      mesh_.positions.push_back({number(tokens[1]), number(tokens[2]), number(tokens[3])});
    } else if (keyword == "f") {
      if (tokens.size() < 4) fail("face needs at least three corners");
      if (mesh_.triangles.size() + (tokens.size() - 3) > kMaxObjTriangles)
        fail("more than " + std::to_string(kMaxObjTriangles) + " triangles");
      corners_.clear();
      for (size_t i = 1; i < tokens.size(); ++i)
        corners_.push_back(index(tokens[i]));
      if (firstFaceLine_ == 0) firstFaceLine_ = lineNumber_;
      for (size_t i = 1; i + 1 < corners_.size(); ++i) {
        mesh_.triangles.push_back({corners_[0], corners_[i], corners_[i + 1]});
        properTriangles_ += corners_[0] != corners_[i] && corners_[i] != corners_[i + 1] &&
                            corners_[0] != corners_[i + 1];
      }
    } else if (keyword == "vt" || keyword == "vn" || keyword == "vp" || keyword == "o" ||
               keyword == "g" || keyword == "s" || keyword == "mtllib" || keyword == "usemtl") {
      // Not geometry 3DVO codes.
    } else {
      fail("unsupported statement '" + std::string(keyword) + "'");
    }
  }

  [[noreturn]] void fail(const std::string& what) const {
    throw Error(name_ + ":" + std::to_string(lineNumber_) + ": " + what);
  }

  double number(std::string_view token) const {
    double value = 0;
    auto [ptr, ec] = std::from_chars(token.data(), token.data() + token.size(), value);
    if (ec != std::errc() || ptr != token.data() + token.size())
      fail("bad number '" + std::string(token) + "'");
    if (!(value == value) || value > 1e300 || value < -1e300)
      fail("non-finite number '" + std::string(token) + "'");
    return value;
  }

  uint32_t index(std::string_view token) {
    std::string_view first = token.substr(0, token.find('/'));
    long long value = 0;
    auto [ptr, ec] = std::from_chars(first.data(), first.data() + first.size(), value);
    if (ec != std::errc() || ptr != first.data() + first.size() || value == 0)
      fail("bad vertex index '" + std::string(token) + "'");
    // Negative indices count back from the last vertex read so far.
    if (value < 0) value += static_cast<long long>(mesh_.positions.size()) + 1;
    if (value < 1 || value > 0xFFFFFFFFLL)
      fail("vertex index '" + std::string(token) + "' out of range");
    const uint32_t result = static_cast<uint32_t>(value - 1);
    if (result > maxIndex_ || maxIndexLine_ == 0) {
      maxIndex_ = result;
      maxIndexLine_ = lineNumber_;
    }
    return result;
  }

  const std::string& name_;
  size_t lineNumber_ = 0;
  uint32_t maxIndex_ = 0;    // largest 0-based vertex index in any face so far
  size_t maxIndexLine_ = 0;  // the line where it first appeared
  size_t firstFaceLine_ = 0;
  size_t properTriangles_ = 0;  // triangles with three different vertices
  Mesh mesh_;
  std::string pending_;  // the unfinished last line of the text fed so far
  std::vector<std::string_view> tokens_;
  std::vector<uint32_t> corners_;
};

void appendNumber(std::string& out, double value) {
  char buffer[32];
  auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  out.append(buffer, result.ptr);
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
  std::string out;
  out.reserve(mesh.positions.size() * 40 + mesh.triangles.size() * 24);
  for (const Vec3d& p : mesh.positions) {
    out += 'v';
    for (double c : p) {
      out += ' ';
      appendNumber(out, c);
    }
    out += '\n';
  }
  for (const Triangle& t : mesh.triangles) {
    out += 'f';
    for (uint32_t v : t) {
      out += ' ';
      out += std::to_string(v + 1);
    }
    out += '\n';
  }
  return out;
}

void writeObj(const std::string& path, const Mesh& mesh) {
  writeFileAtomic(path, formatObj(mesh));
}

}  // namespace tdvo
