#!/usr/bin/env bash
# The orientation check: the camera of bunny-plane with no objects (it sees only the map),
# rendered by Cycles (scene.py --map-alone) and by lumis (lumis-map-alone.json), per map;
# prints both images' mean luminance, a 4x4 grid of region means (relative differences),
# and relMSE.  Then the same without scene.py's 180-degree turn, to show what a wrong
# orientation looks like.  Maps are cleaned by `lumis convert` as in run.sh.
#   bench/cycles/check.sh [MAP...]   (default: blender-courtyard blender-sunset blender-interior)
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
HERE="$ROOT/bench/cycles"
LUMIS="$ROOT/build/lumis"
SPP=${SPP:-256}
WORK=${WORK:-/tmp/cycles/check}
mkdir -p "$WORK"
[ $# -ge 1 ] || set -- blender-courtyard blender-sunset blender-interior
for m in "$@"; do
    map="$WORK/$m.exr"
    "$LUMIS" convert "$ROOT/data/hdri/$m.exr" "$map" --compression none 2>/dev/null
    nice -n 10 "$LUMIS" render "$HERE/lumis-map-alone.json" --env "$map" --spp "$SPP" \
        --threads 1 --no-auto -o "$WORK/$m-lumis.exr" 2>/dev/null
    nice -n 10 blender -b --factory-startup -t 1 -P "$HERE/scene.py" -- --map "$map" \
        --spp "$SPP" --map-alone --out "$WORK/$m-cycles.exr" >/dev/null 2>&1
    nice -n 10 blender -b --factory-startup -t 1 -P "$HERE/scene.py" -- --map "$map" \
        --spp "$SPP" --map-alone --no-env-rotation --out "$WORK/$m-cycles-unturned.exr" \
        >/dev/null 2>&1
    echo "== $m (lumis first; then Cycles; then Cycles without the 180-degree turn)"
    blender -b --factory-startup -P "$HERE/imgstats.py" -- "$WORK/$m-lumis.exr" \
        "$WORK/$m-cycles.exr" "$WORK/$m-cycles-unturned.exr" 2>&1 | grep -E "MEAN|REGION"
    for t in cycles cycles-unturned; do
        echo "relMSE $t vs lumis: $("$LUMIS" compare "$WORK/$m-lumis.exr" "$WORK/$m-$t.exr" \
            --json --no-hdr-flip | sed -n 's/.*"relmse":\([^,}]*\).*/\1/p')"
    done
done
