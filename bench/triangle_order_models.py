#!/usr/bin/python3
"""How many bits the input's triangle order needs, under simple models (issue 17 point 1).

The VERTEX_ORDER unit codes the input's triangle list after the vertex order (docs/bitstream.md
section 4.1). This script estimates, for the first frame of each shared sequence, what a coder
that knows the vertex order would pay for the triangle order under a few context models, as
zeroth-order entropies of each model's symbols (an adaptive arithmetic coder lands near them):

  syntax   the VERTEX_ORDER model: the triangle's first vertex is one of the previous
           triangle's (3 choices) or a delta from its first vertex (magnitude class with context,
           low bits raw), then which of that vertex's remaining triangles it is
  edge     the same, with the remaining triangles at that vertex listed edge-neighbours of the
           previous triangle first
  two      the same, with the first vertex also taken from the triangle before the previous one
  cache    any vertex of the triangle found in a move-to-front cache of the last 32 vertices
           (its position), else the smallest vertex as a delta; then the triangle among that
           vertex's remaining ones, then its rotation
  bound    an arbitrary order and rotation: log2(T!) + T log2(3) bits

Figures: bits per triangle and per vertex. Usage: bench/triangle_order_models.py [DATA_DIR]
(default ../shared/data next to the repository); sequences not present are skipped, saying so.
"""
import collections
import gzip
import math
import os
import sys

SEQUENCES = [("horse-gallop", "0001.obj.gz"), ("samba", "mesh_0000.obj.gz"), ("pcow", "1.obj.gz")]


def load(path):
    vertices, triangles = 0, []
    with gzip.open(path, "rt") as f:
        for line in f:
            if line.startswith("v "):
                vertices += 1
            elif line.startswith("f "):
                triangles.append(tuple(int(x.split("/")[0]) - 1 for x in line.split()[1:4]))
    return vertices, triangles


def cost(counter):
    n = sum(counter.values())
    return -sum(c * math.log2(c / n) for c in counter.values()) if n else 0.0


def delta_cost(symbols, raw):
    return sum(cost(c) for c in symbols.values()) + raw


def syntax_model(triangles, variant):
    corners = collections.defaultdict(list)
    for i, t in enumerate(triangles):
        for k in range(3):
            corners[t[k]].append((t[(k + 1) % 3], t[(k + 2) % 3], i))
    for v in corners:
        corners[v].sort()
    done = [False] * len(triangles)
    reuse = collections.defaultdict(collections.Counter)
    classes = collections.defaultdict(collections.Counter)
    choice = collections.defaultdict(collections.Counter)
    raw = 0
    prev, prev2, ctx = (0, 0, 0), (0, 0, 0), 0
    for i, t in enumerate(triangles):
        candidates = [prev[0], prev[2], prev[1]]
        if variant == "two":
            candidates += [v for v in prev2 if v not in candidates]
        r = candidates.index(t[0]) if t[0] in candidates else len(candidates)
        reuse[ctx][r] += 1
        if r == len(candidates):
            d = t[0] - prev[0]
            c = abs(d).bit_length()
            classes[ctx][(c, d < 0)] += 1
            raw += max(0, c - 2)  # the top bit below the leading one has a context
            ctx = 1 + int(abs(d) > 32)
        else:
            ctx = 0
        a = t[0]
        remaining = [x for x in corners[a] if not done[x[2]]]
        if variant == "edge":
            shared = set(prev)
            remaining.sort(key=lambda x: (-(len({x[0], x[1], a} & shared) >= 2), x))
        if len(remaining) > 1:
            choice[min(len(remaining), 5)][[x[2] for x in remaining].index(i)] += 1
        done[i] = True
        prev2, prev = prev, t
    return sum(cost(c) for c in reuse.values()) + delta_cost(classes, raw) + sum(
        cost(c) for c in choice.values())


def cache_model(triangles, size=32):
    incident = collections.defaultdict(set)
    for i, t in enumerate(triangles):
        for v in t:
            incident[v].add(i)
    done = [False] * len(triangles)
    mtf = []
    hits, rotation = collections.Counter(), collections.Counter()
    misses = collections.defaultdict(collections.Counter)
    choice = collections.defaultdict(collections.Counter)
    raw, previous = 0, 0
    for i, t in enumerate(triangles):
        positions = [mtf.index(v) for v in t if v in mtf]
        if positions:
            hits[min(positions)] += 1
            pivot = mtf[min(positions)]
        else:
            hits["miss"] += 1
            pivot = min(t)
            d = pivot - previous
            c = abs(d).bit_length()
            misses[0][(c, d < 0)] += 1
            raw += max(0, c - 1)
        previous = pivot
        remaining = sorted(j for j in incident[pivot] if not done[j])
        if len(remaining) > 1:
            choice[min(len(remaining), 5)][remaining.index(i)] += 1
        done[i] = True
        rotation[t.index(pivot)] += 1
        for v in t:
            if v in mtf:
                mtf.remove(v)
            mtf.insert(0, v)
        del mtf[size:]
    return cost(hits) + delta_cost(misses, raw) + sum(cost(c) for c in choice.values()) + cost(
        rotation)


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    data = sys.argv[1] if len(sys.argv) > 1 else os.path.join(here, "..", "..", "shared", "data")
    print("%-13s %6s %6s  %s" % ("sequence", "V", "T", "bits per triangle (per vertex)"))
    for name, first in SEQUENCES:
        path = os.path.join(data, "meshseq", name, first)
        if not os.path.exists(path):
            print("%-13s skipped (%s not found)" % (name, path))
            continue
        vertices, triangles = load(path)
        n = len(triangles)
        figures = [("syntax", syntax_model(triangles, "syntax")),
                   ("edge", syntax_model(triangles, "edge")),
                   ("two", syntax_model(triangles, "two")),
                   ("cache", cache_model(triangles)),
                   ("bound", math.lgamma(n + 1) / math.log(2) + n * math.log2(3))]
        print("%-13s %6d %6d  " % (name, vertices, n) + "  ".join(
            "%s %.2f (%.1f)" % (label, bits / n, bits / vertices) for label, bits in figures))


if __name__ == "__main__":
    main()
