#!/usr/bin/env python3
"""The functions the public headers declare, by library (scripts/check-exports.py uses it).

A declaration is a top-level statement of include/lumis/*.h that ends in ';', has a
parameter list and is neither a typedef nor static (static inline helpers are compiled
into the caller, never exported).  Comments and preprocessor lines are blanked first, with
their offsets kept, so that a position found here is a position in the file.

    python3 scripts/public_api.py [--unmarked]   # every declaration: library, header, name
"""
import os
import re
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
INCLUDE = os.path.join(ROOT, "include", "lumis")

# Which library defines the functions of each public header; every other header is the
# core's (lumis).  The export macro of each library is named beside it (lumis/export.h).
LIBRARY_OF_HEADER = {"io.h": "lumis-io", "render.h": "lumis-render", "bsdf.h": "lumis-render"}
MACRO_OF_LIBRARY = {"lumis": "LUMIS_API", "lumis-io": "LUMIS_IO_API",
                    "lumis-render": "LUMIS_RENDER_API"}
LIBRARIES = ("lumis", "lumis-io", "lumis-render")


def library_of(header):
    # render.h includes its parts, render_*.h (scene, lighting, job, ...): all the renderer's
    if header.startswith("render_"):
        return "lumis-render"
    return LIBRARY_OF_HEADER.get(header, "lumis")


def blank(text):
    """Comments, string literals and preprocessor lines replaced by spaces (newlines kept)."""
    out = list(text)

    def wipe(a, b):
        for k in range(a, b):
            if out[k] != "\n":
                out[k] = " "

    for m in re.finditer(r'/\*.*?\*/|//[^\n]*|"(?:\\.|[^"\\\n])*"', text, re.S):
        wipe(m.start(), m.end())
    s = "".join(out)
    # preprocessor lines, with their continuations
    for m in re.finditer(r"^[ \t]*#(?:[^\n]*\\\n)*[^\n]*", s, re.M):
        wipe(m.start(), m.end())
    return "".join(out)


def declarations(path):
    """[(name, start offset of the declaration, declaration text)] of one header."""
    text = open(path, encoding="utf-8").read()
    s = blank(text)
    found = []
    depth = 0  # braces of structs, unions, enums and inline bodies (extern "C" is blanked)
    start = 0
    k = 0
    while k < len(s):
        c = s[k]
        if c == "{":
            # extern "C" { (the string is blanked: `extern   {`) does not count
            if depth == 0 and re.search(r"\bextern\s*$", s[start:k]):
                start = k + 1
                k += 1
                continue
            depth += 1
        elif c == "}":
            if depth == 0:  # the end of extern "C"
                start = k + 1
            else:
                depth -= 1
                if depth == 0 and re.search(r"\)\s*$", s[start:k].split("{")[0]):
                    start = k + 1  # the end of an inline function's body
        elif c == ";" and depth == 0:
            stmt = s[start:k]
            lead = len(stmt) - len(stmt.lstrip())
            body = " ".join(stmt.split())
            if ("(" in body and not re.match(r"(typedef|static)\b", body)
                    and not re.search(r"\b(typedef|struct|union|enum)\b[^(]*\{", body)):
                m = re.search(r"([A-Za-z_]\w*)\s*\(", body)
                # a function pointer variable `T (*name)(...)` is not a function
                if m and not re.search(r"\(\s*\*", body[: m.end() + 1]):
                    found.append((m.group(1), start + lead, body))
            start = k + 1
        k += 1
    return found


def public_functions():
    """{library: {name: header}} of every declared function."""
    out = {lib: {} for lib in LIBRARIES}
    for header in sorted(os.listdir(INCLUDE)):
        if not header.endswith(".h"):
            continue
        for name, _, _ in declarations(os.path.join(INCLUDE, header)):
            out[library_of(header)][name] = header
    return out


def main():
    unmarked = "--unmarked" in sys.argv[1:]
    bad = 0
    for header in sorted(os.listdir(INCLUDE)):
        if not header.endswith(".h"):
            continue
        lib = library_of(header)
        for name, _, body in declarations(os.path.join(INCLUDE, header)):
            marked = body.startswith(MACRO_OF_LIBRARY[lib] + " ")
            if unmarked and not marked:
                print(f"include/lumis/{header}: {name} is not declared {MACRO_OF_LIBRARY[lib]}")
                bad += 1
            elif not unmarked:
                print(lib, header, name)
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
