#!/usr/bin/env bash
# Cycles 3.4 (CPU) on lumis's bunny-plane scene (bench/cycles/scene.py): per map a
# high-spp Cycles reference, then Cycles at spp = 1, 2, 4, ..., 1024 on one thread, each
# timed and compared with Cycles' own reference (relMSE of `lumis compare`).
#
#   bench/cycles/run.sh MAP...        (MAP: a name in data/hdri/, or a path to a .exr)
#
# Environment: REF_SPP (8192), REF_THREADS (1; 2 only on an otherwise idle machine),
# MAX_SPP (1024), SEED (1, the series' Cycles seed; the reference uses SEED + 1000),
# WORK (/tmp/cycles/run: maps, images, logs), CSV (bench/cycles/cycles.csv),
# DETAIL (bench/cycles/cycles-detail.csv), NICE (10).
# Every Blender runs under `nice -n $NICE`.  The CSVs are appended to (a header is written
# when the file is new), so maps can be run one at a time.
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
HERE="$ROOT/bench/cycles"
LUMIS="$ROOT/build/lumis"
REF_SPP=${REF_SPP:-8192}
REF_THREADS=${REF_THREADS:-1}
MAX_SPP=${MAX_SPP:-1024}
SEED=${SEED:-1}
WORK=${WORK:-/tmp/cycles/run}
CSV=${CSV:-$HERE/cycles.csv}
DETAIL=${DETAIL:-$HERE/cycles-detail.csv}
NICE=${NICE:-10}
[ $# -ge 1 ] || { echo "usage: $0 MAP..." >&2; exit 2; }
command -v blender >/dev/null || { echo "run.sh: blender not found (apt-get install blender)" >&2; exit 1; }
[ -x "$LUMIS" ] || { echo "run.sh: $LUMIS not built (make)" >&2; exit 1; }
mkdir -p "$WORK/maps" "$WORK/img" "$WORK/log"
VERSION=$(blender -b --factory-startup --version 2>/dev/null | head -1 | awk '{print $2}')
RENDERER="cycles-$VERSION"
[ -s "$CSV" ] || echo "map,renderer,sequence,spp,seconds,relmse" >"$CSV"
[ -s "$DETAIL" ] ||
    echo "map,spp,threads,seed,sampling_seconds,total_render_seconds,render_call_seconds,relmse" >"$DETAIL"

# One Cycles render; prints "sampling total call" seconds.  sampling: Cycles' "Render time
# (without synchronization)"; total: its "Total render time" (with the scene sync: BVH,
# image, the world's importance map); call: scene.py's wall time of the render call.
render() { # map spp threads seed out log [extra scene.py args]
    local map=$1 spp=$2 threads=$3 seed=$4 out=$5 log=$6
    shift 6
    nice -n "$NICE" blender -b --factory-startup -t "$threads" --debug-cycles \
        -P "$HERE/scene.py" -- --map "$map" --spp "$spp" --seed "$seed" --out "$out" "$@" \
        >"$log" 2>&1 || { echo "run.sh: blender failed, see $log" >&2; exit 1; }
    local s t c
    s=$(sed -n 's/.*Render time (without synchronization): \([0-9.e+-]*\).*/\1/p' "$log" | tail -1)
    t=$(sed -n 's/.*Total render time: \([0-9.e+-]*\).*/\1/p' "$log" | tail -1)
    c=$(sed -n 's/^RENDER_SECONDS \([0-9.e+-]*\).*/\1/p' "$log" | tail -1)
    [ -n "$s" ] && [ -n "$c" ] && [ -s "$out" ] || { echo "run.sh: no timing/image, see $log" >&2; exit 1; }
    echo "$s ${t:-NA} $c"
}

relmse() { "$LUMIS" compare "$1" "$2" --json --no-hdr-flip |
    sed -n 's/.*"relmse":\([^,}]*\).*/\1/p'; }

for m in "$@"; do
    case $m in
    *.exr | *.hdr | *.pfm) src=$m name=$(basename "${m%.*}") ;;
    *) src="$ROOT/data/hdri/$m.exr" name=$m ;;
    esac
    [ -f "$src" ] || { echo "run.sh: $src missing (scripts/fetch-data.sh)" >&2; exit 1; }
    # lumis replaces negative, NaN and infinite channel values by 0 on load; Cycles would
    # use them.  Both renderers get the map as lumis sees it.
    map="$WORK/maps/$name.exr"
    "$LUMIS" convert "$src" "$map" --compression none 2>/dev/null
    ref="$WORK/img/$name-cycles-ref-$REF_SPP.exr"
    if [ ! -s "$ref" ]; then
        echo "== $name: reference, $REF_SPP spp, $REF_THREADS thread(s)"
        r=$(render "$map" "$REF_SPP" "$REF_THREADS" $((SEED + 1000)) "$ref" \
            "$WORK/log/$name-ref.log")
        read -r s t c <<<"$r"
        echo "$name,$REF_SPP,$REF_THREADS,$((SEED + 1000)),$s,$t,$c,0" >>"$DETAIL"
        echo "   sampling $s s (total $t s, call $c s)"
    fi
    spp=1
    while [ "$spp" -le "$MAX_SPP" ]; do
        out="$WORK/img/$name-cycles-$spp.exr"
        r=$(render "$map" "$spp" 1 "$SEED" "$out" "$WORK/log/$name-$spp.log")
        read -r s t c <<<"$r"
        e=$(relmse "$ref" "$out")
        echo "$name,$RENDERER,pmj,$spp,$s,$e" >>"$CSV"
        echo "$name,$spp,1,$SEED,$s,$t,$c,$e" >>"$DETAIL"
        printf '   %5d spp  %9.4f s  relMSE %.5g\n' "$spp" "$s" "$e"
        spp=$((spp * 2))
    done
done
