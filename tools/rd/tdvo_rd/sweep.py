"""The sweep file (TOML) and its expansion into jobs.

A sweep names sequences, coding modes and, per mode, a list of settings (rate points); every
sequence x mode x setting is one job. The format is documented in docs/rd.md; in short:

    [sweep]
    name = "geometry"
    root = "../.."                 # base of relative paths, relative to this file (default ".")
    cfg = ["cfg/base.cfg"]         # optional: cfg files for every job
    results = "build/rd-results/geometry"   # optional default for --results
    timeout = 3600                 # optional: seconds per encode / decode / metrics command

    [[sequence]]
    name = "samba"
    pattern = "../shared/data/meshseq/samba/mesh_%04d.obj.gz"
    first_frame = 0
    frame_count = 50
    frame_rate = 25
    cfg = ["cfg/per-sequence/samba.cfg"]    # optional
    set = { GOMSize = 25 }                   # optional

    [[mode]]
    name = "d3dmc"
    label = "D3DMC"                          # optional: name in tables and plots
    cfg = ["cfg/d3dmc-lossy.cfg"]
    set = { Lambda = -1 }                    # optional
    settings = [ { MotionQuantStep = 4 }, { MotionQuantStep = 16 } ]
    sequences = ["samba"]                    # optional: only these sequences

    [report]                                 # optional, see report.py
    anchors = ["intra"]

Texture sweeps (`kind = "texture"` in [sweep]) code camera videos: each sequence is a dataset
(docs/dataset.md) instead of a mesh pattern, optionally made by `prepare` commands when it does
not exist yet, and each job measures object PSNR (job.py):

    [[sequence]]
    name = "rig"
    dataset = "{results}/data/rig"           # folder holding dataset.json; {results}: the
                                             # results folder (derived data beside the cache)
    prepare = [["{bin}/3dvo-synth", "-o", "{dataset}", "--FrameCount=25"]]   # optional
    frame_count = 25
    pattern = "meshes/%04d.obj"              # optional: InputMeshPattern (default: the dataset's)

Encoder keys naming an input file (GOMListFile) are paths from the root, or "{dataset}/..." in
the sequence's dataset folder (e.g. the goms.txt of a 3dvo-recon dataset made by `prepare`);
the job gets the absolute path, and the cache key the file's content hash.

The encoder configuration of a job is the merge, later wins, of: [sweep].cfg, the sequence's cfg
and set, the mode's cfg and set, the setting, and last the sequence's input keys
(InputMeshPattern, FirstFrame, FrameCount, FrameRate). cfg files are read here with 3dvo-enc's
rules (`Key : value`, a `#` at the start or after a blank starts a comment) and the merged
result goes to the encoder as `--Key=value` options, so the job carries its whole configuration
and the cache key hashes exactly what the encoder receives.
"""

import hashlib
import json
import os
import tomllib

# Keys the runner sets itself or that name files written by the encoder.
_RESERVED_KEYS = ("BitstreamFile", "ReconMeshPattern")
_INPUT_KEYS = ("InputMeshPattern", "Dataset", "FirstFrame", "FrameCount", "FrameRate")
KEY_FORMAT = "3dvo-rd key 1"
# Encoder keys whose value names an input file: the path is taken from the sweep's root (or
# "{dataset}/..." from the sequence's dataset folder) and the cache key hashes the file's
# content instead of its name.
_FILE_KEYS = ("GOMListFile",)
BINARIES = ("3dvo-enc", "3dvo-dec", "3dvo-metrics")
KINDS = ("geometry", "texture")
# Placeholders of prepare commands (see prepare_datasets).
_PREPARE_FIELDS = ("bin", "root", "dataset", "work", "python")
# The dataset fields that name files (docs/dataset.md); the rest is calibration.
_DATASET_FILE_FIELDS = ("images", "video", "masks", "background", "backgroundVideo")


class SweepError(Exception):
    """A malformed sweep file or cfg file, or a missing input; the message names the place."""


def cfg_value(value):
    """A TOML value as the text of a cfg value."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float) and value.is_integer():
        return str(int(value))             # 25.0 -> "25"
    if isinstance(value, (int, float, str)):
        return str(value)
    raise TypeError("not a cfg value: %r" % (value,))


def _without_comment(line):
    """A cfg line without its comment, which starts at a '#' that begins the line or follows a
    space or tab (OptionTable's rule: a value such as take#2/%03d.obj keeps its '#')."""
    for i, c in enumerate(line):
        if c == "#" and (i == 0 or line[i - 1] in " \t"):
            return line[:i]
    return line


def read_cfg_file(path):
    """The (key, value) pairs of a 3dvo cfg file in file order, parsed like
    OptionTable::parseText: a UTF-8 byte-order mark is dropped, a comment runs from a '#' at the
    start or after a blank, then `Key : value` is split at the first colon, both trimmed."""
    try:
        with open(path, encoding="utf-8-sig") as f:
            lines = f.read().split("\n")
    except OSError as e:
        raise SweepError("%s: cannot read cfg file (%s)" % (path, e.strerror)) from None
    except ValueError as e:
        raise SweepError("%s: not UTF-8 text (%s)" % (path, e)) from None
    pairs = []
    for number, line in enumerate(lines, 1):
        line = _without_comment(line).strip(" \t\r")
        if not line:
            continue
        if ":" not in line:
            raise SweepError("%s:%d: expected 'Key : value'" % (path, number))
        key, value = line.split(":", 1)
        key = key.strip(" \t\r")
        if not key:
            raise SweepError("%s:%d: missing key before ':'" % (path, number))
        pairs.append((key, value.strip(" \t\r")))
    return pairs


def frame_path(pattern, number):
    """Frame `number` of a printf pattern with one %d, %Nd or %0Nd (as common/core/sequence.h)."""
    return pattern % number


class Sequence:
    def __init__(self, name, pattern, first_frame, frame_count, frame_rate, cfg, overrides,
                 kind="geometry", dataset=None, prepare=None):
        self.name = name
        self.pattern = pattern          # geometry: the OBJ frames; texture: optional mesh input
        self.first_frame = first_frame
        self.frame_count = frame_count
        self.frame_rate = frame_rate
        self.cfg = cfg
        self.overrides = overrides
        self.kind = kind
        self.dataset = dataset          # texture: the dataset folder (see Sweep.use_results)
        self.dataset_text = dataset     # as written in the sweep file
        self.prepare = prepare or []    # texture: commands (argv lists) that make the dataset

    def frame_paths(self):
        return [frame_path(self.pattern, self.first_frame + k) for k in range(self.frame_count)]

    def input_keys(self):
        keys = [("InputMeshPattern", self.pattern)] if self.pattern else []
        first = self.first_frame
        if self.kind == "texture":
            keys.append(("Dataset", self.dataset))
            # With a Dataset the encoder's FirstFrame is a frame number, frames.first + index.
            first += read_dataset(self).get("frames", {}).get("first", 0)
        keys += [("FirstFrame", str(first)), ("FrameCount", str(self.frame_count))]
        # Not set in a texture sweep: the encoder takes the dataset's frames.rate.
        if self.frame_rate is not None:
            keys.append(("FrameRate", cfg_value(self.frame_rate)))
        return keys


class Mode:
    def __init__(self, name, label, cfg, overrides, settings, sequences):
        self.name = name
        self.label = label
        self.cfg = cfg
        self.overrides = overrides
        self.settings = settings
        self.sequences = sequences


class Job:
    """One sequence x mode x setting, before execution (the spec is made by Sweep.specs)."""

    def __init__(self, sequence, mode, point, setting, config):
        self.sequence = sequence
        self.mode = mode
        self.point = point
        self.setting = setting          # list of (key, value text), the rate point's overrides
        self.config = config            # the merged encoder configuration, dict in merge order

    @property
    def setting_label(self):
        return " ".join("%s=%s" % kv for kv in self.setting) or "(base)"

    def record(self):
        """What a result and a CSV row say about the job."""
        return {"kind": self.sequence.kind, "sequence": self.sequence.name, "mode": self.mode.name,
                "mode_label": self.mode.label, "point": self.point,
                "setting": dict(self.setting), "setting_label": self.setting_label,
                "config": dict(self.config)}


class _Table:
    """A TOML table with the path to it, for error messages and unknown-key checks."""

    def __init__(self, file, where, table):
        if not isinstance(table, dict):
            raise SweepError("%s: %s must be a table" % (file, where))
        self.file, self.where, self.table = file, where, table
        self.used = set()

    def _fail(self, message):
        raise SweepError("%s: %s: %s" % (self.file, self.where, message))

    def get(self, key, kind, default=None, required=False):
        self.used.add(key)
        if key not in self.table:
            if required:
                self._fail("missing key '%s'" % key)
            return default
        value = self.table[key]
        if kind is float and isinstance(value, int) and not isinstance(value, bool):
            value = float(value)
        if not isinstance(value, kind) or (kind is int and isinstance(value, bool)):
            self._fail("'%s' must be %s" % (key, {str: "a string", int: "an integer",
                                                   float: "a number", list: "an array",
                                                   dict: "a table"}[kind]))
        return value

    def finish(self):
        unknown = sorted(set(self.table) - self.used)
        if unknown:
            self._fail("unknown key%s %s" % ("s" if len(unknown) > 1 else "",
                                              ", ".join("'%s'" % k for k in unknown)))


class Sweep:
    """A parsed sweep file. Relative paths in it are taken from `root` (see the module comment)."""

    def __init__(self, path):
        self.path = os.path.abspath(path)
        try:
            with open(self.path, "rb") as f:
                data = tomllib.load(f)
        except OSError as e:
            raise SweepError("%s: cannot read sweep file (%s)" % (path, e.strerror)) from None
        except tomllib.TOMLDecodeError as e:
            raise SweepError("%s: %s" % (path, e)) from None
        top = _Table(path, "top level", data)
        head = _Table(path, "[sweep]", top.get("sweep", dict, {}))
        self.name = head.get("name", str, os.path.splitext(os.path.basename(path))[0])
        self.root = os.path.normpath(os.path.join(os.path.dirname(self.path),
                                                  head.get("root", str, ".")))
        self.cfg = self._paths(head, "cfg")
        results = head.get("results", str)
        self.results = self.resolve(results) if results else None
        self.timeout = head.get("timeout", float, 0.0) or None
        self.kind = head.get("kind", str, "geometry")
        if self.kind not in KINDS:
            head._fail("kind must be one of %s" % ", ".join(KINDS))
        head.finish()

        self.sequences = []
        for i, table in enumerate(top.get("sequence", list, [])):
            t = _Table(path, "[[sequence]] %d" % (i + 1), table)
            name = t.get("name", str, required=True)
            t.where = "[[sequence]] '%s'" % name
            texture = self.kind == "texture"
            dataset = t.get("dataset", str)
            prepare = t.get("prepare", list, [])
            if not texture and (dataset is not None or prepare):
                t._fail("'dataset' and 'prepare' are for texture sweeps ([sweep] kind = "
                        "\"texture\")")
            dataset = t.get("dataset", str, required=texture)
            pattern = t.get("pattern", str, required=not texture)
            for command in prepare:
                if (not isinstance(command, list) or not command or
                        not all(isinstance(a, str) for a in command)):
                    t._fail("prepare must be an array of commands, each an array of strings")
            sequence = Sequence(
                name, self.resolve(pattern) if pattern else None,
                t.get("first_frame", int, 0), t.get("frame_count", int, required=True),
                t.get("frame_rate", float, None if texture else 25.0), self._paths(t, "cfg"),
                self._overrides(t, "set"), self.kind,
                self._dataset_path(dataset) if dataset else None, prepare)
            sequence.dataset_text = dataset
            if sequence.frame_count < 1:
                t._fail("frame_count must be at least 1")
            if (sequence.pattern is not None and
                    sequence.pattern.count("%") - 2 * sequence.pattern.count("%%") != 1):
                t._fail("pattern must hold one %d-style frame number conversion")
            t.finish()
            self.sequences.append(sequence)
        names = [s.name for s in self.sequences]
        if not names:
            top._fail("no [[sequence]]")
        if len(set(names)) != len(names):
            top._fail("two sequences share a name")

        self.modes = []
        for i, table in enumerate(top.get("mode", list, [])):
            t = _Table(path, "[[mode]] %d" % (i + 1), table)
            name = t.get("name", str, required=True)
            t.where = "[[mode]] '%s'" % name
            settings = []
            for j, setting in enumerate(t.get("settings", list, [{}])):
                if not isinstance(setting, dict):
                    t._fail("settings[%d] must be a table of cfg keys" % j)
                settings.append(self._pairs(t, setting, "settings[%d]" % j))
            only = t.get("sequences", list)
            for s in only or []:
                if s not in names:
                    t._fail("sequences: no sequence named '%s'" % s)
            self.modes.append(Mode(name, t.get("label", str, name), self._paths(t, "cfg"),
                                   self._overrides(t, "set"), settings, only))
            t.finish()
        if not self.modes:
            top._fail("no [[mode]]")
        if len({m.name for m in self.modes}) != len(self.modes):
            top._fail("two modes share a name")

        self.report = top.get("report", dict, {})
        self._report_table = _Table(path, "[report]", self.report)
        top.finish()

    def resolve(self, path):
        return os.path.normpath(os.path.join(self.root, path))

    _RESULTS = "{results}"

    def _dataset_path(self, path):
        """A dataset folder: relative to the root, or under the results folder when it starts
        with {results}/ (filled in by use_results, once the results folder is known)."""
        return path if path.startswith(self._RESULTS) else self.resolve(path)

    def use_results(self, results_dir):
        """Places the {results}/... datasets in `results_dir` (the --results folder)."""
        for sequence in self.sequences:
            if sequence.dataset and sequence.dataset_text.startswith(self._RESULTS):
                rest = sequence.dataset_text[len(self._RESULTS):].lstrip("/")
                sequence.dataset = os.path.normpath(os.path.join(os.path.abspath(results_dir),
                                                                 rest))

    def _input_file(self, value, sequence, key):
        """The absolute path of an input file named by an encoder key (see _FILE_KEYS)."""
        field = "{dataset}"
        if value.startswith(field):
            if not sequence.dataset:
                raise SweepError("%s: sequence '%s': %s = %s, but the sequence has no dataset"
                                 % (self.path, sequence.name, key, value))
            return os.path.normpath(os.path.join(sequence.dataset,
                                                 value[len(field):].lstrip("/")))
        return self.resolve(value)

    def _paths(self, table, key):
        paths = table.get(key, list, [])
        for p in paths:
            if not isinstance(p, str):
                table._fail("'%s' must be an array of file names" % key)
        return [self.resolve(p) for p in paths]

    def _pairs(self, table, values, where):
        pairs = []
        for key, value in values.items():
            if key in _RESERVED_KEYS or key in _INPUT_KEYS:
                table._fail("%s: %s is set by the runner (or by the [[sequence]] table)"
                            % (where, key))
            try:
                pairs.append((key, cfg_value(value)))
            except TypeError:
                table._fail("%s: %s must be a string, number or boolean" % (where, key))
        return pairs

    def _overrides(self, table, key):
        return self._pairs(table, table.get(key, dict, {}), key)

    def report_table(self):
        """The [report] table, for report.py (which checks its keys)."""
        return self._report_table

    def jobs(self):
        """All jobs in sweep order: sequences, then modes, then settings, as listed."""
        cfg_cache = {}

        def cfg_pairs(path):
            if path not in cfg_cache:
                cfg_cache[path] = read_cfg_file(path)
            return cfg_cache[path]

        jobs = []
        for sequence in self.sequences:
            if sequence.dataset and sequence.dataset.startswith(self._RESULTS):
                raise SweepError("%s: sequence '%s': dataset %s needs the results folder "
                                 "(Sweep.use_results)" % (self.path, sequence.name,
                                                          sequence.dataset))
            for mode in self.modes:
                if mode.sequences is not None and sequence.name not in mode.sequences:
                    continue
                for point, setting in enumerate(mode.settings):
                    pairs = []
                    for path in self.cfg + sequence.cfg:
                        pairs += cfg_pairs(path)
                    pairs += sequence.overrides
                    for path in mode.cfg:
                        pairs += cfg_pairs(path)
                    pairs += mode.overrides + setting + sequence.input_keys()
                    config = {}
                    for key, value in pairs:
                        if key not in _RESERVED_KEYS:
                            config[key] = value
                    for key in _FILE_KEYS:
                        if config.get(key):
                            config[key] = self._input_file(config[key], sequence, key)
                    jobs.append(Job(sequence, mode, point, setting, config))
        return jobs


def sha256_file(path):
    digest = hashlib.sha256()
    with open(path, "rb") as f:
        for block in iter(lambda: f.read(1 << 20), b""):
            digest.update(block)
    return digest.hexdigest()


class Identity:
    """Hashes of the binaries and inputs, each file hashed once per run."""

    def __init__(self, bin_dir):
        self.binaries = {}
        for name in BINARIES:
            path = os.path.join(bin_dir, name)
            if not os.access(path, os.X_OK):
                raise SweepError("%s: no such executable (build 3dvo first, or pass --bin-dir)"
                                 % path)
            self.binaries[name] = os.path.abspath(path)
        self.binary_hashes = {name: sha256_file(p) for name, p in self.binaries.items()}
        self._inputs = {}

    def input_hashes(self, sequence):
        if sequence.kind == "texture":
            if sequence.name not in self._inputs:
                self._inputs[sequence.name] = dataset_input_hashes(sequence)
            return self._inputs[sequence.name]
        if sequence.name not in self._inputs:
            hashes = []
            for path in sequence.frame_paths():
                try:
                    hashes.append(sha256_file(path))
                except OSError as e:
                    raise SweepError("sequence '%s': cannot read input frame %s (%s)"
                                     % (sequence.name, path, e.strerror)) from None
            self._inputs[sequence.name] = hashes
        return self._inputs[sequence.name]

    def key(self, job):
        """The cache key: sha256 of the binaries' contents, the merged encoder configuration (less
        the input path, which the input frames' content hashes replace; an input file key such as
        GOMListFile by its file's content hash) and the metrics options.
        Moving the data or the binaries keeps the key; changing a byte of either changes it."""
        config = {k: v for k, v in job.config.items() if k not in ("InputMeshPattern", "Dataset")}
        for key in _FILE_KEYS:
            if config.get(key):
                try:
                    config[key] = "sha256:" + sha256_file(config[key])
                except OSError as e:
                    raise SweepError("sequence '%s': cannot read %s %s (%s)"
                                     % (job.sequence.name, key, config[key], e.strerror)) from None
        material = {
            "format": KEY_FORMAT,
            "binaries": self.binary_hashes,
            "config": config,
            "inputs": self.input_hashes(job.sequence),
            "metrics": {"Correspondence": "identity"},
        }
        if job.sequence.kind == "texture":
            # Object PSNR of the decoded dataset, frame PSNR over the texture boxes (job.py).
            material["kind"] = "texture"
            material["metrics"] = {"texture": "object and box PSNR", "version": 1}
        text = json.dumps(material, sort_keys=True, separators=(",", ":"))
        return hashlib.sha256(text.encode("utf-8")).hexdigest()


def make_spec(job, identity, key, results_dir, timeout=None, scratch_dir=None, force=False):
    """The plain-dict job description that job.run_job takes."""
    sequence = job.sequence
    if sequence.kind == "texture":
        reference = {"dataset": sequence.dataset, "first_frame": sequence.first_frame,
                     "frame_count": sequence.frame_count}
    else:
        reference = {"pattern": sequence.pattern, "first_frame": sequence.first_frame,
                     "frame_count": sequence.frame_count}
    return {
        "kind": sequence.kind,
        "key": key,
        "results_dir": os.path.abspath(results_dir),
        "scratch_dir": scratch_dir,
        "timeout": timeout,
        "force": force,
        "binaries": identity.binaries,
        "encoder_args": ["--%s=%s" % kv for kv in job.config.items()],
        "reference": reference,
        "record": job.record(),
    }


def _dataset_path(folder, path, number):
    """A dataset file name (pattern with one frame conversion, or a still) made absolute, as
    Dataset::framePath (docs/dataset.md)."""
    if "%" in path.replace("%%", ""):
        path = path % number
    else:
        path = path.replace("%%", "%")
    return os.path.normpath(os.path.join(folder, path))


def read_dataset(sequence):
    """The dataset.json of a texture sequence, as a dict."""
    name = os.path.join(sequence.dataset, "dataset.json")
    try:
        with open(name, encoding="utf-8") as f:
            dataset = json.load(f)
    except OSError as e:
        raise SweepError("sequence '%s': cannot read %s (%s)%s" % (
            sequence.name, name, e.strerror,
            "; `3dvo-rd run` makes it with the sequence's prepare commands"
            if sequence.prepare else "")) from None
    except ValueError as e:
        raise SweepError("sequence '%s': %s: %s" % (sequence.name, name, e)) from None
    if not isinstance(dataset, dict) or not isinstance(dataset.get("frames", {}), dict):
        raise SweepError("sequence '%s': %s: not a dataset (no frames table)"
                         % (sequence.name, name))
    return dataset


def dataset_input_hashes(sequence):
    """What a texture job reads, by content: the dataset's calibration (dataset.json without its
    file names) and the SHA-256 of every file the encoder and the metrics read for the coded
    frames (each camera's images or its video, and the meshes, or the sequence's pattern)."""
    dataset = read_dataset(sequence)
    frames = dataset.get("frames", {})
    first = frames.get("first", 0)
    numbers = [first + sequence.first_frame + k for k in range(sequence.frame_count)]
    files = []
    for camera in dataset.get("cameras", []):
        if "video" in camera:
            files.append(_dataset_path(sequence.dataset, camera["video"], 0))
        elif "images" in camera:
            files += [_dataset_path(sequence.dataset, camera["images"], n) for n in numbers]
    if sequence.pattern:
        files += sequence.frame_paths()
    elif "meshes" in dataset:
        files += [_dataset_path(sequence.dataset, dataset["meshes"], n) for n in numbers]
    calibration = dict(dataset)
    calibration.pop("description", None)
    calibration.pop("meshes", None)
    calibration["cameras"] = [{k: v for k, v in c.items() if k not in _DATASET_FILE_FIELDS}
                              for c in dataset.get("cameras", [])]
    hashes = [hashlib.sha256(json.dumps(calibration, sort_keys=True).encode()).hexdigest()]
    digests = {}
    for path in files:
        if path not in digests:
            try:
                digests[path] = sha256_file(path)
            except OSError as e:
                raise SweepError("sequence '%s': cannot read %s (%s)"
                                 % (sequence.name, path, e.strerror)) from None
        hashes.append(digests[path])
    return hashes


def prepare_datasets(sweep, bin_dir, log):
    """Runs the prepare commands of each texture sequence whose dataset.json does not exist.

    The commands run in order in the sweep's root with these placeholders filled: {bin} the
    apps' folder, {root} the sweep root, {python} this Python, {dataset} a new folder beside the
    dataset's that becomes the dataset when every command succeeded (renamed; a failure leaves
    nothing), {work} a temporary folder removed afterwards. Returns the names prepared."""
    import shutil
    import subprocess
    import sys
    import tempfile

    prepared = []
    for sequence in sweep.sequences:
        if not sequence.prepare or os.path.exists(os.path.join(sequence.dataset,
                                                               "dataset.json")):
            continue
        if os.path.exists(sequence.dataset):
            raise SweepError("sequence '%s': %s exists but holds no dataset.json; remove it "
                             "to let the prepare commands make it" % (sequence.name,
                                                                      sequence.dataset))
        parent = os.path.dirname(sequence.dataset)
        os.makedirs(parent, exist_ok=True)
        staging = tempfile.mkdtemp(prefix=".prepare-", dir=parent)
        work = tempfile.mkdtemp(prefix="3dvo-rd-prepare-")
        fields = {"bin": os.path.abspath(bin_dir), "root": sweep.root, "dataset": staging,
                  "work": work, "python": sys.executable}
        try:
            for command in sequence.prepare:
                try:
                    argv = [a.format(**fields) for a in command]
                except (KeyError, IndexError, ValueError) as e:
                    raise SweepError("sequence '%s': prepare command %s: unknown placeholder "
                                     "%s (known: %s)" % (sequence.name, command, e,
                                                         ", ".join(_PREPARE_FIELDS))) from None
                print("3dvo-rd: preparing %s: %s" % (sequence.name, " ".join(argv)), file=log)
                try:
                    done = subprocess.run(argv, cwd=sweep.root, stdin=subprocess.DEVNULL,
                                          stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                                          text=True)
                except OSError as e:
                    raise SweepError("sequence '%s': prepare command %s: %s"
                                     % (sequence.name, argv[0], e.strerror)) from None
                if done.returncode != 0:
                    tail = "\n".join((done.stderr or done.stdout).splitlines()[-20:])
                    raise SweepError("sequence '%s': prepare command failed (exit %d): %s\n%s"
                                     % (sequence.name, done.returncode, " ".join(argv), tail))
            if not os.path.exists(os.path.join(staging, "dataset.json")):
                raise SweepError("sequence '%s': the prepare commands wrote no dataset.json "
                                 "into {dataset}" % sequence.name)
            os.replace(staging, sequence.dataset)
            prepared.append(sequence.name)
        finally:
            shutil.rmtree(work, ignore_errors=True)
            shutil.rmtree(staging, ignore_errors=True)
    return prepared
