#!/usr/bin/env bash
# The cost of a sample, lumis against Cycles, in one run on one core: RUNS pairs of renders
# of the same scene and map at SPP (default 1024), in turn (lumis, Cycles, lumis, ...), both
# pinned to CPU (default 1) with taskset; each renderer's own sampling time (lumis's
# sidecar render_seconds, Cycles' "Render time (without synchronization)"), then the median
# of each and of the pairwise ratios.  Prints "map lumis_s cycles_s ratio" per pair and a
# summary line.
#
#   bench/cycles/cost.sh MAP [SEQUENCE]      (MAP: a name in data/hdri/; SEQUENCE: sobol)
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
HERE="$ROOT/bench/cycles"
LUMIS="$ROOT/build/lumis"
SPP=${SPP:-1024}
RUNS=${RUNS:-3}
CPU=${CPU:-1}
WORK=${WORK:-/tmp/cycles/cost}
name=$1
seq=${2:-sobol}
mkdir -p "$WORK"
map="$WORK/$name.exr"
"$LUMIS" convert "$ROOT/data/hdri/$name.exr" "$map" --compression none 2>/dev/null
ratios=()
for r in $(seq 1 "$RUNS"); do
    taskset -c "$CPU" "$LUMIS" render "$HERE/lumis-bunny-plane-noball.json" --env "$map" \
        --spp "$SPP" --threads 1 --sequence "$seq" --no-auto --quiet -o "$WORK/l.exr" 2>/dev/null
    l=$(sed -n 's/.*"render_seconds":[[:space:]]*\([0-9.e+-]*\).*/\1/p' "$WORK/l.json" | head -1)
    taskset -c "$CPU" blender -b --factory-startup -t 1 --debug-cycles -P "$HERE/scene.py" -- \
        --map "$map" --spp "$SPP" --seed 1 --out "$WORK/c.exr" >"$WORK/c.log" 2>&1
    c=$(sed -n 's/.*Render time (without synchronization): \([0-9.e+-]*\).*/\1/p' "$WORK/c.log" |
        tail -1)
    ratio=$(echo "$l $c" | awk '{printf "%.4f", $1 / $2}')
    ratios+=("$ratio")
    echo "$name $l $c $ratio"
done
printf '%s\n' "${ratios[@]}" | sort -g | awk -v n="$name" -v q="$seq" -v s="$SPP" \
    '{a[NR] = $1} END {printf "%s: lumis (%s) / Cycles sampling time at %s spp: median %s (min %s, max %s) over %d pairs\n", n, q, s, a[int((NR + 1) / 2)], a[1], a[NR], NR}'
