#!/bin/bash
# The README's timed commands, whole process, on CPU 0 while CPU 1 spins (issue 35's
# "one core of a 2-core machine with the other core loaded"); farm-bench's medians.
#   scripts/readme-budgets.sh [build/lumis]
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
L=${1:-$here/build/lumis}
D=$here/data/hdri
out=$(mktemp -d)
trap 'kill $hog 2>/dev/null; rm -rf "$out"' EXIT
taskset -c 1 sh -c 'while :; do :; done' &
hog=$!
bench() { farm-bench -n 5 --pin 0 --timeout 300 -- "$@" | grep -E '^A = |A wall'; }
bench "$L" render --scene spheres --method kdtree --time 5 -o "$out/kd.exr" --quiet
bench "$L" render --scene wu-mixed --env "$D/blender-sunset.exr" --lights wu --time 1 \
    -o "$out/wu.exr" --quiet
bench "$L" render --scene wu-diffuse --env "$D/blender-courtyard.exr" --lights median-cut \
    --lights-mode stratified --time 2 -o "$out/strata.exr" --quiet
bench "$L" demo --out "$out/demo" --time 0.5
