#!/usr/bin/env bash
# Global illumination, lumis against Cycles 3.4 (README.md, "Global illumination (issue
# 39)").  Two modes:
#
#   bench/cycles/run-gi.sh match [MAP]
#       the BSDF match: lumis-gi-bsdf.json (a Lambert ball and two glossy balls, direct
#       light) rendered by lumis (glossy; and lumis-gi-bsdf-conductor.json, lumis's own GGX
#       conductor, for the mismatch it would have) and by Cycles at MATCH_SPP (4096) spp;
#       prints mean luminance, 3x3 region means (imgstats.py) and relMSE of each against
#       Cycles; images in $WORK/match.
#   bench/cycles/run-gi.sh series SCENE [MAP]
#       SCENE is bunny (lumis-gi-bunny.json) or interior (lumis-gi-interior.json), path
#       traced with BOUNCES (4) bounces: a lumis reference (inversion-guided + MIS, sobol,
#       seed 1001) and a Cycles reference (seed 1001), REF_SPP (4096) spp each, one thread;
#       then at spp = 1, 2, 4, ..., MAX_SPP (1024), in turn (so a shared machine slows all
#       three alike): Cycles (PMJ, seed 1), lumis inversion-guided + MIS and lumis
#       stratified median cut (K 32, MIS), seed 1, one thread, each against its own
#       renderer's reference.  Rows appended to $CSV (gi.csv):
#       scene,map,renderer,estimator,spp,seconds,relmse (seconds: sampling alone, Cycles'
#       "Render time (without synchronization)", lumis's render_seconds).
#
# MAP: a name in data/hdri/ (default blender-courtyard); cleaned by `lumis convert` as in
# run.sh so both renderers see the same radiance.  Environment: REF_SPP, MAX_SPP,
# MATCH_SPP, BOUNCES, WORK (/tmp/cycles/gi), CSV (bench/cycles/gi.csv), NICE (10).
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
HERE="$ROOT/bench/cycles"
LUMIS="$ROOT/build/lumis"
REF_SPP=${REF_SPP:-4096}
MAX_SPP=${MAX_SPP:-1024}
MATCH_SPP=${MATCH_SPP:-4096}
BOUNCES=${BOUNCES:-4}
WORK=${WORK:-/tmp/cycles/gi}
CSV=${CSV:-$HERE/gi.csv}
NICE=${NICE:-10}
command -v blender >/dev/null || { echo "run-gi.sh: blender not found" >&2; exit 1; }
[ -x "$LUMIS" ] || { echo "run-gi.sh: $LUMIS not built (make)" >&2; exit 1; }
mode=${1:?usage: run-gi.sh match [MAP] | series SCENE [MAP]}
shift
mkdir -p "$WORK/maps" "$WORK/img" "$WORK/log" "$WORK/match"

clean_map() { # name -> path of the cleaned map
    local out="$WORK/maps/$1.exr"
    [ -s "$out" ] || "$LUMIS" convert "$ROOT/data/hdri/$1.exr" "$out" --compression none 2>/dev/null
    echo "$out"
}
cycles() { # scene.json map spp seed bounces out log -> sampling seconds
    nice -n "$NICE" blender -b --factory-startup -t 1 --debug-cycles -P "$HERE/scene.py" -- \
        --lumis-scene "$1" --map "$2" --spp "$3" --seed "$4" --bounces "$5" --out "$6" \
        >"$7" 2>&1 || { echo "run-gi.sh: blender failed, see $7" >&2; exit 1; }
    local s
    s=$(sed -n 's/.*Render time (without synchronization): \([0-9.e+-]*\).*/\1/p' "$7" | tail -1)
    [ -n "$s" ] && [ -s "$6" ] || { echo "run-gi.sh: no timing/image, see $7" >&2; exit 1; }
    echo "$s"
}
lumis() { # scene.json map spp seed bounces out [options] -> render seconds
    local sc=$1 map=$2 spp=$3 seed=$4 b=$5 out=$6
    shift 6
    nice -n "$NICE" "$LUMIS" render "$sc" --env "$map" --spp "$spp" --seed "$seed" \
        --bounces "$b" --threads 1 --no-auto --quiet -o "$out" "$@" 2>/dev/null
    sed -n 's/.*"render_seconds":[[:space:]]*\([0-9.e+-]*\).*/\1/p' "${out%.exr}.json" | head -1
}
relmse() { "$LUMIS" compare "$1" "$2" --json --no-hdr-flip | sed -n 's/.*"relmse":\([^,}]*\).*/\1/p'; }

case $mode in
match)
    name=${1:-blender-courtyard}
    map=$(clean_map "$name")
    d="$WORK/match"
    echo "== BSDF match on $name, $MATCH_SPP spp, direct light"
    t=$(cycles "$HERE/lumis-gi-bsdf.json" "$map" "$MATCH_SPP" 1001 0 "$d/cycles.exr" "$d/cycles.log")
    echo "   cycles $t s"
    t=$(lumis "$HERE/lumis-gi-bsdf.json" "$map" "$MATCH_SPP" 1001 0 "$d/lumis.exr")
    echo "   lumis glossy $t s"
    t=$(lumis "$HERE/lumis-gi-bsdf.json" "$map" "$MATCH_SPP" 7 0 "$d/lumis-seed7.exr")
    echo "   lumis glossy, seed 7 $t s"
    t=$(lumis "$HERE/lumis-gi-bsdf-conductor.json" "$map" "$MATCH_SPP" 1001 0 "$d/lumis-conductor.exr")
    echo "   lumis conductor $t s"
    echo "== mean Y and 3x3 regions: Cycles first, then lumis glossy, lumis glossy seed 7, lumis conductor"
    blender -b --factory-startup -P "$HERE/imgstats.py" -- "$d/cycles.exr" "$d/lumis.exr" \
        "$d/lumis-seed7.exr" "$d/lumis-conductor.exr" --grid 3 2>&1 | grep -E "MEAN|REGION"
    for t in lumis lumis-seed7 lumis-conductor; do
        echo "relMSE $t vs cycles: $(relmse "$d/cycles.exr" "$d/$t.exr")"
    done
    echo "relMSE lumis seed 7 vs lumis seed 1001 (noise of two lumis renders): $(relmse "$d/lumis.exr" "$d/lumis-seed7.exr")"
    ;;
series)
    scene=${1:?series SCENE [MAP]}
    name=${2:-blender-courtyard}
    sc="$HERE/lumis-gi-$scene.json"
    [ -f "$sc" ] || { echo "run-gi.sh: $sc missing" >&2; exit 1; }
    map=$(clean_map "$name")
    [ -s "$CSV" ] || echo "scene,map,renderer,estimator,spp,seconds,relmse" >"$CSV"
    p="$WORK/img/$scene-$name"
    cref="$p-cycles-ref-$REF_SPP.exr"
    lref="$p-lumis-ref-$REF_SPP.exr"
    if [ ! -s "$cref" ]; then
        t=$(cycles "$sc" "$map" "$REF_SPP" 1001 "$BOUNCES" "$cref" "$WORK/log/$scene-$name-ref.log")
        echo "== $scene $name: Cycles reference $REF_SPP spp: $t s"
    fi
    if [ ! -s "$lref" ]; then
        t=$(lumis "$sc" "$map" "$REF_SPP" 1001 "$BOUNCES" "$lref")
        echo "== $scene $name: lumis reference $REF_SPP spp: $t s"
    fi
    echo "   references: relMSE lumis vs Cycles $(relmse "$cref" "$lref")"
    spp=1
    while [ "$spp" -le "$MAX_SPP" ]; do
        o="$p-cycles-$spp.exr"
        t=$(cycles "$sc" "$map" "$spp" 1 "$BOUNCES" "$o" "$WORK/log/$scene-$name-$spp.log")
        echo "$scene,$name,cycles-3.4.1,pmj,$spp,$t,$(relmse "$cref" "$o")" >>"$CSV"
        o="$p-mis-$spp.exr"
        t=$(lumis "$sc" "$map" "$spp" 1 "$BOUNCES" "$o")
        echo "$scene,$name,lumis,inversion-mis,$spp,$t,$(relmse "$lref" "$o")" >>"$CSV"
        o="$p-strat-$spp.exr"
        t=$(lumis "$sc" "$map" "$spp" 1 "$BOUNCES" "$o" --lights median-cut --lights-mode stratified)
        echo "$scene,$name,lumis,stratified-median-cut,$spp,$t,$(relmse "$lref" "$o")" >>"$CSV"
        tail -3 "$CSV" | sed 's/^/   /'
        spp=$((spp * 2))
    done
    ;;
*) echo "run-gi.sh: unknown mode $mode" >&2; exit 2 ;;
esac
