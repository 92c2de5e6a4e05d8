#!/usr/bin/env python3
"""Every public function has a stated oracle (issue 37): each test module opens with a block

    /* Oracles:
       lumis_function — <oracle kind>: <what> (<test function>)
       ... */

naming the public functions it guards and what it checks them against.  This script
extracts every function declared in include/lumis/*.h (declarations over several lines,
static inline definitions, an optional leading export macro (LUMIS_API, LUMIS_IO_API, LUMIS_RENDER_API); not macros, typedefs or
function-pointer members) and fails, listing them, when a public function is named in no
test module's block or when a block names a function that is not public.

    scripts/check-oracles.py [SOURCE_DIR] [--list] [--summary]

--list prints the public functions; --summary counts the functions by the strongest
oracle kind stated for them (see tests/ORACLES.md)."""
import argparse
import glob
import os
import re
import sys

# The kinds of oracle (a line's kind is its text up to the first ':'), in five classes,
# strongest first: an independent value; only through another public function that has
# one; only agreement with other lumis functions; only the refusals of bad arguments;
# nothing.
INDEPENDENT = "independent"
INDIRECT = "indirect"
CONSISTENCY = "consistency"
ERRORS = "error paths only"
NONE = "none"
KINDS = {
    "closed form": INDEPENDENT,  # a formula written out in the test
    "brute force": INDEPENDENT,  # a quadrature, sum or naive algorithm written for the test
    "hand-worked": INDEPENDENT,  # values worked out by hand for a small case
    "invariance": INDEPENDENT,  # brightness scale, rotation, mirror, permutation
    "metamorphic": INDEPENDENT,  # a relation between two runs (halves sum to the whole)
    "external": INDEPENDENT,  # a real file, reference implementation, tool or consumer
    "statistical": INDEPENDENT,  # chi-square, pdf integrates to 1, unbiasedness
    "indirect": INDIRECT,  # only inside another public function that has an oracle
    "consistency": CONSISTENCY,  # only agreement with another lumis function
    "error paths only": ERRORS,
    "error paths": ERRORS,  # after another kind: "hand-worked: ...; error paths: ..."
    "none": NONE,
}


def strip_comments(text):
    text = re.sub(r"/\*.*?\*/", lambda m: "\n" * m.group(0).count("\n"), text, flags=re.S)
    return re.sub(r"//[^\n]*", "", text)


def top_level_statements(text):
    """The file's statements outside any braces (an extern "C" block does not count as
    braces), each ending at ';' or at the '{' of a definition's body."""
    lines, directive = [], False
    for line in text.split("\n"):  # blank preprocessor lines, with their continuations
        directive = directive or line.lstrip().startswith("#")
        lines.append("" if directive else line)
        directive = directive and line.rstrip().endswith("\\")
    text = "\n".join(lines)
    text = re.sub(r'extern\s+"C"\s*\{', " ", text)
    out, cur, depth = [], [], 0
    for ch in text:
        if depth == 0:
            if ch == ";":
                out.append("".join(cur))
                cur = []
            elif ch == "{":
                out.append("".join(cur))
                cur = []
                depth = 1
            elif ch == "}":  # the end of an extern "C" block
                cur = []
            else:
                cur.append(ch)
        elif ch == "{":
            depth += 1
        elif ch == "}":
            depth -= 1
    return out


DECL = re.compile(
    r"^(?:LUMIS_(?:IO_|RENDER_)?API\s+)?(?:(?:static|inline|extern|const|unsigned|signed|struct|enum)\s+)*"
    r"[A-Za-z_]\w*[\s\*]+(?:const[\s\*]+)*(lumis_\w+)\s*\(",
)


def public_functions(root):
    names = {}
    for h in sorted(glob.glob(os.path.join(root, "include", "lumis", "*.h"))):
        with open(h, encoding="utf-8") as f:
            text = strip_comments(f.read())
        for st in top_level_statements(text):
            st = " ".join(st.split())
            if not st or st.startswith("typedef"):
                continue
            m = DECL.match(st)
            if m:
                names.setdefault(m.group(1), os.path.relpath(h, root))
    return names


ENTRY = re.compile(r"^\s*\*?\s*(lumis_\w+)\s*(?:—|--|-)\s*(.*)$")


def oracle_blocks(root):
    """{test file: [(function, text)]} from each module's '/* Oracles:' block."""
    files = sorted(glob.glob(os.path.join(root, "tests", "*.c")) +
                   glob.glob(os.path.join(root, "tests", "stat", "*.c")))
    blocks = {}
    for path in files:
        with open(path, encoding="utf-8") as f:
            text = f.read()
        m = re.search(r"^/\* Oracles:[ \t]*\n(.*?)\*/", text, re.S | re.M)
        if not m:
            continue
        entries = []
        for line in m.group(1).split("\n"):
            e = ENTRY.match(line)
            if e:
                entries.append((e.group(1), e.group(2).strip()))
            elif line.strip() and entries:  # a continuation of the previous entry
                name, rest = entries[-1]
                entries[-1] = (name, rest + " " + line.strip().lstrip("* "))
        blocks[os.path.relpath(path, root)] = entries
    return blocks


def kind_of(text):
    """The strongest class among an entry's kinds, or None when its first kind is not in
    KINDS.  An entry names its kinds before a ':' ("statistical, closed form: ..."), and may
    add others after a '; ' ("consistency: ...; hand-worked: ...")."""
    parts = re.findall(r"(?:^|; )([a-z][a-z ,-]*):", text)
    if not parts or not text.startswith(parts[0]):
        return None
    classes = []
    for i, part in enumerate(parts):
        kinds = [k.strip() for k in part.split(",")]
        if all(k in KINDS for k in kinds):
            classes += [KINDS[k] for k in kinds]
        elif i == 0:
            return None
    return min(classes, key=RANK.index)


RANK = [INDEPENDENT, INDIRECT, CONSISTENCY, ERRORS, NONE]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("root", nargs="?", default=os.path.join(os.path.dirname(__file__), ".."))
    ap.add_argument("--list", action="store_true", help="print the public functions")
    ap.add_argument("--summary", action="store_true", help="count functions by oracle kind")
    args = ap.parse_args()
    root = os.path.abspath(args.root)
    public = public_functions(root)
    if args.list:
        for name in sorted(public):
            print(f"{public[name]}: {name}")
        return 0
    blocks = oracle_blocks(root)
    stated = {}
    bad = []
    for path, entries in blocks.items():
        for name, text in entries:
            if name not in public:
                bad.append(f"{path}: {name} is not a public function (include/lumis/*.h)")
            elif kind_of(text) is None:
                bad.append(f"{path}: {name}: '{text.split(':', 1)[0]}' is not a kind of oracle "
                           f"({', '.join(KINDS)})")
            else:
                stated.setdefault(name, []).append((path, text))
    missing = sorted(set(public) - set(stated))
    for name in missing:
        bad.append(f"{public[name]}: {name} is named in no test module's Oracles: block")
    if args.summary:
        rank = RANK
        best = {n: min((kind_of(t) or NONE for _, t in s), key=rank.index)
                for n, s in stated.items()}
        print(f"{len(public)} public functions, {len(stated)} with a stated oracle")
        for k in rank:
            names = sorted(n for n, b in best.items() if b == k)
            print(f"  {k}: {len(names)}")
            if k != INDEPENDENT:
                for n in names:
                    print(f"    {n}")
    if bad:
        print("check-oracles: " + str(len(bad)) + " problem(s):", file=sys.stderr)
        for b in bad:
            print("  " + b, file=sys.stderr)
        return 1
    if not args.summary:
        print(f"check-oracles: every one of {len(public)} public functions has a stated oracle "
              f"in {len(blocks)} test modules")
    return 0


if __name__ == "__main__":
    sys.exit(main())
