// Texture metrics: the BT.601 conversion and PSNR of tools/eval/metrics.h against hand-computed
// values, and the texture mode of 3dvo-metrics on hand-made datasets and on real decoder output.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <limits>
#include <map>
#include <string>
#include <vector>

#include "common/core/error.h"
#include "common/media/dataset.h"
#include "common/media/png_io.h"
#include "common/views/image.h"
#include "test_support.h"
#include "tools/eval/metrics.h"

namespace tdvo {
namespace {

const std::string kBin = TDVO_BIN_DIR;

// PSNR of a constant grey-level error d on all three RGB channels: only Y' changes, by
// 219 d / 255 (Cb and Cr of grey are 128 whatever the level).
double greyStepPsnr(double d) {
  const double dy = 219.0 * d / 255.0;
  return 10.0 * std::log10(255.0 * 255.0 / (dy * dy));
}

TEST(Ycbcr601, PrimariesMatchTheStandardsTable) {
  // ITU-R BT.601 limited range: black 16/128/128, white 235/128/128, and the primaries.
  const std::vector<std::pair<std::array<uint8_t, 3>, std::array<double, 3>>> cases = {
      {{0, 0, 0}, {16, 128, 128}},           {{255, 255, 255}, {235, 128, 128}},
      {{255, 0, 0}, {81.481, 90.203, 240}},  {{0, 255, 0}, {144.553, 53.797, 34.214}},
      {{0, 0, 255}, {40.966, 240, 109.786}},
  };
  for (const auto& [rgb, expected] : cases) {
    const std::array<double, 3> got = rgbToYcbcr601(rgb[0], rgb[1], rgb[2]);
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(got[c], expected[c], 1e-3)
          << int(rgb[0]) << "," << int(rgb[1]) << "," << int(rgb[2]) << " component " << c;
  }
}

TEST(PictureError, MaskSelectsThePixelsAndPsnrFollowsTheMse) {
  Image reference(8, 4, 3, 100), test(8, 4, 4, 0), mask(8, 4, 1, 0);
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 8; ++x) {
      const bool inside = x < 3;  // 12 pixels with error 2, the rest with error 40
      for (int c = 0; c < 3; ++c)
        test.at(x, y, c) = inside ? 102 : 140;
      test.at(x, y, 3) = 255;
      mask.at(x, y) = inside ? 255 : 0;
    }
  const PictureError object = maskedPictureError(reference, test, mask);
  EXPECT_EQ(object.pixels, 12u);
  EXPECT_NEAR(*object.psnr(0), greyStepPsnr(2), 1e-9);
  EXPECT_TRUE(std::isinf(*object.psnr(1)));  // grey: no chroma error
  EXPECT_TRUE(std::isinf(*object.yuvPsnr()));

  // The region [2, 5) x [1, 10) clipped to the image: 3 x 3 pixels, 1 column inside the mask.
  const PictureError region = regionPictureError(reference, test, 2, 1, 5, 10);
  EXPECT_EQ(region.pixels, 9u);
  const double dy2 = 219.0 * 2 / 255, dy40 = 219.0 * 40 / 255;
  EXPECT_NEAR(*region.mse(0), (3 * dy2 * dy2 + 6 * dy40 * dy40) / 9, 1e-9);

  // Pooling adds squared errors and pixels, not PSNRs.
  PictureError pooled = object;
  pooled.add(region);
  EXPECT_EQ(pooled.pixels, 21u);
  EXPECT_NEAR(*pooled.mse(0), (15 * dy2 * dy2 + 6 * dy40 * dy40) / 21, 1e-9);

  // Nothing counted: no figures.
  const PictureError none = maskedPictureError(reference, test, Image(8, 4, 1, 0));
  EXPECT_EQ(none.pixels, 0u);
  EXPECT_FALSE(none.psnr(0).has_value());
  EXPECT_FALSE(none.yuvPsnr().has_value());
}

TEST(PictureError, YuvPsnrWeightsLumaSixToOne) {
  // Pure blue against black: every component has an error; the weighted mean is (6 Y + Cb + Cr)/8.
  const Image reference(4, 4, 3, 0);
  Image test(4, 4, 3, 0);
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 4; ++x)
      test.at(x, y, 2) = 255;
  const PictureError e = regionPictureError(reference, test, 0, 0, 4, 4);
  auto psnr = [](double d) { return 10.0 * std::log10(255.0 * 255.0 / (d * d)); };
  EXPECT_NEAR(*e.psnr(0), psnr(40.966 - 16), 1e-3);
  EXPECT_NEAR(*e.psnr(1), psnr(240 - 128), 1e-3);
  EXPECT_NEAR(*e.psnr(2), psnr(128 - 109.786), 1e-3);
  EXPECT_NEAR(*e.yuvPsnr(), (6 * *e.psnr(0) + *e.psnr(1) + *e.psnr(2)) / 8, 1e-12);
}

TEST(PictureError, RejectsImagesOfDifferentSizes) {
  EXPECT_THROW(regionPictureError(Image(4, 4, 3), Image(4, 5, 3), 0, 0, 4, 4), Error);
  EXPECT_THROW(maskedPictureError(Image(4, 4, 3), Image(4, 4, 3), Image(4, 4, 3)), Error);
  EXPECT_THROW(regionPictureError(Image(4, 4, 1), Image(4, 4, 1), 0, 0, 4, 4), Error);
}

// ---- The app ----

// The CSV of 3dvo-metrics' texture mode as rows of named cells.
std::vector<std::map<std::string, std::string>> readCsv(const std::string& path) {
  const std::vector<std::string> lines = test::lines(test::readText(path));
  auto split = [](const std::string& line) {
    std::vector<std::string> cells(1);
    for (char ch : line) {
      if (ch == ',')
        cells.emplace_back();
      else
        cells.back() += ch;
    }
    return cells;
  };
  std::vector<std::map<std::string, std::string>> rows;
  const std::vector<std::string> header = split(lines.at(0));
  for (size_t i = 1; i < lines.size(); ++i) {
    if (lines[i].empty()) continue;
    const std::vector<std::string> cells = split(lines[i]);
    EXPECT_EQ(cells.size(), header.size()) << lines[i];
    std::map<std::string, std::string> row;
    for (size_t k = 0; k < header.size() && k < cells.size(); ++k)
      row[header[k]] = cells[k];
    rows.push_back(row);
  }
  return rows;
}

// A one-camera dataset of `frames` images 16 x 8 written by `pixel(frame, x, y, rgba)`.
template <class Pixel>
void makeDataset(const test::TempDir& dir, const std::string& name, int frames, bool alpha,
                 Pixel pixel) {
  const std::string folder = dir.file(name);
  std::filesystem::create_directories(folder + "/cam");
  Dataset d;
  d.folder = folder;
  d.frameCount = frames;
  DatasetCamera c;
  c.camera.name = "cam";
  c.camera.width = 16;
  c.camera.height = 8;
  c.camera.fx = c.camera.fy = 20;
  c.camera.cx = 7.5;
  c.camera.cy = 3.5;
  c.images = "cam/%04d.png";
  c.alphaMask = alpha;
  d.cameras.push_back(c);
  writeDataset(d, folder);
  for (int f = 0; f < frames; ++f) {
    Image image(16, 8, alpha ? 4 : 3, 0);
    for (int y = 0; y < 8; ++y)
      for (int x = 0; x < 16; ++x) {
        std::array<uint8_t, 4> v = pixel(f, x, y);
        for (int ch = 0; ch < image.channels; ++ch)
          image.at(x, y, ch) = v[ch];
      }
    writePng(d.framePath(c.images, f), image);
  }
}

// --CsvFile naming an input (a dataset.json, a compared image; under another name or a link) is
// refused before anything is written, and the input is left as it was: it was replaced by the
// CSV table.
TEST(TextureMetricsApp, CsvFileThatIsAnInputIsRefused) {
  test::TempDir dir("texture-metrics-csv");
  makeDataset(dir, "ref", 2, false, [](int, int, int) {
    return std::array<uint8_t, 4>{100, 100, 100, 255};
  });
  makeDataset(dir, "dec", 2, true, [](int, int, int) {
    return std::array<uint8_t, 4>{100, 100, 100, 255};
  });
  std::filesystem::create_symlink("ref/cam/0001.png", dir.file("link.csv"));
  for (const std::string csv :
       {"ref/dataset.json", "./dec/../dec/dataset.json", "dec/cam/0000.png", "link.csv"}) {
    const std::string target = csv == "link.csv" ? "ref/cam/0001.png" : csv;
    const std::string before = test::readText(dir.file(target));
    const auto r = test::run(dir, kBin + "/3dvo-metrics",
                             {"--ReferenceDataset=ref", "--TestDataset=dec", "--CsvFile=" + csv});
    EXPECT_EQ(r.exitCode, 1) << csv;
    EXPECT_NE(r.err.find(csv + ": is the input "), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("refusing to overwrite it"), std::string::npos) << r.err;
    EXPECT_EQ(test::readText(dir.file(target)), before) << csv;
  }
  // Nor is any other file of the datasets: here a frame that is not compared.
  const std::string before = test::readText(dir.file("dec/cam/0001.png"));
  const auto r = test::run(dir, kBin + "/3dvo-metrics",
                           {"--ReferenceDataset=ref", "--TestDataset=dec", "--FrameCount=1",
                            "--CsvFile=dec/cam/0001.png"});
  EXPECT_EQ(r.exitCode, 1);
  EXPECT_NE(r.err.find("dec/cam/0001.png: is the input dec/cam/0001.png (frame 1 of "),
            std::string::npos)
      << r.err;
  EXPECT_EQ(test::readText(dir.file("dec/cam/0001.png")), before);
}

TEST(TextureMetricsApp, HandMadeDatasetsGiveTheClosedFormPsnr) {
  test::TempDir dir("texture-metrics");
  // Reference: grey 100. Test frame f: inside the shape (x < 4, alpha 255) grey 100 + 2 (f + 1),
  // outside grey 100 + 20 (alpha 0).
  makeDataset(dir, "ref", 3, false, [](int, int, int) {
    return std::array<uint8_t, 4>{100, 100, 100, 255};
  });
  makeDataset(dir, "dec", 2, true, [](int f, int x, int) {
    const uint8_t v = x < 4 ? static_cast<uint8_t>(100 + 2 * (f + 1)) : 120;
    return std::array<uint8_t, 4>{v, v, v, static_cast<uint8_t>(x < 4 ? 255 : 0)};
  });
  // Test frames 0, 1 against reference frames 1, 2; FrameCount 0 = as many as both have.
  const auto r = test::run(dir, kBin + "/3dvo-metrics",
                           {"--ReferenceDataset=ref", "--TestDataset=dec",
                            "--ReferenceFirstFrame=1", "--CsvFile=m.csv"});
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const auto rows = readCsv(dir.file("m.csv"));
  ASSERT_EQ(rows.size(), 4u);  // 2 frames, the camera over all frames, the total
  EXPECT_EQ(rows[0].at("reference_frame"), "1");
  EXPECT_EQ(rows[1].at("test_frame"), "1");
  EXPECT_EQ(rows[0].at("object_pixels"), "32");
  EXPECT_NEAR(std::stod(rows[0].at("object_y_psnr")), greyStepPsnr(2), 1e-7);
  EXPECT_NEAR(std::stod(rows[1].at("object_y_psnr")), greyStepPsnr(4), 1e-7);
  EXPECT_EQ(rows[1].at("frame_region"), "frame");
  EXPECT_EQ(rows[1].at("frame_pixels"), "128");
  const double k = 219.0 / 255;
  const double frameMse = (32 * std::pow(4 * k, 2) + 96 * std::pow(20 * k, 2)) / 128;
  EXPECT_NEAR(std::stod(rows[1].at("frame_y_psnr")), 10 * std::log10(255.0 * 255 / frameMse), 1e-7);
  // The total pools the squared errors of both frames.
  const auto& total = rows.back();
  EXPECT_EQ(total.at("frame"), "all");
  EXPECT_EQ(total.at("camera"), "all");
  EXPECT_EQ(total.at("object_pixels"), "64");
  const double objectMse = (32 * std::pow(2 * k, 2) + 32 * std::pow(4 * k, 2)) / 64;
  EXPECT_NEAR(std::stod(total.at("object_y_psnr")), 10 * std::log10(255.0 * 255 / objectMse), 1e-7);
  EXPECT_EQ(total.at("object_cb_psnr"), "inf");
  EXPECT_NE(r.out.find("object Y-PSNR"), std::string::npos);

  // Bad input: the test side must be decoder output (RGBA with the shape), with the same
  // cameras, enough frames, and meshes and datasets are not mixed.
  auto fails = [&](const std::vector<std::string>& args, const std::string& message) {
    const auto bad = test::run(dir, kBin + "/3dvo-metrics", args);
    EXPECT_EQ(bad.exitCode, 1) << bad.out;
    EXPECT_NE(bad.err.find(message), std::string::npos) << bad.err;
  };
  fails({"--ReferenceDataset=ref", "--TestDataset=ref"}, "no alpha shape");
  fails({"--ReferenceDataset=ref", "--TestDataset=dec", "--FrameCount=3"}, "have only 2");
  fails({"--ReferenceDataset=ref", "--TestDataset=dec", "-r", "a.obj", "-t", "b.obj"}, "not both");
  fails({"--ReferenceDataset=ref"}, "both ReferenceDataset and TestDataset");
  fails({"--ReferenceDataset=ref", "--TestDataset=dec", "--Bitstream=missing.3dvo"},
        "missing.3dvo");
  fails({"-r", "a.obj", "-t", "b.obj", "--Bitstream=s.3dvo"}, "Bitstream is for texture");
}

TEST(TextureMetricsApp, DecodedStreamsFromTheRig) {
  test::TempDir dir("texture-metrics-rig");
  auto ok = [&](const std::string& app, const std::vector<std::string>& args) {
    const auto r = test::run(dir, kBin + "/" + app, args);
    EXPECT_EQ(r.exitCode, 0) << app << ": " << r.err;
    return r;
  };
  ok("3dvo-synth", {"-o", "rig", "--Cameras=2", "--FrameCount=3", "--Width=96", "--Height=64"});
  std::map<std::string, std::map<std::string, std::string>> totals;
  for (const std::string run : {"bbox-qp22", "bbox-qp40", "full-qp22"}) {
    const std::string mode = run.substr(0, 4), qp = run.substr(7);
    ok("3dvo-enc", {"--Dataset=rig", "--FrameCount=3", "--GOMSize=3", "--TextureMode=" + mode,
                    "--TexturePadding=mb128", "--TextureQP=" + qp, "--TexturePreset=fast", "-o",
                    run + ".3dvo"});
    ok("3dvo-dec", {"-i", run + ".3dvo", "-o", run});
    ok("3dvo-metrics", {"--ReferenceDataset=rig", "--TestDataset=" + run,
                        "--Bitstream=" + run + ".3dvo", "--CsvFile=" + run + ".csv"});
    // The decoded dataset.json holds the texture boxes: no Bitstream needed (issue 17.3).
    const auto own = ok("3dvo-metrics", {"--ReferenceDataset=rig", "--TestDataset=" + run,
                                         "--CsvFile=" + run + "-own.csv"});
    EXPECT_EQ(test::readText(dir.file(run + "-own.csv")), test::readText(dir.file(run + ".csv")));
    EXPECT_NE(own.out.find("the texture box of each camera, from " + run + "/dataset.json"),
              std::string::npos)
        << own.out;
    const auto rows = readCsv(dir.file(run + ".csv"));
    ASSERT_EQ(rows.size(), 3u * 2u + 2u + 1u);
    totals[run] = rows.back();
    // Object pixels are exactly the decoded frames' alpha-255 pixels.
    const Dataset decoded = readDataset(dir.file(run));
    uint64_t opaque = 0;
    for (size_t c = 0; c < 2; ++c)
      for (int f = 0; f < 3; ++f) {
        const Image image = readPng(decoded.framePath(decoded.cameras[c].images, f));
        for (int y = 0; y < image.height; ++y)
          for (int x = 0; x < image.width; ++x)
            opaque += image.at(x, y, 3) == 255;
      }
    EXPECT_GT(opaque, 0u);
    EXPECT_EQ(rows.back().at("object_pixels"), std::to_string(opaque)) << run;
    EXPECT_EQ(rows.back().at("frame_region"), "box");
  }
  // The full box is the whole frame; the bbox one is smaller.
  EXPECT_EQ(totals["full-qp22"].at("frame_pixels"), std::to_string(96 * 64 * 2 * 3));
  EXPECT_LT(std::stoul(totals["bbox-qp22"].at("frame_pixels")), 96u * 64u * 2u * 3u);
  // A finer quantiser gives a higher object PSNR; both are plausible for H.264.
  const double fine = std::stod(totals["bbox-qp22"].at("object_y_psnr"));
  const double coarse = std::stod(totals["bbox-qp40"].at("object_y_psnr"));
  EXPECT_GT(fine, coarse + 3);
  EXPECT_GT(coarse, 20);
  EXPECT_LT(fine, 60);
}

}  // namespace
}  // namespace tdvo
