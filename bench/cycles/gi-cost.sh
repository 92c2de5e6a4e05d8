#!/usr/bin/env bash
# Seconds per sample of the GI series' three renders, measured in turn on one core
# (Cycles PMJ, lumis inversion-guided + MIS, lumis stratified median cut; 4 bounces,
# blender-courtyard, one thread), RUNS rounds of SPP spp per scene: a second measurement
# of gi-analyze.py's pooled s/spp when the machine is quieter.  Prints
# "scene renderer run seconds s/spp" lines (gi-cost.txt).
#   bench/cycles/gi-cost.sh [SCENE...]     (default: bunny interior)
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
HERE="$ROOT/bench/cycles"
LUMIS="$ROOT/build/lumis"
SPP=${SPP:-128}
RUNS=${RUNS:-3}
WORK=${WORK:-/tmp/cycles/gi-cost}
mkdir -p "$WORK"
map="$WORK/blender-courtyard.exr"
[ -s "$map" ] || "$LUMIS" convert "$ROOT/data/hdri/blender-courtyard.exr" "$map" --compression none 2>/dev/null
[ $# -ge 1 ] || set -- bunny interior
echo "# $(date -u +%FT%TZ) SPP $SPP RUNS $RUNS; load: $(cut -d' ' -f1-3 /proc/loadavg)"
for sc in "$@"; do
    f="$HERE/lumis-gi-$sc.json"
    for r in $(seq "$RUNS"); do
        nice -n 10 blender -b --factory-startup -t 1 --debug-cycles -P "$HERE/scene.py" -- \
            --lumis-scene "$f" --map "$map" --spp "$SPP" --seed 1 --bounces 4 \
            --out "$WORK/c.exr" >"$WORK/c.log" 2>&1
        t=$(sed -n 's/.*Render time (without synchronization): \([0-9.e+-]*\).*/\1/p' "$WORK/c.log" | tail -1)
        echo "$sc cycles $r $t $(echo "$t / $SPP" | bc -l | cut -c1-7)"
        for est in mis strat; do
            extra=()
            [ $est = strat ] && extra=(--lights median-cut --lights-mode stratified)
            nice -n 10 "$LUMIS" render "$f" --env "$map" --spp "$SPP" --seed 1 --bounces 4 \
                --threads 1 --no-auto --quiet -o "$WORK/l.exr" "${extra[@]}" 2>/dev/null
            t=$(sed -n 's/.*"render_seconds":[[:space:]]*\([0-9.e+-]*\).*/\1/p' "$WORK/l.json" | head -1)
            echo "$sc lumis-$est $r $t $(echo "$t / $SPP" | bc -l | cut -c1-7)"
        done
    done
done
echo "# end $(date -u +%FT%TZ); load: $(cut -d' ' -f1-3 /proc/loadavg)"
