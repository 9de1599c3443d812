#!/usr/bin/python3
"""A static visual hull as the geometry of a multi-camera video dataset, for texture experiments.

Input: a 3DVO dataset (docs/dataset.md) whose cameras have a `video` and a `backgroundVideo`
(e.g. `3dvo-import -i ../shared/data/multiview/uu-4cam -o uu`). Output: OUT/dataset.json, the
same cameras and videos (paths made absolute), with `meshes` set to OUT/hull.obj, one still mesh
used for every frame; and OUT/masks/<camera>.png, the silhouettes that made it.

How (the stand-in for tools/recon's reconstruction before it landed; cfg/rd/texture.toml now
uses tools/rd/recon_dataset.py):

1. Silhouettes of frame `--frame` by background subtraction: the background is the per-pixel
   median of the first `--background-frames` frames of the background video; a pixel is
   foreground when its largest RGB difference exceeds `--threshold`; then a morphological
   opening (3x3) removes noise, the connected components smaller than `--min-area` pixels are
   dropped, holes are filled and the mask is dilated by `--dilate` pixels (the calibration is
   approximate: a hull carved from undilated masks loses parts of the object).
2. Voxel carving: a voxel is kept when its centre projects (OpenCV camera model with lens
   distortion, as common/views/camera.h) inside the image and the silhouette of every camera. A first
   pass over `--search-box` at 4 x `--voxel` finds the object; the second carves its bounding
   box (grown by 2 coarse voxels) at `--voxel`. Only the largest 26-connected part is kept.
3. Surface: marching cubes (scikit-image) at level 0.5 of the occupancy smoothed by a Gaussian of
   one voxel.

Prints the intersection over union of each camera's silhouette with the hull's projection.
Needs Debian's python3-numpy, python3-scipy, python3-skimage and the ffmpeg tool. Deterministic:
the same input gives the same files.

  tools/rd/hull_dataset.py -i uu -o uu-hull --frame 0
"""

import argparse
import json
import os
import subprocess
import sys
import tempfile

import numpy as np
from scipy import ndimage
from skimage import io, measure


def fail(message):
    sys.exit("hull_dataset: error: " + message)


def read_frames(path, width, height, count):
    """The first `count` frames of a video as uint8 RGB arrays (through the ffmpeg tool)."""
    command = ["ffmpeg", "-v", "error", "-nostdin", "-i", path, "-frames:v", str(count),
               "-f", "rawvideo", "-pix_fmt", "rgb24", "-"]
    try:
        data = subprocess.run(command, check=True, stdout=subprocess.PIPE).stdout
    except (OSError, subprocess.CalledProcessError) as e:
        fail("%s: cannot decode (%s)" % (path, e))
    size = width * height * 3
    if len(data) < size * count:
        fail("%s: has fewer than %d frames of %dx%d" % (path, count, width, height))
    return np.frombuffer(data[:size * count], np.uint8).reshape(count, height, width, 3)


def silhouette(frame, background, args):
    difference = np.abs(frame.astype(np.int16) - background.astype(np.int16)).max(axis=2)
    mask = ndimage.binary_opening(difference > args.threshold, np.ones((3, 3), bool))
    labels, count = ndimage.label(mask)
    if count:
        areas = ndimage.sum(mask, labels, index=np.arange(1, count + 1))
        mask = np.isin(labels, 1 + np.flatnonzero(areas >= args.min_area))
    mask = ndimage.binary_fill_holes(mask)
    if args.dilate > 0:
        mask = ndimage.binary_dilation(mask, iterations=args.dilate)
    return mask


def project(camera, points):
    """Pixel coordinates (pixel centres at integers, docs/cameras.md) and a visibility flag."""
    R = np.array(camera["R"], float)
    t = np.array(camera["t"], float)
    q = points @ R.T + t
    z = q[:, 2]
    front = z > 1e-9
    x = np.where(front, q[:, 0] / np.where(front, z, 1), 0)
    y = np.where(front, q[:, 1] / np.where(front, z, 1), 0)
    k1, k2, p1, p2, k3 = (camera.get("distortion") or [0, 0, 0, 0, 0])
    r2 = x * x + y * y
    radial = 1 + k1 * r2 + k2 * r2 * r2 + k3 * r2 * r2 * r2
    xd = x * radial + 2 * p1 * x * y + p2 * (r2 + 2 * x * x)
    yd = y * radial + p1 * (r2 + 2 * y * y) + 2 * p2 * x * y
    # Far outside the field of view the polynomial folds back into the image: only trust points
    # whose radial factor is still positive and increasing (the distorted radius grows with r).
    slope = 1 + 3 * k1 * r2 + 5 * k2 * r2 * r2 + 7 * k3 * r2 * r2 * r2
    valid = front & (radial > 0) & (slope > 0)
    u = np.where(valid, camera["fx"] * xd + camera["cx"], -1)
    v = np.where(valid, camera["fy"] * yd + camera["cy"], -1)
    return u, v, valid


def inside_all(cameras, masks, points):
    keep = np.ones(len(points), bool)
    for camera, mask in zip(cameras, masks):
        u, v, valid = project(camera, points)
        i = np.rint(u).astype(np.int64)
        j = np.rint(v).astype(np.int64)
        valid &= (i >= 0) & (j >= 0) & (i < mask.shape[1]) & (j < mask.shape[0])
        hit = np.zeros(len(points), bool)
        hit[valid] = mask[j[valid], i[valid]]
        keep &= hit
    return keep


def carve(cameras, masks, lo, hi, step):
    """Occupancy of the voxel grid with corner `lo`, voxel size `step`, covering [lo, hi]."""
    shape = np.maximum(np.ceil((hi - lo) / step).astype(int), 1)
    axes = [lo[a] + step * (np.arange(shape[a]) + 0.5) for a in range(3)]
    gx, gy, gz = np.meshgrid(*axes, indexing="ij")
    points = np.stack([gx.ravel(), gy.ravel(), gz.ravel()], axis=1)
    return inside_all(cameras, masks, points).reshape(shape)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("-i", "--input", required=True, help="dataset folder or dataset.json")
    parser.add_argument("-o", "--output", required=True, help="output dataset folder")
    parser.add_argument("--frame", type=int, default=0, help="frame index of the silhouettes")
    parser.add_argument("--voxel", type=float, default=20.0, help="voxel size, world units")
    parser.add_argument("--search-box", type=float, nargs=6, metavar="X",
                        default=[-4000, -4000, -2500, 4000, 4000, 500],
                        help="xmin ymin zmin xmax ymax zmax of the first carving pass "
                        "(default: uu-4cam's room in mm)")
    parser.add_argument("--threshold", type=int, default=40,
                        help="foreground: largest RGB difference to the background above this")
    parser.add_argument("--background-frames", type=int, default=25)
    parser.add_argument("--min-area", type=int, default=400, help="smallest silhouette part, px")
    parser.add_argument("--dilate", type=int, default=4, help="silhouette dilation, px")
    args = parser.parse_args()

    name = args.input if args.input.endswith(".json") else os.path.join(args.input,
                                                                          "dataset.json")
    try:
        with open(name) as f:
            dataset = json.load(f)
    except (OSError, ValueError) as e:
        fail("%s: %s" % (name, e))
    folder = os.path.dirname(os.path.abspath(name))
    first = dataset.get("frames", {}).get("first", 0)
    cameras = dataset["cameras"]
    masks = []
    for camera in cameras:
        for key in ("video", "backgroundVideo"):
            if key not in camera:
                fail("%s: camera %s has no %s" % (name, camera["name"], key))
            camera[key] = os.path.normpath(os.path.join(folder, camera[key]))
        w, h = camera["width"], camera["height"]
        background = np.median(read_frames(camera["backgroundVideo"], w, h,
                                           args.background_frames), axis=0).astype(np.uint8)
        frame = read_frames(camera["video"], w, h, first + args.frame + 1)[-1]
        masks.append(silhouette(frame, background, args))

    search = np.array(args.search_box, float)
    coarse_step = 4 * args.voxel
    coarse = carve(cameras, masks, search[:3], search[3:], coarse_step)
    if not coarse.any():
        fail("no voxel of the search box projects into every silhouette")
    index = np.argwhere(coarse)
    lo = search[:3] + coarse_step * (index.min(axis=0) - 2)
    hi = search[:3] + coarse_step * (index.max(axis=0) + 3)
    occupancy = carve(cameras, masks, lo, hi, args.voxel)
    labels, count = ndimage.label(occupancy, np.ones((3, 3, 3), bool))
    sizes = ndimage.sum(occupancy, labels, index=np.arange(1, count + 1))
    occupancy = labels == 1 + int(np.argmax(sizes))

    field = ndimage.gaussian_filter(np.pad(occupancy, 2).astype(float), 1.0)
    vertices, faces, _, _ = measure.marching_cubes(field, 0.5)
    vertices = lo + args.voxel * (vertices - 2 + 0.5)

    os.makedirs(args.output, exist_ok=True)
    out_folder = os.path.abspath(args.output)
    lines = ["# visual hull of frame %d of %s (tools/rd/hull_dataset.py)\n" % (args.frame, name)]
    lines += ["v %.6f %.6f %.6f\n" % tuple(v) for v in vertices]
    lines += ["f %d %d %d\n" % tuple(f + 1) for f in faces]
    write_atomic(os.path.join(out_folder, "hull.obj"), "".join(lines))
    os.makedirs(os.path.join(out_folder, "masks"), exist_ok=True)
    for camera, mask in zip(cameras, masks):
        io.imsave(os.path.join(out_folder, "masks", camera["name"] + ".png"),
                  (mask * 255).astype(np.uint8), check_contrast=False)
    dataset["meshes"] = "hull.obj"
    dataset["description"] = ("static visual hull of frame %d (tools/rd/hull_dataset.py) with "
                              "the cameras and videos of: %s" % (args.frame,
                                                                 dataset.get("description", name)))
    write_atomic(os.path.join(out_folder, "dataset.json"), json.dumps(dataset, indent=2) + "\n")

    # How well the hull explains each silhouette.
    for camera, mask in zip(cameras, masks):
        hull_mask = np.zeros_like(mask)
        u, v, valid = project(camera, vertices)
        # The projected vertices of a dense hull mark its silhouette well enough for an IoU.
        i, j = np.rint(u[valid]).astype(int), np.rint(v[valid]).astype(int)
        keep = (i >= 0) & (j >= 0) & (i < mask.shape[1]) & (j < mask.shape[0])
        hull_mask[j[keep], i[keep]] = True
        hull_mask = ndimage.binary_fill_holes(ndimage.binary_closing(hull_mask, iterations=2))
        iou = (mask & hull_mask).sum() / max(1, (mask | hull_mask).sum())
        print("%s: silhouette %d px, hull %d px, IoU %.3f" % (camera["name"], mask.sum(),
                                                              hull_mask.sum(), iou))
    print("hull: %d vertices, %d triangles, voxel %g -> %s" % (len(vertices), len(faces),
                                                              args.voxel, out_folder))


def write_atomic(path, text):
    fd, temp = tempfile.mkstemp(prefix=".tmp-", dir=os.path.dirname(path))
    with os.fdopen(fd, "w") as f:
        f.write(text)
    os.replace(temp, path)


if __name__ == "__main__":
    main()
