#!/usr/bin/env python3
"""Generated mutants (issue 37): mutants of the C sources made from libclang's AST, run
against each module's own test programs (tests/mutants/README.md, "Generated mutants").

  scripts/mutagen.py diff [--base REF]        the lines changed since REF (make mutate-diff)
  scripts/mutagen.py all [--sample N]         every line of src/ (make mutate-gen)
  scripts/mutagen.py list FILE... [--lines A-B] [--args ...]   print the mutants, run none
                                              (the generator's own test uses this)

Each file is parsed as the compiler sees it (the flags of compile_commands.json), and the
mutants come from the AST's nodes and tokens, never from the text alone:

  binop    + <-> -, * <-> /, < -> <=, <= -> <, > -> >=, >= -> >, == <-> !=, && <-> ||,
           & <-> |, << <-> >>, += <-> -=, *= <-> /= (pointer - pointer left alone)
  const    integer 0 -> 1, 1 -> 0, n -> n+1; floating 0 -> 1, |x| >= 1 -> 2x, |x| < 1 -> x/2
  unary    -x -> x, !x -> x, ~x -> x, ++ <-> --
  argswap  f(a, b) -> f(b, a) for neighbouring arguments of the same type
  delete   an expression statement (call, assignment, ++/--), continue, break, an early
           return of a void function
  retval   return e -> return 0 (1 where e is the literal 0) in a function returning a
           number, an enum or a pointer
  cond     if (c) -> if (1) and if (0)

Nothing inside a macro expansion, a static assertion, an array declarator's size or a
table's initializer (more than 16 values) is mutated; calls to free, *_destroy, fclose and
close are not deleted (a leak is the sanitizers' job), nor __builtin_prefetch (a hint).  A mutant is applied to a copy of the sources
(build-mutgen/tree), the module's test programs are rebuilt in build-mutgen/build and run
until one fails (killed), each under a timeout of 10x its unmutated time (timeout, counted
as killed), or none does (survived).  A mutant that does not compile is "uncompilable",
neither killed nor survived.  Order and sampling are fixed by --seed.
"""
import argparse
import bisect
import glob
import hashlib
import json
import os
import random
import re
import shlex
import shutil
import subprocess
import sys
import time

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), '..'))

# ---- the test programs of each module ---------------------------------------------------
# src/DIR -> the CTest programs that test it (its own tests, not the end-to-end ones; the
# CLI's and the data's tests are left out: they take minutes).  A file's tests named in the
# curated lists (tests/mutants/*.txt) run first.
MODULE_TESTS = {
    'src/core': ['test_core', 'test_sequence'],
    'src/envmap': ['test_envmap', 'test_sky', 'test_samplers'],
    'src/lights': ['test_lights', 'test_regions', 'test_sun'],
    'src/luminaire': ['test_luminaire', 'test_photometric', 'test_photometric_files',
                      'test_photometric_sampling', 'test_photometric_corpus'],
    'src/metrics': ['test_metrics', 'test_metrics_flip'],
    'src/io': ['test_io', 'test_luminaire_io', 'test_photometric_files', 'test_photometric'],
    'src/render': ['test_render', 'test_bsdf', 'test_sequence', 'test_render_luminaire',
                   'test_render_photometric'],
}
# and for every directory: the edges of every public function (absurd arguments) and an
# allocation failure at every allocation of the libraries (4 s together)
EVERY_MODULE = ['test_edges', 'test_nomem']

BINOP = {'+': '-', '-': '+', '*': '/', '/': '*', '<': '<=', '<=': '<', '>': '>=', '>=': '>',
         '==': '!=', '!=': '==', '&&': '||', '||': '&&', '&': '|', '|': '&', '<<': '>>',
         '>>': '<<'}
COMPOUND = {'+=': '-=', '-=': '+=', '*=': '/=', '/=': '*='}
UNARY_DROP = ('-', '!', '~')
INCDEC = {'++': '--', '--': '++'}
# deleting these leaks (a sanitizer's or memcheck's find) or changes no result (a hint)
NO_DELETE = re.compile(r'^(free|.*_destroy|.*_free|fclose|close|closedir|__builtin_prefetch)$')
# their arguments swapped give the same value: an equivalent mutant, not generated
# (libm's, and the project's vector helpers: src/render/vec.h, src/lights/env_direct.c)
COMMUTATIVE = {'fmin', 'fmax', 'fminf', 'fmaxf', 'fminl', 'fmaxl', 'hypot', 'hypotf',
               'dot', 'dot3', 'add'}
TABLE = 16  # initializer lists longer than this are tables: their numbers are not mutated


def restore_devices():
    """A mutant of the output guard (src/io/atomic.c: never rename over a device) lets a
    test that writes to /dev/null, run as root, replace it with a regular file: the test
    kills the mutant, but leaves the machine without /dev/null.  Put the devices back."""
    for name, minor in (('null', 3), ('full', 7)):
        path = '/dev/' + name
        if os.path.exists(path) and not os.path.isfile(path):
            continue
        print(f'mutagen: {path} was replaced by a mutant; restoring it', file=sys.stderr)
        try:
            if os.path.lexists(path):
                os.remove(path)
            os.mknod(path, 0o666 | 0o020000, os.makedev(1, minor))
            os.chmod(path, 0o666)
        except OSError:
            pass


def die(msg, code=2):
    print('mutagen: ' + msg, file=sys.stderr)
    sys.exit(code)


# ---- libclang ----------------------------------------------------------------------------
def load_cindex():
    """clang.cindex from Debian's python3-clang-N, and the libclang .so that matches it."""
    try:
        import clang.cindex as ci
    except ImportError:
        # a python3 other than Debian's (pyenv, venv) does not see dist-packages
        for p in ['/usr/lib/python3/dist-packages'] + sorted(
                glob.glob('/usr/lib/llvm-*/lib/python3*/site-packages')):
            if os.path.isdir(os.path.join(p, 'clang')) and p not in sys.path:
                sys.path.append(p)
        try:
            import clang.cindex as ci
        except ImportError:
            return None, 'no clang.cindex (Debian: apt-get install python3-clang-14)'
    lib = os.environ.get('LUMIS_LIBCLANG')
    if not lib:
        cands = []
        try:
            libdir = subprocess.run(['llvm-config', '--libdir'], capture_output=True,
                                    text=True).stdout.strip()
            if libdir:
                cands += sorted(glob.glob(libdir + '/libclang.so*'))
        except OSError:
            pass
        # Debian: /usr/lib/llvm-N/lib/libclang.so.1 (libclang1-N); the bindings of
        # python3-clang-N match version N, so the newest of those present first
        def ver(p):
            m = re.search(r'llvm-(\d+)|libclang-(\d+)', p)
            return int(m.group(1) or m.group(2)) if m else 0
        found = glob.glob('/usr/lib/llvm-*/lib/libclang.so*') + \
            glob.glob('/usr/lib/*/libclang-*.so*') + glob.glob('/usr/lib/*/libclang.so*')
        cands += sorted(found, key=lambda p: (-ver(p), len(p)))
        cands = [c for c in cands if os.path.isfile(c)]
        if not cands:
            return None, 'no libclang shared library (Debian: apt-get install libclang1-14)'
        lib = cands[0]
    try:
        ci.Config.set_library_file(lib)
        ci.Index.create()
    except Exception as e:  # noqa: BLE001 (any failure to load is the same answer)
        return None, 'libclang %s does not load: %s' % (lib, e)
    return ci, lib


# ---- compile flags -----------------------------------------------------------------------
def load_compdb(path):
    with open(path) as f:
        entries = json.load(f)
    out = {}
    for e in entries:
        args = e['arguments'] if 'arguments' in e else shlex.split(e['command'])
        out[e['file']] = (e['directory'], args)
    return out


def parse_args_for(compdb, rel):
    """The compile command of the entry whose file ends with /REL, as clang arguments
    (compiler, -c, -o and the source removed; GCC-only options dropped)."""
    for fname, (d, args) in sorted(compdb.items()):
        if fname.endswith('/' + rel):
            out = []
            skip = False
            for a in args[1:]:
                if skip:
                    skip = False
                    continue
                if a in ('-o', '-MF', '-MT', '-MQ'):
                    skip = True
                    continue
                if a == '-c' or a == fname or a.endswith('/' + rel) or a in ('-MD', '-MMD'):
                    continue
                if a.startswith(('-fvect-cost-model', '-fprofile-update')):
                    continue
                out.append(a)
            obj = None
            for i, a in enumerate(args):
                if a == '-o' and i + 1 < len(args):
                    obj = os.path.join(d, args[i + 1])
            return out, obj
    return None, None


# ---- the generator -----------------------------------------------------------------------
class Tokens:
    """The file's tokens by offset: libclang's token list, read once."""

    def __init__(self, ci, tu, path):
        f = tu.get_file(path)
        size = os.path.getsize(path)
        ext = ci.SourceRange.from_locations(ci.SourceLocation.from_offset(tu, f, 0),
                                            ci.SourceLocation.from_offset(tu, f, size))
        self.toks = [(t.extent.start.offset, t.extent.end.offset, t.kind.name, t.spelling)
                     for t in tu.get_tokens(extent=ext)]
        self.starts = [t[0] for t in self.toks]

    def first_at_or_after(self, off):
        i = bisect.bisect_left(self.starts, off)
        return self.toks[i] if i < len(self.toks) else None

    def at(self, off):
        i = bisect.bisect_left(self.starts, off)
        return self.toks[i] if i < len(self.toks) and self.starts[i] == off else None

    def before(self, off):
        i = bisect.bisect_left(self.starts, off) - 1
        return self.toks[i] if i >= 0 else None

    def last_before(self, end):
        i = bisect.bisect_left(self.starts, end) - 1
        return self.toks[i] if i >= 0 else None


def fmt_float(v, suffix):
    s = repr(v)
    if 'e' not in s and '.' not in s and 'inf' not in s and 'nan' not in s:
        s += '.0'
    return s + suffix


def const_mutation(kind, text):
    """The replacement of a literal's token, or None."""
    if kind == 'INTEGER_LITERAL':
        m = re.fullmatch(r'(0[xX][0-9a-fA-F]+|0[0-7]*|[1-9][0-9]*)([uUlL]*)', text)
        if not m:
            return None
        body, suf = m.groups()
        if body[:2] in ('0x', '0X'):
            v = int(body, 16)
            fmt = lambda n: hex(n)  # noqa: E731
        elif len(body) > 1 and body[0] == '0':
            v = int(body, 8)
            fmt = lambda n: '0' + oct(n)[2:]  # noqa: E731
        else:
            v = int(body)
            fmt = str
        n = 1 if v == 0 else 0 if v == 1 else v + 1
        return fmt(n) + suf
    if kind == 'FLOATING_LITERAL':
        m = re.fullmatch(r'([0-9]*\.?[0-9]*(?:[eE][-+]?[0-9]+)?)([fFlL]?)', text)
        if not m or not m.group(1) or m.group(1) == '.':
            return None  # hex floats and the like: left alone
        body, suf = m.groups()
        v = float(body)
        if v == 0:
            return '1.0' + suf
        n = v * 2 if abs(v) >= 1 else v / 2
        if n != n or n in (float('inf'), float('-inf')):
            return None
        return fmt_float(n, suf)
    return None


def generate(ci, path, rel, args, lines=None):
    """The mutants of file PATH (shown as REL) whose line is in LINES (None: all).  A header
    is parsed through ARGS['tu'] (a source file that includes it)."""
    tu_path = args.get('tu', path)
    tu = ci.Index.create().parse(tu_path, args=args['flags'],
                                 options=ci.TranslationUnit.PARSE_DETAILED_PROCESSING_RECORD)
    errors = [d for d in tu.diagnostics if d.severity >= 3]
    if errors:
        print('mutagen: warning: %s: %d parse errors (first: %s)' %
              (rel, len(errors), errors[0].spelling), file=sys.stderr)
    with open(path, 'rb') as f:
        src = f.read()
    real = os.path.realpath(path)
    toks = Tokens(ci, tu, path)
    nl = [i for i, ch in enumerate(src) if ch == 10]
    # macro expansions in the file: nothing inside one is mutated (its tokens are not the
    # ones the AST's nodes stand for)
    macro = []
    mutants = []

    def in_file(c):
        loc = c.extent.start
        return loc.file is not None and os.path.realpath(loc.file.name) == real

    def in_macro(a, b):
        for (s, e) in macro:
            if s < b and a < e:
                return True
        return False

    def text(a, b):
        return src[a:b].decode('utf-8', 'replace')

    def add(op, edits, anchor, desc, func):
        edits = sorted(edits)
        line = bisect.bisect_left(nl, anchor) + 1
        if lines is not None and line not in lines:
            return
        for (a, b, _r) in edits:
            if in_macro(a, b):
                return
        new = src
        for (a, b, r) in reversed(edits):
            new = new[:a] + r.encode() + new[b:]
        if new == src:
            return
        a0, b0 = edits[0][0], edits[-1][1]
        mutants.append({
            'file': rel, 'line': line, 'col': anchor - src.rfind(b'\n', 0, anchor),
            'op': op, 'desc': desc, 'function': func,
            'edits': [[a, b, r] for (a, b, r) in edits],
            'original': text(a0, b0),
            'digest': hashlib.sha1(new).hexdigest()[:16],
        })
        m = mutants[-1]
        # the mutated span as it reads after the edits
        shifted = src[a0:b0]
        for (a, b, r) in reversed(edits):
            shifted = shifted[:a - a0] + r.encode() + shifted[b - a0:]
        m['mutated'] = shifted.decode('utf-8', 'replace')
        # the whole source lines, before and after (what a reviewer reads)
        ls = src.rfind(b'\n', 0, a0) + 1
        le = src.find(b'\n', b0)
        le = len(src) if le < 0 else le
        m['line_before'] = src[ls:le].decode('utf-8', 'replace').strip()
        m['line_after'] = (src[ls:a0] + shifted + src[b0:le]).decode('utf-8', 'replace').strip()

    for c in tu.cursor.walk_preorder():
        if c.kind == ci.CursorKind.MACRO_INSTANTIATION and in_file(c):
            macro.append((c.extent.start.offset, c.extent.end.offset))

    K = ci.CursorKind

    def visit(c, parent, func, ret_type, skip_consts):
        kind = c.kind
        if kind in (K.STATIC_ASSERT,) or kind.name == 'STATIC_ASSERT':
            return
        if kind == K.FUNCTION_DECL:
            func = c.spelling
            ret_type = c.result_type
        if kind == K.ENUM_DECL:
            return
        if kind == K.INIT_LIST_EXPR and len(list(c.get_children())) > TABLE:
            skip_consts = True
        children = list(c.get_children())
        here = in_file(c)
        s, e = c.extent.start.offset, c.extent.end.offset
        # (a node that spans a macro expansion is still mutated where the edit lies outside
        # it: add() refuses edits that overlap one)
        if here:
            mutate_node(c, kind, children, parent, func, ret_type, skip_consts, s, e)
        for ch in children:
            visit(ch, c, func, ret_type, skip_consts)

    def op_token_between(lhs, rhs):
        t = toks.first_at_or_after(lhs.extent.end.offset)
        if t is None or t[1] > rhs.extent.start.offset or t[2] != 'PUNCTUATION':
            return None
        return t

    def is_pointer(t):
        return t.get_canonical().kind in (ci.TypeKind.POINTER, ci.TypeKind.CONSTANTARRAY,
                                          ci.TypeKind.INCOMPLETEARRAY)

    def mutate_node(c, kind, children, parent, func, ret_type, skip_consts, s, e):
        if skip_consts:
            return  # inside a table
        if kind in (K.BINARY_OPERATOR, K.COMPOUND_ASSIGNMENT_OPERATOR) and len(children) == 2:
            lhs, rhs = children
            t = op_token_between(lhs, rhs)
            if t is None:
                return
            table = BINOP if kind == K.BINARY_OPERATOR else COMPOUND
            if t[3] in table:
                if t[3] == '-' and is_pointer(lhs.type) and is_pointer(rhs.type):
                    return
                add('binop', [(t[0], t[1], table[t[3]])], t[0],
                    '%s -> %s' % (t[3], table[t[3]]), func)
            return
        if kind == K.UNARY_OPERATOR and len(children) == 1:
            op = children[0]
            first = toks.at(s)
            if first and first[2] == 'PUNCTUATION' and op.extent.start.offset > s:
                if first[3] in UNARY_DROP:
                    add('unary', [(first[0], first[1], '')], first[0],
                        'drop %s' % first[3], func)
                elif first[3] in INCDEC:
                    add('unary', [(first[0], first[1], INCDEC[first[3]])], first[0],
                        '%s -> %s' % (first[3], INCDEC[first[3]]), func)
            else:
                last = toks.last_before(e)
                if last and last[3] in INCDEC and last[0] >= op.extent.end.offset:
                    add('unary', [(last[0], last[1], INCDEC[last[3]])], last[0],
                        '%s -> %s' % (last[3], INCDEC[last[3]]), func)
            return
        if kind in (K.INTEGER_LITERAL, K.FLOATING_LITERAL):
            t = toks.at(s)
            if t is None or t[1] != e or t[2] != 'LITERAL':
                return
            prev = toks.before(s)
            if prev and prev[3] == '[' and parent is not None and parent.kind in (
                    K.VAR_DECL, K.FIELD_DECL, K.PARM_DECL, K.TYPEDEF_DECL):
                return  # an array's size
            r = const_mutation(kind.name, t[3])
            if r is not None:
                add('const', [(s, e, r)], s, '%s -> %s' % (t[3], r), func)
            return
        if kind == K.CALL_EXPR:
            if c.spelling in COMMUTATIVE:
                return
            argl = list(c.get_arguments())
            for a, b in zip(argl, argl[1:]):
                if a.type.get_canonical().spelling != b.type.get_canonical().spelling:
                    continue
                ra = (a.extent.start.offset, a.extent.end.offset)
                rb = (b.extent.start.offset, b.extent.end.offset)
                if not (s <= ra[0] < ra[1] <= rb[0] < rb[1] <= e):
                    continue
                ta, tb = text(*ra), text(*rb)
                if ta == tb or '"' in ta or '"' in tb:
                    continue  # (a message's words swapped: the tests read no messages)
                add('argswap', [(ra[0], ra[1], tb), (rb[0], rb[1], ta)], ra[0],
                    'swap %s, %s' % (ta, tb), func)
            return
        if kind in (K.FOR_STMT, K.WHILE_STMT) and children:
            deletion(children[-1], func, ret_type, last=False)  # a body without braces
            return
        if kind in (K.COMPOUND_STMT, K.IF_STMT):
            stmts = children if kind == K.COMPOUND_STMT else children[1:]
            for i, st in enumerate(stmts):
                deletion(st, func, ret_type, last=(kind == K.COMPOUND_STMT and
                                                   parent is not None and
                                                   parent.kind == K.FUNCTION_DECL and
                                                   i == len(stmts) - 1))
            if kind == K.IF_STMT and children:
                cond = children[0]
                a, b = cond.extent.start.offset, cond.extent.end.offset
                for v in ('1', '0'):
                    add('cond', [(a, b, v)], a, 'if (%s)' % v, func)
            return
        if kind == K.RETURN_STMT and children and ret_type is not None:
            v = children[0]
            tk = ret_type.get_canonical().kind
            TK = ci.TypeKind
            if tk in (TK.POINTER, TK.ENUM, TK.BOOL, TK.INT, TK.UINT, TK.LONG, TK.ULONG,
                      TK.LONGLONG, TK.ULONGLONG, TK.SHORT, TK.USHORT, TK.CHAR_S, TK.SCHAR,
                      TK.UCHAR, TK.FLOAT, TK.DOUBLE, TK.LONGDOUBLE):
                a, b = v.extent.start.offset, v.extent.end.offset
                r = '1' if text(a, b).strip() in ('0', 'NULL', '0.0', '0.0f') else '0'
                add('retval', [(a, b, r)], a, 'return %s' % r, func)

    def deletion(st, func, ret_type, last):
        k = st.kind
        s, e = st.extent.start.offset, st.extent.end.offset
        if k in (K.CONTINUE_STMT, K.BREAK_STMT):
            add('delete', [(s, e, '')], s, 'delete %s' % text(s, e), func)
            return
        if k == K.RETURN_STMT:
            if not list(st.get_children()) and not last:
                add('delete', [(s, e, '')], s, 'delete return', func)
            return
        ch = list(st.get_children())
        if k == K.CALL_EXPR:
            callee = st.spelling or ''
            if NO_DELETE.match(callee):
                return
            add('delete', [(s, e, '')], s, 'delete call %s' % callee, func)
        elif k == K.BINARY_OPERATOR and len(ch) == 2:
            t = op_token_between(ch[0], ch[1])
            if t is not None and t[3] == '=':
                add('delete', [(s, e, '')], s, 'delete assignment', func)
        elif k == K.COMPOUND_ASSIGNMENT_OPERATOR:
            add('delete', [(s, e, '')], s, 'delete assignment', func)
        elif k == K.UNARY_OPERATOR:
            first, last_t = toks.at(s), toks.last_before(e)
            if (first and first[3] in INCDEC) or (last_t and last_t[3] in INCDEC):
                add('delete', [(s, e, '')], s, 'delete %s' % text(s, e), func)

    for c in tu.cursor.get_children():
        visit(c, None, None, None, False)
    # one mutant per distinct mutated file, in source order
    seen = set()
    out = []
    for m in sorted(mutants, key=lambda m: (m['edits'][0][0], m['op'], m['mutated'])):
        if m['digest'] in seen:
            continue
        seen.add(m['digest'])
        m['id'] = '%s:%d:%d:%s:%s' % (rel, m['line'], m['col'], m['op'], m['digest'][:8])
        out.append(m)
    return out


# ---- which lines, which files -----------------------------------------------------------
def git(*a):
    return subprocess.run(['git', '-C', ROOT] + list(a), capture_output=True, text=True)


def main_ref():
    for r in ('main', 'origin/main'):
        if git('rev-parse', '--verify', '-q', r).returncode == 0:
            return r
    return None


def resolve_base(base):
    """auto: the merge base with main, or HEAD~1 when HEAD is on main.
    last-landing: what CI tests on a clone of main: the commit named in .ci/landed (main as
    the previous stop landed it, written at the start of each stop's work) when it is an
    ancestor of HEAD; else the first parent of HEAD if HEAD is a merge, else back along the
    first parents to the newest merge, at most 20 commits."""
    if base == 'auto':
        m = main_ref()
        if m:
            mb = git('merge-base', m, 'HEAD').stdout.strip()
            head = git('rev-parse', 'HEAD').stdout.strip()
            if mb and mb != head:
                return mb
        return 'HEAD~1'
    if base == 'last-landing':
        landed = os.path.join(ROOT, '.ci', 'landed')
        if os.path.exists(landed):
            with open(landed) as f:
                rev = f.read().split('#')[0].strip()
            if rev and git('merge-base', '--is-ancestor', rev, 'HEAD').returncode == 0:
                return rev
            print('mutagen: .ci/landed (%s) is not an ancestor of HEAD; back to the newest merge'
                  % (rev or 'empty'), file=sys.stderr)
        revs = git('rev-list', '--first-parent', '--parents', '-n', '21', 'HEAD').stdout.split('\n')
        revs = [r.split() for r in revs if r.strip()]
        if not revs:
            return 'HEAD~1'
        if len(revs[0]) > 2:
            return revs[0][1]
        for r in revs[1:]:
            if len(r) > 2:  # a merge: the previous landing
                return r[0]
        return revs[-1][0]
    return base


def changed_lines(base):
    """{src/… file: set of lines} changed from BASE to the working tree."""
    r = git('diff', '-U0', '--no-color', '--no-ext-diff', base, '--', 'src')
    if r.returncode != 0:
        die('git diff %s failed: %s' % (base, r.stderr.strip()))
    out = {}
    cur = None
    for ln in r.stdout.split('\n'):
        if ln.startswith('+++ '):
            p = ln[4:]
            cur = p[2:] if p.startswith('b/') else None
            if cur and not cur.endswith(('.c', '.h')):
                cur = None
        elif ln.startswith('@@') and cur:
            m = re.match(r'@@ -\S+ \+(\d+)(?:,(\d+))? @@', ln)
            start, n = int(m.group(1)), int(m.group(2) if m.group(2) is not None else 1)
            out.setdefault(cur, set()).update(range(start, start + n))
    return {f: s for f, s in out.items() if s}


def all_sources():
    out = []
    for d, _ts in sorted(MODULE_TESTS.items()):
        for f in sorted(glob.glob(os.path.join(ROOT, d, '*.[ch]'))):
            out.append(os.path.relpath(f, ROOT))
    return out


def tests_for(rel, curated):
    d = os.path.dirname(rel)
    base = MODULE_TESTS.get(d)
    if base is None:
        return []
    base = base + [t for t in EVERY_MODULE if t not in base]
    first = [t for t in curated.get(rel, []) if t in base or t.startswith('test_')]
    return first + [t for t in base if t not in first]


def curated_tests():
    """file -> the test programs its curated mutants name (tests/mutants/*.txt)."""
    out = {}
    for f in sorted(glob.glob(os.path.join(ROOT, 'tests/mutants/*.txt'))):
        with open(f) as h:
            for rec in h.read().split('\n\n'):
                e = dict(re.findall(r'^(file|test):\s?(.*)$', rec, re.M))
                if 'file' in e and 'test' in e:
                    lst = out.setdefault(e['file'], [])
                    if e['test'] not in lst:
                        lst.append(e['test'])
    return out


# ---- the build and the runs --------------------------------------------------------------
class Runner:
    def __init__(self, opt):
        self.opt = opt
        self.dir = os.path.join(ROOT, opt.dir)
        self.tree = os.path.join(self.dir, 'tree')
        self.build = os.path.join(self.dir, 'build')
        self.pristine = os.path.join(self.dir, 'pristine')
        self.marker = os.path.join(self.dir, 'applied.json')
        self.compdb = None

    def log(self, msg):
        print('mutagen: ' + msg, flush=True)

    def sync(self):
        """The copy of the sources: files whose bytes differ are copied (mtime kept), so the
        build stays incremental; a mutant left by an interrupted run is undone here."""
        if os.path.exists(self.marker):
            with open(self.marker) as f:
                m = json.load(f)
            p = os.path.join(self.tree, m['file'])
            if os.path.exists(p):
                os.utime(p)  # rebuilt from the restored bytes below
            os.remove(self.marker)
        for top in ('CMakeLists.txt', 'cmake', 'include', 'src', 'tests', 'tools', 'fuzz',
                    'bench', 'assets', 'docs/examples', 'examples'):
            src = os.path.join(ROOT, top)
            paths = [src] if os.path.isfile(src) else [
                os.path.join(dp, fn) for dp, _dn, fns in os.walk(src) for fn in fns]
            for p in paths:
                rel = os.path.relpath(p, ROOT)
                dst = os.path.join(self.tree, rel)
                if os.path.exists(dst):
                    with open(p, 'rb') as a, open(dst, 'rb') as b:
                        if a.read() == b.read():
                            continue
                os.makedirs(os.path.dirname(dst), exist_ok=True)
                shutil.copy2(p, dst)
        data = os.path.join(ROOT, 'data')
        link = os.path.join(self.tree, 'data')
        if os.path.isdir(data) and not os.path.islink(link):
            os.symlink(data, link)

    def configure(self):
        r = subprocess.run(['cmake', '-S', self.tree, '-B', self.build,
                            '-DCMAKE_BUILD_TYPE=RelWithDebInfo', '-DLUMIS_BUILD_BENCH=OFF',
                            '-DLUMIS_WERROR=OFF', '-DCMAKE_EXPORT_COMPILE_COMMANDS=ON'],
                           capture_output=True, text=True)
        if r.returncode != 0:
            die('cmake configure failed:\n' + r.stderr[-2000:])
        self.compdb = load_compdb(os.path.join(self.build, 'compile_commands.json'))

    def cmake_build(self, targets, timeout=None):
        cmd = ['cmake', '--build', self.build, '-j%d' % self.opt.jobs, '--target'] + targets
        try:
            r = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout)
        except subprocess.TimeoutExpired:
            return False, 'build timed out'
        return r.returncode == 0, r.stdout[-3000:] + r.stderr[-3000:]

    def run_test(self, t, timeout):
        env = dict(os.environ, CMOCKA_MESSAGE_OUTPUT='stdout',
                   XDG_CACHE_HOME=os.path.join(self.build, 'test-cache'))
        t0 = time.monotonic()
        try:
            p = subprocess.Popen([os.path.join(self.build, 'tests', t)],
                                 cwd=os.path.join(self.build, 'tests'), env=env,
                                 stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                                 start_new_session=True)
            rc = p.wait(timeout=timeout)
        except subprocess.TimeoutExpired:
            os.killpg(p.pid, 9)
            p.wait()
            return 'timeout', time.monotonic() - t0
        finally:
            restore_devices()
        return ('pass' if rc == 0 else 'fail'), time.monotonic() - t0

    def baseline(self, tests):
        ok, outp = self.cmake_build(tests)
        if not ok:
            die('the unmutated build fails:\n' + outp)
        self.normal = {}
        for t in tests:
            res, dt = self.run_test(t, 1800)
            if res != 'pass':
                self.log('warning: %s fails unmutated: left out' % t)
                continue
            self.normal[t] = dt
            self.log('baseline %-28s %6.1f s' % (t, dt))

    def objects(self, rel):
        _flags, obj = parse_args_for(self.compdb, rel)
        return obj

    def save_pristine(self, rels):
        self.pobj = {}
        for rel in rels:
            obj = self.objects(rel)
            if rel.endswith('.c') and obj and os.path.exists(obj):
                dst = os.path.join(self.pristine, rel + '.o')
                os.makedirs(os.path.dirname(dst), exist_ok=True)
                shutil.copy2(obj, dst)
                self.pobj[rel] = (obj, dst)

    def apply(self, m):
        p = os.path.join(self.tree, m['file'])
        with open(p, 'rb') as f:
            orig = f.read()
        st = os.stat(p)
        new = orig
        for (a, b, r) in sorted(m['edits'], reverse=True):
            new = new[:a] + r.encode() + new[b:]
        with open(self.marker, 'w') as f:
            json.dump({'file': m['file']}, f)
        with open(p, 'wb') as f:
            f.write(new)
        # newer than the object file, whatever the clock's grain
        t = time.time_ns()
        if m['file'] in self.pobj and os.path.exists(self.pobj[m['file']][0]):
            t = max(t, os.stat(self.pobj[m['file']][0]).st_mtime_ns + 10**6)
        os.utime(p, ns=(t, t))
        return p, orig, st

    def restore(self, m, p, orig, st):
        with open(p, 'wb') as f:
            f.write(orig)
        if m['file'] in self.pobj:
            # the unmutated object back, newer than its source and than the archive the
            # mutant's build wrote: the next build re-archives it without compiling
            os.utime(p, ns=(st.st_atime_ns, st.st_mtime_ns))
            obj, saved = self.pobj[m['file']]
            shutil.copyfile(saved, obj)
            t = time.time_ns()
            os.utime(obj, ns=(t, t))
        else:
            os.utime(p)  # a header: whatever includes it is rebuilt
        os.remove(self.marker)

    def run_one(self, m, tests, deadline=None):
        """killed, timeout, survived or uncompilable; "not run" when DEADLINE (the time
        budget's end) came first: a mutant cut short is neither killed nor survived."""
        p, orig, st = self.apply(m)
        t0 = time.monotonic()
        left = lambda: (deadline - time.monotonic()) if deadline else 1e9  # noqa: E731
        try:
            for t in tests:
                if left() <= 0:
                    return 'not run', None, time.monotonic() - t0
                ok, out = self.cmake_build([t], timeout=max(1, min(900, left())))
                if not ok:
                    return ('not run' if left() <= 0 else 'uncompilable'), None, \
                        time.monotonic() - t0
                limit = min(self.opt.max_timeout, max(
                    self.opt.min_timeout, self.opt.timeout_factor * self.normal[t]))
                avail = max(1, left())
                res, _dt = self.run_test(t, min(limit, avail))
                if res == 'timeout' and avail < limit:  # the budget's end, not the test's
                    return 'not run', None, time.monotonic() - t0
                if res == 'fail':
                    return 'killed', t, time.monotonic() - t0
                if res == 'timeout':
                    return 'timeout', t, time.monotonic() - t0
            return 'survived', None, time.monotonic() - t0
        finally:
            self.restore(m, p, orig, st)


# ---- selection and reports ---------------------------------------------------------------
def sample(mutants, per_line, total, seed):
    """At most PER_LINE mutants a line and TOTAL in all, drawn with SEED; then in a random
    order fixed by SEED, so a run cut short by its time budget is still a fair sample."""
    rng = random.Random(seed)
    bylines = {}
    for m in mutants:
        bylines.setdefault((m['file'], m['line']), []).append(m)
    kept = []
    for key in sorted(bylines):
        lst = sorted(bylines[key], key=lambda m: m['id'])
        if per_line and len(lst) > per_line:
            lst = sorted(random.Random('%d:%s:%d' % (seed, key[0], key[1])).sample(lst, per_line),
                         key=lambda m: m['id'])
        kept += lst
    if total and len(kept) > total:
        kept = sorted(rng.sample(kept, total), key=lambda m: m['id'])
    rng.shuffle(kept)
    return kept


def write_reports(opt, res, out_json, out_md):
    with open(out_json, 'w') as f:
        json.dump(res, f, indent=1)
    c = res['counts']
    lines = ['# Generated mutants: %s' % res['what'], '',
             '%s; %d mutants generated on %d lines of %d files, %d selected (%s), %d run in '
             '%.0f s.' % (res['date'], res['generated'], res['lines'], res['files'],
                          res['selected'], res['sampling'], res['run'], res['seconds']), '',
             '| killed | timeout | survived | uncompilable | not run (budget) | score |',
             '|---|---|---|---|---|---|',
             '| %d | %d | %d | %d | %d | %s |' % (c['killed'], c['timeout'], c['survived'],
                                                c['uncompilable'], c['not_run'],
                                                res['score']), '']
    surv = [m for m in res['mutants'] if m.get('status') == 'survived']
    if surv:
        lines += ['## Survivors', '', '| file:line | function | operator | original | mutated | tests run |',
                  '|---|---|---|---|---|---|']
        for m in sorted(surv, key=lambda m: (m['file'], m['line'], m['col'])):
            lines.append('| %s:%d | %s | %s | `%s` | `%s` | %s |' % (
                m['file'], m['line'], m['function'] or '', m['op'],
                short(m['line_before'], 90), short(m['line_after'], 90), ', '.join(m['tests'])))
    with open(out_md, 'w') as f:
        f.write('\n'.join(lines) + '\n')
    return '\n'.join(lines)


def short(s, n=70):
    s = ' '.join(s.split()).replace('|', '\\|').replace('`', "'")
    return s if len(s) <= n else s[:n - 3] + '...'


def make_mutants(ci, compdb, files, lines_by_file):
    """Parse each file with its flags (a header through a source file that includes it)."""
    out = []
    src_entries = sorted(f for f in compdb if f.endswith('.c'))
    for rel in files:
        path = os.path.join(ROOT, rel)
        if not os.path.exists(path):
            continue
        flags, _obj = parse_args_for(compdb, rel)
        args = {'flags': flags}
        if rel.endswith('.h'):
            # a source file of the same directory first, then any
            d = os.path.dirname(rel)
            cands = sorted(src_entries, key=lambda f: (('/' + d + '/') not in f, f))
            for cand in cands:
                crel = cand[cand.rfind('/src/') + 1:] if '/src/' in cand else None
                if not crel or not os.path.exists(os.path.join(ROOT, crel)):
                    continue
                cflags, _o = parse_args_for(compdb, crel)
                cflags = [a.replace(os.path.join(ROOT, opt_dir_tree()), ROOT) for a in cflags]
                tu = ci.Index.create().parse(os.path.join(ROOT, crel), args=cflags)
                if not any(os.path.realpath(i.include.name) == os.path.realpath(path)
                           for i in tu.get_includes()):
                    continue
                args = {'flags': cflags, 'tu': os.path.join(ROOT, crel)}
                break
            else:
                print('mutagen: warning: %s: no source file includes it' % rel, file=sys.stderr)
                continue
        if args['flags'] is None:
            print('mutagen: warning: %s: not in compile_commands.json' % rel, file=sys.stderr)
            continue
        # the worktree's include/ and src/, not the copy's (same bytes, real paths)
        args['flags'] = [a.replace(os.path.join(ROOT, opt_dir_tree()), ROOT)
                         for a in args['flags']]
        out += generate(ci, path, rel, args, lines_by_file.get(rel) if lines_by_file else None)
    return out


_OPT_DIR = ['build-mutgen']


def opt_dir_tree():
    return os.path.join(_OPT_DIR[0], 'tree')


def cmd_list(opt, ci):
    flags = opt.args.split() if opt.args else ['-std=c11']
    lines = None
    if opt.lines:
        a, b = opt.lines.split('-')
        lines = set(range(int(a), int(b) + 1))
    for path in opt.files:
        rel = os.path.relpath(os.path.abspath(path), os.getcwd())
        for m in generate(ci, os.path.abspath(path), rel, {'flags': flags}, lines):
            if opt.json:
                print(json.dumps(m))
            else:
                print('%d:%d %s %s | %s -> %s' % (m['line'], m['col'], m['op'], m['desc'],
                                                  ' '.join(m['original'].split()),
                                                  ' '.join(m['mutated'].split())))


def finish(res, sel, t_start, out_json, out_md, opt):
    c = res['counts']
    scored = c['killed'] + c['timeout'] + c['survived']
    res['score'] = '%.1f %%' % (100.0 * (c['killed'] + c['timeout']) / scored) if scored else 'n/a'
    res['seconds'] = round(time.monotonic() - t_start, 1)
    res['mutants'] = sorted(sel, key=lambda m: m['id'])
    return write_reports(opt, res, out_json, out_md)


def cmd_run(opt, ci):
    t_start = time.monotonic()
    _OPT_DIR[0] = opt.dir
    runner = Runner(opt)
    if opt.rerun:
        with open(opt.rerun) as f:
            old = json.load(f)
        rerun = [m for m in old['mutants'] if m.get('status') == 'survived']
        lines_by_file = None
        files = sorted({m['file'] for m in rerun})
        what = 'the survivors of %s (%s)' % (opt.rerun, old['what'])
    elif opt.mode == 'diff':
        base = resolve_base(opt.base)
        lines_by_file = changed_lines(base)
        rev = git('rev-parse', '--short', base).stdout.strip() or base
        what = 'the lines changed since %s (%s)' % (opt.base, rev)
        files = sorted(lines_by_file)
    else:
        lines_by_file = None
        files = all_sources()
        what = 'every line of src/'
    files = [f for f in files if os.path.dirname(f) in MODULE_TESTS and
             (not opt.only or any(f.startswith(o) for o in opt.only.split(',')))]
    os.makedirs(runner.dir, exist_ok=True)
    name = 'rerun' if opt.rerun else opt.mode
    out_json = os.path.join(runner.dir, 'report-%s.json' % name)
    out_md = os.path.join(runner.dir, 'report-%s.md' % name)
    res = {'what': what, 'date': time.strftime('%Y-%m-%d'), 'generated': 0, 'lines': 0,
           'files': len(files), 'selected': 0, 'run': 0, 'seconds': 0.0, 'mutants': [],
           'counts': dict(killed=0, timeout=0, survived=0, uncompilable=0, not_run=0),
           'score': 'n/a', 'sampling': '', 'seed': opt.seed,
           'commit': git('rev-parse', 'HEAD').stdout.strip()}
    if not files:
        runner.log('no changed C file under src/ (%s): nothing to mutate' % what)
        write_reports(opt, res, out_json, out_md)
        return 0
    runner.log('%s: %d files' % (what, len(files)))
    runner.sync()
    runner.configure()
    if opt.rerun:
        mutants = []
        for m in rerun:  # the same bytes must still be where the edits go
            with open(os.path.join(ROOT, m['file']), 'rb') as f:
                src = f.read()
            a0, b0 = m['edits'][0][0], m['edits'][-1][1]
            if src[a0:b0].decode('utf-8', 'replace') == m['original']:
                mutants.append({k: v for k, v in m.items()
                                if k not in ('status', 'killed_by', 'seconds', 'tests')})
            else:
                runner.log('%s: stale (its file changed), left out' % m['id'])
    else:
        mutants = make_mutants(ci, runner.compdb, files, lines_by_file)
    res['generated'] = len(mutants)
    res['lines'] = len({(m['file'], m['line']) for m in mutants})
    sel = sample(mutants, opt.per_line, opt.sample, opt.seed)
    res['selected'] = len(sel)
    res['sampling'] = ('at most %s a line, %s in all, seed %d' %
                       (opt.per_line or 'any', opt.sample or 'all', opt.seed))
    by_op = {}
    for m in mutants:
        by_op[m['op']] = by_op.get(m['op'], 0) + 1
    res['generated_by_op'] = by_op
    runner.log('%d mutants on %d lines (%s); %d selected (%s)' % (
        len(mutants), res['lines'], ', '.join('%s %d' % kv for kv in sorted(by_op.items())),
        len(sel), res['sampling']))
    if opt.dry_run:
        for m in sorted(sel, key=lambda m: m['id']):
            print('%s:%d %s %s | %s -> %s' % (m['file'], m['line'], m['op'], m['desc'],
                                              short(m['original']), short(m['mutated'])))
        return 0
    cur = curated_tests()
    for m in sel:
        m['tests'] = tests_for(m['file'], cur)
        if opt.tests:
            m['tests'] = [t for t in m['tests'] if t in opt.tests.split(',')]
    needed = sorted({t for m in sel for t in m['tests']})
    runner.log('building and timing the unmutated tests: %s' % ' '.join(needed))
    runner.baseline(needed)
    for m in sel:
        # the file's curated tests first (the likeliest to kill), then the fastest
        first = cur.get(m['file'], [])
        m['tests'] = sorted((t for t in m['tests'] if t in runner.normal),
                            key=lambda t: (t not in first, runner.normal[t]))
    runner.save_pristine(sorted({m['file'] for m in sel}))
    budget_end = t_start + opt.budget if opt.budget else None
    avg = None
    for i, m in enumerate(sel):
        now = time.monotonic()
        if budget_end and now + (avg or 0) > budget_end:
            m['status'] = 'not run'
            res['counts']['not_run'] += 1
            continue
        status, by, dt = runner.run_one(m, m['tests'], budget_end)
        m['status'], m['killed_by'], m['seconds'] = status, by, round(dt, 1)
        if status == 'not run':
            res['counts']['not_run'] += 1
            print('  [%d/%d] not run: the time budget ended during it' % (i + 1, len(sel)))
            continue
        res['counts'][status] += 1
        res['run'] += 1
        avg = dt if avg is None else 0.8 * avg + 0.2 * dt
        finish(res, sel, t_start, out_json, out_md, opt)  # a report even if stopped later
        print('  [%d/%d] %-12s %s:%d %s: %s%s' % (
            i + 1, len(sel), status.upper() if status == 'survived' else status,
            m['file'], m['line'], m['op'], short(m['line_after'], 80),
            (' (%s, %.0f s)' % (by, dt)) if by else ' (%.0f s)' % dt), flush=True)
    table = finish(res, sel, t_start, out_json, out_md, opt)
    # the unmutated sources built again, so that the build directory matches them
    runner.cmake_build(needed)
    c = res['counts']
    print()
    print(table)
    print('mutagen: reports: %s, %s' % (os.path.relpath(out_md, ROOT), os.path.relpath(out_json, ROOT)))
    if c['not_run']:
        print('mutagen: %d mutants not run: the time budget (%d s) ran out' % (c['not_run'], opt.budget))
    return 1 if (opt.fail_on_survivor and c['survived']) else 0


def main():
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter,
                                 epilog=__doc__.split('\n', 1)[1])
    sub = ap.add_subparsers(dest='mode', required=True)
    for name in ('diff', 'all'):
        p = sub.add_parser(name)
        p.add_argument('--base', default='auto',
                       help='diff: a git revision, "auto" (the merge base with main, or HEAD~1 '
                            'on main) or "last-landing" (CI: back to the previous merge)')
        p.add_argument('--per-line', type=int, default=3 if name == 'diff' else 0,
                       help='at most this many mutants a line (0: all)')
        p.add_argument('--sample', type=int, default=0, help='at most this many in all (0: all)')
        p.add_argument('--seed', type=int, default=37)
        p.add_argument('--budget', type=float, default=0,
                       help='seconds (from the start, build included) after which no mutant '
                            'is started; the rest are reported "not run"')
        p.add_argument('--only', help='comma-separated prefixes: only these files '
                                      '(e.g. src/core,src/io/hdr.c)')
        p.add_argument('--dir', default='build-mutgen')
        p.add_argument('--jobs', type=int, default=os.cpu_count() or 2)
        p.add_argument('--timeout-factor', type=float, default=10.0)
        p.add_argument('--min-timeout', type=float, default=10.0)
        p.add_argument('--max-timeout', type=float, default=600.0)
        p.add_argument('--fail-on-survivor', action='store_true')
        p.add_argument('--dry-run', action='store_true', help='list the selected mutants, run none')
        p.add_argument('--tests', help='comma-separated: run only these of each file\'s tests')
        p.add_argument('--rerun', metavar='REPORT.json',
                       help='run again the survivors of a report (after new tests)')
    p = sub.add_parser('list')
    p.add_argument('files', nargs='+')
    p.add_argument('--args', default='', help='compiler flags (default -std=c11)')
    p.add_argument('--lines', help='A-B: only these lines')
    p.add_argument('--json', action='store_true')
    opt = ap.parse_args()
    ci, lib = load_cindex()
    if ci is None:
        die(lib, 3)
    if opt.mode == 'list':
        cmd_list(opt, ci)
        return 0
    return cmd_run(opt, ci)


if __name__ == '__main__':
    sys.exit(main())
