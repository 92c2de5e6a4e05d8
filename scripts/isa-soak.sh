#!/usr/bin/env bash
# N small renders per light kind with Embree pinned to each kernel set (issue 25's check that
# no render aborts on a CPU without AVX-512): environment MIS, median cut, variance
# minimisation, Wu with upsampling, the headlight with exact and approximate visibility.
#
#   scripts/isa-soak.sh [N] [BUILD_DIR]     (default 100, build)
set -uo pipefail
cd "$(dirname "$0")/.."
N=${1:-100} B=${2:-build}
L="$B/lumis"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
"$L" luminaire create "$tmp/lum.json" --preset small >/dev/null 2>&1 || exit 1
kinds=("env-mis|--scene spheres --env sky:64x32"
       "median-cut|--scene spheres --env sky:64x32 --lights median-cut --lights-k 37"
       "variance-min|--scene bunny-plane --env sky:64x32 --lights variance-min --lights-k 37"
       "wu-upsample|--scene wu-mixed --env sky:128x64 --lights wu --lights-k 37 --upsample 2"
       "headlight-exact|--scene headlight --luminaire $tmp/lum.json --visibility exact"
       "headlight-approx|--scene headlight --luminaire $tmp/lum.json --visibility approx")
bad=0
for isa in sse4.2 avx2; do
    for k in "${kinds[@]}"; do
        name=${k%%|*} args=${k#*|} ok=0
        for i in $(seq "$N"); do
            # shellcheck disable=SC2086 # the arguments are meant to split
            if LUMIS_EMBREE_CONFIG="isa=$isa" "$L" render $args --size 16x12 --spp 2 \
                --threads $((1 + i % 2)) --seed "$i" --quiet --no-sidecar -o "$tmp/o.exr" \
                >"$tmp/log" 2>&1; then
                ok=$((ok + 1))
            else
                echo "  $isa $name seed $i: exit $?: $(tail -n 2 "$tmp/log")"
            fi
        done
        printf '%-7s %-17s %d of %d exit 0\n' "$isa" "$name" "$ok" "$N"
        [ "$ok" -eq "$N" ] || bad=1
    done
done
exit $bad
