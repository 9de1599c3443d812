"""Shared set-up of the Python module's tests (ctest runs them: tools/python/CMakeLists.txt).

ctest gives the paths in the environment: PYTHONPATH (the built package), TDVO_SOURCE_DIR,
TDVO_BUILD_DIR, TDVO_BIN_DIR (3dvo-enc, 3dvo-dec of the same build), TDVO_PYTHON_SITE_PACKAGES
(where the install component goes). Run by hand from the checkout's root (defaults: build/,
build/bin/, the interpreter's platlib):

    PYTHONPATH=build/python /usr/bin/python3 -m pytest -p no:cacheprovider tools/python/tests
"""

import gzip
import os
import pathlib

import numpy as np

SOURCE_DIR = pathlib.Path(
    os.environ.get("TDVO_SOURCE_DIR", pathlib.Path(__file__).resolve().parents[3])).resolve()
BUILD_DIR = pathlib.Path(os.environ.get("TDVO_BUILD_DIR", SOURCE_DIR / "build")).resolve()
BIN_DIR = pathlib.Path(os.environ.get("TDVO_BIN_DIR", BUILD_DIR / "bin")).resolve()
CONFORMANCE = SOURCE_DIR / "conformance"
STREAMS = sorted((CONFORMANCE / "streams").glob("*.3dvo"))

# No stream found would make the parametrised tests vanish: fail instead.
assert STREAMS, f"no conformance streams in {CONFORMANCE / 'streams'}"


def md5_file_lines(stream):
    """The committed MD5 lines of a conformance stream (its .md5 file)."""
    text = stream.with_suffix(".md5").read_text()
    return [line for line in text.splitlines() if line.startswith("MD5 ")]


def app(name):
    path = BIN_DIR / name
    assert path.exists(), f"{path} is not built"
    return str(path)


def read_obj(path):
    """The v and f lines of a (gzip-compressed) OBJ file as float64 (N, 3) and int64 (M, 3)
    arrays: enough for the committed inputs, which hold triangles with plain indices."""
    opener = gzip.open if str(path).endswith(".gz") else open
    positions, triangles = [], []
    with opener(path, "rt") as f:
        for line in f:
            words = line.split()
            if not words or words[0].startswith("#"):
                continue
            if words[0] == "v":
                positions.append([float(w) for w in words[1:4]])
            elif words[0] == "f":
                corners = [int(w.split("/")[0]) for w in words[1:]]
                assert len(corners) == 3 and all(c > 0 for c in corners), line
                triangles.append([c - 1 for c in corners])
    return np.array(positions, dtype=np.float64), np.array(triangles, dtype=np.int64)


def read_cfg(path):
    """A cfg file as a dict of its keys (values as the text after ':')."""
    keys = {}
    for line in pathlib.Path(path).read_text().splitlines():
        line = line.split("#", 1)[0].strip()
        if line:
            key, value = line.split(":", 1)
            keys[key.strip()] = value.strip()
    return keys


def deforming_sequence(frames=10, seed=3):
    """A twisting, breathing torus as numpy arrays: float32 positions, uint32 triangles."""
    rows, columns = 12, 20
    u, v = np.meshgrid(np.linspace(0, 2 * np.pi, rows, endpoint=False),
                       np.linspace(0, 2 * np.pi, columns, endpoint=False), indexing="ij")
    i, j = np.meshgrid(np.arange(rows), np.arange(columns), indexing="ij")
    a = i * columns + j
    b = ((i + 1) % rows) * columns + j
    c = ((i + 1) % rows) * columns + (j + 1) % columns
    d = i * columns + (j + 1) % columns
    triangles = np.concatenate([np.stack([a, b, c], -1).reshape(-1, 3),
                                np.stack([a, c, d], -1).reshape(-1, 3)]).astype(np.uint32)
    noise = np.random.default_rng(seed).normal(0, 0.002, size=(frames, rows * columns, 3))
    sequence = []
    for k in range(frames):
        r = 0.3 + 0.05 * np.sin(k / 3 + 2 * v)
        twist = u + 0.1 * k * np.cos(v)
        x = (1 + r * np.cos(twist)) * np.cos(v)
        y = (1 + r * np.cos(twist)) * np.sin(v)
        z = r * np.sin(twist) + 0.02 * k
        p = np.stack([x, y, z], -1).reshape(-1, 3) + noise[k]
        sequence.append((p.astype(np.float32), triangles))
    return sequence
