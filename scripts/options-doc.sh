#!/usr/bin/env bash
# docs/options.md is generated from the option tables of tools/lumis (one table per command
# gives its parser, its --help and this page): `lumis help --markdown` prints it.
#
#   scripts/options-doc.sh LUMIS            writes docs/options.md      (make options-doc)
#   scripts/options-doc.sh LUMIS --check    exit 1 when docs/options.md is not what the
#                                           tables give, or when README.md's "All options
#                                           at a glance" names an option no table has
#                                           (the test options_documented)
#
# LUMIS: the lumis binary, e.g. build/lumis.  Exit status 2 on a usage error.
set -uo pipefail

if [ $# -lt 1 ] || [ ! -x "$1" ] || { [ $# -gt 1 ] && [ "$2" != --check ]; }; then
    echo "usage: $0 path/to/lumis [--check]" >&2
    exit 2
fi
ROOT="$(cd "$(dirname "$0")/.." && pwd)"
DOC="$ROOT/docs/options.md"
tmp="$(mktemp)" || exit 2
trap 'rm -f "$tmp"' EXIT
"$1" help --markdown >"$tmp" || { echo "$0: $1 help --markdown failed" >&2; exit 2; }
if [ "${2:-}" = --check ]; then
    if ! diff -u "$DOC" "$tmp" >&2; then
        echo "docs/options.md is stale: the option tables of tools/lumis say otherwise" \
            "(run 'make options-doc')" >&2
        exit 1
    fi
    # the README's synopsis of every command: each option it names is in a table
    glance="$(awk '/^### All options at a glance/ {on = 1; next} on && /^##/ {exit} on' \
        "$ROOT/README.md")"
    [ -n "$glance" ] || { echo "README.md: no \"All options at a glance\" section" >&2; exit 1; }
    bad=0
    while read -r opt; do
        case "$opt" in --help | --version | --markdown) continue ;; esac
        if ! grep -q -- "\`${opt}[ \`]\|, ${opt}[ \`]" "$tmp"; then
            echo "README.md names $opt (All options at a glance), which no option table has" >&2
            bad=1
        fi
    done < <(grep -o -- '--[a-z][a-z0-9-]*' <<<"$glance" | sort -u)
    [ "$bad" -eq 0 ] || exit 1
    echo "docs/options.md: as the option tables give it; README.md's options exist"
    exit 0
fi
cp "$tmp" "$DOC" && echo "wrote docs/options.md"
