"""Fixtures of the Python package's tests: the lumis tool to check against (LUMIS_CLI, set
by ctest), the source tree, and a helper that runs the tool."""
import os
import subprocess
import sys

import pytest

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
if os.path.join(ROOT, "python") not in sys.path and "LUMIS_TEST_INSTALLED" not in os.environ:
    sys.path.insert(0, os.path.join(ROOT, "python"))


@pytest.fixture(scope="session")
def cli():
    path = os.environ.get("LUMIS_CLI", os.path.join(ROOT, "build", "lumis"))
    if not os.path.exists(path):
        pytest.skip("no lumis tool at %s (set LUMIS_CLI)" % path)

    def run(*args, stdin=None):
        r = subprocess.run([path, *map(str, args)], input=stdin, capture_output=True, text=True)
        if r.returncode != 0:
            raise AssertionError("lumis %s: exit %d: %s" % (" ".join(map(str, args)), r.returncode,
                                                          r.stderr))
        return r.stdout
    return run


@pytest.fixture(scope="session")
def root():
    return ROOT


@pytest.fixture(scope="session")
def real_map():
    p = os.path.join(ROOT, "data", "hdri", "pmndrs-forest.exr")
    if not os.path.exists(p):
        pytest.skip("no %s (scripts/fetch-data.sh)" % p)
    return p
