"""The package's hand-written declarations (python/lumis/_cdefs.py) lay every struct out as
the C compiler does: sizes and offsets of every field, from a program compiled against the
public headers.  Needs a C compiler (LUMIS_CC, else cc)."""
import json
import os
import shutil
import subprocess

import pytest

import lumis
from lumis._cdefs import RENDER_STRUCTS, STRUCTS

STRUCTS = {**STRUCTS, **RENDER_STRUCTS}

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))


def test_struct_layouts_match_the_headers(tmp_path):
    cc = os.environ.get("LUMIS_CC") or shutil.which("cc")
    if not cc:
        pytest.skip("no C compiler (set LUMIS_CC)")
    lines = ["#include <stddef.h>", "#include <stdio.h>", "#include \"lumis/lumis.h\"",
             "#include \"lumis/io.h\"", "#include \"lumis/render.h\"", "int main(void) {", "printf(\"{\");"]
    for i, (name, fields) in enumerate(STRUCTS.items()):
        sep = "," if i else ""
        lines.append('printf("%s\\"%s\\": [%%zu", sizeof(%s));' % (sep, name, name))
        for f in fields:
            lines.append('printf(", %%zu", offsetof(%s, %s));' % (name, f))
        lines.append('printf("]");')
    lines += ['printf("}\\n");', "return 0; }"]
    src = tmp_path / "layout.c"
    src.write_text("\n".join(lines))
    exe = tmp_path / "layout"
    subprocess.run([cc, "-std=c11", "-I", os.path.join(ROOT, "include"), str(src), "-o", str(exe)],
                   check=True)
    want = json.loads(subprocess.run([str(exe)], check=True, capture_output=True, text=True).stdout)
    ffi = lumis.ffi
    for name, fields in STRUCTS.items():
        got = [ffi.sizeof(name)] + [ffi.offsetof(name, f) for f in fields]
        assert got == want[name], name
