"""Sweep files: expansion into jobs, configuration merge order, errors, cache keys."""

import os
import resource
import subprocess
import sys
import textwrap
import time
from unittest import mock

from tests import support
from tests.support import TempDirTestCase
from tdvo_rd import sweep as sweep_module
from tdvo_rd.sweep import Identity, Sweep, SweepError, read_cfg_file


class SweepTest(TempDirTestCase):
    def write(self, name, text):
        path = os.path.join(self.tmp, name)
        os.makedirs(os.path.dirname(path), exist_ok=True)
        with open(path, "w") as f:
            f.write(textwrap.dedent(text))
        return path

    def make_inputs(self):
        for seq in ("a", "b"):
            for k in range(1, 4):
                self.write("data/%s/%d.obj" % (seq, k), "v 0 0 %d\n" % k)

    def sweep_text(self, extra_mode=""):
        return """
            [sweep]
            root = ".."
            cfg = ["cfg/base.cfg"]

            [[sequence]]
            name = "a"
            pattern = "data/a/%d.obj"
            first_frame = 1
            frame_count = 3
            frame_rate = 30
            cfg = ["cfg/seq-a.cfg"]
            set = { GOMSize = 3 }

            [[sequence]]
            name = "b"
            pattern = "data/b/%d.obj"
            first_frame = 2
            frame_count = 2

            [[mode]]
            name = "intra"
            cfg = ["cfg/intra.cfg"]
            settings = [ { GridBits = 8 }, { GridBits = 10 } ]

            [[mode]]
            name = "d3dmc"
            label = "D3DMC"
            cfg = ["cfg/d3dmc.cfg"]
            set = { Lambda = 0.5 }
            settings = [ { MotionQuantStep = 4 }, { MotionQuantStep = 2 }, { MotionQuantStep = 1 } ]
            sequences = ["a"]
            """ + extra_mode

    def setUp(self):
        super().setUp()
        self.make_inputs()
        self.write("cfg/base.cfg", "GridBits : 11   # every job\nDracoSpeed : 3\n")
        self.write("cfg/seq-a.cfg", "GOMSize : 5\nInputMeshPattern : elsewhere/%d.obj\n")
        self.write("cfg/intra.cfg", "PMeshMode : intra\nGOMSize : 1\n")
        self.write("cfg/d3dmc.cfg", "PMeshMode : d3dmc\nLambda : 7  # replaced by set\n")
        self.path = self.write("sweeps/s.toml", self.sweep_text())
        self.bin = os.path.join(self.tmp, "bin")
        os.makedirs(self.bin)
        for name in ("3dvo-enc", "3dvo-dec", "3dvo-metrics"):
            self.write_binary(name, "#!/bin/sh\n# %s\n" % name)

    def write_binary(self, name, text):
        path = os.path.join(self.bin, name)
        with open(path, "w") as f:
            f.write(text)
        os.chmod(path, 0o755)

    def test_expansion_order_and_count(self):
        jobs = Sweep(self.path).jobs()
        self.assertEqual(
            [(j.sequence.name, j.mode.name, j.point, j.setting_label) for j in jobs],
            [("a", "intra", 0, "GridBits=8"), ("a", "intra", 1, "GridBits=10"),
             ("a", "d3dmc", 0, "MotionQuantStep=4"), ("a", "d3dmc", 1, "MotionQuantStep=2"),
             ("a", "d3dmc", 2, "MotionQuantStep=1"),
             ("b", "intra", 0, "GridBits=8"), ("b", "intra", 1, "GridBits=10")])

    def test_merge_order(self):
        jobs = Sweep(self.path).jobs()
        root = os.path.normpath(self.tmp)
        # Sequence cfg then set, then the mode's cfg (intra.cfg's GOMSize 1 wins), the setting,
        # and the sequence's input keys last (over the InputMeshPattern of seq-a.cfg).
        self.assertEqual(jobs[0].config, {
            "GridBits": "8", "DracoSpeed": "3", "GOMSize": "1",
            "InputMeshPattern": os.path.join(root, "data/a/%d.obj"), "PMeshMode": "intra",
            "FirstFrame": "1", "FrameCount": "3", "FrameRate": "30"})
        d3dmc = jobs[3].config
        self.assertEqual(d3dmc["GOMSize"], "3")          # sequence set over seq-a.cfg
        self.assertEqual(d3dmc["Lambda"], "0.5")         # mode set over the mode's cfg
        self.assertEqual(d3dmc["MotionQuantStep"], "2")
        self.assertEqual(d3dmc["GridBits"], "11")        # from the sweep's base cfg
        self.assertEqual(jobs[5].config["FrameRate"], "25")  # default frame rate
        self.assertEqual(jobs[3].mode.label, "D3DMC")

    def test_cfg_file_rules(self):
        path = self.write("x.cfg", "\ufeff# comment\n\n  Key :  a:b  # c\nOther:1\n"
                          "Pattern : take#2/%03d.obj\t# the second take\nEmpty : # none\n")
        self.assertEqual(read_cfg_file(path), [("Key", "a:b"), ("Other", "1"),
                                               ("Pattern", "take#2/%03d.obj"), ("Empty", "")])
        bad = self.write("bad.cfg", "GridBits 12\n")
        with self.assertRaisesRegex(SweepError, "bad.cfg:1: expected 'Key : value'"):
            read_cfg_file(bad)

    def test_errors_name_the_place(self):
        cases = [
            ("[[mode]]\nname = \"x\"\nsettings = [ { BitstreamFile = \"a\" } ]\n",
             "'x'.*BitstreamFile is set by the runner"),
            ("[[mode]]\nname = \"y\"\nsequences = [\"nope\"]\n", "no sequence named 'nope'"),
            ("[[mode]]\nname = \"z\"\nsetings = []\n",
             "\\[\\[mode\\]\\] 'z': unknown key 'setings'"),
            ("[[mode]]\nname = \"intra\"\n", "two modes share a name"),
            ("[[mode]]\nname = \"w\"\nlabel = \"D3DMC\"\n", "two modes share a label"),
            ("[[mode]]\nname = \"v\"\nlabel = \"a|b\"\n", "label 'a\\|b' holds '\\|'"),
            ("[[sequence]]\nname = \"../../escaped\"\npattern = \"data/a/%d.obj\"\n"
             "frame_count = 1\n", "the name '../../escaped' cannot name files"),
            ("[[sequence]]\nname = \"average\"\npattern = \"data/a/%d.obj\"\n"
             "frame_count = 1\n", "the name 'average' is taken"),
            ("[[sequence]]\nname = \"c\"\npattern = \"data/a/%s.obj\"\nframe_count = 1\n",
             "pattern must hold one frame number conversion"),
            ("[[sequence]]\nname = \"c\"\npattern = \"data/a/%(x)04d.obj\"\n"
             "frame_count = 1\n", "pattern must hold one frame number conversion"),
        ]
        for extra, message in cases:
            with self.subTest(message=message):
                path = self.write("sweeps/bad.toml", self.sweep_text(extra))
                with self.assertRaisesRegex(SweepError, message):
                    Sweep(path).jobs()
        path = self.write("sweeps/syntax.toml", "[sweep\n")
        with self.assertRaisesRegex(SweepError, "syntax.toml"):
            Sweep(path)

    def test_a_mode_with_no_job_is_an_error(self):
        # An empty list would silently drop the mode from the sweep; leaving the key out is
        # how to ask for one job per sequence, or for every sequence.
        for extra, message in (
                ("[[mode]]\nname = \"e\"\nsettings = []\n",
                 "s.toml: \\[\\[mode\\]\\] 'e': settings is empty"),
                ("[[mode]]\nname = \"f\"\nsequences = []\n",
                 "s.toml: \\[\\[mode\\]\\] 'f': sequences is empty")):
            with self.subTest(message=message):
                self.write("sweeps/s.toml", self.sweep_text(extra))
                with self.assertRaisesRegex(SweepError, message):
                    Sweep(self.path)

    def test_a_sweep_file_that_is_not_utf8_is_an_error(self):
        with open(self.path, "wb") as f:
            f.write(b'[sweep]\nname = "caf\xe9"\n')
        with self.assertRaisesRegex(SweepError, "s.toml: not UTF-8 text"):
            Sweep(self.path)

    def run_rd_bounded(self, *args):
        """3dvo-rd with 1 GiB of address space and a minute: what a sweep file asks for must
        be refused, not attempted."""
        def limit():
            resource.setrlimit(resource.RLIMIT_AS, (1 << 30, 1 << 30))

        return subprocess.run(support.rd_command(*args), stdout=subprocess.PIPE,
                              stderr=subprocess.PIPE, text=True, timeout=60, preexec_fn=limit)

    def test_frame_counts_and_widths_beyond_the_apps_limits_are_refused_at_once(self):
        # A sweep file's size bounds what checking it costs: frame_count and first_frame within
        # 3dvo-enc's FrameCount and FirstFrame ranges, the %0Nd width within the apps' 32.
        base = self.sweep_text()
        cases = [
            (base.replace("frame_count = 3", "frame_count = 1000000000000"),
             "frame_count must be 1 .. 1000000"),
            (base.replace("frame_count = 3", "frame_count = 1000001"),
             "frame_count must be 1 .. 1000000"),
            (base.replace("frame_count = 3", "frame_count = 0"),
             "frame_count must be 1 .. 1000000"),
            (base.replace("first_frame = 1", "first_frame = -1"),
             "first_frame must be 0 .. 1000000000"),
            (base.replace("data/a/%d.obj", "data/a/%09999999999d.obj"),
             "pattern: the width of its frame number conversion is at most 32"),
            (base.replace("data/a/%d.obj", "data/a/%0999999999999999999999d.obj"),
             "pattern: the width of its frame number conversion is at most 32"),
            (base.replace("data/a/%d.obj", "data/a/%0" + "9" * 5000 + "d.obj"),
             "pattern: the width of its frame number conversion is at most 32"),
            (base.replace("data/a/%d.obj", "data/a/%33d.obj"),
             "pattern: the width of its frame number conversion is at most 32"),
        ]
        for text, message in cases:
            with self.subTest(message=message, text=text[190:260]):
                path = self.write("sweeps/big.toml", text)
                start = time.monotonic()
                out = self.run_rd_bounded("list", path, "--results",
                                          os.path.join(self.tmp, "results"), "--bin-dir",
                                          self.bin)
                self.assertLess(time.monotonic() - start, 10)
                self.assertEqual(out.returncode, 1, out.stderr[-2000:])
                self.assertEqual(out.stderr.count("\n"), 1, out.stderr[-2000:])
                self.assertTrue(out.stderr.startswith("3dvo-rd: error: %s: [[sequence]] 'a': "
                                                      % path), out.stderr[-2000:])
                self.assertIn(message, out.stderr)
        # The widest conversion the apps take is fine.
        self.write("sweeps/big.toml", base.replace("data/a/%d.obj", "data/a/%032d.obj"))
        self.assertEqual(Sweep(os.path.join(self.tmp, "sweeps/big.toml")).sequences[0]
                         .frame_paths().__next__(), os.path.join(self.tmp, "data/a/" +
                                                                 "%032d.obj" % 1))

    def test_input_frames_are_named_one_at_a_time(self):
        # The most frames 3dvo-enc codes, of which 3 exist: the first missing one stops the
        # hashing before the names of the others are made.
        self.write("sweeps/s.toml", self.sweep_text().replace("frame_count = 3",
                                                              "frame_count = 1000000"))
        job = Sweep(self.path).jobs()[0]
        with mock.patch.object(sweep_module, "frame_path",
                               wraps=sweep_module.frame_path) as frame_path:
            with self.assertRaisesRegex(SweepError,
                                        "sequence 'a': cannot read input frame .*a/4.obj"):
                Identity(self.bin).key(job)
        self.assertEqual(frame_path.call_count, 4)

    def test_a_scratch_folder_that_cannot_be_made_is_a_one_line_failure(self):
        # On a Dask worker --scratch is the worker's: a job that cannot make its folder there
        # fails with a one-line reason (a local run checks --scratch before any job, cli.py).
        from tdvo_rd import job
        results = os.path.join(self.tmp, "results")
        spec = {"key": "0" * 64, "results_dir": results, "scratch_dir": self.path,
                "timeout": None, "force": True, "binaries": {}, "encoder_args": [],
                "record": {"sequence": "a", "mode": "intra", "setting_label": "(base)"}}
        result = job.run_job(spec)
        self.assertEqual(result["status"], "failed")
        self.assertEqual(result["stage"], "scratch")
        self.assertIn("cannot make a temporary folder in %s" % self.path, result["error"])
        self.assertTrue(os.path.isfile(job.failure_path(results, "0" * 64)))

    def test_a_cache_file_that_is_not_a_result_is_no_result(self):
        from tdvo_rd import job
        for text in ("null", "[1, 2]", "\"text\"", "{\"format\":"):
            with self.subTest(text=text):
                self.write("results/jobs/k.json", text)
                self.assertIsNone(job.read_result(os.path.join(self.tmp, "results"), "k"))

    def test_a_geometry_sweep_refuses_a_dataset_from_a_cfg_file(self):
        # It would code textures, and the cache key leaves Dataset out: results of the
        # geometry-only coding would be reused.
        self.write("cfg/intra.cfg", "PMeshMode : intra\nGOMSize : 1\nDataset : /nowhere\n")
        with self.assertRaisesRegex(SweepError, "a cfg file sets Dataset, which is for texture "
                                                "sweeps"):
            Sweep(self.path).jobs()

    def test_missing_cfg_and_input_are_errors(self):
        os.unlink(os.path.join(self.tmp, "cfg/intra.cfg"))
        with self.assertRaisesRegex(SweepError, "intra.cfg: cannot read cfg file"):
            Sweep(self.path).jobs()
        self.write("cfg/intra.cfg", "PMeshMode : intra\n")
        os.unlink(os.path.join(self.tmp, "data/b/3.obj"))
        identity = Identity(self.bin)
        jobs = Sweep(self.path).jobs()
        with self.assertRaisesRegex(SweepError, "sequence 'b': cannot read input frame .*3.obj"):
            identity.key(jobs[-1])

    def test_keys_follow_content_not_paths(self):
        jobs = Sweep(self.path).jobs()
        keys = [Identity(self.bin).key(j) for j in jobs]
        self.assertEqual(len(set(keys)), len(keys))
        self.assertEqual(keys, [Identity(self.bin).key(j) for j in Sweep(self.path).jobs()])

        # A comment in a cfg file changes nothing; a value does.
        self.write("cfg/intra.cfg", "PMeshMode : intra   # edited\nGOMSize : 1\n")
        self.assertEqual([Identity(self.bin).key(j) for j in Sweep(self.path).jobs()], keys)
        self.write("cfg/intra.cfg", "PMeshMode : intra\nGOMSize : 2\n")
        changed = [Identity(self.bin).key(j) for j in Sweep(self.path).jobs()]
        self.assertEqual([a == b for a, b in zip(keys, changed)],
                         [False, False, True, True, True, False, False])
        self.write("cfg/intra.cfg", "PMeshMode : intra\nGOMSize : 1\n")

        # Moving the input data keeps the keys; changing a frame's bytes changes its sequence's.
        os.rename(os.path.join(self.tmp, "data"), os.path.join(self.tmp, "moved"))
        self.write("sweeps/s.toml", self.sweep_text().replace("data/", "moved/"))
        self.assertEqual([Identity(self.bin).key(j) for j in Sweep(self.path).jobs()], keys)
        self.write("moved/b/2.obj", "v 0 0 9\n")
        changed = [Identity(self.bin).key(j) for j in Sweep(self.path).jobs()]
        self.assertEqual(changed[:5], keys[:5])
        self.assertNotEqual(changed[5], keys[5])
        self.assertNotEqual(changed[6], keys[6])

        # Any binary's content is part of every key.
        self.write("moved/b/2.obj", "v 0 0 2\n")
        self.write_binary("3dvo-metrics", "#!/bin/sh\n# rebuilt\n")
        changed = [Identity(self.bin).key(j) for j in Sweep(self.path).jobs()]
        self.assertTrue(all(a != b for a, b in zip(keys, changed)))

    def test_an_input_file_key_is_resolved_and_keyed_by_content(self):
        mode = """
            [[mode]]
            name = "listed"
            set = { GOMListFile = "lists/goms.txt" }
            settings = [ {} ]
            sequences = ["a"]
            """
        self.write("sweeps/s.toml", self.sweep_text(mode))
        def listed():
            return next(j for j in Sweep(self.path).jobs() if j.mode.name == "listed")

        with self.assertRaisesRegex(SweepError, "sequence 'a': cannot read GOMListFile .*goms.txt"):
            Identity(self.bin).key(listed())
        self.write("lists/goms.txt", "0 2\n2 1\n")
        job = listed()
        self.assertEqual(job.config["GOMListFile"], os.path.join(self.tmp, "lists", "goms.txt"))
        key = Identity(self.bin).key(job)

        # Moving the list keeps the key; changing its content changes it.
        os.rename(os.path.join(self.tmp, "lists"), os.path.join(self.tmp, "moved-lists"))
        self.write("sweeps/s.toml", self.sweep_text(mode.replace("lists/", "moved-lists/")))
        self.assertEqual(Identity(self.bin).key(listed()), key)
        self.write("moved-lists/goms.txt", "0 1\n1 2\n")
        self.assertNotEqual(Identity(self.bin).key(listed()), key)

        # {dataset}/... needs a sequence with a dataset.
        self.write("sweeps/s.toml", self.sweep_text(mode.replace("lists/", "{dataset}/")))
        with self.assertRaisesRegex(SweepError, "sequence 'a': GOMListFile = .* has no dataset"):
            Sweep(self.path).jobs()

    def test_missing_binary_is_an_error(self):
        os.unlink(os.path.join(self.bin, "3dvo-dec"))
        with self.assertRaisesRegex(SweepError, "3dvo-dec: no such executable"):
            Identity(self.bin)


class StartUpTest(TempDirTestCase):
    def run_without_report_packages(self, *args):
        """3dvo-rd with numpy, scipy and matplotlib made unimportable."""
        code = ("import runpy, sys\n"
                "for name in ('numpy', 'scipy', 'matplotlib'):\n"
                "    sys.modules[name] = None\n"
                "sys.argv = [%r] + %r\n"
                "runpy.run_path(%r, run_name='__main__')\n"
                % (support.SCRIPT, list(args), support.SCRIPT))
        return subprocess.run([sys.executable, "-c", code], stdout=subprocess.PIPE,
                              stderr=subprocess.PIPE, text=True)

    def test_help_and_list_need_no_report_packages(self):
        # The report's packages are loaded only by run and report.
        result = self.run_without_report_packages("--help")
        self.assertEqual(result.returncode, 0, result.stderr)
        self.assertIn("usage: 3dvo-rd", result.stdout)
        support.require_binaries(self)
        sweep = support.write_sweep(os.path.join(self.tmp, "sweep.toml"),
                                    support.make_sequences(self.tmp))
        result = self.run_without_report_packages(
            "list", sweep, "--results", os.path.join(self.tmp, "results"),
            "--bin-dir", support.bin_dir())
        self.assertEqual(result.returncode, 0, result.stderr)
        self.assertEqual(result.stdout.count("todo "), 12, result.stdout)


if __name__ == "__main__":
    import unittest
    unittest.main()
