"""One rate-distortion job: encode -> decode -> metrics, and its cached result.

Two kinds (spec["kind"]): "geometry" measures the decoded meshes against the input OBJ frames;
"texture" decodes the camera textures too and measures object PSNR against the dataset's camera
frames, with the rate of the TEXTURE units (docs/rd.md, "Texture sweeps").

This module is what runs on the workers. It uses the standard library only and nothing else of
this package, because the Dask executor ships it to the workers by value (cloudpickle), so a
worker needs Python and the 3dvo binaries on the shared filesystem, not this package.

A job is described by a plain dict (the "spec", made by sweep.py) and returns a plain dict (the
"result"). Both are JSON-serialisable. The result of a successful job is also written, atomically,
to <results>/jobs/<key>.json; that file is the cache entry. A failed job is written to
<results>/failed/<key>.json for inspection and is not a cache entry (a rerun tries it again).
"""

import csv
import glob
import json
import math
import os
import re
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import threading
import time

RESULT_FORMAT = "3dvo-rd result 1"

# Lines of stderr kept in a failure report.
STDERR_TAIL_LINES = 20


class _ChildProcesses:
    """The child processes of the jobs running in this process, so that an interrupted local run
    can stop them (see cancel_all). Pickling gives a fresh, empty registry: the Dask executor ships
    this module by value and locks cannot be pickled."""

    def __init__(self):
        self.lock = threading.Lock()
        self.running = set()
        self.cancelled = threading.Event()

    def __reduce__(self):
        return (_ChildProcesses, ())


_children = _ChildProcesses()


class JobCancelled(Exception):
    """The run was interrupted (cancel_all) while this job was running."""


def cancel_all():
    """Stops every child process started by jobs of this process; their jobs raise JobCancelled."""
    _children.cancelled.set()
    with _children.lock:
        for process in list(_children.running):
            _kill_group(process)


def _kill_group(process):
    """Kills a child and whatever it started (it leads a process group of its own)."""
    try:
        os.killpg(process.pid, signal.SIGKILL)
    except OSError:
        pass


def result_path(results_dir, key):
    return os.path.join(results_dir, "jobs", key + ".json")


def failure_path(results_dir, key):
    return os.path.join(results_dir, "failed", key + ".json")


def read_result(results_dir, key):
    """The cached result of job `key`, or None when there is none (or it is unreadable)."""
    try:
        with open(result_path(results_dir, key), encoding="utf-8") as f:
            result = json.load(f)
    except (OSError, ValueError):
        return None
    if (not isinstance(result, dict) or result.get("format") != RESULT_FORMAT or
            result.get("key") != key):
        return None
    return result


def _replace_atomically(path, temp, f, write):
    """Calls write(f) on `f`, the open temporary file `temp` beside `path`, flushes it to disk
    and renames it to `path`: readers see either no file or the whole file, also when the
    writer is killed midway. On any failure the temporary file is removed."""
    try:
        with f:
            write(f)
            f.flush()
            os.fsync(f.fileno())
        os.replace(temp, path)
    except BaseException:
        try:
            os.unlink(temp)
        except OSError:
            pass
        raise


def write_json_atomic(path, value):
    """Writes a job result as JSON (_replace_atomically; the file is private, mode 0600, as
    mkstemp makes it)."""
    folder = os.path.dirname(path)
    os.makedirs(folder, exist_ok=True)
    fd, temp = tempfile.mkstemp(prefix=".tmp-", suffix=".json", dir=folder)

    def write(f):
        json.dump(value, f, indent=1, sort_keys=True)
        f.write("\n")

    _replace_atomically(path, temp, os.fdopen(fd, "w", encoding="utf-8"), write)


def write_atomic(path, write, binary=False):
    """Writes a file (a page, a CSV, a plot; _replace_atomically) by calling write(f), with the
    permissions a new file gets. The temporary name is new, created exclusively, so no file of
    that name is overwritten; the rename replaces `path` itself (a symbolic link there is
    replaced, its target is left alone)."""
    folder = os.path.dirname(os.path.abspath(path))
    os.makedirs(folder, exist_ok=True)
    while True:
        temp = os.path.join(folder, ".tmp-%s-%s" % (os.path.basename(path),
                                                    os.urandom(4).hex()))
        try:
            f = open(temp, "xb") if binary else open(temp, "x", encoding="utf-8", newline="")
            break
        except FileExistsError:
            continue
    _replace_atomically(path, temp, f, write)


def write_text_atomic(path, text):
    """Writes a text file atomically (write_atomic)."""
    write_atomic(path, lambda f: f.write(text))


class _StageFailed(Exception):
    def __init__(self, record):
        super().__init__(record["error"])
        self.record = record


def _tail(path, lines=STDERR_TAIL_LINES):
    try:
        with open(path, encoding="utf-8", errors="replace") as f:
            return "".join(f.readlines()[-lines:])
    except OSError:
        return ""


def _run_stage(stage, command, workdir, timeout):
    """Runs one command in workdir with stdout/stderr in <stage>.out/<stage>.err; returns the wall
    time in seconds. Raises _StageFailed on a non-zero exit, a crash (signal) or a timeout."""
    out_path = os.path.join(workdir, stage + ".out")
    err_path = os.path.join(workdir, stage + ".err")
    if _children.cancelled.is_set():
        raise JobCancelled()
    start = time.monotonic()
    with open(out_path, "wb") as out, open(err_path, "wb") as err:
        # A session of its own: a Ctrl-C on the terminal reaches the runner, which then stops the
        # children itself (cancel_all), instead of the children dying first and looking like
        # failed jobs.
        process = subprocess.Popen(
            command, cwd=workdir, stdout=out, stderr=err, stdin=subprocess.DEVNULL,
            start_new_session=True)
        with _children.lock:
            _children.running.add(process)
        try:
            try:
                returncode = process.wait(timeout=timeout)
                timed_out = False
            except subprocess.TimeoutExpired:
                _kill_group(process)
                returncode = process.wait()
                timed_out = True
        finally:
            with _children.lock:
                _children.running.discard(process)
    seconds = time.monotonic() - start
    if _children.cancelled.is_set():
        raise JobCancelled()
    if timed_out or returncode != 0:
        if timed_out:
            error = "timed out after %g s" % timeout
        elif returncode < 0:
            error = "killed by signal %d" % -returncode
        else:
            error = "exit code %d" % returncode
        raise _StageFailed({
            "stage": stage,
            "command": command,
            "returncode": returncode,
            "error": error,
            "stderr_tail": _tail(err_path) or _tail(out_path),
        })
    return seconds


def _parse_key_values(lines):
    """`Key : value` lines (the encoder's effective configuration and the apps' summaries).
    Comment lines are left out: the effective configuration prints a key the encoder derives
    while it is unset (e.g. GridBits, chosen by Quality) as `# Key : default  (not set: ...)`."""
    values = {}
    for line in lines:
        if ":" in line and not line.lstrip().startswith("#"):
            key, value = line.split(":", 1)
            values[key.strip()] = value.strip()
    return values


def parse_encoder_output(text):
    """(effective configuration, summary) dicts from 3dvo-enc's stdout."""
    config, summary, md5 = [], [], []
    section = None
    for line in text.splitlines():
        if line.startswith("# 3dvo-enc effective configuration"):
            section = config
        elif line.startswith("# summary"):
            section = summary
        elif line.startswith("MD5 "):
            md5.append(line)
            section = None
        elif not line.strip():
            section = None
        elif section is not None:
            section.append(line)
    return _parse_key_values(config), _parse_key_values(summary), md5


def _executor():
    """The Dask worker running this job (its address), or "local"."""
    if "distributed" in sys.modules:    # never imported by a local run
        try:
            return sys.modules["distributed"].get_worker().address
        except Exception:  # noqa: BLE001 - not inside a Dask task
            pass
    return "local"


def _number(text):
    """A metrics CSV cell: float, or None for an empty (undefined) or infinite cell (JSON has no
    infinity; the text keeps "inf")."""
    if text == "":
        return None
    value = float(text)
    return value if math.isfinite(value) else None


def _frame_rate(encoder_summary):
    """The frame rate the encoder used (FrameRate, or a Dataset's frames.rate), from its
    summary: the effective configuration holds FrameRate only when it was set."""
    return float(encoder_summary["frame rate"])


def _geometry_stages(spec, workdir, timeout, encoder_summary):
    """Decode the meshes, compare them with the input OBJ frames; the result's own fields."""
    binaries = spec["binaries"]
    reference = spec["reference"]
    decode_command = [binaries["3dvo-dec"], "-i", "stream.3dvo", "-o", "decoded",
                      "--verify", "encode.out"]
    decode_s = _run_stage("decode", decode_command, workdir, timeout)

    # Decoded frames come in the input's vertex order (syntax version 2, docs/bitstream.md
    # section 4.1): vertex i is reference vertex i, no matching (docs/metrics.md, "Vertex
    # correspondence").
    metrics_command = [
        binaries["3dvo-metrics"], "-r", reference["pattern"],
        "--ReferenceFirstFrame=%d" % reference["first_frame"],
        # The decoded files carry the input's frame numbers (3dvo-dec's default).
        "-t", os.path.join("decoded", "%04d.obj"),
        "--TestFirstFrame=%d" % reference["first_frame"],
        "--FrameCount=%d" % reference["frame_count"],
        "--Correspondence=identity",
        "--CsvFile=metrics.csv"]
    metrics_s = _run_stage("metrics", metrics_command, workdir, timeout)
    with open(os.path.join(workdir, "metrics.csv"), encoding="utf-8", newline="") as f:
        rows = list(csv.DictReader(f))
    frames = [row for row in rows if row["frame"] != "all"]
    summary_row = next(row for row in rows if row["frame"] == "all")

    stream_bytes = os.path.getsize(os.path.join(workdir, "stream.3dvo"))
    frame_count = len(frames)
    frame_rate = _frame_rate(encoder_summary)
    vertices = sum(int(row["reference_vertices"]) for row in frames)
    bits = 8.0 * stream_bytes
    metric_names = [name for name in summary_row
                    if name not in ("frame", "reference_frame", "test_frame",
                                    "reference_vertices", "test_vertices", "unit")]
    return {
        "frames": frame_count,
        "vertices": vertices,
        "bytes": stream_bytes,
        "frame_rate": frame_rate,
        # The same definitions as 3dvo-enc's summary (docs/user-guide.md), unrounded.
        "kbit_s": bits / 1000.0 * frame_rate / frame_count,
        "bits_per_vertex_frame": bits / vertices,
        # Exactly as 3dvo-metrics printed them (10 significant digits) and as numbers.
        "metrics_text": {name: summary_row[name] for name in metric_names},
        "metrics": {name: _number(summary_row[name]) for name in metric_names},
        "metrics_per_frame": [
            {name: row[name] for name in row if name != "unit"} for row in frames],
    }, decode_s, metrics_s


# The encoder summary's byte split: "bytes : N (headers h, I meshes i, P meshes p, textures t)".
_TEXTURE_BYTES = re.compile(r"\btextures (\d+)\)")


def _texture_stages(spec, workdir, timeout, encoder_summary, encode_command):
    """Decode meshes and textures (and the H.264 of each camera), compare the decoded camera
    frames with the dataset's; the result's own fields."""
    binaries = spec["binaries"]
    reference = spec["reference"]
    match = _TEXTURE_BYTES.search(encoder_summary.get("bytes", ""))
    if not match:
        raise _StageFailed({"stage": "encode", "command": encode_command, "returncode": 0,
                            "error": "no texture bytes in the encoder summary (is Dataset "
                            "set?)", "stderr_tail": encoder_summary.get("bytes", "")})
    texture_bytes = int(match.group(1))
    decode_command = [binaries["3dvo-dec"], "-i", "stream.3dvo", "-o", "decoded",
                      "--verify", "encode.out", "--extract-textures", "h264"]
    decode_s = _run_stage("decode", decode_command, workdir, timeout)
    h264_bytes = sum(os.path.getsize(p)
                     for p in glob.glob(os.path.join(workdir, "h264", "cam*.264")))

    metrics_command = [
        binaries["3dvo-metrics"], "--ReferenceDataset=" + reference["dataset"],
        "--ReferenceFirstFrame=%d" % reference["first_frame"],
        "--TestDataset=decoded", "--TestFirstFrame=0",
        "--FrameCount=%d" % reference["frame_count"], "--Bitstream=stream.3dvo",
        "--CsvFile=metrics.csv"]
    metrics_s = _run_stage("metrics", metrics_command, workdir, timeout)
    with open(os.path.join(workdir, "metrics.csv"), encoding="utf-8", newline="") as f:
        rows = list(csv.DictReader(f))
    pictures = [row for row in rows if row["frame"] != "all"]
    summary_row = next(row for row in rows if row["frame"] == "all" and row["camera"] == "all")
    cameras = len({row["camera"] for row in pictures})

    stream_bytes = os.path.getsize(os.path.join(workdir, "stream.3dvo"))
    frame_count = reference["frame_count"]
    frame_rate = _frame_rate(encoder_summary)
    seconds = frame_count / frame_rate
    metric_names = [name for name in summary_row
                    if name not in ("frame", "reference_frame", "test_frame", "camera",
                                    "frame_region")]
    return {
        "frames": frame_count,
        "cameras": cameras,
        "bytes": stream_bytes,
        "texture_bytes": texture_bytes,
        "h264_bytes": h264_bytes,
        "frame_rate": frame_rate,
        # The rate of the TEXTURE units, as 3dvo-enc's "texture kbit/s", unrounded; the H.264
        # streams alone; the whole stream.
        "kbit_s": 8.0 * texture_bytes / 1000.0 / seconds,
        "h264_kbit_s": 8.0 * h264_bytes / 1000.0 / seconds,
        "stream_kbit_s": 8.0 * stream_bytes / 1000.0 / seconds,
        "frame_region": summary_row["frame_region"],
        "metrics_text": {name: summary_row[name] for name in metric_names},
        "metrics": {name: _number(summary_row[name]) for name in metric_names},
        "metrics_per_frame": [
            {name: row[name] for name in row if name != "frame_region"} for row in pictures],
    }, decode_s, metrics_s


def run_job(spec):
    """Runs one job (see the module comment) and returns its result dict.

    The returned dict has "status": "ok" (also written to the cache), "cached" (the cache entry
    already existed and spec["force"] is false) or "failed" (with stage, command, error and
    stderr_tail). Raises JobCancelled when cancel_all() interrupts it."""
    key = spec["key"]
    results_dir = spec["results_dir"]
    if not spec.get("force"):
        cached = read_result(results_dir, key)
        if cached is not None:
            cached["status"] = "cached"
            return cached
    scratch = spec.get("scratch_dir") or None
    timeout = spec.get("timeout") or None
    binaries = spec["binaries"]
    base = {"format": RESULT_FORMAT, "key": key, "job": spec["record"],
            "host": socket.gethostname(), "executor": _executor()}
    try:
        if scratch:
            os.makedirs(scratch, exist_ok=True)
        workdir = tempfile.mkdtemp(prefix="3dvo-rd-" + key[:12] + "-", dir=scratch)
    except OSError as e:
        # A failure of this machine's scratch folder (a file, unwritable), in one line.
        result = dict(base)
        result.update({"status": "failed", "stage": "scratch", "command": [], "returncode": None,
                       "error": "cannot make a temporary folder in %s (%s)"
                       % (scratch or tempfile.gettempdir(), e.strerror or e),
                       "stderr_tail": ""})
        write_json_atomic(failure_path(results_dir, key), result)
        return result
    try:
        encode_command = ([binaries["3dvo-enc"]] + spec["encoder_args"] +
                          ["--BitstreamFile=stream.3dvo"])
        encode_s = _run_stage("encode", encode_command, workdir, timeout)
        with open(os.path.join(workdir, "encode.out"), encoding="utf-8") as f:
            encoder_text = f.read()
        config, encoder_summary, md5 = parse_encoder_output(encoder_text)
        if not md5:
            raise _StageFailed({"stage": "encode", "command": encode_command, "returncode": 0,
                                "error": "no MD5 lines in the encoder output",
                                "stderr_tail": encoder_text[-2000:]})

        if spec.get("kind", "geometry") == "texture":
            fields, decode_s, metrics_s = _texture_stages(spec, workdir, timeout,
                                                          encoder_summary, encode_command)
        else:
            fields, decode_s, metrics_s = _geometry_stages(spec, workdir, timeout,
                                                           encoder_summary)
        result = dict(base)
        result["status"] = "ok"
        result.update(fields)
        result.update({
            "encoder_config": config,
            "encoder_summary": encoder_summary,
            "md5": md5,
            "time": {"encode_s": encode_s, "decode_s": decode_s, "metrics_s": metrics_s},
        })
        write_json_atomic(result_path(results_dir, key), result)
        try:
            os.unlink(failure_path(results_dir, key))
        except OSError:
            pass
        return result
    except _StageFailed as failure:
        result = dict(base)
        result.update({"status": "failed"}, **failure.record)
        write_json_atomic(failure_path(results_dir, key), result)
        return result
    finally:
        # Decoded OBJ frames are large: never keep them (spec "keep_workdir" is for debugging).
        if not spec.get("keep_workdir"):
            shutil.rmtree(workdir, ignore_errors=True)
