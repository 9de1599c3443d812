"""Runs the jobs of a sweep: cache lookup, a local pool or a Dask cluster, progress, summary.

Both executors call the same function, job.run_job, on the same plain-dict specs:

- local (default): a pool of `jobs` threads (default: the core count). Each thread drives one
  job's 3dvo-enc / 3dvo-dec / 3dvo-metrics child processes, where all the work happens, so threads
  give the same parallelism as a process pool and let an interrupt stop the children at once.
- Dask: `scheduler` is the address of a running Dask scheduler (tcp://HOST:PORT) or the JSON
  file its --scheduler-file option wrote; each job is one Dask task. job.py is sent to the
  workers by value (cloudpickle), so workers need only Python, Dask and a shared filesystem
  holding the binaries, the inputs and the results folder.
"""

import concurrent.futures
import os
import signal
import sys
import traceback

from . import job as job_module
from . import security
from .sweep import Identity, SweepError, make_spec, prepare_datasets

# Task retries on Dask for exceptions raised by run_job itself (e.g. an I/O error of the shared
# filesystem). A failing 3dvo command is not an exception (run_job returns a failure record) and
# is not retried; a lost worker's tasks are rerun by the scheduler (distributed's
# "allowed-failures", 3 by default), whatever this says.
DASK_RETRIES = 2


class Summary:
    def __init__(self, total):
        self.total = total
        self.ran = 0
        self.cached = 0
        self.failures = []          # failure records (dicts)
        self.interrupted = False

    @property
    def failed(self):
        return len(self.failures)

    def line(self):
        text = "%d jobs: %d ran, %d cached, %d failed" % (self.total, self.ran, self.cached,
                                                          self.failed)
        if self.interrupted:
            text += ", %d not run (interrupted)" % (self.total - self.ran - self.cached
                                                    - self.failed)
        return text


def failure_text(record):
    """A failed job for the terminal: what, which command, the end of its stderr."""
    job = record.get("job", {})
    lines = ["FAILED %s / %s / %s: %s %s" % (job.get("sequence"), job.get("mode"),
                                              job.get("setting_label"), record.get("stage"),
                                              record.get("error")),
             "  command: " + " ".join(record.get("command") or [])]
    tail = (record.get("stderr_tail") or "").rstrip()
    if tail:
        lines.append("  stderr (last lines):")
        lines += ["    " + line for line in tail.splitlines()]
    return "\n".join(lines)


def _progress_bar(total, initial):
    from tqdm import tqdm
    return tqdm(total=total, initial=initial, unit="job", desc="3dvo-rd", dynamic_ncols=True,
                disable=not sys.stderr.isatty())


def _exception_record(spec, exc_text):
    return {"status": "failed", "key": spec["key"], "job": spec["record"], "stage": "runner",
            "command": [], "error": "exception in the job", "stderr_tail": exc_text}


# Signals that end a run as Ctrl-C does (KeyboardInterrupt): SIGTERM (kill, a batch system's
# time limit) and SIGHUP (the terminal closed). Either way the running commands are stopped and
# their folders removed; without this a hangup would leave them running (each leads a session
# of its own, job.py) and exit at once with 129.
INTERRUPT_SIGNALS = (signal.SIGTERM, signal.SIGHUP)


class _SignalsInterrupt:
    """While active, the INTERRUPT_SIGNALS that have their default action raise
    KeyboardInterrupt in the main thread (a signal set to something else, e.g. SIG_IGN by
    nohup, is left alone)."""

    def __enter__(self):
        self.previous = {}

        def interrupt(signum, frame):
            raise KeyboardInterrupt()

        for signum in INTERRUPT_SIGNALS:
            previous = signal.getsignal(signum)
            if previous in (signal.SIG_DFL, None):
                self.previous[signum] = previous
                signal.signal(signum, interrupt)
        return self

    def __exit__(self, *exc):
        for signum, previous in self.previous.items():
            signal.signal(signum, previous or signal.SIG_DFL)
        return False


def _run_local(pending, jobs, on_result):
    """Runs the specs on a local thread pool; on Ctrl-C (or INTERRUPT_SIGNALS, see run_sweep)
    stops the children and re-raises KeyboardInterrupt."""
    pool = concurrent.futures.ThreadPoolExecutor(max_workers=jobs)
    try:
        futures = {pool.submit(job_module.run_job, spec): spec for spec in pending}
        for future in concurrent.futures.as_completed(futures):
            try:
                result = future.result()
            except job_module.JobCancelled:
                continue
            except Exception:
                result = _exception_record(futures[future], traceback.format_exc())
            on_result(result)
    except KeyboardInterrupt:
        job_module.cancel_all()
        pool.shutdown(wait=True, cancel_futures=True)
        raise
    finally:
        pool.shutdown(wait=True)


def _run_dask(pending, scheduler, on_result, tls=None, log=None):
    import cloudpickle
    from distributed import Client, as_completed

    warning = security.insecure_scheduler_warning(scheduler, tls=bool(tls))
    if warning:
        print(warning, file=log or sys.stderr, flush=True)
    sec = security.make_security(tls)

    # Workers import nothing of this package: the job module travels with the task.
    cloudpickle.register_pickle_by_value(job_module)
    try:
        if os.path.isfile(scheduler):    # a file written by `dask scheduler --scheduler-file`
            client = Client(scheduler_file=scheduler, timeout=30, security=sec)
        else:
            client = Client(scheduler, timeout=30, security=sec)
    except (OSError, ValueError, TypeError, KeyError) as e:  # unreachable, malformed, not a file
        raise SweepError("--scheduler %s: cannot reach a Dask scheduler (%s: %s)"
                         % (scheduler, type(e).__name__, e)) from None
    futures = {}
    try:
        try:
            workers = len(client.scheduler_info().get("workers", {}))
        except Exception:  # noqa: BLE001 - only for the message below
            workers = None
        if workers == 0:
            print("3dvo-rd: waiting for workers: the Dask scheduler %s has none yet"
                  % security.scheduler_address(scheduler), file=log or sys.stderr, flush=True)
        for spec in pending:
            future = client.submit(job_module.run_job, spec, key="3dvo-rd-" + spec["key"],
                                   retries=DASK_RETRIES)
            futures[future.key] = (future, spec)
        for future in as_completed([f for f, _ in futures.values()]):
            spec = futures[future.key][1]
            try:
                result = future.result()
            except Exception:
                result = _exception_record(spec, traceback.format_exc())
            on_result(result)
    except KeyboardInterrupt:
        client.cancel([f for f, _ in futures.values()])
        raise
    finally:
        client.close()


def run_sweep(sweep, bin_dir, results_dir, scheduler=None, jobs=None, force=False, timeout=None,
              scratch_dir=None, log=None, tls=None):
    """Runs every job of the sweep that has no cached result (all of them with force), after
    making the datasets of texture sequences that have prepare commands and no dataset yet.

    Returns (summary, results) with results[i] the result dict of job i, or None when it failed
    or did not run. Failures are printed to `log` (stderr) with their command and stderr tail as
    they happen; the sweep goes on."""
    log = log or sys.stderr
    identity = Identity(bin_dir)
    prepare_datasets(sweep, bin_dir, log)   # texture sequences made by commands, when missing
    all_jobs = sweep.jobs()
    keys = [identity.key(j) for j in all_jobs]
    timeout = timeout if timeout is not None else sweep.timeout
    summary = Summary(len(all_jobs))
    results = [None] * len(all_jobs)
    by_key = {}
    pending = []
    for index, (j, key) in enumerate(zip(all_jobs, keys)):
        by_key.setdefault(key, []).append(index)
        if len(by_key[key]) > 1:
            continue            # the same job twice in the sweep: run it once
        cached = None if force else job_module.read_result(results_dir, key)
        if cached is not None:
            cached["status"] = "cached"
            results[index] = cached
        else:
            pending.append(make_spec(j, identity, key, results_dir, timeout, scratch_dir, force))
    for key, indices in by_key.items():
        for index in indices[1:]:
            results[index] = results[indices[0]]
    summary.cached = sum(1 for r in results if r is not None)
    os.makedirs(results_dir, exist_ok=True)

    bar = _progress_bar(summary.total, summary.cached)

    def on_result(result):
        indices = by_key[result["key"]]
        if result["status"] == "failed":
            summary.failures.append(result)
            bar.write(failure_text(result), file=log)
        else:
            for index in indices:
                results[index] = result
            if result["status"] == "cached":
                summary.cached += len(indices)
            else:
                summary.ran += len(indices)
        bar.update(len(indices))

    try:
        if pending:
            with _SignalsInterrupt():
                if scheduler:
                    _run_dask(pending, scheduler, on_result, tls=tls, log=log)
                else:
                    _run_local(pending, jobs or os.cpu_count() or 1, on_result)
    except KeyboardInterrupt:
        summary.interrupted = True
    finally:
        bar.close()
    return summary, results
