#include "common/core/ply_io.h"

#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <string_view>
#include <vector>

#include "common/core/error.h"
#include "common/core/file_io.h"
#include "common/core/mesh_attributes.h"
#include "common/core/number_text.h"
#include "common/core/text_tokens.h"
#include "common/core/warnings.h"

namespace tdvo {

namespace {

enum class Type : uint8_t { kInt8, kUint8, kInt16, kUint16, kInt32, kUint32, kFloat32, kFloat64 };

size_t typeSize(Type t) {
  switch (t) {
    case Type::kInt8:
    case Type::kUint8:
      return 1;
    case Type::kInt16:
    case Type::kUint16:
      return 2;
    case Type::kInt32:
    case Type::kUint32:
    case Type::kFloat32:
      return 4;
    case Type::kFloat64:
      return 8;
  }
  return 0;
}

bool isInteger(Type t) {
  return t != Type::kFloat32 && t != Type::kFloat64;
}

bool typeNamed(std::string_view name, Type& t) {
  static const struct {
    const char* name;
    Type type;
  } kTypes[] = {{"char", Type::kInt8},      {"int8", Type::kInt8},       {"uchar", Type::kUint8},
                {"uint8", Type::kUint8},    {"short", Type::kInt16},     {"int16", Type::kInt16},
                {"ushort", Type::kUint16},  {"uint16", Type::kUint16},   {"int", Type::kInt32},
                {"int32", Type::kInt32},    {"uint", Type::kUint32},     {"uint32", Type::kUint32},
                {"float", Type::kFloat32},  {"float32", Type::kFloat32}, {"double", Type::kFloat64},
                {"float64", Type::kFloat64}};
  for (const auto& k : kTypes)
    if (name == k.name) {
      t = k.type;
      return true;
    }
  return false;
}

struct Property {
  std::string name;
  Type type = Type::kFloat32;  // the value type (a list's entries)
  bool list = false;
  Type countType = Type::kUint8;  // a list's count
};

// What the reader does with a property of the vertex or face element.
// kU .. kNz: the vertex's texture coordinates and normal (mesh.h's attributes, per vertex).
enum class Role : uint8_t { kSkip, kX, kY, kZ, kIndices, kU, kV, kNx, kNy, kNz };

struct Element {
  std::string name;
  uint64_t count = 0;
  size_t line = 0;  // header line declaring it
  std::vector<Property> properties;
  std::vector<Role> roles;
  bool isVertex = false, isFace = false;
};

class PlyParser {
 public:
  explicit PlyParser(const std::string& name) : name_(name) {}

  void feed(std::string_view data) {
    if (done_ && !data.empty() && !ascii_) {
      // Binary bytes after the last element.
      failAt(offset_, "bytes after the last element (" + std::to_string(data.size()) +
                          " or more); the header declares fewer elements than the file holds");
    }
    buffer_.append(data);
    if (!headerDone_) {
      parseHeader();
      if (!headerDone_) {
        if (buffer_.size() > kMaxPlyHeaderBytes)
          failLine(headerLine_ + 1, "header longer than " + std::to_string(kMaxPlyHeaderBytes) +
                                        " bytes (no end_header)");
        return;
      }
    }
    parseBody();
    // Keep only what the next record still needs.
    buffer_.erase(0, pos_);
    pos_ = 0;
  }

  Mesh finish() {
    if (!headerDone_) {
      if (buffer_.empty() && headerLine_ == 0) fail("empty file (not a PLY file)");
      failLine(headerLine_ + 1, "file ends inside the header (no end_header)");
    }
    if (ascii_ && !done_ && pos_ < buffer_.size()) {
      // The last line has no line break.
      buffer_ += '\n';
      parseBody();
    }
    if (!done_) {
      const Element& e = elements_[element_];
      const std::string where = "file ends in element '" + e.name + "' (record " +
                                std::to_string(record_ + 1) + " of " + std::to_string(e.count) +
                                "): truncated file";
      if (ascii_) failLine(line_ + 1, where);
      failAt(offset_, where);
    }
    if (pos_ < buffer_.size()) {
      if (ascii_) {
        // Only blank lines may follow.
        std::string_view rest(buffer_.data() + pos_, buffer_.size() - pos_);
        size_t line = line_;
        size_t start = 0;
        while (start < rest.size()) {
          size_t end = rest.find('\n', start);
          if (end == std::string_view::npos) end = rest.size();
          ++line;
          std::string_view l = rest.substr(start, end - start);
          for (char c : l)
            if (!isSpace(c))
              failLine(line,
                       "text after the last element; the header declares fewer elements "
                       "than the file holds");
          start = end + 1;
        }
      } else {
        failAt(offset_, "bytes after the last element (" + std::to_string(buffer_.size() - pos_) +
                            "); the header declares fewer elements than the file holds");
      }
    }
    if (maxIndexKnown_ && maxIndex_ >= mesh_.positions.size()) {
      throw Error(name_ + maxIndexWhere_ + ": vertex index " + std::to_string(maxIndex_) +
                  " out of range (the file has " + std::to_string(mesh_.positions.size()) +
                  " vertices)");
    }
    if (mesh_.positions.empty()) fail("no vertices");
    if (hasUv_) mesh_.attributes.uvTriangles = mesh_.triangles;  // per vertex
    if (hasNormal_) mesh_.attributes.normalTriangles = mesh_.triangles;
    if (mesh_.triangles.empty()) fail("no faces");
    if (properTriangles_ == 0)
      throw Error(name_ + firstFaceWhere_ +
                  ": every face has a repeated vertex (degenerate): no triangle is left to code");
    if (!firstPolygonWhere_.empty())
      warnForFile(kPolygonsSplit, name_ + firstPolygonWhere_ + ": " + kPolygonsSplit + " (first)");
    return std::move(mesh_);
  }

 private:
  [[noreturn]] void fail(const std::string& what) const { throw Error(name_ + ": " + what); }
  [[noreturn]] void failLine(size_t line, const std::string& what) const {
    throw Error(name_ + ":" + std::to_string(line) + ": " + what);
  }
  [[noreturn]] void failAt(uint64_t offset, const std::string& what) const {
    throw Error(name_ + ": byte " + std::to_string(offset) + ": " + what);
  }
  // Where the current record is (":12" or ": byte 345"), for messages raised after the fact.
  std::string here() const {
    if (ascii_) return ":" + std::to_string(line_);
    return ": byte " + std::to_string(recordOffset_);
  }

  // ---- Header ----

  void parseHeader() {
    while (!headerDone_) {
      const size_t end = buffer_.find('\n', pos_);
      if (end == std::string::npos) return;
      std::string_view line(buffer_.data() + pos_, end - pos_);
      headerBytes_ += end + 1 - pos_;
      pos_ = end + 1;
      ++headerLine_;
      if (headerBytes_ > kMaxPlyHeaderBytes)
        failLine(headerLine_,
                 "header longer than " + std::to_string(kMaxPlyHeaderBytes) + " bytes");
      headerStatement(line);
    }
    offset_ = headerBytes_;
  }

  void headerStatement(std::string_view line) {
    tokenize(line, tokens_);
    const size_t n = headerLine_;
    if (n == 1) {
      if (tokens_.size() != 1 || tokens_[0] != "ply")
        failLine(n, "not a PLY file (the first line is not 'ply')");
      return;
    }
    if (tokens_.empty()) return;
    const std::string_view keyword = tokens_[0];
    if (keyword == "comment" || keyword == "obj_info") {
      // Meshlab's link to the texture image: the one comment a user would miss.
      if (keyword == "comment" && tokens_.size() > 1 && tokens_[1] == "TextureFile" &&
          textureFileLine_ == 0)
        textureFileLine_ = n;
      return;
    }
    if (keyword == "format") {
      if (formatSeen_) failLine(n, "a second format line");
      if (tokens_.size() != 3) failLine(n, "format needs an encoding and a version");
      if (tokens_[1] == "ascii")
        ascii_ = true;
      else if (tokens_[1] == "binary_little_endian")
        bigEndian_ = false;
      else if (tokens_[1] == "binary_big_endian")
        bigEndian_ = true;
      else
        failLine(n, "unknown format '" + std::string(tokens_[1]) + "'");
      if (tokens_[2] != "1.0" && tokens_[2] != "1")
        failLine(n, "unsupported version '" + std::string(tokens_[2]) + "' (1.0 is read)");
      formatSeen_ = true;
      return;
    }
    if (!formatSeen_) failLine(n, "expected the format line after 'ply'");
    if (keyword == "element") {
      if (tokens_.size() != 3) failLine(n, "element needs a name and a count");
      finishElement();
      Element e;
      e.name = std::string(tokens_[1]);
      e.line = n;
      uint64_t count = 0;
      auto [ptr, ec] =
          std::from_chars(tokens_[2].data(), tokens_[2].data() + tokens_[2].size(), count);
      if (ec != std::errc() || ptr != tokens_[2].data() + tokens_[2].size())
        failLine(n, "bad element count '" + std::string(tokens_[2]) + "'");
      e.count = count;
      e.isVertex = e.name == "vertex";
      e.isFace = e.name == "face";
      for (const Element& other : elements_)
        if ((e.isVertex || e.isFace) && other.name == e.name)
          failLine(n, "a second '" + e.name + "' element");
      if (e.isVertex && count > kMaxPlyVertices)
        failLine(n, "more than " + std::to_string(kMaxPlyVertices) + " vertices");
      if (e.isFace && count > kMaxPlyTriangles)
        failLine(n, "more than " + std::to_string(kMaxPlyTriangles) + " triangles");
      elements_.push_back(std::move(e));
      return;
    }
    if (keyword == "property") {
      if (elements_.empty()) failLine(n, "property before any element");
      Element& e = elements_.back();
      if (e.properties.size() == kMaxPlyProperties)
        failLine(n, "more than " + std::to_string(kMaxPlyProperties) + " properties");
      Property p;
      if (tokens_.size() >= 2 && tokens_[1] == "list") {
        if (tokens_.size() != 5) failLine(n, "list property needs two types and a name");
        if (!typeNamed(tokens_[2], p.countType))
          failLine(n, "unknown type '" + std::string(tokens_[2]) + "'");
        if (!typeNamed(tokens_[3], p.type))
          failLine(n, "unknown type '" + std::string(tokens_[3]) + "'");
        if (!isInteger(p.countType)) failLine(n, "a list's count type must be an integer type");
        p.list = true;
        p.name = std::string(tokens_[4]);
      } else {
        if (tokens_.size() != 3) failLine(n, "property needs a type and a name");
        if (!typeNamed(tokens_[1], p.type))
          failLine(n, "unknown type '" + std::string(tokens_[1]) + "'");
        p.name = std::string(tokens_[2]);
      }
      Role role = Role::kSkip;
      if (e.isVertex && !p.list) {
        if (p.name == "x") role = Role::kX;
        if (p.name == "y") role = Role::kY;
        if (p.name == "z") role = Role::kZ;
        if (p.name == "u" || p.name == "s" || p.name == "texture_u" || p.name == "texture_s")
          role = Role::kU;
        if (p.name == "v" || p.name == "t" || p.name == "texture_v" || p.name == "texture_t")
          role = Role::kV;
        if (p.name == "nx") role = Role::kNx;
        if (p.name == "ny") role = Role::kNy;
        if (p.name == "nz") role = Role::kNz;
      }
      if (e.isFace && (p.name == "vertex_indices" || p.name == "vertex_index")) {
        if (!p.list) failLine(n, "face property '" + p.name + "' must be a list");
        if (!isInteger(p.type)) failLine(n, "vertex indices must be of an integer type");
        role = Role::kIndices;
      }
      for (size_t i = 0; i < e.roles.size(); ++i)
        if (role != Role::kSkip && e.roles[i] == role)
          failLine(n, "a second '" + p.name + "' property in element '" + e.name + "'" +
                          (p.name != e.properties[i].name
                               ? " (as '" + e.properties[i].name + "', the same coordinate)"
                               : std::string()));
      e.properties.push_back(std::move(p));
      e.roles.push_back(role);
      return;
    }
    if (keyword == "end_header") {
      if (tokens_.size() != 1) failLine(n, "text after end_header");
      finishElement();
      bool vertex = false, face = false;
      for (const Element& e : elements_) {
        vertex |= e.isVertex;
        face |= e.isFace;
      }
      if (!vertex) failLine(n, "no 'vertex' element: no vertices");
      if (!face) failLine(n, "no 'face' element: no faces");
      warnLeftOut();
      headerDone_ = true;
      line_ = n;  // body lines are numbered on from the header's
      element_ = 0;
      record_ = 0;
      skipEmptyElements();
      return;
    }
    failLine(n, "unsupported header statement '" + std::string(keyword) + "'");
  }

  // What of the file's data is not read (properties of vertices and faces other than those
  // above, elements other than vertex and face that hold records) is said, in one warning.
  void warnLeftOut() const {
    // `list` names what and how much; `kind` what only, the same for every file that leaves
    // the same things out (common/core/warnings.h, warnForFile).
    std::string list, kind;
    const auto add = [&list, &kind](const std::string& what, const std::string& amount,
                                    const char* close = "") {
      list += (list.empty() ? "" : "; ") + what + amount + close;
      kind += (kind.empty() ? "" : "; ") + what + close;
    };
    for (const Element& e : elements_) {
      if (e.isVertex || e.isFace) {
        std::string names;
        size_t count = 0;
        for (size_t i = 0; i < e.properties.size(); ++i)
          if (e.roles[i] == Role::kSkip) names += (count++ ? ", " : "") + e.properties[i].name;
        if (count > 0 && e.count > 0)
          add(e.name + " propert" + (count == 1 ? "y " : "ies ") + names, "");
      } else if (e.count > 0) {
        add("element " + e.name,
            " (" + std::to_string(e.count) + (e.count == 1 ? " record)" : " records)"));
      }
    }
    if (textureFileLine_ > 0)
      add("the texture image's name (comment TextureFile",
          ", header line " + std::to_string(textureFileLine_), ")");
    if (!list.empty())
      warnForFile("left out (not read): " + kind, name_ + ": left out (not read): " + list);
  }

  // Checks the element declared last, once its properties are known.
  void finishElement() {
    if (elements_.empty()) return;
    const Element& e = elements_.back();
    if (e.properties.empty() && e.count > 0)
      failLine(e.line, "element '" + e.name + "' has no properties");
    if (e.isVertex) {
      int found = 0;
      for (Role r : e.roles)
        found += r == Role::kX || r == Role::kY || r == Role::kZ;
      if (found != 3) failLine(e.line, "the vertex element needs properties x, y and z");
      int uv = 0, normal = 0;
      for (Role r : e.roles) {
        uv += r == Role::kU || r == Role::kV;
        normal += r == Role::kNx || r == Role::kNy || r == Role::kNz;
      }
      if (uv == 1)
        failLine(e.line, "the vertex element has one texture coordinate (u and v go together)");
      if (normal != 0 && normal != 3)
        failLine(e.line, "the vertex element has part of a normal (nx, ny and nz go together)");
      hasUv_ = uv == 2;
      hasNormal_ = normal == 3;
    }
    if (e.isFace) {
      bool indices = false;
      for (Role r : e.roles)
        indices |= r == Role::kIndices;
      if (!indices) failLine(e.line, "the face element needs a vertex_indices list");
    }
  }

  void skipEmptyElements() {
    while (element_ < elements_.size() && record_ == elements_[element_].count) {
      ++element_;
      record_ = 0;
    }
    done_ = element_ == elements_.size();
  }

  // ---- Body ----

  void parseBody() {
    while (!done_) {
      if (!(ascii_ ? asciiRecord() : binaryRecord())) return;
      ++record_;
      skipEmptyElements();
    }
  }

  // One ascii record (a line); false when the line is not complete yet.
  bool asciiRecord() {
    size_t end;
    std::string_view line;
    for (;;) {
      end = buffer_.find('\n', pos_);
      if (end == std::string::npos) {
        if (buffer_.size() - pos_ > kMaxPlyLineBytes)
          failLine(line_ + 1, "line longer than " + std::to_string(kMaxPlyLineBytes) + " bytes");
        return false;
      }
      line = std::string_view(buffer_.data() + pos_, end - pos_);
      ++line_;
      pos_ = end + 1;
      if (line.size() > kMaxPlyLineBytes)
        failLine(line_, "line longer than " + std::to_string(kMaxPlyLineBytes) + " bytes");
      tokenize(line, tokens_);
      if (!tokens_.empty()) break;  // blank lines between records are allowed
    }
    const Element& e = elements_[element_];
    size_t t = 0;
    auto next = [&](const char* what) -> std::string_view {
      if (t == tokens_.size())
        failLine(line_,
                 "element '" + e.name + "' record has too few values (missing " + what + ")");
      return tokens_[t++];
    };
    beginRecord(e);
    for (size_t i = 0; i < e.properties.size(); ++i) {
      const Property& p = e.properties[i];
      if (!p.list) {
        value(e.roles[i], p.type, next(p.name.c_str()));
        continue;
      }
      const uint64_t count = listCount(asciiInteger(next(p.name.c_str()), p.countType));
      for (uint64_t k = 0; k < count; ++k)
        listValue(e.roles[i], p.type, k, next(p.name.c_str()));
      endList(e.roles[i], count);
    }
    if (t != tokens_.size())
      failLine(line_, "element '" + e.name + "' record has more values than its " +
                          std::to_string(e.properties.size()) + " properties");
    endRecord(e);
    return true;
  }

  // One binary record; false when its bytes are not all there yet.
  bool binaryRecord() {
    const Element& e = elements_[element_];
    // First the record's size (lists make it vary), then its values.
    size_t size = 0;
    for (const Property& p : e.properties) {
      if (!p.list) {
        size += typeSize(p.type);
        continue;
      }
      if (buffer_.size() - pos_ < size + typeSize(p.countType)) return false;
      const uint64_t count = listCount(rawInteger(pos_ + size, p.countType));
      size += typeSize(p.countType) + count * typeSize(p.type);
    }
    if (buffer_.size() - pos_ < size) return false;
    recordOffset_ = offset_;
    beginRecord(e);
    size_t at = pos_;
    for (size_t i = 0; i < e.properties.size(); ++i) {
      const Property& p = e.properties[i];
      const Role role = e.roles[i];
      if (!p.list) {
        if (role != Role::kSkip) binaryValue(role, p.type, at);
        at += typeSize(p.type);
        continue;
      }
      const uint64_t count = static_cast<uint64_t>(rawInteger(at, p.countType));
      at += typeSize(p.countType);
      if (role == Role::kIndices)
        for (uint64_t k = 0; k < count; ++k) {
          const int64_t index = rawInteger(at, p.type);
          corner(index, std::to_string(index));
          at += typeSize(p.type);
        }
      else
        at += count * typeSize(p.type);
      endList(role, count);
    }
    pos_ = at;
    offset_ += size;
    endRecord(e);
    return true;
  }

  uint64_t listCount(int64_t count) {
    if (count < 0) failHere("negative list count " + std::to_string(count));
    if (static_cast<uint64_t>(count) > kMaxPlyListLength)
      failHere("list of " + std::to_string(count) + " entries (more than " +
               std::to_string(kMaxPlyListLength) + ")");
    return static_cast<uint64_t>(count);
  }

  [[noreturn]] void failHere(const std::string& what) const {
    if (ascii_) failLine(line_, what);
    failAt(offset_, what);
  }

  void beginRecord(const Element& e) {
    recordOffset_ = offset_;
    if (e.isFace) corners_.clear();
  }

  void endRecord(const Element& e) {
    if (e.isVertex) {
      if (mesh_.positions.size() >= kMaxPlyVertices)
        failHere("more than " + std::to_string(kMaxPlyVertices) + " vertices");
      mesh_.positions.push_back(vertex_);
      if (hasUv_) mesh_.attributes.uvs.push_back(uv_);
      if (hasNormal_) mesh_.attributes.normals.push_back(normal_);
    }
  }

  // A face's corners are complete: its triangles (a fan).
  void endList(Role role, uint64_t count) {
    if (role != Role::kIndices) return;
    if (count < 3)
      failHere("face needs at least three corners (it has " + std::to_string(count) + ")");
    if (mesh_.triangles.size() + (count - 2) > kMaxPlyTriangles)
      failHere("more than " + std::to_string(kMaxPlyTriangles) + " triangles");
    if (firstFaceWhere_.empty()) firstFaceWhere_ = here();
    if (count > 3 && firstPolygonWhere_.empty()) firstPolygonWhere_ = here();
    for (size_t i = 1; i + 1 < corners_.size(); ++i) {
      mesh_.triangles.push_back({corners_[0], corners_[i], corners_[i + 1]});
      properTriangles_ += corners_[0] != corners_[i] && corners_[i] != corners_[i + 1] &&
                          corners_[0] != corners_[i + 1];
    }
    corners_.clear();
  }

  void corner(int64_t index, const std::string& text) {
    if (index < 0 || index > 0xFFFFFFFFLL) failHere("vertex index " + text + " out of range");
    const uint32_t v = static_cast<uint32_t>(index);
    // Faces may come before the vertices: indices are checked at the end, against the
    // largest one and where it was.
    if (!maxIndexKnown_ || v > maxIndex_) {
      maxIndex_ = v;
      maxIndexKnown_ = true;
      maxIndexWhere_ = here();
    }
    corners_.push_back(v);
  }

  void setCoordinate(Role role, double v) {
    if (role >= Role::kU) return setAttribute(role, static_cast<float>(v));
    if (!std::isfinite(v)) failHere("non-finite coordinate");
    if (isBeyondCoordinateRange(v))
      failHere("coordinate " + coordinateText(v) + kBeyondCoordinateRange);
    vertex_[static_cast<int>(role) - static_cast<int>(Role::kX)] = v;
  }

  // A texture coordinate or normal component, as float (mesh.h).
  void setAttribute(Role role, float v) {
    if (!std::isfinite(v)) failHere("non-finite texture coordinate or normal");
    if (role == Role::kU || role == Role::kV)
      uv_[role == Role::kV] = v;
    else
      normal_[static_cast<int>(role) - static_cast<int>(Role::kNx)] = v;
  }

  // ascii values
  void value(Role role, Type type, std::string_view token) {
    if (role == Role::kSkip) {
      // Still a number of its type.
      if (isInteger(type))
        asciiInteger(token, type);
      else
        asciiFloat(token);
      return;
    }
    if (role >= Role::kU && !isInteger(type))
      return setAttribute(role, asciiFloat32(token));  // as float: no double rounding
    setCoordinate(
        role, isInteger(type) ? static_cast<double>(asciiInteger(token, type)) : asciiFloat(token));
  }

  void listValue(Role role, Type type, uint64_t, std::string_view token) {
    if (role == Role::kIndices) {
      corner(asciiInteger(token, type), std::string(token));
      return;
    }
    if (isInteger(type))
      asciiInteger(token, type);
    else
      asciiFloat(token);
  }

  int64_t asciiInteger(std::string_view token, Type type) {
    int64_t v = 0;
    if (!parseNumber(token, v)) failLine(line_, "bad integer '" + std::string(token) + "'");
    const int64_t lo[] = {-128, 0, -32768, 0, INT32_MIN, 0};
    const int64_t hi[] = {127, 255, 32767, 65535, INT32_MAX, UINT32_MAX};
    const size_t k = static_cast<size_t>(type);
    if (v < lo[k] || v > hi[k])
      failLine(line_, "integer '" + std::string(token) + "' out of its type's range");
    return v;
  }

  float asciiFloat32(std::string_view token) {
    float v = 0;
    if (!parseNumber(token, v)) failLine(line_, "bad number '" + std::string(token) + "'");
    return v;
  }

  double asciiFloat(std::string_view token) {
    double v = 0;
    if (!parseNumber(token, v)) failLine(line_, "bad number '" + std::string(token) + "'");
    return v;
  }

  // binary values
  template <class T>
  T load(size_t at) const {
    unsigned char b[sizeof(T)];
    std::memcpy(b, buffer_.data() + at, sizeof(T));
    if (bigEndian_)
      for (size_t i = 0; i < sizeof(T) / 2; ++i)
        std::swap(b[i], b[sizeof(T) - 1 - i]);
    T v;
    std::memcpy(&v, b, sizeof(T));
    return v;
  }

  int64_t rawInteger(size_t at, Type type) const {
    switch (type) {
      case Type::kInt8:
        return load<int8_t>(at);
      case Type::kUint8:
        return load<uint8_t>(at);
      case Type::kInt16:
        return load<int16_t>(at);
      case Type::kUint16:
        return load<uint16_t>(at);
      case Type::kInt32:
        return load<int32_t>(at);
      case Type::kUint32:
        return load<uint32_t>(at);
      default:
        return 0;  // not an integer type (the header refuses those for counts and indices)
    }
  }

  void binaryValue(Role role, Type type, size_t at) {
    if (role >= Role::kU && type == Type::kFloat32) return setAttribute(role, load<float>(at));
    double v;
    if (type == Type::kFloat32)
      v = load<float>(at);
    else if (type == Type::kFloat64)
      v = load<double>(at);
    else
      v = static_cast<double>(rawInteger(at, type));
    setCoordinate(role, v);
  }

  const std::string& name_;
  std::string buffer_;  // bytes read and not consumed yet (from pos_)
  size_t pos_ = 0;
  bool headerDone_ = false, formatSeen_ = false, ascii_ = false, bigEndian_ = false;
  bool done_ = false;      // every element read
  size_t headerLine_ = 0;  // header lines read
  size_t headerBytes_ = 0;
  size_t line_ = 0;            // ascii: the current line number
  uint64_t offset_ = 0;        // binary: the file offset of buffer_[pos_]
  uint64_t recordOffset_ = 0;  // binary: where the current record starts
  std::vector<Element> elements_;
  size_t element_ = 0;   // the element being read
  uint64_t record_ = 0;  // the record of it being read
  std::vector<std::string_view> tokens_;
  std::vector<uint32_t> corners_;
  Vec3d vertex_{};
  bool hasUv_ = false, hasNormal_ = false;  // the vertex element has u, v / nx, ny, nz
  Vec2f uv_{};
  Vec3f normal_{};
  Mesh mesh_;
  uint32_t maxIndex_ = 0;
  bool maxIndexKnown_ = false;
  std::string maxIndexWhere_, firstFaceWhere_;
  std::string firstPolygonWhere_;  // the first face with more than three corners
  size_t textureFileLine_ = 0;     // the first 'comment TextureFile' header line
  size_t properTriangles_ = 0;
};

}  // namespace

Mesh parsePly(const std::string& data, const std::string& name) {
  PlyParser parser(name);
  parser.feed(data);
  return parser.finish();
}

Mesh readPly(const std::string& path) {
  PlyParser parser(path);
  readFileMaybeGzChunks(
      path, [&](const char* data, size_t size) { parser.feed(std::string_view(data, size)); });
  return parser.finish();
}

std::string formatPly(const Mesh& input, PlyEncoding encoding) {
  // PLY attributes are per vertex: seams are split into appended vertex copies (mesh_attributes.h).
  size_t copies = 0;
  Mesh split = splitAttributeSeams(input, &copies);
  setUvOrigin(split.attributes, UvOrigin::kBottom);  // PLY's v = 0: the image's bottom row
  const Mesh& mesh = split;
  const bool uvs = mesh.attributes.hasUvs(), normals = mesh.attributes.hasNormals();
  const bool ascii = encoding == PlyEncoding::kAscii;
  std::string out = "ply\nformat ";
  out += ascii ? "ascii" : "binary_little_endian";
  out += " 1.0\ncomment 3DVO\n";
  if (copies > 0)
    out += "comment 3DVO: the last " + std::to_string(copies) + " of " +
           std::to_string(mesh.positions.size()) +
           " vertices are copies made at texture-coordinate or normal seams\n";
  out += "element vertex " + std::to_string(mesh.positions.size()) +
         "\nproperty double x\nproperty double y\nproperty double z\n";
  if (uvs) out += "property float u\nproperty float v\n";
  if (normals) out += "property float nx\nproperty float ny\nproperty float nz\n";
  out += "element face " + std::to_string(mesh.triangles.size()) +
         "\nproperty list uchar int vertex_indices\nend_header\n";
  if (ascii) {
    char buffer[32];
    auto number = [&](auto value, char after) {
      auto r = std::to_chars(buffer, buffer + sizeof buffer, value);
      out.append(buffer, r.ptr);
      out += after;
    };
    for (size_t v = 0; v < mesh.positions.size(); ++v) {
      const Vec3d& p = mesh.positions[v];
      for (int c = 0; c < 3; ++c)
        number(p[c], c < 2 || uvs || normals ? ' ' : '\n');
      if (uvs)
        for (int c = 0; c < 2; ++c)
          number(mesh.attributes.uvs[v][c], c < 1 || normals ? ' ' : '\n');
      if (normals)
        for (int c = 0; c < 3; ++c)
          number(mesh.attributes.normals[v][c], c < 2 ? ' ' : '\n');
    }
    for (const Triangle& t : mesh.triangles)
      out += "3 " + std::to_string(t[0]) + ' ' + std::to_string(t[1]) + ' ' + std::to_string(t[2]) +
             '\n';
    return out;
  }
  // Little-endian bytes whatever the host (the codec's hosts are little-endian; this does not
  // assume it).
  auto put = [&out](uint64_t bits, int bytes) {
    for (int i = 0; i < bytes; ++i)
      out += static_cast<char>((bits >> (8 * i)) & 0xFF);
  };
  auto putFloat = [&put](float f) {
    uint32_t bits;
    std::memcpy(&bits, &f, 4);
    put(bits, 4);
  };
  out.reserve(out.size() + mesh.positions.size() * (24 + 8 * uvs + 12 * normals) +
              mesh.triangles.size() * 13);
  for (size_t v = 0; v < mesh.positions.size(); ++v) {
    for (double c : mesh.positions[v]) {
      uint64_t bits;
      std::memcpy(&bits, &c, 8);
      put(bits, 8);
    }
    if (uvs)
      for (float c : mesh.attributes.uvs[v])
        putFloat(c);
    if (normals)
      for (float c : mesh.attributes.normals[v])
        putFloat(c);
  }
  for (const Triangle& t : mesh.triangles) {
    put(3, 1);
    for (uint32_t v : t)
      put(v, 4);
  }
  return out;
}

void writePly(const std::string& path, const Mesh& mesh, PlyEncoding encoding) {
  writeFileAtomic(path, formatPly(mesh, encoding));
}

}  // namespace tdvo
