// Rendering quality by leaving one camera out: each held-out camera's viewpoint is rendered from
// the other cameras only and compared with that camera's real image, inside its mask; the same
// viewpoint rendered with all cameras (the camera's own texture included) is the sanity check.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "common/core/file_io.h"
#include "common/media/dataset.h"
#include "tools/render/masked_ssim.h"
#include "tools/render/view_renderer.h"

namespace tdvo {

struct LeaveOneOutRow {
  std::string camera;
  size_t maskPixels = 0;      // pixels compared, over all frames
  SquaredError heldOut;       // rendered from the other cameras
  SquaredError ownPose;       // rendered from all cameras
  SsimSum heldOutSsim;        // SSIM of the held-out render inside the mask (masked_ssim.h)
  size_t fallbackPixels = 0;  // mask pixels no other camera sees (fallback colours)
};

// Frame indices first .. first + count - 1 of a dataset, without a list of them (a dataset may
// declare up to 2^30 frames).
struct FrameRange {
  FrameRange(int first_, int count_) : first(first_), count(count_) {}
  int first, count;
  int operator[](size_t k) const { return first + static_cast<int>(k); }
};

// Evaluates every camera of `dataset` (frame indices `frames`) as held-out camera. The PSNR
// mask is the camera's silhouette (mask files or alpha) when it has one, else the pixels the
// rendered mesh covers. With a `reference` dataset, the held-out camera's image and mask are
// that dataset's camera of the same name at the same frame number (frames.first + index), e.g.
// `dataset` a decoded 3DVO (its mesh and decoded pictures are what the renderer uses) and
// `reference` the original captures; the cameras must have the same image size. When `renderFolder`
// is not empty the held-out renders are written there as <camera>/<frame number %04d>.png (an
// output folder: common/core/file_io.h, OutputFolder; a non-empty one is refused unless
// `overwrite`). `beforeCommit`, when given, is called with the rows before the folder is committed
// (a caller stages its other outputs there), and `commitWith` are committed with the folder
// (commitAll, common/core/file_io.h: all in place, or each as it was). Progress on stderr when it
// is a terminal.
std::vector<LeaveOneOutRow> leaveOneOut(
    const Dataset& dataset, const FrameRange& frames, const RenderOptions& options,
    const std::string& renderFolder = "", bool overwrite = false,
    const std::vector<std::string>& inputs = {}, const Dataset* reference = nullptr,
    const std::function<void(const std::vector<LeaveOneOutRow>&)>& beforeCommit = {},
    const std::vector<CommittableOutput*>& commitWith = {});

// A Markdown table: camera, pixels, leave-one-out PSNR, own-pose PSNR, % of the mask pixels
// that fell back (no other camera sees them), leave-one-out SSIM, and a last row pooling every
// camera (the SSIM there is the mean over all mask pixels of all frames and cameras).
std::string formatLeaveOneOutTable(const std::vector<LeaveOneOutRow>& rows);
// The same as CSV
// (camera,mask_pixels,psnr_leave_one_out,psnr_own_pose,fallback_percent,ssim_leave_one_out).
std::string formatLeaveOneOutCsv(const std::vector<LeaveOneOutRow>& rows);

}  // namespace tdvo
