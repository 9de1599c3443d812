// Helpers shared by the GoogleTest suites: unique temporary folders, small text/gzip file
// writers, generated deforming mesh sequences and running the apps as child processes.
// Header-only so that each suite stays one executable with no extra library.
#pragma once

#include <sys/wait.h>
#include <unistd.h>
#include <zlib.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "common/core/error.h"
#include "common/core/mesh.h"
#include "common/core/obj_io.h"
#include "tools/eval/sample_mesh.h"

namespace tdvo {
namespace test {

// A fresh folder under the system temp folder, removed with everything in it on destruction.
class TempDir {
 public:
  explicit TempDir(const std::string& tag) {
    static std::atomic<int> counter{0};
    const auto ticks = std::chrono::steady_clock::now().time_since_epoch().count();
    path_ = std::filesystem::temp_directory_path() /
            ("tdvo-" + tag + "-" + std::to_string(::getpid()) + "-" + std::to_string(counter++) +
             "-" + std::to_string(ticks));
    std::filesystem::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;

  const std::filesystem::path& path() const { return path_; }
  std::string file(const std::string& name) const { return (path_ / name).string(); }

 private:
  std::filesystem::path path_;
};

// The process's working folder set to `to` for the guard's lifetime, and restored when it ends,
// also when the code under test throws: the cases of one suite may share a process
// (TDVO_TEST_PER_SUITE), so a case must not leave the next in its folder.
class WorkingDirectory {
 public:
  explicit WorkingDirectory(const std::filesystem::path& to)
      : previous_(std::filesystem::current_path()) {
    std::filesystem::current_path(to);
  }
  ~WorkingDirectory() {
    std::error_code ignored;
    std::filesystem::current_path(previous_, ignored);
  }
  WorkingDirectory(const WorkingDirectory&) = delete;
  WorkingDirectory& operator=(const WorkingDirectory&) = delete;

 private:
  std::filesystem::path previous_;
};

// The Draco payload `p` (Edgebreaker) with its connectivity counts replaced: 11 header bytes,
// the traversal type, then num_encoded_vertices, num_faces, num_attribute_data,
// num_encoded_symbols, num_encoded_split_symbols (varints) and the rest, kept.
inline std::vector<uint8_t> withDracoCounts(const std::vector<uint8_t>& p, uint32_t vertices,
                                            uint32_t faces, uint32_t symbols) {
  if (p.size() < 12 || p[8] != 1)
    throw std::invalid_argument("withDracoCounts: not an Edgebreaker Draco payload");
  size_t pos = 12;
  auto readVarint = [&]() {
    uint64_t v = 0;
    for (int shift = 0;; shift += 7) {
      const uint8_t b = p.at(pos++);
      v |= uint64_t{b & 0x7Fu} << shift;
      if (!(b & 0x80)) return v;
    }
  };
  auto writeVarint = [](std::vector<uint8_t>& out, uint64_t v) {
    do {
      out.push_back(static_cast<uint8_t>((v & 0x7F) | (v > 0x7F ? 0x80 : 0)));
      v >>= 7;
    } while (v);
  };
  readVarint();
  readVarint();
  const uint8_t attributeData = p.at(pos++);
  readVarint();
  const uint64_t splits = readVarint();
  std::vector<uint8_t> out(p.begin(), p.begin() + 12);
  writeVarint(out, vertices);
  writeVarint(out, faces);
  out.push_back(attributeData);
  writeVarint(out, symbols);
  writeVarint(out, splits);
  out.insert(out.end(), p.begin() + static_cast<std::ptrdiff_t>(pos), p.end());
  return out;
}

inline void writeText(const std::string& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
  if (!out) throw std::runtime_error("test: cannot write " + path);
}

inline std::string readText(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("test: cannot read " + path);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

inline std::vector<uint8_t> readBytes(const std::string& path) {
  const std::string text = readText(path);
  return std::vector<uint8_t>(text.begin(), text.end());
}

inline void writeBytes(const std::string& path, const std::vector<uint8_t>& bytes) {
  writeText(path, std::string(bytes.begin(), bytes.end()));
}

// Writes `text` gzip-compressed through zlib.
inline void writeGz(const std::string& path, const std::string& text) {
  gzFile gz = gzopen(path.c_str(), "wb9");
  if (!gz) throw std::runtime_error("test: cannot create " + path);
  const int n = gzwrite(gz, text.data(), static_cast<unsigned>(text.size()));
  if (gzclose(gz) != Z_OK || n != static_cast<int>(text.size()))
    throw std::runtime_error("test: cannot write " + path);
}

// Non-empty lines of a text.
inline std::vector<std::string> lines(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line))
    if (!line.empty()) out.push_back(line);
  return out;
}

// The lines of a text that start with `prefix`.
inline std::vector<std::string> linesStartingWith(const std::string& text,
                                                  const std::string& prefix) {
  std::vector<std::string> out;
  for (const std::string& line : lines(text))
    if (line.rfind(prefix, 0) == 0) out.push_back(line);
  return out;
}

// Files in a folder (names only), sorted.
inline std::vector<std::string> listFolder(const std::filesystem::path& folder) {
  std::vector<std::string> names;
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(folder, ec))
    names.push_back(entry.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

// ---- Generated meshes ----

// `frames` frames of an icosphere (radius ~`radius`, centred at `centre`) breathing and
// wobbling over time: every vertex moves differently in every frame.
inline std::vector<Mesh> wobblingSphere(int subdivisions, int frames, double radius = 1.0,
                                        const Vec3d& centre = {0, 0, 0}) {
  const Mesh base = icosphere(subdivisions);
  std::vector<Mesh> out;
  for (int f = 0; f < frames; ++f) {
    Mesh m = base;
    const double phase = 0.45 * f;
    for (Vec3d& p : m.positions) {
      const double r = radius * (1.0 + 0.15 * std::sin(3 * p[0] + phase) * std::cos(2 * p[1]) +
                                 0.05 * std::sin(phase));
      p = {centre[0] + r * p[0] + 0.1 * f, centre[1] + r * p[1], centre[2] + r * p[2]};
    }
    out.push_back(std::move(m));
  }
  return out;
}

// Frames `first` .. `first` + `count` - 1 of horse-gallop from the shared data folder
// `sharedDir` (TDVO_SHARED_DATA_DIR); empty, with `missing` set to a message for a skip, when
// the data is not there.
inline std::vector<Mesh> sharedHorseFrames(const std::string& sharedDir, int first, int count,
                                           std::string& missing) {
  const std::string pattern = sharedDir + "/meshseq/horse-gallop/%04d.obj.gz";
  char name[4096];
  std::snprintf(name, sizeof name, pattern.c_str(), first);
  std::vector<Mesh> frames;
  if (!std::filesystem::exists(name)) {
    missing =
        "horse-gallop data not found (" + pattern + "); the generated-mesh round trips still ran";
    return frames;
  }
  for (int f = first; f < first + count; ++f) {
    std::snprintf(name, sizeof name, pattern.c_str(), f);
    frames.push_back(readObj(name));
  }
  return frames;
}

// What `f` throws as tdvo::Error, or "no error".
inline std::string errorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "no error";
}

// The largest extent of the frames' bounding box over all axes.
inline double extentOf(const std::vector<Mesh>& frames) {
  double lo[3] = {1e300, 1e300, 1e300}, hi[3] = {-1e300, -1e300, -1e300};
  for (const Mesh& m : frames)
    for (const Vec3d& p : m.positions)
      for (int c = 0; c < 3; ++c) {
        lo[c] = std::min(lo[c], p[c]);
        hi[c] = std::max(hi[c], p[c]);
      }
  return std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]});
}

// Gives `frames` texture coordinates and normals (issue 19 point 6). Texture coordinates are
// the same in every frame, made from the first frame's positions; with `perCorner` they are per
// corner with seams (every third triangle's first corner has a value of its own, appended), else
// per vertex. Normals are per vertex, each frame's own (area-weighted, as float), or with
// `constantNormals` the first frame's in every frame.
inline void addAttributes(std::vector<Mesh>& frames, bool perCorner, bool constantNormals = false) {
  const Mesh& first = frames[0];
  MeshAttributes uv;
  for (const Vec3d& p : first.positions)
    uv.uvs.push_back({static_cast<float>(0.5 + 0.5 * std::atan2(p[2], p[0]) / 3.14159265358979),
                      static_cast<float>(p[1] * 0.37 + 0.25)});
  uv.uvTriangles = first.triangles;
  if (perCorner)
    for (size_t t = 0; t < uv.uvTriangles.size(); t += 3) {
      const Vec2f base = uv.uvs[uv.uvTriangles[t][0]];
      uv.uvTriangles[t][0] = static_cast<uint32_t>(uv.uvs.size());
      uv.uvs.push_back({base[0] + 0.125f, base[1] - 1.0f / 3});
    }
  auto normalsOf = [](const Mesh& m) {
    std::vector<Vec3f> n(m.positions.size(), Vec3f{0, 0, 0});
    for (const Triangle& t : m.triangles) {
      const Vec3d &a = m.positions[t[0]], &b = m.positions[t[1]], &c = m.positions[t[2]];
      const double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
      const double w[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
      const double x[3] = {u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2],
                           u[0] * w[1] - u[1] * w[0]};
      for (uint32_t v : t)
        for (int k = 0; k < 3; ++k)
          n[v][k] += static_cast<float>(x[k]);
    }
    for (Vec3f& v : n) {
      const float l = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
      if (l > 0) v = {v[0] / l, v[1] / l, v[2] / l};
    }
    return n;
  };
  const std::vector<Vec3f> firstNormals = normalsOf(first);
  for (Mesh& m : frames) {
    m.attributes = uv;
    m.attributes.normals = constantNormals ? firstNormals : normalsOf(m);
    m.attributes.normalTriangles = m.triangles;
  }
}

// An nx × ny sheet of vertices (2 (nx-1)(ny-1) triangles) in the x/y plane with a travelling
// sine wave in z.
inline std::vector<Mesh> waveSheet(int nx, int ny, int frames) {
  Mesh base;
  for (int y = 0; y < ny; ++y)
    for (int x = 0; x < nx; ++x)
      base.positions.push_back({x * 0.1, y * 0.07, 0.0});
  for (int y = 0; y + 1 < ny; ++y)
    for (int x = 0; x + 1 < nx; ++x) {
      const uint32_t a = static_cast<uint32_t>(y * nx + x), b = a + 1,
                     c = a + static_cast<uint32_t>(nx), d = c + 1;
      base.triangles.push_back({a, b, d});
      base.triangles.push_back({a, d, c});
    }
  std::vector<Mesh> out;
  for (int f = 0; f < frames; ++f) {
    Mesh m = base;
    for (Vec3d& p : m.positions)
      p[2] = 0.3 * std::sin(6.0 * p[0] - 0.5 * f) * std::cos(4.0 * p[1] + 0.2 * f);
    out.push_back(std::move(m));
  }
  return out;
}

// ---- Child processes ----

struct CommandResult {
  int exitCode = -1;
  std::string out, err;
};

inline std::string shellQuote(const std::string& s) {
  std::string q = "'";
  for (char c : s) {
    if (c == '\'')
      q += "'\\''";
    else
      q += c;
  }
  return q + "'";
}

// Runs `command` through the shell in `folder`, capturing stdout and stderr. `args` are quoted.
inline CommandResult run(const TempDir& folder, const std::string& program,
                         const std::vector<std::string>& args) {
  static std::atomic<int> counter{0};
  const int n = counter++;
  const std::string outPath = (folder.path() / ("stdout." + std::to_string(n))).string();
  const std::string errPath = (folder.path() / ("stderr." + std::to_string(n))).string();
  std::string command = "cd " + shellQuote(folder.path().string()) + " && " + shellQuote(program);
  for (const std::string& a : args)
    command += " " + shellQuote(a);
  command += " >" + shellQuote(outPath) + " 2>" + shellQuote(errPath) + " </dev/null";
  const int status = std::system(command.c_str());
  CommandResult r;
  r.exitCode = (status != -1 && WIFEXITED(status)) ? WEXITSTATUS(status) : -1;
  r.out = readText(outPath);
  r.err = readText(errPath);
  std::filesystem::remove(outPath);
  std::filesystem::remove(errPath);
  return r;
}

}  // namespace test
}  // namespace tdvo
