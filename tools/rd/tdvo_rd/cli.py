"""The 3dvo-rd command line (docs/rd.md)."""

import argparse
import os
import shlex
import sys
import tempfile

from . import job as job_module
from . import security
from .runner import run_sweep
from .sweep import Identity, Sweep, SweepError, check_page

_REPO = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..",
                                      ".."))


def default_bin_dir():
    """TDVO_BIN_DIR (set by the build/bin/3dvo-rd launcher), else <repo>/build/bin."""
    return os.environ.get("TDVO_BIN_DIR") or os.path.join(_REPO, "build", "bin")


class _Parser(argparse.ArgumentParser):
    """argparse with the apps' exit code for bad arguments: 1 (argparse's 2 means an internal
    error in the 3DVO apps, docs/user-guide.md, "Errors")."""

    def error(self, message):
        self.print_usage(sys.stderr)
        self.exit(1, "3dvo-rd: error: %s\n" % message)


def _parser():
    parser = _Parser(
        prog="3dvo-rd",
        description="Rate-distortion sweeps of 3dvo-enc: every sequence x coding mode x setting "
                    "is a cached job (encode, decode, metrics); outputs CSV, BD-rate tables, "
                    "RD plots and a results page. See docs/rd.md.")
    sub = parser.add_subparsers(dest="command", required=True)

    def common(p):
        p.add_argument("sweep", help="sweep file (TOML)")
        p.add_argument("--results", metavar="DIR",
                       help="results folder (the cache); default: [sweep] results of the sweep")
        p.add_argument("--bin-dir", metavar="DIR", default=None,
                       help="folder of 3dvo-enc, 3dvo-dec, 3dvo-metrics (default: %s)" %
                       default_bin_dir())

    run = sub.add_parser("run", help="run the jobs that have no cached result, then write "
                         "<results>/rd.csv and bd.csv (and a page with --report)")
    common(run)
    run.add_argument("--scheduler", metavar="ADDRESS",
                     help="send the jobs to this running Dask scheduler (tcp://HOST:PORT, or "
                     "the file of `dask scheduler --scheduler-file`) instead of the local pool")
    run.add_argument("--tls-ca-file", metavar="PEM", default=None,
                     help="with --tls-cert and --tls-key: reach the scheduler over TLS (a "
                     "tls:// address), trusting this CA (docs/rd.md, Security)")
    run.add_argument("--tls-cert", metavar="PEM", default=None,
                     help="the client's TLS certificate")
    run.add_argument("--tls-key", metavar="PEM", default=None,
                     help="the client's TLS private key")
    run.add_argument("--jobs", "-j", type=int, default=None, metavar="N",
                     help="local pool size (default: the core count)")
    run.add_argument("--force", action="store_true", help="recompute cached jobs too")
    run.add_argument("--timeout", type=float, default=None, metavar="SECONDS",
                     help="limit per encode/decode/metrics command (default: [sweep] timeout, "
                     "else none)")
    run.add_argument("--scratch", metavar="DIR", default=None,
                     help="where each job makes its temporary folder (default: the system's "
                     "temporary folder of the machine running the job)")
    run.add_argument("--report", metavar="PAGE.md",
                     help="also write the results page (as the report command's --out)")

    report = sub.add_parser("report", help="write CSV, BD tables, plots and the results page "
                            "from cached results, without running anything")
    common(report)
    report.add_argument("--out", metavar="PAGE.md",
                        help="results page to write; its figures and CSV go into the folder "
                        "of the same name without .md")
    report.add_argument("--partial", action="store_true",
                        help="write the outputs even when some jobs have no result")

    show = sub.add_parser("list", help="print the jobs of a sweep and whether each is cached")
    common(show)
    return parser


def _results_dir(args, sweep):
    results = args.results or sweep.results
    if not results:
        raise SweepError("%s: no results folder: pass --results DIR or set [sweep] results"
                         % args.sweep)
    return os.path.abspath(results)


def _inside(path, folder):
    """True when `path` is `folder` or lies inside it (both real absolute paths)."""
    return path == folder or path.startswith(folder.rstrip(os.sep) + os.sep)


def _check_page_folder(page, results_dir, scratch):
    """The page's folder of figures must not be, nor hold, what the run itself writes (the
    results folder, --scratch), nor be one of the results folder's own folders: the run would
    fill it and then refuse it as someone else's folder (check_page) after every job ran."""
    figures = os.path.realpath(page[:-3])
    results = os.path.realpath(results_dir)
    for folder, what in ((results, "the results folder"),
                         (os.path.realpath(scratch) if scratch else None, "the --scratch folder")):
        if folder and _inside(folder, figures):
            raise SweepError("%s: the page's folder of figures %s would %s %s %s; name another "
                             "page or folder" % (page, page[:-3],
                                                 "be" if folder == figures else "hold", what,
                                                 folder))
    for name in ("jobs", "failed"):
        if figures == os.path.join(results, name):
            raise SweepError("%s: the page's folder of figures %s is the results folder's %s/ "
                             "folder; name another page" % (page, page[:-3], name))


def _check_scratch(scratch):
    """--scratch of a local run: a folder (made when missing) where the jobs can make their
    temporary folders, checked before any job runs."""
    if os.path.exists(scratch) and not os.path.isdir(scratch):
        raise SweepError("%s: --scratch: not a folder" % scratch)
    try:
        os.makedirs(scratch, exist_ok=True)
        os.rmdir(tempfile.mkdtemp(prefix="3dvo-rd-check-", dir=scratch))
    except OSError as e:
        raise SweepError("%s: --scratch: cannot make the jobs' temporary folders there (%s)"
                         % (scratch, e.strerror or e)) from None


def _command_line(sweep, page):
    """The command that regenerates a page, paths relative to the sweep root. Where the cache
    lives (--results) changes nothing in the page, so the command leaves it out."""
    parts = ["tools/rd/3dvo-rd", "run", os.path.relpath(sweep.path, sweep.root), "--report",
             os.path.relpath(os.path.abspath(page), sweep.root)]
    return " ".join(shlex.quote(p) for p in parts)


def main(argv=None):
    args = _parser().parse_args(argv)
    try:
        if getattr(args, "jobs", None) is not None and args.jobs < 1:
            raise SweepError("--jobs must be at least 1")
        if getattr(args, "timeout", None) is not None and not args.timeout > 0:
            raise SweepError("--timeout must be a positive number of seconds")
        sweep = Sweep(args.sweep)
        results_dir = _results_dir(args, sweep)
        sweep.use_results(results_dir)
        bin_dir = args.bin_dir or default_bin_dir()
        # The page is checked before any job runs: one that 3dvo-rd did not write is not
        # replaced (sweep.check_page).
        page = getattr(args, "report", None) or getattr(args, "out", None)
        if page:
            check_page(page)
            _check_page_folder(page, results_dir, getattr(args, "scratch", None))
        if args.command == "list":
            identity = Identity(bin_dir)
            for j in sweep.jobs():
                key = identity.key(j)
                state = "cached" if job_module.read_result(results_dir, key) else "todo"
                print("%-6s %s  %s / %s / %s" % (state, key[:16], j.sequence.name, j.mode.name,
                                                 j.setting_label))
            return 0
        # The report's imports (numpy, scipy, matplotlib) are loaded here, not at start-up:
        # --help and list need none of them, and run fails before its jobs, not after, when
        # one is missing.
        from .report import ReportOptions, write_outputs
        ReportOptions(sweep)  # the [report] table, checked before any job runs
        if args.command == "run":
            try:
                tls = security.tls_options(args.tls_ca_file, args.tls_cert, args.tls_key)
                if args.scheduler is not None:
                    security.check_scheduler(args.scheduler)
            except ValueError as e:
                print("3dvo-rd: error: %s" % e, file=sys.stderr)
                return 1
            if args.scratch and args.scheduler is None:
                _check_scratch(args.scratch)   # (a cluster's is on its workers)
            summary, results = run_sweep(sweep, bin_dir, results_dir, scheduler=args.scheduler,
                                         jobs=args.jobs, force=args.force, timeout=args.timeout,
                                         scratch_dir=args.scratch, tls=tls)
            page = args.report
            missing = sum(1 for r in results if r is None)

            def say(text, file=sys.stdout):
                try:
                    print(text, file=file)
                except OSError:
                    # After SIGHUP the terminal is gone: the exit status still says 130.
                    if not summary.interrupted:
                        raise

            say(summary.line())
            if missing:
                # As `report` without --partial: rd.csv, bd.csv and the page of the last
                # complete run stay as they are.
                say("3dvo-rd: %d of %d jobs have no result, so %s%s are left as they were; "
                    "`3dvo-rd report --partial` writes partial tables"
                    % (missing, len(results), os.path.join(results_dir, "rd.csv"),
                       ", bd.csv and the page %s" % page if page else " and bd.csv"),
                    file=sys.stderr)
            else:
                write_outputs(sweep, results, Identity(bin_dir).binary_hashes, results_dir,
                              page, _command_line(sweep, page) if page else None)
                say("rows: %s" % os.path.join(results_dir, "rd.csv"))
                if page:
                    say("page: %s" % page)
            if summary.interrupted:
                say("interrupted: finished jobs are cached; rerun to continue", file=sys.stderr)
                return 130
            return 1 if summary.failed or missing else 0
        # report
        identity = Identity(bin_dir)
        results = [job_module.read_result(results_dir, identity.key(j)) for j in sweep.jobs()]
        missing = sum(1 for r in results if r is None)
        if missing and not args.partial:
            raise SweepError("%d of %d jobs have no result in %s for the current binaries and "
                             "inputs: run `3dvo-rd run` first (or pass --partial)"
                             % (missing, len(results), results_dir))
        page = args.out
        write_outputs(sweep, results, identity.binary_hashes, results_dir, page,
                      _command_line(sweep, page) if page else None)
        print("rows: %s (%d of %d jobs)" % (os.path.join(results_dir, "rd.csv"),
                                           len(results) - missing, len(results)))
        if page:
            print("page: %s" % page)
        return 0
    except SweepError as e:
        print("3dvo-rd: error: %s" % e, file=sys.stderr)
        return 1
    except OSError as e:  # a file or folder the run needs (e.g. --results naming a file)
        print("3dvo-rd: error: %s%s" % (e.filename + ": " if e.filename else "",
                                        e.strerror or e), file=sys.stderr)
        return 1
