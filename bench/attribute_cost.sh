#!/usr/bin/env bash
# Issue 19 point 6's figures: what texture coordinates and normals (ATTRIBUTES units) cost, on
# horse-gallop frames 1-8 (8431 vertices) given a spherical texture map (per vertex, made from
# frame 1: the same in every frame) and each frame's own area-weighted normals, as OBJ
# (v/vt/vn). Skipped, saying so, when ../shared/data is absent.
#
#   bench/attribute_cost.sh [BUILD_DIR]      (default: build)
#
# For intra GOMs (every frame's attributes coded) and one GOM of 8 d3dmc frames (texture
# coordinates once, normals computed by the decoder since they change), lossless and with
# UVQuantBits 12 / NormalQuantBits 10: the stream's bytes and those of its ATTRIBUTES units.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
root="$(cd "$here/.." && pwd)"
build="$(cd "${1:-$root/build}" && pwd)"
data="$root/../shared/data/meshseq/horse-gallop"
if [ ! -f "$data/0001.obj.gz" ]; then
  echo "attribute_cost.sh: $data/0001.obj.gz not found: skipped"
  exit 0
fi
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
python3 - "$data" "$tmp" <<'PY'
import gzip, math, sys
data, out = sys.argv[1], sys.argv[2]
def read(path):
    v, f = [], []
    for line in gzip.open(path, 'rt'):
        t = line.split()
        if t and t[0] == 'v':
            v.append(tuple(map(float, t[1:4])))
        elif t and t[0] == 'f':
            f.append(tuple(int(x.split('/')[0]) - 1 for x in t[1:4]))
    return v, f
v0, _ = read('%s/0001.obj.gz' % data)
c = [sum(p[i] for p in v0) / len(v0) for i in range(3)]
def uv(p):
    d = [p[i] - c[i] for i in range(3)]
    r = math.sqrt(sum(x * x for x in d)) or 1
    return (math.atan2(d[2], d[0]) / (2 * math.pi) + 0.5,
            math.acos(max(-1, min(1, d[1] / r))) / math.pi)
uvs = [uv(p) for p in v0]
for k in range(1, 9):
    v, f = read('%s/%04d.obj.gz' % (data, k))
    n = [[0.0] * 3 for _ in v]
    for a, b, e in f:
        u = [v[b][i] - v[a][i] for i in range(3)]
        w = [v[e][i] - v[a][i] for i in range(3)]
        x = [u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]]
        for q in (a, b, e):
            for i in range(3):
                n[q][i] += x[i]
    n = [tuple(x / (math.sqrt(sum(y * y for y in q)) or 1) for x in q) for q in n]
    with open('%s/%04d.obj' % (out, k), 'w') as o:
        o.write(''.join('v %r %r %r\n' % p for p in v))
        o.write(''.join('vt %.6g %.6g\n' % t for t in uvs))
        o.write(''.join('vn %.6g %.6g %.6g\n' % q for q in n))
        o.write(''.join('f %d/%d/%d %d/%d/%d %d/%d/%d\n' % ((a + 1,) * 3 + (b + 1,) * 3 + (e + 1,) * 3)
                        for a, b, e in f))
PY
printf "%-28s %-9s %9s %10s\n" coding values bytes attributes
for mode in "--PMeshMode=intra" "--PMeshMode=d3dmc --GOMSize=8"; do
  for quant in "" "--UVQuantBits=12 --NormalQuantBits=10"; do
    line="$("$build/bin/3dvo-enc" --InputMeshPattern="$tmp/%04d.obj" --FirstFrame=1 --FrameCount=8 \
      --GridBits=12 $mode $quant -o "$tmp/x.3dvo" 2>/dev/null | grep '^bytes')"
    total="$(echo "$line" | sed 's/^bytes *: *\([0-9]*\).*/\1/')"
    attributes="$(echo "$line" | sed 's/.*attributes \([0-9]*\).*/\1/')"
    label=exact
    [ -n "$quant" ] && label=UV12/N10
    printf "%-28s %-9s %9s %10s\n" "${mode#--}" "$label" "$total" "$attributes"
  done
done
