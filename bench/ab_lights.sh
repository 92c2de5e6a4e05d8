#!/usr/bin/env bash
# Alternates two builds of bench_lights on one core and prints, per method, the median of
# the per-round medians and every round's median (ms): on a shared machine only ratios
# measured in the same minutes mean anything (docs/lights.md, Performance).
#
#   bench/ab_lights.sh OLD/bench_lights NEW/bench_lights METHODS [MAP] [ROUNDS]
#   e.g. bench/ab_lights.sh /tmp/old/bench_lights build/bench/bench_lights median-cut,wu \
#            data/hdri/blender-sunset.exr 5
# MAP empty: the procedural sky.  Each round runs each build once (11 runs after a warm-up).
set -euo pipefail
if [ $# -lt 3 ]; then
    sed -n '2,9p' "$0" >&2
    exit 2
fi
A=$1 B=$2 M=$3 MAP=${4:-} R=${5:-5} CPU=${CPU:-1}
for bin in "$A" "$B"; do
    [ -x "$bin" ] || { echo "ab_lights: no executable $bin" >&2; exit 1; }
done
for _ in $(seq "$R"); do
    for x in A B; do
        bin=$A; [ "$x" = B ] && bin=$B
        taskset -c "$CPU" "$bin" --methods "$M" --runs 11 ${MAP:+--map "$MAP"} 2>&1 |
            awk -v x="$x" '$2 == "median" {print x, $1, $3}'
    done
done | python3 -c '
import collections, statistics, sys
d = collections.defaultdict(list)
for line in sys.stdin:
    x, m, v = line.split()
    d[(m, x)].append(float(v))
for (m, x), v in sorted(d.items()):
    print(f"{m:14s} {x}  median {statistics.median(v):7.2f} ms   rounds " + " ".join(f"{t:.1f}" for t in v))
'
