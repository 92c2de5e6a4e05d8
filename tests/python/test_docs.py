"""Every ```python block of docs/python.md runs as written."""
import os
import re

import pytest

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
with open(os.path.join(ROOT, "docs", "python.md")) as f:
    BLOCKS = re.findall(r"```python\n(.*?)```", f.read(), re.S)


def test_there_are_examples():
    assert len(BLOCKS) >= 2
    assert all(len(b.strip().splitlines()) <= 20 for b in BLOCKS)


@pytest.mark.parametrize("k", range(len(BLOCKS)))
def test_example_runs(k, capsys):
    exec(compile(BLOCKS[k], "docs/python.md block %d" % k, "exec"), {"__name__": "__doc__"})
    assert capsys.readouterr().out.strip()
