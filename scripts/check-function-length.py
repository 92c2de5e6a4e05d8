#!/usr/bin/env python3
"""No function in tools/ longer than 120 lines (issue 38 item 2).

    scripts/check-function-length.py [ROOT] [--max N] [--top K]

Reads every .c and .h file under ROOT/tools (ROOT: the repository, by default this
script's) and prints one line per function longer than the limit:
    path:line: function: N lines (max 120)
and exits 1 if there is any.  --top K also prints the K longest functions, longest first
(information only).

The parsing is tolerant, not a C parser; it holds for the project's clang-format style
(BreakBeforeBraces: Linux), where a function's body opens with a `{` alone at column 0
and closes with a `}` at column 0, and a struct's or an initializer's `{` is on the line
that opens it.  A function starts at the last line before its `{` that begins at column 0
with neither a blank, a comment, a preprocessor line nor a brace (its signature's first
line: continuation lines are indented), and ends at the next `}` at column 0; its length
counts both lines and all between.  Its name is the identifier before the signature's
first `(`.
"""
import os
import re
import sys

LIMIT = 120


def functions(path):
    """(name, first line, length) of each function of the file at path."""
    with open(path, encoding="utf-8", errors="replace") as f:
        lines = f.read().split("\n")
    found = []
    start = None  # index of the last column-0 line that may begin a declaration
    i = 0
    while i < len(lines):
        line = lines[i]
        if line.startswith("{"):
            if start is not None:
                end = i + 1
                while end < len(lines) and not lines[end].startswith("}"):
                    end += 1
                signature = " ".join(lines[start:i])
                m = re.search(r"([A-Za-z_]\w*)\s*\(", signature)
                name = m.group(1) if m else "?"
                found.append((name, start + 1, min(end, len(lines) - 1) - start + 1))
                i = end + 1
                start = None
                continue
        elif line[:1] and (line[0].isalpha() or line[0] == "_"):
            start = i
        elif line.startswith("}") or line.startswith("#"):
            start = None
        i += 1
    return found


def main(argv):
    args = list(argv)
    limit, top = LIMIT, 0
    if "--max" in args:
        k = args.index("--max")
        limit = int(args[k + 1])
        del args[k:k + 2]
    if "--top" in args:
        k = args.index("--top")
        top = int(args[k + 1])
        del args[k:k + 2]
    root = os.path.abspath(args[0] if args else
                           os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    tools = os.path.join(root, "tools")
    if not os.path.isdir(tools):
        print("check-function-length: no folder %s" % tools, file=sys.stderr)
        return 2
    every = []
    for folder, dirs, files in os.walk(tools):
        dirs.sort()
        for name in sorted(files):
            if name.endswith((".c", ".h")):
                path = os.path.join(folder, name)
                rel = os.path.relpath(path, root)
                every += [(rel, fn, line, n) for fn, line, n in functions(path)]
    if not every:
        print("check-function-length: no function found under %s" % tools, file=sys.stderr)
        return 2
    over = [f for f in every if f[3] > limit]
    for rel, fn, line, n in over:
        print("%s:%d: %s: %d lines (max %d)" % (rel, line, fn, n, limit))
    if top:
        for rel, fn, line, n in sorted(every, key=lambda f: -f[3])[:top]:
            print("  %4d  %s  (%s:%d)" % (n, fn, rel, line))
    return 1 if over else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
