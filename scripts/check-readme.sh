#!/usr/bin/env bash
# Checks that what README.md names exists:
#   1. every `lumis SUBCOMMAND` in its code (code blocks and `code spans`): LUMIS
#      SUBCOMMAND --help exits 0;
#   2. every repository path it names, in links, code or prose (docs/..., scripts/..., tests/...,
#      bench/..., tools/..., src/..., include/lumis/..., assets/..., fuzz/..., cmake/...,
#      and headers named lumis/NAME.h), and every file a layout block lists beside its
#      folder ("    src/lights/   median_cut.c, ..."): the file or folder exists (globs
#      must match);
#   3. every `make TARGET` in its code: the Makefile has that target;
#   4. its C program (a ```c block with main) is docs/examples/readme_example.c.
#
#   scripts/check-readme.sh LUMIS [README]     (LUMIS: the lumis binary, e.g. build/lumis)
#
# Prints what is missing; exit status 0 when nothing is, 1 when something is, 2 on a
# usage error.  CHECK_README_LIST=1 also prints every name it checks.  Needs bash, perl
# and grep.
set -uo pipefail

if [ $# -lt 1 ] || [ ! -x "$1" ]; then
    echo "usage: $0 path/to/lumis [README.md]${1:+  ($1 is not an executable)}" >&2
    exit 2
fi
ROOT="$(cd "$(dirname "$0")/.." && pwd)"
LUMIS="$1"
case "$LUMIS" in /*) ;; *) LUMIS="$PWD/$LUMIS" ;; esac
README="${2:-$ROOT/README.md}"
case "$README" in /*) ;; *) README="$PWD/$README" ;; esac
[ -f "$README" ] || { echo "$0: $README: no such file" >&2; exit 2; }
cd "$ROOT" || exit 2

# One line per name: "cmd NAME", "path PATH" or "make TARGET" (sorted, unique).
names="$(perl -e '
use strict; use warnings;
local $/; my $t = <STDIN>;
my @code;                                  # the README'"'"'s code: blocks and spans
my $rest = "";
my $in = 0; my $fence = "";
my $prev_blank = 1; my $in_indented = 0;
for my $line (split /\n/, $t) {
    if ($in) {
        if ($line =~ /^\s*\Q$fence\E\s*$/) { $in = 0 } else { push @code, $line }
        next;
    }
    if ($line =~ /^\s*(```+|~~~+)/) { $in = 1; $fence = $1; next }
    if ($line =~ /^    / && ($prev_blank || $in_indented)) {
        push @code, $line; $in_indented = 1; $prev_blank = 0; next;
    }
    $in_indented = 0 unless $line =~ /^\s*$/;
    $prev_blank = $line =~ /^\s*$/;
    $rest .= "$line\n";
}
my @spans; while ($rest =~ /(`+)(.+?)\1/sg) { push @spans, $2 }
my $code = join("\n", @code, @spans);
my @links; while ($rest =~ /\]\(([^)\s]+)\)/g) { push @links, $1 }
my %out;
while ($code =~ /(?:^|[\s\/(|;&`])lumis[ \t]+([a-z][a-z0-9-]*)/mg) { $out{"cmd $1"} = 1 }
while ($code =~ /(?:^|[\s(|;&`])make[ \t]+((?:[a-z][a-z0-9-]*[ \t]*)+)/mg) {
    $out{"make $_"} = 1 for split /[ \t]+/, $1;
}
my $roots = qr{(?:docs|scripts|tests|bench|tools|src|include/lumis|assets|fuzz|cmake)/};
for my $s ($t) {                           # paths: anywhere (code, links, prose)
    while ($s =~ m{(?<![\w./-])((?:\./)?$roots[\w.*/+-]*)}g) {
        my $p = $1;
        $p =~ s{^\./}{}; $p =~ s{#.*}{}; $p =~ s{[.,:;]+$}{};
        next if $p =~ /[A-Z]{3,}/ && $p !~ /README|LICENSE/;   # placeholders: docs/results/NAME
        $out{"path $p"} = 1;
    }
    while ($s =~ m{(?<![\w./-])lumis/(\w+\.h)\b}g) { $out{"path include/lumis/$1"} = 1 }
}
my $dir;                                   # a layout block: "    src/lights/   a.c, b.c"
for my $line (@code) {
    my $rest;
    if ($line =~ m{^ {4}((?:[\w.-]+/)+)\s{2,}(.*)$}) { ($dir, $rest) = ($1, $2) }
    elsif (defined $dir && $line =~ m{^ {14,}(\S.*)$}) { $rest = $1 }
    else { undef $dir; next }
    while ($rest =~ m{(?<![\w/.-])([\w*+-]+\.(?:c|cpp|h|sh|py|json|md|txt|glb))\b}g) {
        $out{"path $dir$1"} = 1;
    }
}
for my $l (@links) {                       # relative links to anything in the repository
    next if $l =~ m{^(?:[a-z]+:|#|/)};
    (my $p = $l) =~ s{#.*}{};
    $p =~ s{^\./}{};
    $out{"path $p"} = 1 if length $p;
}
print "$_\n" for sort keys %out;
' <"$README")" || { echo "$0: could not read $README" >&2; exit 2; }

[ -z "${CHECK_README_LIST:-}" ] || printf '%s\n' "$names" # CHECK_README_LIST=1: what is checked
missing=0 checked=0
report() { echo "missing: $*"; missing=$((missing + 1)); }
while read -r kind name; do
    [ -n "$kind" ] || continue
    checked=$((checked + 1))
    case "$kind" in
    cmd)
        if ! "$LUMIS" "$name" --help >/dev/null 2>&1; then
            report "lumis $name (\`$LUMIS $name --help\` fails)"
        fi
        ;;
    make)
        if ! grep -Eq "^$name[[:space:]]*:([^=]|$)" Makefile; then
            report "make $name (no such target in Makefile)"
        fi
        ;;
    path)
        p="${name%/}"
        if [[ "$p" == *'*'* ]]; then
            shopt -s nullglob
            # shellcheck disable=SC2206
            matches=($p)
            shopt -u nullglob
            [ ${#matches[@]} -gt 0 ] || report "$name (matches no file)"
        elif [ ! -e "$p" ]; then
            report "$name (no such file or folder)"
        fi
        ;;
    esac
done <<<"$names"

# 4. The README's C program (its ```c block with main) is docs/examples/readme_example.c,
#    which the test readme_example builds and runs.
example=docs/examples/readme_example.c
program="$(perl -ne 'if (/^```c\s*$/) { $in = 1; $b = ""; next }
    if ($in && /^```\s*$/) { $in = 0; if ($b =~ /\bint main\b/) { print $b; exit } next }
    $b .= $_ if $in;' "$README")"
if [ -n "$program" ]; then
    checked=$((checked + 1))
    if [ ! -f "$example" ]; then
        report "$example (no such file: the README's program should be there)"
    elif [ "$program" != "$(cat "$example")" ]; then
        report "the README's C program differs from $example (copy one over the other)"
    fi
fi

if [ "$missing" -gt 0 ]; then
    echo "README.md: $missing of $checked names are missing"
    exit 1
fi
echo "README.md: all $checked names exist (subcommands, paths, make targets, the C program)"
