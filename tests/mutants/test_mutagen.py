#!/usr/bin/env python3
"""The mutant generator's own test (scripts/mutagen.py, tests/mutants/README.md):

- gen/sample.c gives exactly the mutants of gen/expected.txt (each construct there is
  commented with what it must or must not give);
- every one of them, applied, still compiles (the rewriting follows the tokens);
- the literal rules and the sampling (fixed by the seed, at most N a line).

Exit 77 (CTest: skipped) when libclang's Python bindings are missing.
  tests/mutants/test_mutagen.py [--update]   (--update rewrites expected.txt)
"""
import json
import os
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.abspath(os.path.join(HERE, '..', '..'))
sys.path.insert(0, os.path.join(ROOT, 'scripts'))
import mutagen  # noqa: E402

FLAGS = '-std=c11 -Wall'


def main():
    ci, lib = mutagen.load_cindex()
    if ci is None:
        print('test_mutagen: SKIP: %s' % lib)
        return 77
    fails = 0

    def check(cond, what):
        nonlocal fails
        if not cond:
            fails += 1
            print('FAIL: ' + what)

    sample = os.path.join(HERE, 'gen', 'sample.c')
    expected = os.path.join(HERE, 'gen', 'expected.txt')
    r = subprocess.run([sys.executable, os.path.join(ROOT, 'scripts', 'mutagen.py'), 'list',
                        sample, '--args', FLAGS], capture_output=True, text=True, cwd=HERE)
    check(r.returncode == 0, 'mutagen.py list exits 0 (%s)' % r.stderr.strip())
    got = r.stdout.replace(os.path.join(HERE, ''), '')
    if '--update' in sys.argv:
        with open(expected, 'w') as f:
            f.write(got)
    with open(expected) as f:
        want = f.read()
    if got != want:
        gl, wl = set(got.splitlines()), set(want.splitlines())
        for ln in sorted(wl - gl):
            print('FAIL: missing  ' + ln)
        for ln in sorted(gl - wl):
            print('FAIL: extra    ' + ln)
        fails += 1

    # every mutant compiles: applied to a copy, checked by the C compiler
    muts = mutagen.generate(ci, sample, 'sample.c', {'flags': FLAGS.split()})
    with open(sample, 'rb') as f:
        src = f.read()
    cc = os.environ.get('CC', 'cc')
    with tempfile.TemporaryDirectory() as d:
        for m in muts:
            new = src
            for (a, b, rep) in sorted(m['edits'], reverse=True):
                new = new[:a] + rep.encode() + new[b:]
            check(new != src, '%s changes the file' % m['id'])
            p = os.path.join(d, 'm.c')
            with open(p, 'wb') as f:
                f.write(new)
            r = subprocess.run([cc, '-std=c11', '-fsyntax-only', '-w', p],
                               capture_output=True, text=True)
            check(r.returncode == 0, '%s compiles: %s' % (m['id'], r.stderr.strip()[:300]))
    check(len({m['id'] for m in muts}) == len(muts), 'mutant ids are unique')

    # the literal rules
    for kind, text, want in [('INTEGER_LITERAL', '0', '1'), ('INTEGER_LITERAL', '1', '0'),
                             ('INTEGER_LITERAL', '41u', '42u'), ('INTEGER_LITERAL', '0xff', '0x100'),
                             ('INTEGER_LITERAL', '017', '020'),
                             ('FLOATING_LITERAL', '0.0', '1.0'), ('FLOATING_LITERAL', '1.0f', '2.0f'),
                             ('FLOATING_LITERAL', '0.5', '0.25'), ('FLOATING_LITERAL', '3.', '6.0'),
                             ('FLOATING_LITERAL', '1e-6', '5e-07'), ('FLOATING_LITERAL', '.5f', '0.25f'),
                             ('FLOATING_LITERAL', '0x1p-3', None)]:
        got1 = mutagen.const_mutation(kind, text)
        check(got1 == want, '%s -> %r (got %r)' % (text, want, got1))

    # sampling: fixed by the seed, at most N a line, the same set whatever the input order
    fake = [{'file': 'a.c', 'line': 1 + i // 5, 'id': 'a.c:%03d' % i} for i in range(50)]
    s1 = mutagen.sample(fake, 2, 12, 7)
    s2 = mutagen.sample(list(reversed(fake)), 2, 12, 7)
    check([m['id'] for m in s1] == [m['id'] for m in s2], 'sampling is fixed by the seed')
    check(len(s1) == 12, 'sampling keeps 12 (got %d)' % len(s1))
    per = {}
    for m in s1:
        per[m['line']] = per.get(m['line'], 0) + 1
    check(max(per.values()) <= 2, 'at most 2 a line')
    check([m['id'] for m in mutagen.sample(fake, 2, 12, 8)] != [m['id'] for m in s1],
          'another seed, another sample')

    # last-landing: .ci/landed when it names an ancestor of HEAD, else back to the newest merge
    with tempfile.TemporaryDirectory() as repo:
        def g(*a):
            return subprocess.run(['git', '-C', repo, '-c', 'user.name=t', '-c', 'user.email=t@t']
                                  + list(a), capture_output=True, text=True, check=True).stdout.strip()
        g('init', '-q')
        shas = []
        for i in range(4):
            g('commit', '-q', '--allow-empty', '-m', 'c%d' % i)
            shas.append(g('rev-parse', 'HEAD'))
        saved = mutagen.ROOT
        mutagen.ROOT = repo
        try:
            check(mutagen.resolve_base('last-landing') == shas[0],
                  'last-landing without .ci/landed and no merge: the oldest of the 20')
            os.makedirs(os.path.join(repo, '.ci'))
            with open(os.path.join(repo, '.ci', 'landed'), 'w') as f:
                f.write(shas[1] + ' # a comment\n')
            check(mutagen.resolve_base('last-landing') == shas[1], 'last-landing: .ci/landed')
            with open(os.path.join(repo, '.ci', 'landed'), 'w') as f:
                f.write('0' * 40 + '\n')
            check(mutagen.resolve_base('last-landing') == shas[0],
                  'last-landing: a .ci/landed naming no ancestor is not taken')
        finally:
            mutagen.ROOT = saved
    print(json.dumps({'mutants': len(muts), 'failures': fails}))
    return 1 if fails else 0


if __name__ == '__main__':
    sys.exit(main())
