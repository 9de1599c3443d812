#!/usr/bin/env python3
"""Makes the conformance inputs with texture coordinates and normals from inputs/blob
(conformance/README.md):

  blob-uv      12 OBJ frames: per-corner texture coordinates (a spherical map with a seam where
               u wraps: corners across it get values of their own), the same in every frame;
               per-vertex normals (vn, indexed like the vertices), frame 0's in frames 0-5 and
               each frame's own in frames 6-11.
  blob-uv-ply  6 PLY frames (ascii): per-vertex s, t and nx, ny, nz, each frame's own.

Run from conformance/: python3 inputs/make_attributes.py
"""
import gzip
import math
import os


def read(path):
    v, f = [], []
    for line in gzip.open(path, 'rt'):
        t = line.split()
        if t and t[0] == 'v':
            v.append(tuple(float(x) for x in t[1:4]))
        elif t and t[0] == 'f':
            f.append(tuple(int(x.split('/')[0]) - 1 for x in t[1:4]))
    return v, f


def normals(v, f):
    n = [[0.0, 0.0, 0.0] for _ in v]
    for a, b, c in f:
        u = [v[b][i] - v[a][i] for i in range(3)]
        w = [v[c][i] - v[a][i] for i in range(3)]
        x = [u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]]
        for k in (a, b, c):
            for i in range(3):
                n[k][i] += x[i]
    out = []
    for q in n:
        length = math.sqrt(sum(c * c for c in q)) or 1.0
        out.append(tuple(c / length for c in q))
    return out


def uv(p, centre):
    d = [p[i] - centre[i] for i in range(3)]
    r = math.sqrt(sum(c * c for c in d)) or 1.0
    return (math.atan2(d[2], d[0]) / (2 * math.pi) + 0.5,
            math.acos(max(-1.0, min(1.0, d[1] / r))) / math.pi)


def main():
    frames = [read('inputs/blob/%04d.obj.gz' % k) for k in range(12)]
    v0, f0 = frames[0]
    centre = [sum(p[i] for p in v0) / len(v0) for i in range(3)]
    uvs, index, corners = [], {}, []
    for tri in f0:
        values = [uv(v0[x], centre) for x in tri]
        if max(u for u, _ in values) - min(u for u, _ in values) > 0.5:  # across the seam
            values = [(u + 1 if u < 0.5 else u, w) for u, w in values]
        ids = []
        for x, value in zip(tri, values):
            key = (x, value)
            if key not in index:
                index[key] = len(uvs)
                uvs.append(value)
            ids.append(index[key])
        corners.append(ids)
    n0 = normals(v0, f0)
    os.makedirs('inputs/blob-uv', exist_ok=True)
    for k, (v, f) in enumerate(frames):
        n = n0 if k < 6 else normals(v, f)
        with gzip.GzipFile('inputs/blob-uv/%04d.obj.gz' % k, 'wb', mtime=0) as out:
            text = ''.join('v %.17g %.17g %.17g\n' % p for p in v)
            text += ''.join('vt %.6g %.6g\n' % t for t in uvs)
            text += ''.join('vn %.6g %.6g %.6g\n' % q for q in n)
            for tri, ids in zip(f, corners):
                text += 'f ' + ' '.join('%d/%d/%d' % (x + 1, i + 1, x + 1)
                                        for x, i in zip(tri, ids)) + '\n'
            out.write(text.encode())
    os.makedirs('inputs/blob-uv-ply', exist_ok=True)
    for k, (v, f) in enumerate(frames[:6]):
        n = normals(v, f)
        header = ('ply\nformat ascii 1.0\nelement vertex %d\nproperty float x\nproperty float y\n'
                  'property float z\nproperty float s\nproperty float t\nproperty float nx\n'
                  'property float ny\nproperty float nz\nelement face %d\n'
                  'property list uchar int vertex_indices\nend_header\n' % (len(v), len(f)))
        body = ''.join('%.9g %.9g %.9g %.6g %.6g %.6g %.6g %.6g\n' % (p + uv(p, centre) + q)
                       for p, q in zip(v, n))
        body += ''.join('3 %d %d %d\n' % t for t in f)
        with gzip.GzipFile('inputs/blob-uv-ply/%04d.ply.gz' % k, 'wb', mtime=0) as out:
            out.write((header + body).encode())


main()
