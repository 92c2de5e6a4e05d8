#!/usr/bin/env bash
# The cost of a camera sample with each sequence against PCG32's: RUNS pairs of renders in
# turn (PCG32, then the sequence) of bunny-plane at 160x120 and SPP samples, one thread
# pinned to CPU, each timed by its sidecar's render_seconds (the sampling alone: not the
# map's load nor the sampler's build), then the median of the pairwise ratios.
#
#   docs/results/sampling/cost.sh [MAP] [SEQUENCE...]   (default: blender-courtyard; sobol
#                                                        zsobol pmj02 halton stratified)
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/../../.." && pwd)
L=${LUMIS:-$ROOT/build/lumis}
MAP=${1:-blender-courtyard}
shift || true
SEQS=${*:-sobol zsobol pmj02 halton stratified}
RUNS=${RUNS:-9}
SPP=${SPP:-256}
CPU=${CPU:-1}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
"$L" convert "$ROOT/data/hdri/$MAP.exr" "$tmp/map.exr" --compression none 2>/dev/null
secs() {
    taskset -c "$CPU" "$L" render --scene bunny-plane --env "$tmp/map.exr" --size 160x120 \
        --spp "$SPP" --threads 1 --quiet --sequence "$1" -o "$tmp/$1.exr"
    sed -n 's/.*"render_seconds":[[:space:]]*\([0-9.e+-]*\).*/\1/p' "$tmp/$1.json" | head -1
}
for q in $SEQS; do
    ratios=()
    for r in $(seq 1 "$RUNS"); do
        b=$(secs pcg)
        a=$(secs "$q")
        ratios+=("$(echo "$a $b" | awk '{printf "%.4f", $1 / $2}')")
    done
    printf '%s\n' "${ratios[@]}" | sort -g | awk -v q="$q" -v m="$MAP" -v s="$SPP" \
        '{a[NR] = $1} END {printf "%s / pcg, %s, %s spp: median %s (min %s, max %s), %d pairs\n", q, m, s, a[int((NR + 1) / 2)], a[1], a[NR], NR}'
done
