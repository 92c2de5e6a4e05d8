#!/usr/bin/env python3
"""Each library exports exactly the functions its public headers declare.

    scripts/check-exports.py LIBRARY...        # liblumis*.a or liblumis*.so*
    scripts/check-exports.py --shared [DIR]    # build the shared libraries in DIR (default
                                               # build-shared) and check them

The libraries are compiled with hidden visibility and every public declaration carries its
library's export macro (lumis/export.h), so a shared library's dynamic symbol table is its
interface.  This fails on a symbol a library exports that no public header of that library
declares (a lumis__ helper, a C++ template, a public function of another library's
header), and on a declared function the library does not export (a missing export macro, a
declaration nobody defines).

A static archive is read as the shared library would be linked: its defined global symbols
of default visibility (readelf).  That is cheap, so ctest runs it on the build's archives
(check_exports); CI builds the shared libraries too (--shared), which also proves that they
link with -Wl,--no-undefined (no library calls another's hidden helper) and that the tool
and examples/ link against the exported functions alone.
"""
import os
import re
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import public_api  # noqa: E402

# Symbols the linker defines in every shared object, and the compiler's and runtimes' own
# (reserved names: sanitizer and coverage builds add some).
LINKER_SYMBOLS = {"_init", "_fini", "_edata", "_end"}


def ours(name):
    return name not in LINKER_SYMBOLS and not name.startswith("__")


def vague(name, weak):
    """A C++ template or inline function instantiated from a third-party header (OpenEXR's
    Imath, libstdc++), weak and with the visibility that header gives it: an unoptimised build
    keeps such copies out of line, an optimised one inlines them.  Not part of lumis's API
    and not a lumis__ helper: C names and strong symbols are all checked."""
    return weak and name.startswith("_Z")


def library_name(path):
    m = re.match(r"lib(lumis(?:-io|-render)?)\.(?:a|so)", os.path.basename(path))
    if not m:
        sys.exit(f"check-exports: {path}: not one of liblumis, liblumis-io, liblumis-render")
    return m.group(1)


def exported(path):
    """The names a library exports (a shared object) or would export (a static archive)."""
    if ".so" in os.path.basename(path):
        out = subprocess.run(["nm", "-D", "--defined-only", path], check=True,
                             capture_output=True, text=True).stdout
        names = {f[-1] for f in (line.split() for line in out.splitlines())
                 if len(f) >= 3 and not vague(f[-1], f[1] in ("W", "V", "u"))}
        return {n.split("@")[0] for n in names if ours(n)}
    out = subprocess.run(["readelf", "-sW", path], check=True, capture_output=True,
                         text=True).stdout
    names = set()
    for line in out.splitlines():
        f = line.split()
        # Num: Value Size Type Bind Vis Ndx Name
        if (len(f) >= 8 and f[0].endswith(":") and f[4] in ("GLOBAL", "WEAK")
                and f[5] == "DEFAULT" and f[6] != "UND" and f[3] in ("FUNC", "OBJECT", "IFUNC")):
            if ours(f[7]) and not vague(f[7], f[4] == "WEAK"):
                names.add(f[7])
    return names


def check(paths):
    declared = public_api.public_functions()
    bad = 0
    for path in paths:
        lib = library_name(path)
        have = exported(path)
        want = declared[lib]
        macro = public_api.MACRO_OF_LIBRARY[lib]
        before = bad
        for name in sorted(have - set(want)):
            where = next((f"{h} ({other})" for other in public_api.LIBRARIES
                          for n, h in declared[other].items() if n == name), None)
            why = (f"declared in {where}, another library's header" if where
                   else "declared in no public header: static, or a lumis__ helper left "
                        "visible")
            print(f"check-exports: {path}: exports {name}: {why}")
            bad += 1
        for name in sorted(set(want) - have):
            print(f"check-exports: {path}: does not export {name} (include/lumis/{want[name]}): "
                  f"declare it {macro}, or define it in {lib}")
            bad += 1
        if bad == before:
            print(f"check-exports: {path}: {len(have)} functions, the public headers' {len(want)}")
    return bad


def shared_build(build_dir):
    root = public_api.ROOT
    cmake = ["cmake", "-S", root, "-B", build_dir, "-DBUILD_SHARED_LIBS=ON",
             "-DLUMIS_BUILD_TESTS=OFF", "-DLUMIS_BUILD_BENCH=OFF", "-DLUMIS_WERROR=ON",
             "-DCMAKE_BUILD_TYPE=RelWithDebInfo"]
    subprocess.run(cmake, check=True, stdout=subprocess.DEVNULL)
    targets = ["lumis", "lumis-io", "lumis-render", "lumis-cli", "wu_session"]
    jobs = os.environ.get("JOBS", "2")
    subprocess.run(["cmake", "--build", build_dir, "-j" + jobs, "--target"] + targets,
                   check=True)
    return [os.path.join(build_dir, f"lib{lib}.so") for lib in public_api.LIBRARIES]


def main(argv):
    if argv[:1] == ["--shared"]:
        paths = shared_build(argv[1] if len(argv) > 1 else "build-shared")
    elif argv and not any(a.startswith("-") for a in argv):
        paths = argv
    else:
        sys.exit(__doc__)
    bad = check(paths)
    if bad:
        print(f"check-exports: {bad} difference(s) between the exported symbols and "
              "include/lumis/ (lumis/export.h says how a function is exported)")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
