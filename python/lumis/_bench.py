"""lumis.bench: a bench suite run by the lumis tool (`lumis bench`) in a subprocess, its
results read back as records (docs/python.md, "Bench suites").  The harness is a static
library of the tool (tools/harness), not installed and not part of the C API, so the
package runs the tool rather than binding it."""

import csv
import json
import os
import shutil
import subprocess

from . import _lib
from ._lib import invalid

_HERE = os.path.dirname(os.path.abspath(__file__))


class BenchError(_lib.Error):
    """`lumis bench` failed at run time (exit 1: a file it could not read or write, a render
    that failed): .returncode, .message the tool's last lines; .status is no library status
    (the tool's own exit), so .status_name is "unknown-status"."""

    def __init__(self, returncode, message):
        super().__init__(1000 + int(returncode), message)
        self.returncode = int(returncode)


BenchError.__module__ = "lumis"


class BenchRecords(list):
    """The items of a bench run as dicts (results/ID.json: map, scene, method, budget, spp,
    the timings and every metric), one per row of results.csv, in its order; .summary is
    results.json (means and rankings per budget and method, convergence), .out_dir the
    folder, .log what the tool printed."""

    summary = None
    out_dir = None
    log = ""


def find_tool():
    """The lumis tool lumis.bench runs: LUMIS_CLI, else the one installed with this package,
    else the one built beside the libraries it loaded (make run), else `lumis` on PATH."""
    env = os.environ.get("LUMIS_CLI")
    if env:
        return env
    cands = []
    try:
        from . import _install  # noqa: PLC0415
        cands.append(os.path.join(_HERE, getattr(_install, "BINDIR_FROM_PACKAGE", ""), "lumis"))
    except ImportError:
        pass
    if _lib._libdir:
        cands.append(os.path.join(_lib._libdir, "lumis"))
    for c in cands:
        c = os.path.normpath(c)
        if os.path.isfile(c) and os.access(c, os.X_OK):
            return c
    found = shutil.which("lumis")
    if found:
        return found
    raise FileNotFoundError("lumis.bench runs the lumis tool, and found none (looked at %s and "
                            "PATH): build it (make run), install it (make install) or set "
                            "LUMIS_CLI" % (", ".join(cands) or "no install folder"))


def bench(suite, out_dir=None, jobs=1, threads=0, report_only=False, tool=None, quiet=True):
    """Runs the bench suite `suite` (a JSON file, docs/bench.md) as `lumis bench SUITE --out
    OUT_DIR` does (it is that command, in a subprocess: an interrupted run resumes, finished
    items are kept) and returns its items as a BenchRecords list of dicts.  out_dir: None:
    bench-out/SUITE_NAME in the current folder, as the tool's default; jobs, threads: the
    tool's --jobs and --threads (0: its default); report_only: render nothing, report on
    what out_dir holds.  A failed run raises lumis.Error with the tool's message."""
    suite = os.fspath(suite)
    if not os.path.isfile(suite):
        raise invalid("suite: no file %s" % suite)
    if int(jobs) < 1 or int(threads) < 0:
        raise invalid("jobs: %r, threads: %r (expected jobs >= 1, threads >= 0)" % (jobs, threads))
    if out_dir is None:
        with open(suite, encoding="utf-8") as f:
            try:
                name = json.load(f).get("name")
            except (ValueError, AttributeError):
                name = None
        out_dir = os.path.join("bench-out", name or os.path.splitext(os.path.basename(suite))[0])
    out_dir = os.fspath(out_dir)
    cmd = [tool or find_tool(), "bench", suite, "--out", out_dir, "--jobs", str(int(jobs))]
    if int(threads):
        cmd += ["--threads", str(int(threads))]
    if report_only:
        cmd.append("--report-only")
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode != 0:
        lines = (r.stderr.strip() or r.stdout.strip()).splitlines()
        text = "lumis bench %s: exit %d: %s" % (suite, r.returncode,
                                                "; ".join(lines[-3:]) or "no message")
        if r.returncode == 2:  # the tool's usage error: a suite or option it refuses
            raise invalid(text)
        raise BenchError(r.returncode, text)
    return read_results(out_dir, log=r.stdout + r.stderr)


def read_results(out_dir, log=""):
    """The records of a bench folder (results.csv's rows, each its results/ID.json) without
    running anything."""
    out = BenchRecords()
    out.out_dir, out.log = out_dir, log
    with open(os.path.join(out_dir, "results.json"), encoding="utf-8") as f:
        out.summary = json.load(f)
    with open(os.path.join(out_dir, "results.csv"), newline="", encoding="utf-8") as f:
        for row in csv.DictReader(f):
            ident = "__".join((row["map"], row["scene"], row["method"], row["budget"]))
            with open(os.path.join(out_dir, "results", ident + ".json"), encoding="utf-8") as g:
                out.append(json.load(g))
    return out
