"""Makes inputs/blob-walk/ from inputs/blob/: frame k of the blob moved by 0.6 * k along x, so
that the object (about 2.2 wide) walks across a path about four times its size (the object-fit
grid, GridFit object). Run from conformance/: python3 inputs/make_walk.py"""
import gzip
import os

os.makedirs("inputs/blob-walk", exist_ok=True)
for k in range(12):
    with gzip.open("inputs/blob/%04d.obj.gz" % k, "rt") as f:
        lines = f.read().split("\n")
    out = []
    for line in lines:
        if line.startswith("v "):
            x, y, z = (float(v) for v in line.split()[1:4])
            line = "v %r %r %r" % (x + 0.6 * k, y, z)
        out.append(line)
    # mtime 0: the same bytes on every run
    with open("inputs/blob-walk/%04d.obj.gz" % k, "wb") as raw:
        with gzip.GzipFile(fileobj=raw, mode="wb", mtime=0, filename="") as f:
            f.write("\n".join(out).encode())
