#!/usr/bin/env python3
"""The floors of ARCHITECTURE.md, held by the includes.

    scripts/check-includes.py [ROOT]     # exit 1 and one line per forbidden include

Every file of include/lumis, src, tools, bench, fuzz, examples and docs/examples stands on
a floor (below); the programs' own modules tools/app (the render pipeline) and
tools/harness (the bench harness) are floors under the programs.  It fails on:
  - an include of a higher floor: a public header (lumis/X.h) or a private one (src/M/...);
  - another module's private header (any header under src/M/ but the including file's own
    module) that the allow-list below does not name; across libraries only
    src/core/internal.h is allowed, and what the other libraries use of it is inline (a
    shared library that called a hidden core symbol would not link: check-exports.py);
  - a third-party header in the core (lumis: the C standard library and the x86
    intrinsics only) or in a public header, and Embree, assimp or OpenMP in lumis-io.
The tests (tests/) are exempt: they test internals by design.
"""
import os
import re
import sys

ROOT = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else
                       os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

# Bottom to top.  The core library is five modules on floors of their own (ARCHITECTURE.md
# draws them stacked); lumis-io and lumis-render above; then the programs' own modules: the
# render pipeline a program runs (tools/app), the benchmark harness on it (tools/harness);
# the programs on top (the CLI, bench/, fuzz/, examples).
FLOORS = ["src/core", "src/envmap", "src/metrics", "src/luminaire", "src/lights",
          "src/io", "src/render", "tools/app", "tools/harness", "top"]
LIBRARY = {"src/core": "lumis", "src/envmap": "lumis", "src/metrics": "lumis",
           "src/luminaire": "lumis", "src/lights": "lumis", "src/io": "lumis-io",
           "src/render": "lumis-render", "tools/app": None, "tools/harness": None, "top": None}
TOOL_MODULES = ("tools/app", "tools/harness")
TOP_DIRS = ("tools", "bench", "fuzz", "examples", "docs/examples")

# The public headers' floors: the module that defines what each declares.
PUBLIC = {
    "export.h": "src/core", "status.h": "src/core", "types.h": "src/core",
    "image.h": "src/core", "rng.h": "src/core", "version.h": "src/core",
    "envmap.h": "src/envmap", "sampler.h": "src/envmap", "sky.h": "src/envmap",
    "metrics.h": "src/metrics",
    "luminaire.h": "src/luminaire", "photometry.h": "src/luminaire",
    "lights.h": "src/lights", "sun.h": "src/lights", "lumis.h": "src/lights",  # the core's umbrella header
    "io.h": "src/io",
    "render.h": "src/render", "bsdf.h": "src/render",
    # render.h's parts, one per idea
    "render_scene.h": "src/render", "render_lighting.h": "src/render",
    "render_job.h": "src/render", "render_gbuffer.h": "src/render",
    "render_session.h": "src/render", "render_scene_file.h": "src/render",
}

# Private headers included outside their module: (including module or file, header).  A
# new entry is a decision about the architecture: say why beside it.
ALLOWED = {
    # the one sanctioned cross-library private header: status-and-message helper, SIMD
    # dispatch macros, small inline math (src/core/internal.h)
    ("src/envmap", "src/core/internal.h"),
    ("src/metrics", "src/core/internal.h"),
    ("src/luminaire", "src/core/internal.h"),
    ("src/lights", "src/core/internal.h"),
    ("src/io", "src/core/internal.h"),
    ("src/render", "src/core/internal.h"),
    # the core's CDFs and alias tables, inside the core library
    ("src/envmap", "src/core/distrib.h"),
    ("src/luminaire", "src/core/distrib.h"),
    ("src/lights", "src/core/distrib.h"),
    # light sets are made from an environment map's internals, inside the core library
    ("src/lights", "src/envmap/internal.h"),
    # programs that measure or generate internals (they link the static libraries)
    ("bench/bench_pick.c", "src/envmap/sampler_method.h"),
    ("bench/bench_warps.c", "src/envmap/sampler_method.h"),
    ("bench/bench_render.c", "src/render/internal.h"),
    ("fuzz/fuzz_scene.c", "src/render/internal.h"),
    ("tools/fhis_lut.c", "src/lights/fhis_lut.h"),
    ("tools/fhis_lut.c", "src/lights/penrose.h"),
}

STANDARD_C = {
    "assert.h", "complex.h", "ctype.h", "errno.h", "fenv.h", "float.h", "inttypes.h",
    "iso646.h", "limits.h", "locale.h", "math.h", "setjmp.h", "signal.h", "stdalign.h",
    "stdarg.h", "stdatomic.h", "stdbool.h", "stddef.h", "stdint.h", "stdio.h", "stdlib.h",
    "stdnoreturn.h", "string.h", "tgmath.h", "time.h", "uchar.h", "wchar.h", "wctype.h",
}
INTRINSICS = {"emmintrin.h", "immintrin.h", "xmmintrin.h", "pmmintrin.h", "smmintrin.h",
              "nmmintrin.h", "x86intrin.h", "cpuid.h"}
NOT_IN_IO = re.compile(r"^(embree\d*/|assimp/|omp\.h$)")

INCLUDE = re.compile(r'^\s*#\s*include\s*([<"])([^>"]+)[>"]', re.M)


def rel(path):
    return os.path.relpath(path, ROOT).replace(os.sep, "/")


def module_of(path):
    """The floor of a file of the tree (None: not checked)."""
    r = rel(path)
    if r.startswith("include/lumis/"):
        return PUBLIC.get(os.path.basename(r), "?")
    m = re.match(r"(src/[^/]+)/", r)
    if m:
        return m.group(1) if m.group(1) in FLOORS else "?"
    for mod in TOOL_MODULES:
        if r.startswith(mod + "/"):
            return mod
    if r.startswith(TOP_DIRS):
        return "top"
    return None


def resolve(including, name):
    """The file an include names (relative, then the include paths the build gives)."""
    for base in (os.path.dirname(including), os.path.join(ROOT, "include"),
                 os.path.join(ROOT, "src"), os.path.join(ROOT, "tests")):
        p = os.path.normpath(os.path.join(base, name))
        if os.path.isfile(p):
            return p
    return None


def files():
    for top in ("include/lumis", "src") + TOP_DIRS:
        for d, _, names in os.walk(os.path.join(ROOT, top)):
            for n in sorted(names):
                if n.endswith((".c", ".h", ".cpp")):
                    yield os.path.join(d, n)


def check_file(path):
    errors = []
    own = module_of(path)
    if own is None:
        return errors
    r = rel(path)
    if own == "?":
        return [f"{r}: not on any floor of scripts/check-includes.py (add its module)"]
    text = open(path, encoding="utf-8", errors="replace").read()
    for m in INCLUDE.finditer(text):
        kind, name = m.groups()
        line = text.count("\n", 0, m.start()) + 1
        where = f"{r}:{line}: #include {kind}{name}{'>' if kind == '<' else kind}"
        if kind == "<":
            core = LIBRARY[own] == "lumis"
            if (core or r.startswith("include/")) and name not in STANDARD_C | INTRINSICS:
                errors.append(f"{where}: the core and the public headers are C11 and libm "
                              "only")
            elif own == "src/io" and NOT_IN_IO.match(name):
                errors.append(f"{where}: lumis-io does not use the renderer's libraries")
            continue
        target = resolve(path, name)
        if target is None:
            errors.append(f"{where}: no such header")
            continue
        tr = rel(target)
        tmod = module_of(target)
        if tmod is None or tmod == "?":
            # programs share their own helpers, and the tests' file generators
            if not (own == "top" and tr.startswith(TOP_DIRS + ("tests/",))):
                errors.append(f"{where}: {tr} is on no floor")
            continue
        if FLOORS.index(tmod) > FLOORS.index(own):
            errors.append(f"{where}: {tmod} is a higher floor than {own} (ARCHITECTURE.md)")
            continue
        if tr.startswith("src/") and tmod != own:
            if (own, tr) not in ALLOWED and (r, tr) not in ALLOWED:
                errors.append(f"{where}: {tr} is private to {tmod}; publish what is needed "
                              "or add a reasoned entry to ALLOWED")
    return errors


def main():
    errors = [e for p in files() for e in check_file(p)]
    for e in errors:
        print("check-includes: " + e)
    if errors:
        print(f"check-includes: {len(errors)} forbidden include(s)")
        return 1
    print("check-includes: every include keeps to its floor")
    return 0


if __name__ == "__main__":
    sys.exit(main())
