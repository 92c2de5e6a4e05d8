#!/usr/bin/env bash
# lumis on the scene of bench/cycles/run.sh (lumis-bunny-plane-noball.json: the built-in
# bunny-plane without its sphere, as Cycles renders it): per map a lumis reference, then
# lumis at spp = 1, 2, 4, ..., 1024 on one thread for each sample sequence, each compared
# with lumis's own reference (relMSE of `lumis compare`), rows appended to the same CSV
# format as Cycles' (map,renderer,sequence,spp,seconds,relmse; seconds: the sidecar's
# render time, sampling only, as Cycles' "without synchronization").
# The sequence "default" is `lumis render` with no estimator option and no --sequence: the
# automatic estimator (docs/render.md); its seconds add the sidecar's auto_estimator.seconds
# (the pilots and the prior's regions, which are in prep_seconds) to render_seconds.
# default.sh runs that series side by side with Cycles.
#
#   bench/cycles/lumis.sh MAP...      (MAP: a name in data/hdri/)
#
# Environment: SEQUENCES ("sobol zsobol pmj02 pcg"), REF_SPP (8192), REF_THREADS (1),
# MAX_SPP (1024), SEED (1; the reference uses SEED + 1000 and sobol), WORK
# (/tmp/cycles/lumis), CSV (bench/cycles/lumis.csv).
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
HERE="$ROOT/bench/cycles"
LUMIS="$ROOT/build/lumis"
SEQUENCES=${SEQUENCES:-sobol zsobol pmj02 pcg}
REF_SPP=${REF_SPP:-8192}
REF_THREADS=${REF_THREADS:-1}
MAX_SPP=${MAX_SPP:-1024}
SEED=${SEED:-1}
WORK=${WORK:-/tmp/cycles/lumis}
CSV=${CSV:-$HERE/lumis.csv}
SCENE="$HERE/lumis-bunny-plane-noball.json"
[ $# -ge 1 ] || { echo "usage: $0 MAP..." >&2; exit 2; }
[ -x "$LUMIS" ] || { echo "lumis.sh: $LUMIS not built (make)" >&2; exit 1; }
mkdir -p "$WORK"
[ -s "$CSV" ] || echo "map,renderer,sequence,spp,seconds,relmse" >"$CSV"
VERSION=$("$LUMIS" --version | awk '{print $2}')

render() { # map spp threads seed sequence out
    local estimator=(--sequence "$5" --no-auto)
    [ "$5" = default ] && estimator=()
    "$LUMIS" render "$SCENE" --env "$1" --spp "$2" --threads "$3" --seed "$4" \
        "${estimator[@]}" --quiet -o "$6" 2>/dev/null
}
seconds() {
    local r a
    r=$(sed -n 's/.*"render_seconds":[[:space:]]*\([0-9.e+-]*\).*/\1/p' "${1%.exr}.json" | head -1)
    a=$(python3 -c 'import json, sys; print((json.load(open(sys.argv[1])).get("auto_estimator") or {}).get("seconds", 0))' "${1%.exr}.json")
    echo "$r $a" | awk '{printf "%.17g", $1 + $2}'
}
relmse() { "$LUMIS" compare "$1" "$2" --json --no-hdr-flip |
    sed -n 's/.*"relmse":\([^,}]*\).*/\1/p'; }

for name in "$@"; do
    src="$ROOT/data/hdri/$name.exr"
    [ -f "$src" ] || { echo "lumis.sh: $src missing (scripts/fetch-data.sh)" >&2; exit 1; }
    ref="$WORK/$name-ref-$REF_SPP.exr"
    if [ ! -s "$ref" ]; then
        echo "== $name: reference, $REF_SPP spp (sobol, seed $((SEED + 1000)))"
        render "$src" "$REF_SPP" "$REF_THREADS" $((SEED + 1000)) sobol "$ref"
    fi
    for q in $SEQUENCES; do
        spp=1
        while [ "$spp" -le "$MAX_SPP" ]; do
            out="$WORK/$name-$q-$spp.exr"
            render "$src" "$spp" 1 "$SEED" "$q" "$out"
            echo "$name,lumis-$VERSION,$q,$spp,$(seconds "$out"),$(relmse "$ref" "$out")" >>"$CSV"
            spp=$((spp * 2))
        done
        echo "   $name $q: done"
    done
done
