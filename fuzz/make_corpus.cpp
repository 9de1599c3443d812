// fuzz_make_corpus SOURCE_DIR OUT_DIR: writes the seed corpus of every fuzz target, one folder
// per target (OUT_DIR/stream, units, imesh, pmesh, cfg, obj, ply, gltf, ...), from files in the
// source tree:
//
//   stream, units  every conformance stream (conformance/streams/*.3dvo), as it is
//   imesh, draco   every I-mesh unit's im_draco_payload of those streams
//   texture        the conformance streams with cameras, fuzz/seeds/texture/*
//   pmesh          every P-mesh unit's pm_cabac_payload, behind the 4-byte header that
//                  pmesh_fuzz.cpp reads (mode, quant step, octree depth of the unit's GOM)
//   cfg            cfg/**/*.cfg, conformance/cfg/*.cfg, fuzz/seeds/cfg/*
//   obj            frame 0 of each conformance input (decompressed), fuzz/seeds/obj/*
//   ply            frame 0 of each conformance input as binary and ascii PLY, and a hand-made
//                  big-endian file with properties and an element to skip
//   gltf           frame 0 of each conformance input as .gltf and .glb, and an animated .glb
//                  of its first four frames
//   dataset        fuzz/seeds/dataset/*
//   png            small PNGs of 1 to 4 channels written by encodePng
//   arrays         frame 0 of each conformance input as the numpy arrays arrays_fuzz.cpp reads
//                  (float64 positions, uint32 triangles)
//
// Seeds are generated rather than committed so that they follow the conformance streams when
// those are regenerated. Exit code 1 (one error line) on any problem.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "bitstream/syntax.h"
#include "bitstream/units.h"
#include "common/core/app.h"
#include "common/core/file_io.h"
#include "common/core/gltf_io.h"
#include "common/core/obj_io.h"
#include "common/core/ply_io.h"
#include "common/core/sequence.h"
#include "common/media/png_io.h"
#include "common/views/image.h"

using namespace tdvo;
namespace fs = std::filesystem;

namespace {

std::vector<fs::path> filesIn(const fs::path& folder, const std::string& extension,
                              bool recursive) {
  std::vector<fs::path> files;
  if (!fs::is_directory(folder)) return files;
  auto take = [&](const fs::directory_entry& entry) {
    if (entry.is_regular_file() && (extension.empty() || entry.path().extension() == extension))
      files.push_back(entry.path());
  };
  if (recursive) {
    for (const auto& entry : fs::recursive_directory_iterator(folder))
      take(entry);
  } else {
    for (const auto& entry : fs::directory_iterator(folder))
      take(entry);
  }
  std::sort(files.begin(), files.end());
  return files;
}

void write(const fs::path& path, const std::vector<uint8_t>& bytes) {
  writeFileAtomic(path.string(), bytes.data(), bytes.size());
}

void copyTo(const fs::path& file, const fs::path& folder, const std::string& name) {
  write(folder / name, readFileBytes(file.string()));
}

template <class T>
void parseUnitInto(const UnitView& unit, T& value) {
  ByteReader reader(unit.payload, unit.size, unit.describe(), unit.payloadOffset);
  transfer(reader, value);
  reader.expectEnd("the structure");
}

template <class T>
T parseUnit(const UnitView& unit) {
  T value;
  parseUnitInto(unit, value);
  return value;
}

// The I- and P-mesh payloads of one conformance stream.
int extractPayloads(const fs::path& streamPath, const fs::path& out) {
  const std::vector<uint8_t> stream = readFileBytes(streamPath.string());
  const std::string stem = streamPath.stem().string();
  UnitReader units(stream.data(), stream.size(), streamPath.string());
  UnitView unit;
  GomHeader gh;
  uint16_t syntaxVersion = kSyntaxVersion;
  int written = 0;
  while (units.next(unit)) {
    const std::string name = stem + "-unit" + std::to_string(unit.index);
    if (unit.type == static_cast<uint8_t>(UnitType::kGomHeader)) {
      gh = parseUnit<GomHeader>(unit);
    } else if (unit.type == static_cast<uint8_t>(UnitType::kSequenceHeader)) {
      const SequenceHeader sh = parseUnit<SequenceHeader>(unit);
      syntaxVersion = sh.sh_syntax_version;
      if (!sh.cameras.empty()) copyTo(streamPath, out / "texture", streamPath.filename().string());
    } else if (unit.type == static_cast<uint8_t>(UnitType::kIMesh)) {
      IMeshUnit im;
      im.syntaxVersion = syntaxVersion;
      parseUnitInto(unit, im);
      write(out / "imesh" / (name + ".draco"), im.im_draco_payload);
      write(out / "draco" / (name + ".draco"), im.im_draco_payload);
      ++written;
    } else if (unit.type == static_cast<uint8_t>(UnitType::kPMesh)) {
      const PMeshUnit pm = parseUnit<PMeshUnit>(unit);
      // A B mesh (a frame between keyframes) has its own quantiser.
      const bool keyframe = std::find(gh.keyframes.begin(), gh.keyframes.end(),
                                      pm.pm_frame - gh.gh_first_frame) != gh.keyframes.end();
      const uint16_t step = static_cast<uint16_t>(
          (hasBMeshes(gh) && !keyframe ? gh.gh_bmesh_quant_step : gh.gh_motion_quant_step) - 1);
      std::vector<uint8_t> seed = {
          static_cast<uint8_t>(gh.gh_pmesh_mode == static_cast<uint8_t>(PMeshMode::kAfxic)),
          static_cast<uint8_t>(step & 0xFF), static_cast<uint8_t>(step >> 8),
          gh.gh_max_octree_depth};
      seed.insert(seed.end(), pm.pm_cabac_payload.begin(), pm.pm_cabac_payload.end());
      write(out / "pmesh" / (name + ".pmesh"), seed);
      ++written;
    }
  }
  return written;
}

// A frame as the input of arrays_fuzz.cpp: float64 positions (element 1), uint32 triangles
// (element 8), 3 columns each, row-major, then the row count and the elements.
std::string arraysSeed(const Mesh& mesh) {
  std::string seed = {1, 8, 3, 3, 0};
  const uint32_t rows = static_cast<uint32_t>(mesh.positions.size());
  for (int i = 0; i < 4; ++i)
    seed += static_cast<char>(rows >> (8 * i));
  seed.append(reinterpret_cast<const char*>(mesh.positions.data()),
              mesh.positions.size() * sizeof(Vec3d));
  seed.append(reinterpret_cast<const char*>(mesh.triangles.data()),
              mesh.triangles.size() * sizeof(Triangle));
  return seed;
}

}  // namespace

int main(int argc, char** argv) {
  return runApp("fuzz_make_corpus", [&]() {
    check(argc == 3, "usage: fuzz_make_corpus SOURCE_DIR OUT_DIR");
    const fs::path source = argv[1], out = argv[2];
    for (const char* target : {"stream", "units", "imesh", "draco", "texture", "pmesh", "cfg",
                               "obj", "ply", "gltf", "dataset", "png", "arrays"}) {
      std::error_code ec;
      fs::remove_all(out / target, ec);
      makeDirectories((out / target).string());
    }

    const std::vector<fs::path> streams = filesIn(source / "conformance/streams", ".3dvo", false);
    check(!streams.empty(), (source / "conformance/streams").string() + ": no .3dvo streams");
    int payloads = 0;
    for (const fs::path& s : streams) {
      copyTo(s, out / "stream", s.filename().string());
      copyTo(s, out / "units", s.filename().string());
      payloads += extractPayloads(s, out);
    }

    int cfgs = 0;
    for (const fs::path& folder : {source / "cfg", source / "conformance/cfg"})
      for (const fs::path& f : filesIn(folder, ".cfg", true)) {
        std::string name = fs::relative(f, source).string();
        std::replace(name.begin(), name.end(), '/', '_');
        copyTo(f, out / "cfg", name);
        ++cfgs;
      }
    for (const fs::path& f : filesIn(source / "fuzz/seeds/cfg", "", false)) {
      copyTo(f, out / "cfg", "seed_" + f.filename().string());
      ++cfgs;
    }

    int objs = 0;
    for (const auto& entry : fs::directory_iterator(source / "conformance/inputs")) {
      const fs::path frame0 = entry.path() / "0000.obj.gz";
      if (!fs::exists(frame0)) continue;
      const std::string text = readFileMaybeGz(frame0.string());
      writeFileAtomic((out / "obj" / (entry.path().filename().string() + "-0000.obj")).string(),
                      text);
      ++objs;
    }
    // PLY and glTF seeds from the same frames (and the first four as an animation).
    int plys = 0, gltfs = 0;
    for (const auto& entry : fs::directory_iterator(source / "conformance/inputs")) {
      const std::string pattern = (entry.path() / "%04d.obj.gz").string();
      if (!fs::exists(framePath(pattern, 0))) continue;
      const std::string name = entry.path().filename().string();
      const Mesh frame0 = readObj(framePath(pattern, 0));
      writeFileAtomic((out / "ply" / (name + "-0000.ply")).string(), formatPly(frame0));
      writeFileAtomic((out / "ply" / (name + "-0000-ascii.ply")).string(),
                      formatPly(frame0, PlyEncoding::kAscii));
      writeFileAtomic((out / "gltf" / (name + "-0000.gltf")).string(),
                      formatGltf(frame0, GltfContainer::kGltf));
      writeFileAtomic((out / "gltf" / (name + "-0000.glb")).string(),
                      formatGltf(frame0, GltfContainer::kGlb));
      GltfAnimationWriter animation(25.0);
      for (int f = 0; f < 4 && fs::exists(framePath(pattern, f)); ++f)
        animation.add(f == 0 ? frame0 : readObj(framePath(pattern, f)));
      writeFileAtomic((out / "gltf" / (name + "-animation.glb")).string(), animation.finish());
      writeFileAtomic((out / "arrays" / (name + "-0000.bin")).string(), arraysSeed(frame0));
      plys += 2;
      gltfs += 3;
    }
    {
      // Big-endian, a skipped list and float before the indices, an element to skip.
      std::string be =
          "ply\nformat binary_big_endian 1.0\nelement vertex 3\nproperty float x\n"
          "property uchar red\nproperty int y\nproperty double z\nelement edge 1\n"
          "property short a\nelement face 1\nproperty list uchar short flags\n"
          "property list uchar uint vertex_indices\nend_header\n";
      const char vertex[] = {0x3f, char(0x80), 0, 0, 7, 0, 0, 0, 2, 0x40, 0, 0, 0, 0, 0, 0, 0};
      for (int v = 0; v < 3; ++v)
        be.append(vertex, sizeof vertex);
      be += std::string("\0\1\1\0\2\3", 6);
      const char indices[] = {0, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 2};
      be.append(indices, sizeof indices);
      writeFileAtomic((out / "ply" / "big-endian.ply").string(), be);
      ++plys;
    }
    for (const fs::path& f : filesIn(source / "fuzz/seeds/obj", "", false)) {
      copyTo(f, out / "obj", "seed_" + f.filename().string());
      ++objs;
    }
    for (const fs::path& f : filesIn(source / "fuzz/seeds/texture", "", false))
      copyTo(f, out / "texture", "seed_" + f.filename().string());
    int datasets = 0;
    for (const fs::path& f : filesIn(source / "fuzz/seeds/dataset", "", false)) {
      copyTo(f, out / "dataset", f.filename().string());
      ++datasets;
    }

    int pngs = 0;
    for (int channels = 1; channels <= 4; ++channels)
      for (int size : {1, 3, 16}) {
        Image image(size, size + 1, channels);
        for (size_t i = 0; i < image.pixels.size(); ++i)
          image.pixels[i] = static_cast<uint8_t>(i * 37 + channels);
        write(out / "png" / ("c" + std::to_string(channels) + "-" + std::to_string(size) + ".png"),
              encodePng(image));
        ++pngs;
      }
    std::printf(
        "fuzz_make_corpus: %zu streams, %d mesh payloads, %d cfg, %d obj, %d ply, %d gltf, "
        "%d dataset, %d png -> %s\n",
        streams.size(), payloads, cfgs, objs, plys, gltfs, datasets, pngs, out.c_str());
    return 0;
  });
}
