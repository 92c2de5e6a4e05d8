#!/usr/bin/env bash
# lumis's default (`lumis render` with no estimator option: the automatic estimator,
# docs/render.md) against Cycles on the scene of run.sh / lumis.sh, side by side: per map
# and per spp = 1, 2, 4, ..., MAX_SPP, one lumis render and then one Cycles render of the
# same spp, both on one thread and pinned to the same CPU (taskset), so that both series'
# times see the same load.  lumis's relMSE is against lumis's own reference (lumis.sh's:
# REF_SPP of inversion + MIS, sobol, seed SEED + 1000); Cycles' relMSE is the one
# recorded in cycles.csv for the same map, spp and seed (run.sh: against Cycles' own
# reference; the same seed and settings give the same image), and for a check also
# against lumis's reference (the two references agree to relMSE ~2e-5, README).
#
#   bench/cycles/default.sh MAP...      (MAP: a name in data/hdri/)
#
# Environment: REF_SPP (8192), REF_THREADS (2: the reference is not timed), MAX_SPP
# (1024), SEED (1), CPU (1), CYCLES (1; 0 leaves Cycles out), WORK
# (/tmp/cycles/lumis-default), CSV (bench/cycles/lumis-default.csv).
#
# Columns: map, renderer, sequence ("default"), spp, seconds, relmse — as lumis.csv, with
# seconds = the sidecar's render_seconds + auto_estimator.seconds (the pilots and the
# prior's regions are in prep_seconds, not in render_seconds; the default pays them, so
# they are counted) — then estimator (what the default chose), auto_why, render_seconds,
# auto_seconds, pilot_seconds, lumis_wall_seconds (the sidecar's wall_seconds), cycles_seconds
# (Cycles' "Render time (without synchronization)"), cycles_total_seconds ("Total render
# time", with the sync), cycles_relmse_vs_lumis_ref, load (1-minute load average before
# the pair).
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
HERE="$ROOT/bench/cycles"
LUMIS="$ROOT/build/lumis"
REF_SPP=${REF_SPP:-8192}
REF_THREADS=${REF_THREADS:-2}
MAX_SPP=${MAX_SPP:-1024}
SEED=${SEED:-1}
CPU=${CPU:-1}
CYCLES=${CYCLES:-1}
WORK=${WORK:-/tmp/cycles/lumis-default}
CSV=${CSV:-$HERE/lumis-default.csv}
SCENE="$HERE/lumis-bunny-plane-noball.json"
[ $# -ge 1 ] || { echo "usage: $0 MAP..." >&2; exit 2; }
[ -x "$LUMIS" ] || { echo "default.sh: $LUMIS not built (make)" >&2; exit 1; }
if [ "$CYCLES" = 1 ]; then
    command -v blender >/dev/null || { echo "default.sh: blender not found (CYCLES=0?)" >&2; exit 1; }
fi
mkdir -p "$WORK"
[ -s "$CSV" ] || echo "map,renderer,sequence,spp,seconds,relmse,estimator,auto_why,render_seconds,auto_seconds,pilot_seconds,lumis_wall_seconds,cycles_seconds,cycles_total_seconds,cycles_relmse_vs_lumis_ref,load" >"$CSV"
VERSION=$("$LUMIS" --version | awk '{print $2}')

relmse() { "$LUMIS" compare "$1" "$2" --json --no-hdr-flip |
    sed -n 's/.*"relmse":\([^,}]*\).*/\1/p'; }
# The sidecar's fields, read by python (the sidecar is JSON).
fields() {
    python3 - "$1" <<'EOF'
import json, sys
d = json.load(open(sys.argv[1]))
a = d.get("auto_estimator") or {}
t = d["timing"] if "timing" in d else d
def find(o, k):
    if isinstance(o, dict):
        if k in o and not isinstance(o[k], (dict, list)):
            return o[k]
        for v in o.values():
            r = find(v, k)
            if r is not None:
                return r
    return None
r = find(d, "render_seconds")
s = a.get("seconds", 0.0) or 0.0
print("%r %r %r %r %r %s %s" % (r + s, r, s, a.get("pilot_seconds", 0.0) or 0.0,
                                find(d, "wall_seconds"), a.get("chosen", "none"),
                                (a.get("why") or "none").replace(" ", "_").replace(",", ";")))
EOF
}

for name in "$@"; do
    src="$ROOT/data/hdri/$name.exr"
    [ -f "$src" ] || { echo "default.sh: $src missing (scripts/fetch-data.sh)" >&2; exit 1; }
    ref="$WORK/$name-ref-$REF_SPP.exr"
    if [ ! -s "$ref" ]; then
        echo "== $name: lumis reference, $REF_SPP spp (inversion + MIS, sobol, seed $((SEED + 1000)))"
        "$LUMIS" render "$SCENE" --env "$src" --spp "$REF_SPP" --threads "$REF_THREADS" \
            --seed $((SEED + 1000)) --sequence sobol --no-auto --quiet -o "$ref" 2>/dev/null
    fi
    map="$WORK/$name-converted.exr" # Cycles' map: as lumis sees it (run.sh)
    [ "$CYCLES" = 1 ] && "$LUMIS" convert "$src" "$map" --compression none 2>/dev/null
    spp=1
    while [ "$spp" -le "$MAX_SPP" ]; do
        load=$(cut -d' ' -f1 /proc/loadavg)
        out="$WORK/$name-default-$spp.exr"
        # No estimator option: what `lumis render` does by default.
        taskset -c "$CPU" "$LUMIS" render "$SCENE" --env "$src" --spp "$spp" --threads 1 \
            --seed "$SEED" --quiet -o "$out" 2>/dev/null
        read -r sec rs as ps lw chosen why <<<"$(fields "${out%.exr}.json")"
        e=$(relmse "$ref" "$out")
        cs=NA ct=NA ce=NA
        if [ "$CYCLES" = 1 ]; then
            cout="$WORK/$name-cycles-$spp.exr" clog="$WORK/$name-cycles-$spp.log"
            taskset -c "$CPU" blender -b --factory-startup -t 1 --debug-cycles \
                -P "$HERE/scene.py" -- --map "$map" --spp "$spp" --seed "$SEED" \
                --out "$cout" >"$clog" 2>&1 || { echo "default.sh: blender failed, see $clog" >&2; exit 1; }
            cs=$(sed -n 's/.*Render time (without synchronization): \([0-9.e+-]*\).*/\1/p' "$clog" | tail -1)
            ct=$(sed -n 's/.*Total render time: \([0-9.e+-]*\).*/\1/p' "$clog" | tail -1)
            ce=$(relmse "$ref" "$cout")
        fi
        echo "$name,lumis-$VERSION,default,$spp,$sec,$e,$chosen,$why,$rs,$as,$ps,$lw,$cs,$ct,$ce,$load" >>"$CSV"
        echo "   $name $spp spp: $chosen, ${sec} s, relMSE $e; Cycles ${cs} s (load $load)"
        spp=$((spp * 2))
    done
done
