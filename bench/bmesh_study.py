#!/usr/bin/env python3
"""BD-rates of bench/bmesh_study.cpp's output (docs/prediction.md, "B meshes").

    build/bin/bmesh_study > /tmp/bmesh.csv
    /usr/bin/python3 bench/bmesh_study.py /tmp/bmesh.csv

Per sequence: the BD-rate of every variant against "P" (every frame a keyframe), PCHIP, quality
10·log10(4095² / MSE) with the MSE against the quantised input in grid units (the peak does not
change a BD-rate). MotionQuantStep 1 is left out: lossless P points (no error) have no finite
quality. Then each variant's points, step:bytes/dB.
"""
import csv
import math
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tools", "rd"))
from tdvo_rd.bdrate import bd_rate  # noqa: E402


def main(path):
    rows = [r for r in csv.DictReader(open(path)) if int(r["step"]) > 1]
    sequences = []
    for r in rows:
        if r["sequence"] not in sequences:
            sequences.append(r["sequence"])
    for s in sequences:
        by = {}
        for r in rows:
            if r["sequence"] != s:
                continue
            mse = float(r["sse"]) / float(r["values"])
            quality = 10 * math.log10(4095 ** 2 / max(mse, 1e-9))
            by.setdefault(r["variant"], []).append((float(r["bytes"]), quality, int(r["step"])))
        anchor = by["P"]
        line = s + ":"
        for variant, points in by.items():
            if variant == "P":
                continue
            b = bd_rate([p[0] for p in anchor], [p[1] for p in anchor],
                        [p[0] for p in points], [p[1] for p in points])
            line += " %s %+.1f%%" % (variant, b)
        print(line)
        for variant, points in by.items():
            print("   ", variant, " ".join("%d:%.0fB/%.1fdB" % (p[2], p[0], p[1]) for p in points))


if __name__ == "__main__":
    main(sys.argv[1])
