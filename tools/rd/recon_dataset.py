#!/usr/bin/python3
"""A dataset whose geometry is a 3dvo-recon reconstruction, for texture experiments.

Input: a 3DVO dataset (docs/dataset.md; e.g. `3dvo-import -i ../shared/data/multiview/uu-4cam
-o uu`) and the Output folder of a `3dvo-recon` run over frames 0 .. N-1 of the same cameras
(docs/reconstruction.md). Output: OUT/dataset.json, the input's cameras and files (paths made
absolute) with `frames.count` N and `meshes` set to OUT/recon/%04d.obj, and OUT/recon/ holding
the reconstruction's OBJ frames, goms.txt, report.txt and frames.csv (copied; the rest of the
recon output, e.g. encode.cfg with its absolute paths, is left out).

Checks, each failing with one error line: the reconstruction starts at dataset frame 0 (the
`source` column of frames.csv is the frame number), its GOM list tiles frames 0 .. N-1, and
every OBJ frame exists. Prints the GOM list, so that a texture sweep can code the same GOMs
(GOMSize when there is one, else the encoder's GOMListFile). Standard library only;
deterministic: the same input gives the same files.

  tools/rd/recon_dataset.py -i uu -r recon-uu -o uu-recon
"""

import argparse
import csv
import json
import os
import shutil
import sys

# dataset.json fields that name files (docs/dataset.md), per camera.
_CAMERA_FILE_FIELDS = ("images", "video", "masks", "background", "backgroundVideo")
_RECON_PATTERN = "%04d.obj"      # 3dvo-recon's default OutputMeshPattern


def fail(message):
    sys.exit("recon_dataset: error: " + message)


def read_gom_list(path):
    """(first, count) per GOM of a goms.txt (format: docs/reconstruction.md, "GOM list")."""
    try:
        with open(path, encoding="utf-8") as f:
            lines = f.read().splitlines()
    except OSError as e:
        fail("%s: cannot read (%s)" % (path, e.strerror))
    goms, expected = [], 0
    for number, line in enumerate(lines, 1):
        fields = line.split("#", 1)[0].split()
        if not fields:
            continue
        try:
            first, count = (int(x) for x in fields)
        except ValueError:
            fail("%s:%d: expected '<first frame> <frame count>'" % (path, number))
        if first != expected or count < 1:
            fail("%s:%d: GOM %d %d does not follow the previous one" % (path, number, first, count))
        goms.append((first, count))
        expected = first + count
    if not goms:
        fail("%s: no GOM listed" % path)
    return goms


def check_starts_at_frame_zero(path, frames):
    """3dvo-recon names its output files with the dataset's frame numbers and writes `source`,
    the dataset frame each came from; this script copies files 0 .. N-1, so the reconstruction
    must start at frame 0 (frame and source agree)."""
    try:
        with open(path, encoding="utf-8", newline="") as f:
            rows = list(csv.DictReader(f))
    except OSError as e:
        fail("%s: cannot read (%s)" % (path, e.strerror))
    if len(rows) != frames:
        fail("%s: %d frames, but goms.txt lists %d" % (path, len(rows), frames))
    for row in rows:
        if row.get("frame") != row.get("source"):
            fail("%s: output frame %s comes from dataset frame %s; reconstruct from frame 0 "
                 "(FirstFrame 0)" % (path, row.get("frame"), row.get("source")))


def absolute(folder, path):
    return path if os.path.isabs(path) else os.path.normpath(os.path.join(os.path.abspath(folder),
                                                                          path))


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("-i", "--input", required=True, help="dataset folder (dataset.json)")
    parser.add_argument("-r", "--recon", required=True, help="3dvo-recon Output folder")
    parser.add_argument("-o", "--output", required=True, help="dataset folder to write")
    args = parser.parse_args()

    name = os.path.join(args.input, "dataset.json")
    try:
        with open(name, encoding="utf-8") as f:
            dataset = json.load(f)
    except (OSError, ValueError) as e:
        fail("%s: cannot read (%s)" % (name, e))
    if dataset.get("frames", {}).get("first", 0) != 0:
        fail("%s: frames.first must be 0 (the recon/ files are numbered from 0)" % name)

    goms = read_gom_list(os.path.join(args.recon, "goms.txt"))
    frames = goms[-1][0] + goms[-1][1]
    if frames > dataset["frames"]["count"]:
        fail("%s: %d frames reconstructed, but the dataset has %d"
             % (args.recon, frames, dataset["frames"]["count"]))
    check_starts_at_frame_zero(os.path.join(args.recon, "frames.csv"), frames)

    os.makedirs(os.path.join(args.output, "recon"), exist_ok=True)
    names = [_RECON_PATTERN % k for k in range(frames)] + ["goms.txt", "report.txt", "frames.csv"]
    for file in names:
        source = os.path.join(args.recon, file)
        if not os.path.isfile(source):
            fail("%s: missing" % source)
        shutil.copyfile(source, os.path.join(args.output, "recon", file))

    for camera in dataset["cameras"]:
        for field in _CAMERA_FILE_FIELDS:
            if field in camera:
                camera[field] = absolute(args.input, camera[field])
    dataset["frames"]["count"] = frames
    dataset["meshes"] = "recon/" + _RECON_PATTERN
    dataset["description"] = ("%s; meshes: 3dvo-recon, frames 0 .. %d in %d GOM%s"
                              % (dataset.get("description", args.input), frames - 1, len(goms),
                                 "" if len(goms) == 1 else "s"))
    with open(os.path.join(args.output, "dataset.json"), "w", encoding="utf-8") as f:
        json.dump(dataset, f, indent=2)
        f.write("\n")
    print("recon_dataset: %d frames, GOMs (first, count): %s"
          % (frames, " ".join("%d,%d" % g for g in goms)))


if __name__ == "__main__":
    main()
