"""Shared pieces of the 3dvo-rd tests: the binaries, small sample sequences, a counting encoder
wrapper, a small sweep, and running the 3dvo-rd script."""

import csv
import os
import shutil
import subprocess
import sys
import tempfile
import unittest

RD_DIR = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
REPO = os.path.dirname(os.path.dirname(RD_DIR))
SCRIPT = os.path.join(RD_DIR, "3dvo-rd")
BINARIES = ("3dvo-enc", "3dvo-dec", "3dvo-metrics", "3dvo-sample")


def bin_dir():
    """The built apps: TDVO_BIN_DIR (set by ctest), else <repo>/build/bin."""
    return os.environ.get("TDVO_BIN_DIR") or os.path.join(REPO, "build", "bin")


def require_binaries(test_case):
    missing = [b for b in BINARIES if not os.access(os.path.join(bin_dir(), b), os.X_OK)]
    if missing:
        raise unittest.SkipTest("the 3dvo apps are not built in %s (missing %s); build them or "
                                "set TDVO_BIN_DIR" % (bin_dir(), ", ".join(missing)))


def make_sequences(folder):
    """Two small deforming blobs (162 and 642 vertices, 8 frames) written by 3dvo-sample."""
    patterns = {}
    for name, subdivisions in (("blob2", 2), ("blob3", 3)):
        out = os.path.join(folder, name)
        subprocess.run([os.path.join(bin_dir(), "3dvo-sample"), "-o", out,
                        "--Subdivisions=%d" % subdivisions, "--FrameCount=8"], check=True,
                       stdout=subprocess.DEVNULL)
        patterns[name] = os.path.join(out, "%04d.obj")
    return patterns


def make_counting_bin_dir(folder, count_file, delay=0.0):
    """A bin folder whose 3dvo-enc appends a line to count_file (then waits `delay` seconds) and
    runs the real encoder; 3dvo-dec and 3dvo-metrics link to the real ones."""
    os.makedirs(folder, exist_ok=True)
    real = os.path.join(bin_dir(), "3dvo-enc")
    with open(os.path.join(folder, "3dvo-enc"), "w") as f:
        f.write("#!/bin/sh\necho x >> '%s'\nsleep %g\nexec '%s' \"$@\"\n"
                % (count_file, delay, real))
    os.chmod(os.path.join(folder, "3dvo-enc"), 0o755)
    for name in ("3dvo-dec", "3dvo-metrics"):
        os.symlink(os.path.join(bin_dir(), name), os.path.join(folder, name))
    return folder


def count_lines(path):
    try:
        with open(path) as f:
            return sum(1 for _ in f)
    except FileNotFoundError:
        return 0


def write_sweep(path, patterns, extra=""):
    """The test sweep: two sequences x two modes x three rate points = 12 jobs."""
    text = """
[sweep]
name = "test"
root = "%(repo)s"

[[sequence]]
name = "blob2"
pattern = "%(blob2)s"
frame_count = 8
set = { GOMSize = 8 }

[[sequence]]
name = "blob3"
pattern = "%(blob3)s"
frame_count = 8
set = { GOMSize = 4 }

[[mode]]
name = "intra"
label = "intra-only"
cfg = ["cfg/intra.cfg"]
settings = [ { GridBits = 8 }, { GridBits = 10 }, { GridBits = 12 } ]

[[mode]]
name = "d3dmc"
cfg = ["cfg/d3dmc-lossy.cfg"]
settings = [ { MotionQuantStep = 32 }, { MotionQuantStep = 8 }, { MotionQuantStep = 2 } ]

[report]
anchors = ["intra"]
""" % dict(repo=REPO, **patterns)
    with open(path, "w") as f:
        f.write(text + extra)
    return path


def rd_command(*args):
    return [sys.executable, SCRIPT] + list(args)


def run_rd(*args, check=True, **kwargs):
    """Runs 3dvo-rd; returns the CompletedProcess (output captured as text)."""
    result = subprocess.run(rd_command(*args), stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            text=True, **kwargs)
    if check and result.returncode != 0:
        raise AssertionError("3dvo-rd %s failed (%d):\n%s\n%s" % (
            " ".join(args), result.returncode, result.stdout, result.stderr))
    return result


def read_text(path):
    with open(path, encoding="utf-8") as f:
        return f.read()


def csv_rows(path, drop=("encode_s", "decode_s", "metrics_s")):
    """The rows of an rd.csv without the wall-clock columns."""
    with open(path, newline="") as f:
        return [{k: v for k, v in row.items() if k not in drop} for row in csv.DictReader(f)]


class TempDirTestCase(unittest.TestCase):
    """A test case with a fresh temporary folder per test (self.tmp)."""

    def setUp(self):
        self.tmp = tempfile.mkdtemp(prefix="3dvo-rd-test-")
        self.addCleanup(shutil.rmtree, self.tmp, True)
