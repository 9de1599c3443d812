"""The Dask executor against a real `dask scheduler` and two `dask worker` processes on
127.0.0.1 (issue 12, acceptance 1 and 2): the same rows as the local pool, and every row when a
worker is killed in the middle of the sweep. The processes are stopped in every case."""

import glob
import json
import os
import shutil
import signal
import socket
import subprocess
import sys
import time

from tests import support
from tests.support import TempDirTestCase

JOBS = 12
START_TIMEOUT = 60


def dask_command():
    """`dask` of the Python running the tests (Debian: /usr/bin/dask), else the one on PATH."""
    beside = os.path.join(os.path.dirname(sys.executable), "dask")
    return beside if os.access(beside, os.X_OK) else shutil.which("dask")


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


class LocalCluster:
    """A scheduler and workers as separate process groups, logs in `folder`."""

    def __init__(self, folder):
        self.folder = folder
        self.processes = {}
        self.address = None

    def _spawn(self, name, args):
        log = open(os.path.join(self.folder, name + ".log"), "w")
        # A session per process: killing a worker kills its nanny and worker process together.
        self.processes[name] = subprocess.Popen([dask_command()] + args, stdout=log,
                                                stderr=subprocess.STDOUT,
                                                stdin=subprocess.DEVNULL,
                                                start_new_session=True)
        log.close()

    def start(self, workers):
        port = free_port()
        self.address = "tcp://127.0.0.1:%d" % port
        self.scheduler_file = os.path.join(self.folder, "scheduler.json")
        self._spawn("scheduler", ["scheduler", "--host", "127.0.0.1", "--port", str(port),
                                  "--no-dashboard", "--scheduler-file", self.scheduler_file])
        for i in range(workers):
            self._spawn("worker%d" % i, ["worker", self.address, "--host", "127.0.0.1",
                                         "--nthreads", "1", "--nworkers", "1", "--no-dashboard",
                                         "--death-timeout", str(START_TIMEOUT)])
        from distributed import Client
        with Client(self.address, timeout=START_TIMEOUT) as client:
            if workers:
                client.wait_for_workers(workers, timeout=START_TIMEOUT)

    def kill(self, name):
        process = self.processes[name]
        try:
            os.killpg(process.pid, signal.SIGKILL)
        except ProcessLookupError:
            pass
        process.wait()

    def stop(self):
        """Stops every process: SIGTERM, then SIGKILL for any still alive after 10 s."""
        for process in self.processes.values():
            if process.poll() is None:
                try:
                    os.killpg(process.pid, signal.SIGTERM)
                except ProcessLookupError:
                    pass
        deadline = time.monotonic() + 10
        for process in self.processes.values():
            try:
                process.wait(timeout=max(0.1, deadline - time.monotonic()))
            except subprocess.TimeoutExpired:
                try:
                    os.killpg(process.pid, signal.SIGKILL)
                except ProcessLookupError:
                    pass
                process.wait()

    def logs(self):
        text = []
        for name in self.processes:
            text.append("--- %s.log (end) ---\n%s" % (
                name, support.read_text(os.path.join(self.folder, name + ".log"))[-3000:]))
        return "\n".join(text)


class DaskRunTest(TempDirTestCase):
    def setUp(self):
        super().setUp()
        support.require_binaries(self)
        if not dask_command():
            self.skipTest("no `dask` command (Debian package python3-distributed)")
        self.patterns = support.make_sequences(os.path.join(self.tmp, "seq"))
        self.sweep = support.write_sweep(os.path.join(self.tmp, "sweep.toml"), self.patterns)
        self.cluster = LocalCluster(self.tmp)
        self.addCleanup(self.cluster.stop)
        self.count = os.path.join(self.tmp, "encoder-calls")

    def run_args(self, results, bin_dir, *extra):
        return ["run", self.sweep, "--results", os.path.join(self.tmp, results), "--bin-dir",
                bin_dir, "--scratch", os.path.join(self.tmp, "scratch-" + results)] + list(extra)

    def rows(self, results):
        return support.csv_rows(os.path.join(self.tmp, results, "rd.csv"))

    def test_cluster_rows_equal_local_rows(self):
        bin_dir = support.make_counting_bin_dir(os.path.join(self.tmp, "bin"), self.count)
        self.cluster.start(workers=2)
        out = support.run_rd(*self.run_args("dask", bin_dir, "--scheduler",
                                            self.cluster.address))
        self.assertIn("12 jobs: 12 ran, 0 cached, 0 failed", out.stdout, self.cluster.logs())
        support.run_rd(*self.run_args("local", bin_dir))
        self.assertEqual(support.count_lines(self.count), 2 * JOBS)
        local, dask = self.rows("local"), self.rows("dask")
        self.assertEqual(len(local), JOBS)
        for a, b in zip(local, dask):
            self.assertEqual(a, b)
        # Both workers ran jobs, and left no temporary folder behind.
        executors = set()
        for path in glob.glob(os.path.join(self.tmp, "dask", "jobs", "*.json")):
            executors.add(json.loads(support.read_text(path))["executor"])
        self.assertEqual(len(executors), 2, executors)
        self.assertTrue(all(e.startswith("tcp://127.0.0.1:") for e in executors), executors)
        self.assertEqual(os.listdir(os.path.join(self.tmp, "scratch-dask")), [])

        # A rerun through the cluster (named by its scheduler file) finds everything cached.
        out = support.run_rd(*self.run_args("dask", bin_dir, "--scheduler",
                                            self.cluster.scheduler_file))
        self.assertIn("12 jobs: 0 ran, 12 cached, 0 failed", out.stdout)
        self.assertEqual(support.count_lines(self.count), 2 * JOBS)

    def test_a_scheduler_without_workers_is_said_to_be_waited_for(self):
        # Nothing would run: 3dvo-rd says on stderr that it waits, and a hangup (the terminal
        # closed) ends it as an interrupt does.
        self.cluster.start(workers=0)
        err_path = os.path.join(self.tmp, "stderr.txt")
        with open(err_path, "w") as err:
            process = subprocess.Popen(
                support.rd_command(*self.run_args("dask", support.bin_dir(), "--scheduler",
                                                  self.cluster.address)),
                stdout=subprocess.PIPE, stderr=err, text=True)
        try:
            deadline = time.monotonic() + START_TIMEOUT
            while "waiting for workers" not in support.read_text(err_path):
                self.assertIsNone(process.poll(), support.read_text(err_path))
                self.assertLess(time.monotonic(), deadline, "no message:\n" +
                                support.read_text(err_path))
                time.sleep(0.1)
            process.send_signal(signal.SIGHUP)
            stdout, _ = process.communicate(timeout=60)
        finally:
            if process.poll() is None:
                process.kill()
                process.wait()
        stderr = support.read_text(err_path)
        self.assertIn("3dvo-rd: waiting for workers: the Dask scheduler %s has none yet\n"
                      % self.cluster.address, stderr)
        self.assertEqual(process.returncode, 130, stdout + stderr)
        self.assertIn("12 jobs: 0 ran, 0 cached, 0 failed, 12 not run (interrupted)", stdout)

    def test_killing_a_worker_mid_sweep_loses_no_row(self):
        # Slow encodes (0.4 s each) so that the kill lands while both workers are busy.
        bin_dir = support.make_counting_bin_dir(os.path.join(self.tmp, "bin"), self.count,
                                                delay=0.4)
        self.cluster.start(workers=2)
        process = subprocess.Popen(
            support.rd_command(*self.run_args("dask", bin_dir, "--scheduler",
                                              self.cluster.address)),
            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        try:
            jobs_dir = os.path.join(self.tmp, "dask", "jobs")
            deadline = time.monotonic() + 60
            while len(glob.glob(os.path.join(jobs_dir, "*.json"))) < 2:
                self.assertIsNone(process.poll(), "the sweep ended before the kill")
                self.assertLess(time.monotonic(), deadline, "no progress:\n" +
                                self.cluster.logs())
                time.sleep(0.05)
            self.cluster.kill("worker0")
            finished_at_kill = len(glob.glob(os.path.join(jobs_dir, "*.json")))
            stdout, stderr = process.communicate(timeout=120)
        finally:
            if process.poll() is None:
                process.kill()
                process.wait()
        self.assertLess(finished_at_kill, JOBS, "the kill came too late to test anything")
        self.assertEqual(process.returncode, 0, stdout + stderr + self.cluster.logs())
        self.assertIn("0 failed", stdout)
        support.run_rd(*self.run_args("local", bin_dir))
        dask, local = self.rows("dask"), self.rows("local")
        self.assertEqual(len(dask), JOBS)
        self.assertEqual(dask, local)


if __name__ == "__main__":
    import unittest
    unittest.main()
