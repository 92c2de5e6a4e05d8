#!/usr/bin/env python3
"""Runs the Python package's tests (pytest) as ctest's python_bindings: exit 77 (skipped)
with the reason when numpy, cffi or pytest is missing, unless CI=true, where that fails."""
import os
import sys

missing = []
for mod, pkg in (("numpy", "python3-numpy"), ("cffi", "python3-cffi"), ("pytest", "python3-pytest")):
    try:
        __import__(mod)
    except ImportError:
        missing.append(pkg)
if missing:
    print("python_bindings: SKIPPED: %s lacks %s (scripts/install-deps.sh installs them)"
          % (sys.executable, " ".join(missing)))
    sys.exit(1 if os.environ.get("CI") == "true" else 77)

import pytest  # noqa: E402

here = os.path.dirname(os.path.abspath(__file__))
sys.exit(pytest.main(["-q", "-p", "no:cacheprovider", here] + sys.argv[1:]))
