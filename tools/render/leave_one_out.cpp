#include "tools/render/leave_one_out.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <optional>

#include "common/core/error.h"
#include "common/core/file_io.h"
#include "common/core/progress.h"
#include "common/media/png_io.h"
#include "common/views/image.h"

namespace tdvo {

std::vector<LeaveOneOutRow> leaveOneOut(
    const Dataset& dataset, const FrameRange& frames, const RenderOptions& options,
    const std::string& renderFolder, bool overwrite, const std::vector<std::string>& inputs,
    const Dataset* reference,
    const std::function<void(const std::vector<LeaveOneOutRow>&)>& beforeCommit,
    const std::vector<CommittableOutput*>& commitWith) {
  const size_t n = dataset.cameras.size();
  std::vector<LeaveOneOutRow> rows(n);
  for (size_t i = 0; i < n; ++i)
    rows[i].camera = dataset.cameras[i].camera.name;
  std::vector<CameraFrames> cameraFrames;
  for (size_t i = 0; i < n; ++i)
    cameraFrames.emplace_back(dataset, i);
  std::vector<CameraFrames> referenceFrames;
  if (reference)
    for (size_t i = 0; i < n; ++i) {
      const Camera& own = dataset.cameras[i].camera;
      const size_t r = reference->cameraIndex(own.name);
      const Camera& other = reference->cameras[r].camera;
      check(other.width == own.width && other.height == own.height,
            "reference camera " + own.name + ": its images are " + std::to_string(other.width) +
                " x " + std::to_string(other.height) + ", the input's " +
                std::to_string(own.width) + " x " + std::to_string(own.height));
      referenceFrames.emplace_back(*reference, r);
    }
  std::optional<OutputFolder> files;
  if (!renderFolder.empty()) files.emplace(renderFolder, overwrite, inputs);
  Progress progress("3dvo-render: leave-one-out", static_cast<size_t>(frames.count) * n);
  size_t done = 0;
  for (int frame = frames.first; frame < frames.first + frames.count; ++frame) {
    const FrameViews views = loadFrameViews(dataset, cameraFrames, frame);
    const int referenceFrame = reference ? dataset.firstFrame + frame - reference->firstFrame : 0;
    if (reference)
      check(referenceFrame >= 0 && referenceFrame < reference->frameCount,
            "the reference dataset has no frame number " +
                std::to_string(dataset.firstFrame + frame));
    for (size_t h = 0; h < n; ++h) {
      std::vector<bool> others(n, true);
      others[h] = false;
      const Camera& camera = views.cameras[h];
      Image sources;
      const Image heldOut = renderView(views, camera, options, others, nullptr, &sources);
      const Image ownPose = renderView(views, camera, options);
      Image image = views.images[h], mask = views.masks[h];
      if (reference) {
        image = referenceFrames[h].frame(referenceFrame);
        mask = referenceFrames[h].hasMasks() ? referenceFrames[h].mask(referenceFrame) : Image();
      }
      if (mask.empty()) {  // no silhouette: compare where the mesh is drawn
        mask = Image(camera.width, camera.height, 1);
        for (size_t p = 0; p < mask.pixels.size(); ++p)
          mask.pixels[p] = ownPose.pixels[4 * p + 3];
      }
      LeaveOneOutRow& row = rows[h];
      const SquaredError e = maskedSquaredError(heldOut, image, mask);
      row.heldOut += e;
      row.ownPose += maskedSquaredError(ownPose, image, mask);
      row.heldOutSsim += maskedSsim(heldOut, image, mask);
      row.maskPixels += e.count / 3;
      for (size_t p = 0; p < mask.pixels.size(); ++p)
        if (mask.pixels[p] != 0 && isFallback(sources.pixels[p])) ++row.fallbackPixels;
      if (!renderFolder.empty()) {
        char name[32];
        // Named by the frame's number (as 3dvo-recon and 3dvo-dec name theirs), not its index.
        std::snprintf(name, sizeof name, "%04d.png", dataset.firstFrame + frame);
        const std::string folder = (std::filesystem::path(renderFolder) / camera.name).string();
        const std::vector<uint8_t> png = encodePng(heldOut);
        files->write((std::filesystem::path(folder) / name).string(), png.data(), png.size());
      }
      progress.tick(++done);
    }
  }
  if (beforeCommit) beforeCommit(rows);  // (e.g. staging the caller's CSV of these rows)
  std::vector<CommittableOutput*> outputs = commitWith;
  if (files) outputs.insert(outputs.begin(), &*files);
  commitAll(outputs);
  return rows;
}

namespace {

std::string psnrText(double psnr) {
  if (std::isinf(psnr)) return "inf";
  if (std::isnan(psnr)) return "-";
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.2f", psnr);
  return buffer;
}

std::string ssimText(double ssim) {
  if (std::isnan(ssim)) return "-";
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.4f", ssim);
  return buffer;
}

double fallbackPercent(const LeaveOneOutRow& r) {
  return r.maskPixels ? 100.0 * double(r.fallbackPixels) / double(r.maskPixels) : 0;
}

LeaveOneOutRow pooled(const std::vector<LeaveOneOutRow>& rows) {
  LeaveOneOutRow all;
  all.camera = "all";
  for (const LeaveOneOutRow& r : rows) {
    all.maskPixels += r.maskPixels;
    all.heldOut += r.heldOut;
    all.ownPose += r.ownPose;
    all.heldOutSsim += r.heldOutSsim;
    all.fallbackPixels += r.fallbackPixels;
  }
  return all;
}

}  // namespace

std::string formatLeaveOneOutTable(const std::vector<LeaveOneOutRow>& rows) {
  std::string out =
      "| held-out camera | mask pixels | PSNR from the other cameras (dB) | PSNR at own pose, all "
      "cameras (dB) | fallback pixels (%) | SSIM from the other cameras |\n"
      "|---|---:|---:|---:|---:|---:|\n";
  std::vector<LeaveOneOutRow> all = rows;
  all.push_back(pooled(rows));
  for (const LeaveOneOutRow& r : all) {
    char line[512];
    const bool total = &r == &all.back();
    std::snprintf(line, sizeof line, "| %s%s%s | %zu | %s | %s | %.2f | %s |\n", total ? "**" : "",
                  r.camera.c_str(), total ? "**" : "", r.maskPixels,
                  psnrText(r.heldOut.psnr()).c_str(), psnrText(r.ownPose.psnr()).c_str(),
                  fallbackPercent(r), ssimText(r.heldOutSsim.mean()).c_str());
    out += line;
  }
  return out;
}

std::string formatLeaveOneOutCsv(const std::vector<LeaveOneOutRow>& rows) {
  std::string out =
      "camera,mask_pixels,psnr_leave_one_out,psnr_own_pose,fallback_percent,ssim_leave_one_out\n";
  std::vector<LeaveOneOutRow> all = rows;
  all.push_back(pooled(rows));
  for (const LeaveOneOutRow& r : all) {
    char line[512];
    std::snprintf(line, sizeof line, "%s,%zu,%s,%s,%.4f,%s\n", r.camera.c_str(), r.maskPixels,
                  psnrText(r.heldOut.psnr()).c_str(), psnrText(r.ownPose.psnr()).c_str(),
                  fallbackPercent(r), ssimText(r.heldOutSsim.mean()).c_str());
    out += line;
  }
  return out;
}

}  // namespace tdvo
