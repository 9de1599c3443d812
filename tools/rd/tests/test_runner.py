"""The local executor with the real apps: results, caching, --force, interrupt and resume,
failed jobs, and redrawing the outputs from the cache."""

import glob
import json
import os
import signal
import subprocess
import time

from tests import support
from tests.support import TempDirTestCase

JOBS = 12  # support.write_sweep: 2 sequences x 2 modes x 3 settings


class LocalRunTest(TempDirTestCase):
    def setUp(self):
        super().setUp()
        support.require_binaries(self)
        self.patterns = support.make_sequences(os.path.join(self.tmp, "seq"))
        self.sweep = support.write_sweep(os.path.join(self.tmp, "sweep.toml"), self.patterns)
        self.results = os.path.join(self.tmp, "results")
        self.scratch = os.path.join(self.tmp, "scratch")
        self.count = os.path.join(self.tmp, "encoder-calls")

    def bin_dir(self, delay=0.0):
        return support.make_counting_bin_dir(os.path.join(self.tmp, "bin"), self.count, delay)

    def run_args(self, bin_dir, *extra):
        return ["run", self.sweep, "--results", self.results, "--bin-dir", bin_dir,
                "--scratch", self.scratch] + list(extra)

    def assert_no_leftovers(self):
        self.assertEqual(os.listdir(self.scratch) if os.path.isdir(self.scratch) else [], [],
                         "job temporary folders left behind")
        self.assertEqual(glob.glob(os.path.join(self.results, "jobs", ".tmp-*")), [],
                         "half-written results left behind")

    def test_run_then_rerun_recomputes_nothing(self):
        bin_dir = self.bin_dir()
        out = support.run_rd(*self.run_args(bin_dir, "--jobs", "2"))
        self.assertIn("12 jobs: 12 ran, 0 cached, 0 failed", out.stdout)
        self.assertEqual(support.count_lines(self.count), JOBS)
        self.assert_no_leftovers()
        rows = support.csv_rows(os.path.join(self.results, "rd.csv"))
        self.assertEqual(len(rows), JOBS)
        self.assertEqual([(r["sequence"], r["mode"], r["setting"]) for r in rows[:4]],
                         [("blob2", "intra", "GridBits=8"), ("blob2", "intra", "GridBits=10"),
                          ("blob2", "intra", "GridBits=12"),
                          ("blob2", "d3dmc", "MotionQuantStep=32")])
        for row in rows:
            self.assertEqual(row["frames"], "8")
            self.assertEqual(row["vertices"], str(8 * (162 if row["sequence"] == "blob2"
                                                       else 642)))
            # kbit/s from the stream size: bytes * 8 / 1000 * 25 fps / 8 frames.
            self.assertAlmostEqual(float(row["kbit_s"]), int(row["bytes"]) * 0.025, places=6)
            self.assertGreater(float(row["D_A"]), 0)
            # STED: decoded frames keep the input's connectivity and order.
            self.assertGreater(float(row["sted_s"]), 0)
            self.assertGreaterEqual(float(row["sted"]), float(row["sted_s"]))
        # Finer quantisation costs rate and lowers D_A.
        intra = [r for r in rows if r["sequence"] == "blob2" and r["mode"] == "intra"]
        self.assertLess(int(intra[0]["bytes"]), int(intra[2]["bytes"]))
        self.assertGreater(float(intra[0]["D_A"]), float(intra[2]["D_A"]))
        # A result file holds the job, sizes, timings and every metric.
        result = json.loads(support.read_text(
            glob.glob(os.path.join(self.results, "jobs", "*.json"))[0]))
        self.assertEqual(result["status"], "ok")
        self.assertEqual(result["executor"], "local")
        for name in ("vertex_rmse", "vertex_mean_error", "kg_error", "sted_s", "sted_t", "sted",
                     "hausdorff_max", "hausdorff_mean", "diagonal"):
            self.assertIn(name, result["metrics"])
        self.assertEqual(set(result["time"]), {"encode_s", "decode_s", "metrics_s"})

        out = support.run_rd(*self.run_args(bin_dir))
        self.assertIn("12 jobs: 0 ran, 12 cached, 0 failed", out.stdout)
        self.assertEqual(support.count_lines(self.count), JOBS)

        out = support.run_rd(*self.run_args(bin_dir, "--force"))
        self.assertIn("12 jobs: 12 ran, 0 cached, 0 failed", out.stdout)
        self.assertEqual(support.count_lines(self.count), 2 * JOBS)
        # Deterministic apps: a recomputed sweep gives the same rows (times aside).
        self.assertEqual(support.csv_rows(os.path.join(self.results, "rd.csv")), rows)

    def test_changed_setting_recomputes_only_its_jobs(self):
        bin_dir = self.bin_dir()
        support.run_rd(*self.run_args(bin_dir))
        with open(self.sweep) as f:
            text = f.read()
        with open(self.sweep, "w") as f:
            f.write(text.replace("{ MotionQuantStep = 2 }", "{ MotionQuantStep = 3 }"))
        out = support.run_rd(*self.run_args(bin_dir))
        self.assertIn("12 jobs: 2 ran, 10 cached, 0 failed", out.stdout)
        self.assertEqual(support.count_lines(self.count), JOBS + 2)

    def test_rows_name_the_current_jobs_when_a_cached_result_is_reused(self):
        # Renaming a mode and moving its setting into `set` keeps every cache key: nothing is
        # recomputed, and the rows carry the new names, not the ones recorded in the cache.
        bin_dir = self.bin_dir()
        support.run_rd(*self.run_args(bin_dir))
        with open(self.sweep) as f:
            text = f.read()
        text = text.replace('name = "d3dmc"', 'name = "d3dmc-renamed"')
        text = text.replace("settings = [ { MotionQuantStep = 32 }, { MotionQuantStep = 8 }, "
                            "{ MotionQuantStep = 2 } ]",
                            "settings = [ { MotionQuantStep = 32, Lambda = -1 }, "
                            "{ MotionQuantStep = 8 }, { MotionQuantStep = 2 } ]")
        with open(self.sweep, "w") as f:
            f.write(text)
        out = support.run_rd(*self.run_args(bin_dir))
        self.assertIn("12 jobs: 0 ran, 12 cached, 0 failed", out.stdout)
        rows = support.csv_rows(os.path.join(self.results, "rd.csv"))
        self.assertEqual(sorted({r["mode"] for r in rows}), ["d3dmc-renamed", "intra"])
        self.assertIn("MotionQuantStep=32 Lambda=-1", [r["setting"] for r in rows])

    def test_interrupted_sweep_resumes_with_the_unfinished_jobs_only(self):
        # One job at a time, each encode delayed, so that the interrupt lands mid-sweep.
        bin_dir = self.bin_dir(delay=0.3)
        process = subprocess.Popen(support.rd_command(*self.run_args(bin_dir, "--jobs", "1")),
                                   stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        jobs_dir = os.path.join(self.results, "jobs")
        deadline = time.monotonic() + 60
        try:
            while len(glob.glob(os.path.join(jobs_dir, "*.json"))) < 3:
                self.assertIsNone(process.poll(), "the sweep ended before the interrupt")
                self.assertLess(time.monotonic(), deadline, "no progress")
                time.sleep(0.05)
            process.send_signal(signal.SIGINT)        # what Ctrl-C does
            stdout, stderr = process.communicate(timeout=60)
        finally:
            if process.poll() is None:
                process.kill()
                process.wait()
        self.assertEqual(process.returncode, 130, stdout + stderr)
        self.assertIn("interrupted", stderr)
        self.assert_no_leftovers()
        finished = len(glob.glob(os.path.join(jobs_dir, "*.json")))
        self.assertGreaterEqual(finished, 3)
        self.assertLess(finished, JOBS)
        calls_before = support.count_lines(self.count)

        out = support.run_rd(*self.run_args(bin_dir, "--jobs", "2"))
        self.assertIn("12 jobs: %d ran, %d cached, 0 failed" % (JOBS - finished, finished),
                      out.stdout)
        self.assertEqual(support.count_lines(self.count) - calls_before, JOBS - finished)
        self.assertEqual(len(support.csv_rows(os.path.join(self.results, "rd.csv"))), JOBS)

    def test_failed_job_is_reported_and_the_sweep_goes_on(self):
        with open(self.sweep) as f:
            text = f.read()
        with open(self.sweep, "w") as f:
            f.write(text.replace("{ GridBits = 12 }", "{ GridBits = 30 }"))
        bin_dir = self.bin_dir()
        out = support.run_rd(*self.run_args(bin_dir), check=False)
        self.assertEqual(out.returncode, 1)
        self.assertIn("12 jobs: 10 ran, 0 cached, 2 failed", out.stdout)
        # The failure names the job, the stage, the command and the encoder's error.
        self.assertIn("FAILED blob2 / intra / GridBits=30: encode exit code 1", out.stderr)
        self.assertIn("--GridBits=30", out.stderr)
        self.assertIn("GridBits: value 30 out of range", out.stderr)
        self.assertEqual(len(glob.glob(os.path.join(self.results, "failed", "*.json"))), 2)
        self.assertEqual(len(support.csv_rows(os.path.join(self.results, "rd.csv"))), 10)
        self.assert_no_leftovers()
        # Failures are not cached: a rerun tries them again.
        out = support.run_rd(*self.run_args(bin_dir), check=False)
        self.assertIn("12 jobs: 0 ran, 10 cached, 2 failed", out.stdout)

    def test_crash_and_timeout_are_failures(self):
        one_job = os.path.join(self.tmp, "one.toml")
        with open(one_job, "w") as f:
            f.write('[[sequence]]\nname = "blob2"\npattern = "%s"\nframe_count = 8\n'
                    '[[mode]]\nname = "intra"\ncfg = ["%s"]\n'
                    % (self.patterns["blob2"], os.path.join(support.REPO, "cfg", "intra.cfg")))
        bin_dir = self.bin_dir()
        encoder = os.path.join(bin_dir, "3dvo-enc")
        for script, expected in (("#!/bin/sh\nkill -SEGV $$\n", "encode killed by signal 11"),
                                 ("#!/bin/sh\nsleep 30\n", "encode timed out after 0.5 s")):
            with self.subTest(expected=expected):
                with open(encoder, "w") as f:
                    f.write(script)
                start = time.monotonic()
                out = support.run_rd("run", one_job, "--results", self.results, "--bin-dir",
                                     bin_dir, "--scratch", self.scratch, "--timeout", "0.5",
                                     check=False)
                self.assertLess(time.monotonic() - start, 20)
                self.assertEqual(out.returncode, 1)
                self.assertIn("1 jobs: 0 ran, 0 cached, 1 failed", out.stdout)
                self.assertIn(expected, out.stderr)
                self.assert_no_leftovers()

    def test_report_redraws_from_the_cache(self):
        # BD figures and plots by D_A, by the KG error and by STED.
        support.write_sweep(self.sweep, self.patterns,
                            extra='distortion = ["D_A", "kg_error", "sted"]\n')
        bin_dir = self.bin_dir()
        page = os.path.join(self.tmp, "docs", "results-test.md")
        support.run_rd(*self.run_args(bin_dir, "--report", page))
        calls = support.count_lines(self.count)
        files = os.path.join(self.tmp, "docs", "results-test")
        expected = {"rd.csv", "bd.csv"}
        for seq in ("blob2", "blob3"):
            for distortion in ("D_A", "kg_error", "sted"):
                expected |= {"%s-%s.png" % (seq, distortion), "%s-%s.svg" % (seq, distortion)}
        self.assertEqual(set(os.listdir(files)), expected)
        first = support.read_text(page)
        for name in ("D_A", "KG error", "STED"):
            self.assertIn("### %s, against intra-only" % name, first)
        self.assertIn("![blob2, D_A](results-test/blob2-D_A.svg)", first)
        self.assertIn("| KG % | STED | STED_s | STED_t |", first)
        svg = support.read_text(os.path.join(files, "blob3-D_A.svg"))
        bd = support.read_text(os.path.join(files, "bd.csv"))
        for distortion in ("D_A", "kg_error", "sted"):
            self.assertIn("blob3,%s,intra,d3dmc,pchip," % distortion, bd)

        # A plot that is a symbolic link is replaced, not written through.
        elsewhere = os.path.join(self.tmp, "elsewhere.svg")
        with open(elsewhere, "w") as f:
            f.write("not a plot\n")
        os.unlink(os.path.join(files, "blob3-D_A.svg"))
        os.symlink(elsewhere, os.path.join(files, "blob3-D_A.svg"))
        out = support.run_rd("report", self.sweep, "--results", self.results, "--bin-dir",
                             bin_dir, "--out", page)
        self.assertEqual(support.read_text(elsewhere), "not a plot\n")
        self.assertFalse(os.path.islink(os.path.join(files, "blob3-D_A.svg")))
        self.assertIn("12 of 12 jobs", out.stdout)
        self.assertEqual(support.count_lines(self.count), calls)   # nothing encoded
        self.assertEqual(support.read_text(page), first)                  # the same page
        self.assertEqual(support.read_text(os.path.join(files, "blob3-D_A.svg")), svg)
        self.assertEqual(support.read_text(os.path.join(files, "bd.csv")), bd)

        # A page 3dvo-rd did not write is not replaced, by report or by run (before any job).
        mine = os.path.join(self.tmp, "docs", "notes.md")
        with open(mine, "w") as f:
            f.write("# My notes\n")
        out = support.run_rd("report", self.sweep, "--results", self.results, "--bin-dir",
                             bin_dir, "--out", mine, check=False)
        self.assertEqual(out.returncode, 1)
        self.assertIn("notes.md exists and is not a page this tool wrote", out.stderr)
        out = support.run_rd(*self.run_args(bin_dir, "--report", mine, "--force"), check=False)
        self.assertEqual(out.returncode, 1)
        self.assertEqual(support.count_lines(self.count), calls)   # no job ran
        self.assertEqual(support.read_text(mine), "# My notes\n")
        self.assertFalse(os.path.exists(os.path.join(self.tmp, "docs", "notes")))

        # Nor are the files of a folder that has the figures' name but no page beside it.
        theirs = os.path.join(self.tmp, "docs", "theirs")
        os.makedirs(theirs)
        with open(os.path.join(theirs, "rd.csv"), "w") as f:
            f.write("my own rows\n")
        out = support.run_rd("report", self.sweep, "--results", self.results, "--bin-dir",
                             bin_dir, "--out", theirs + ".md", check=False)
        self.assertEqual(out.returncode, 1)
        self.assertIn("theirs exists, is not empty and has no page theirs.md", out.stderr)
        self.assertEqual(support.read_text(os.path.join(theirs, "rd.csv")), "my own rows\n")
        self.assertFalse(os.path.exists(theirs + ".md"))

        # Without results for the current binaries, report refuses (unless --partial).
        empty = os.path.join(self.tmp, "empty")
        out = support.run_rd("report", self.sweep, "--results", empty, "--bin-dir", bin_dir,
                             check=False)
        self.assertEqual(out.returncode, 1)
        self.assertIn("12 of 12 jobs have no result", out.stderr)


if __name__ == "__main__":
    import unittest
    unittest.main()
