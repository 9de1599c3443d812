#!/usr/bin/python3
"""Visual hull of a still multi-view dataset by voxel carving, for rendering tests.

Reads a 3DVO dataset (docs/dataset.md) with silhouettes (mask files or alphaMask), keeps the
voxels whose centre falls inside the silhouette of every camera that sees it (in front of the
camera and inside its image), and turns the kept voxels into a triangle mesh with marching cubes
(scikit-image) on the occupancy grown by one voxel and smoothed by a Gaussian of one voxel, at
level 0.5. Writes
OUT/hull.obj and OUT/dataset.json: the input dataset with absolute image paths and "meshes"
set to hull.obj. One frame (frame index 0) only: a stand-in for the reconstruction, good enough
to give the renderer a surface (the hull contains the object, so concavities are filled).

  tools/render/carve_hull.py -i lego -o lego-hull [--resolution 192]

Needs Debian's python3-numpy, python3-scipy and python3-skimage.
"""
import argparse
import json
import os
import sys

import numpy as np
from scipy import ndimage
from skimage import io, measure


def frame_path(folder, pattern, number):
    """A dataset path (pattern with one %d-style conversion, or a still file) made absolute."""
    path = pattern
    if "%" in pattern.replace("%%", ""):
        path = pattern % number
    path = path.replace("%%", "%")
    return path if os.path.isabs(path) else os.path.normpath(os.path.join(folder, path))


def load_dataset(folder):
    name = folder if folder.endswith(".json") else os.path.join(folder, "dataset.json")
    with open(name) as f:
        dataset = json.load(f)
    return dataset, os.path.dirname(os.path.abspath(name))


def silhouette(camera, folder, number):
    if camera.get("alphaMask"):
        image = io.imread(frame_path(folder, camera["images"], number))
        if image.ndim != 3 or image.shape[2] not in (2, 4):
            sys.exit("carve_hull: %s: alphaMask is set but the image has no alpha" %
                     camera["images"])
        return image[:, :, -1] >= 128
    if "masks" in camera:
        mask = io.imread(frame_path(folder, camera["masks"], number))
        return (mask if mask.ndim == 2 else mask[:, :, 0]) >= 128
    sys.exit("carve_hull: camera %s has no silhouette (masks or alphaMask)" % camera["name"])


def project(camera, points):
    """Pixel coordinates (pixel-centre convention, docs/cameras.md) and camera depth."""
    R = np.array(camera["R"], dtype=np.float64)
    t = np.array(camera["t"], dtype=np.float64)
    q = points @ R.T + t
    z = q[:, 2]
    safe = np.where(z > 0, z, 1.0)
    x, y = q[:, 0] / safe, q[:, 1] / safe
    k1, k2, p1, p2, k3 = camera.get("distortion", [0, 0, 0, 0, 0])
    r2 = x * x + y * y
    s = 1 + k1 * r2 + k2 * r2 * r2 + k3 * r2 * r2 * r2
    xd = x * s + 2 * p1 * x * y + p2 * (r2 + 2 * x * x)
    yd = y * s + p1 * (r2 + 2 * y * y) + 2 * p2 * x * y
    return camera["fx"] * xd + camera["cx"], camera["fy"] * yd + camera["cy"], z


def dilate(mask, radius):
    """The mask grown by a disc of `radius` pixels."""
    if radius <= 0:
        return mask
    y, x = np.mgrid[-radius:radius + 1, -radius:radius + 1]
    return ndimage.binary_dilation(mask, structure=x * x + y * y <= radius * radius)


def carve(cameras, masks, lo, hi, shape):
    """Occupancy of the voxel centres of the box [lo, hi] split into `shape` voxels: a voxel
    is kept when its centre falls inside every silhouette, each grown by the projected half
    diagonal of a voxel, so that every voxel that meets the object is kept."""
    voxel = np.max((hi - lo) / np.array(shape))
    middle = 0.5 * (lo + hi)
    grown = []
    for camera, mask in zip(cameras, masks):
        R, t = np.array(camera["R"]), np.array(camera["t"])
        distance = np.linalg.norm(middle + R.T @ t)  # from the camera centre −Rᵀt
        grown.append(dilate(mask, int(np.ceil(0.87 * voxel * camera["fx"] / distance))))
    masks = grown
    axes = [lo[i] + (np.arange(shape[i]) + 0.5) * (hi[i] - lo[i]) / shape[i] for i in range(3)]
    grid = np.stack(np.meshgrid(*axes, indexing="ij"), -1).reshape(-1, 3)
    keep = np.ones(len(grid), dtype=bool)
    seen_by_any = np.zeros(len(grid), dtype=bool)
    for camera, mask in zip(cameras, masks):
        at = np.flatnonzero(keep)
        u, v, z = project(camera, grid[at])
        i, j = np.rint(u).astype(np.int64), np.rint(v).astype(np.int64)
        h, w = mask.shape
        seen = (z > 0) & (i >= 0) & (j >= 0) & (i < w) & (j < h)
        inside = np.ones(len(u), dtype=bool)
        inside[seen] = mask[j[seen], i[seen]]
        seen_by_any[at[seen]] = True
        keep[at[~inside]] = False
    # Voxels no camera sees carry no evidence; of the rest keep the largest connected part.
    occupancy = (keep & seen_by_any).reshape(shape)
    labels, count = ndimage.label(occupancy)
    if count > 1:
        sizes = np.bincount(labels.ravel())
        sizes[0] = 0
        occupancy = labels == np.argmax(sizes)
    return occupancy


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("-i", "--input", required=True, help="dataset folder or dataset.json")
    parser.add_argument("-o", "--output", required=True, help="folder to write")
    parser.add_argument("--resolution", type=int, default=192,
                        help="voxels along the longest side of the object's box")
    args = parser.parse_args()

    dataset, folder = load_dataset(args.input)
    cameras = dataset["cameras"]
    number = dataset.get("frames", {}).get("first", 0)
    masks = [silhouette(c, folder, number) for c in cameras]

    # Start from a cube around the point nearest to every optical axis, half as wide as the
    # nearest camera is far, carve coarsely, then carve finely in the occupied box.
    centres, axes = [], []
    for c in cameras:
        R, t = np.array(c["R"]), np.array(c["t"])
        centres.append(-R.T @ t)
        axes.append(R[2])
    A = sum(np.eye(3) - np.outer(a, a) for a in axes)
    b = sum((np.eye(3) - np.outer(a, a)) @ p for a, p in zip(axes, centres))
    centre = np.linalg.solve(A, b)
    half = 0.5 * min(np.linalg.norm(p - centre) for p in centres)
    lo, hi = centre - half, centre + half
    coarse = carve(cameras, masks, lo, hi, (64, 64, 64))
    if not coarse.any():
        sys.exit("carve_hull: nothing is inside every silhouette")
    step = (hi - lo) / 64
    idx = np.argwhere(coarse)
    lo, hi = lo + (idx.min(0) - 2) * step, lo + (idx.max(0) + 3) * step
    voxel = (hi - lo).max() / args.resolution
    shape = tuple(int(np.ceil((hi[i] - lo[i]) / voxel)) for i in range(3))
    hi = lo + np.array(shape) * voxel
    occupancy = carve(cameras, masks, lo, hi, shape)

    # Grown by one voxel before smoothing, so that parts one voxel thin survive the smoothing
    # and the surface stays outside every kept voxel centre (the hull contains the silhouettes).
    grown = ndimage.binary_dilation(np.pad(occupancy, 2))
    field = ndimage.gaussian_filter(grown.astype(np.float32), 1.0)
    vertices, faces, _, _ = measure.marching_cubes(field, 0.5)
    vertices = lo + (vertices - 2 + 0.5) * voxel  # padded index → voxel centre → world

    os.makedirs(args.output, exist_ok=True)
    out_obj = os.path.join(args.output, "hull.obj")
    with open(out_obj + ".partial", "w") as f:
        f.write("# visual hull: tools/render/carve_hull.py, %d^3-voxel box side %.6g\n"
                % (args.resolution, voxel))
        for v in vertices:
            f.write("v %.6f %.6f %.6f\n" % tuple(v))
        for t in faces:
            f.write("f %d %d %d\n" % (t[0] + 1, t[1] + 1, t[2] + 1))
    os.replace(out_obj + ".partial", out_obj)

    for c in cameras:
        for key in ("images", "masks", "background", "video", "backgroundVideo"):
            if key in c and not os.path.isabs(c[key]):
                c[key] = os.path.normpath(os.path.join(folder, c[key]))
    dataset["meshes"] = "hull.obj"
    dataset["description"] = (dataset.get("description", "") +
                              "; visual hull by tools/render/carve_hull.py").lstrip("; ")
    out_json = os.path.join(args.output, "dataset.json")
    with open(out_json + ".partial", "w") as f:
        json.dump(dataset, f, indent=1)
        f.write("\n")
    os.replace(out_json + ".partial", out_json)
    print("carve_hull: %d x %d x %d voxels of %.4g, %d kept; %d vertices, %d triangles -> %s"
          % (shape[0], shape[1], shape[2], voxel, int(occupancy.sum()), len(vertices),
             len(faces), out_obj))


if __name__ == "__main__":
    main()
