// Importers: calibrated multi-view data in the formats it is published in, turned into the 3DVO
// dataset layout (common/media/dataset.h). Each importer only reads calibration and file names; the
// images and videos stay where they are and the dataset refers to them.
#pragma once

#include <string>

#include "common/media/dataset.h"

namespace tdvo {

enum class ImportFormat { automatic, dataset, middlebury, opencv, nerf };

struct ImportOptions {
  ImportFormat format = ImportFormat::automatic;
  // OpenCV camera folders: the video files looked for beside each calibration file.
  std::string video = "video.avi";
  std::string backgroundVideo = "background.avi";
  // OpenCV camera folders: an image sequence pattern (e.g. "%04d.png") beside each calibration
  // file, used instead of a video when set; numbering starts at 0 or 1.
  std::string images;
  // The world's up direction as "x,y,z" (empty: unknown).
  std::string up;
};

// Middlebury multi-view stereo `*_par.txt`: a view count, then per view
// `name k11 … k33 r11 … r33 t1 t2 t3` with P = K [R | t] (Seitz et al. 2006). One still frame;
// the images (named in the file, beside it) give the image size.
Dataset importMiddlebury(const std::string& parFile);

// OpenCV FileStorage XML calibration: CameraMatrix (3×3), DistortionCoeffs (k1 k2 p1 p2 [k3]),
// Rotation (Rodrigues 3-vector or 3×3 matrix), Translation (3-vector), P = K [R | t].
// `input` is one XML file or a folder whose sub-folders each hold one XML file (one camera per
// sub-folder, named after it, in name order). A video named options.video beside the XML file
// becomes the camera's frames (and gives the image size, frame rate and frame count), one named
// options.backgroundVideo its background. With options.images set, that image sequence is used
// instead (frame count: the files present in every camera folder).
Dataset importOpenCv(const std::string& input, const ImportOptions& options);

// NeRF `transforms*.json`: camera_angle_x (or fl_x/fl_y/cx/cy/w/h), per frame a file_path and a
// camera-to-world transform_matrix in OpenGL axes (converted with setFromOpenGlCameraToWorld).
// Principal point at (w/2, h/2) unless cx, cy are given. Images with alpha get alphaMask.
Dataset importNerf(const std::string& transformsFile);

// Recognises the format of `input` (a file or a folder): dataset.json (an existing 3DVO
// dataset), *_par.txt, transforms*.json, *.xml or a folder holding one of them (for OpenCV: in
// its sub-folders). Throws Error saying what was looked for when nothing matches.
ImportFormat detectImportFormat(const std::string& input);

// Imports `input` in options.format (detected when automatic); an existing 3DVO dataset is read
// as it is. The result's paths are absolute or relative to its `folder`.
Dataset importAny(const std::string& input, const ImportOptions& options);

// Parses "x,y,z" (used for the up direction); `what` names the option in errors.
Vec3d parseVector3(const std::string& text, const std::string& what);
// The same for a direction (the world's up): also refuses the zero vector, naming `what`.
Vec3d parseDirection(const std::string& text, const std::string& what);

}  // namespace tdvo
