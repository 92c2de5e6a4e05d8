#!/bin/sh
# Equal-CPU-time measurements of docs/results/tenth/README.md, section "Region draws by
# inversion".  From the repository's root, after building this commit and the commit before
# the region sampler's inversion (the alias tables) apart:
#   OLD=path/to/old/lumis docs/results/tenth/measure-inv.sh OUT_DIR [SPP_STRATA SPP_MIS]
# As measure.sh: each configuration twice at a fixed spp, seeds 11 and 12, one thread; the
# relMSE between the two images is twice each image's (no reference needed), and the
# sidecars' cpu_seconds (both seeds') is the cost.  Default sequence (Sobol').
#   COST=1 OLD=... measure-inv.sh OUT_DIR     the cost per stratified sample instead: the
# two builds' strata renders at 16 spp alternated 4 times per pair, medians of CPU seconds.
set -e
OUT=${1:?usage: OLD=old/lumis measure-inv.sh OUT_DIR [SPP_STRATA SPP_MIS]}
NEW=${LUMIS:-./build/lumis}
OLD=${OLD:?OLD=path to the lumis with the alias-table region draws}
SS=${2:-64} SM=${3:-256}
mkdir -p "$OUT"
pair() { # BIN MAP SCENE SPP LABEL ARGS...
    B=$1 MAP=$2 SCENE=$3 SPP=$4 LABEL=$5
    shift 5
    for s in 11 12; do
        "$B" render --scene "$SCENE" --env "data/hdri/$MAP.exr" --spp "$SPP" --size 160x120 \
            --threads 1 --seed $s "$@" -o "$OUT/$LABEL-$s.exr" >/dev/null 2>&1
    done
    r=$("$NEW" compare "$OUT/$LABEL-11.exr" "$OUT/$LABEL-12.exr" | awk '/^relmse/{print $2}')
    c=$(python3 -c "import json;print(sum(json.load(open('$OUT/$LABEL-%d.json'%s))['timings']['cpu_seconds'] for s in (11,12))/2)")
    echo "$MAP $SCENE $SPP $LABEL relmse=$(python3 -c "print($r/2)") cpu_s=$c"
}
S="--lights median-cut --lights-mode stratified --lights-k 32"
M="--method inversion --mis balance"
if [ -n "$COST" ]; then
    for mp in "blender-courtyard wu-diffuse" "pmndrs-lobby wu-glossy" "blender-sunrise wu-diffuse"; do
        set -- $mp
        for i in 1 2 3 4; do
            for B in "$OLD" "$NEW"; do
                "$B" render --scene $2 --env "data/hdri/$1.exr" --spp 16 --size 160x120 \
                    --threads 1 --seed 11 $S -o "$OUT/cost.exr" >/dev/null 2>&1
                python3 -c "import json;print('$B', json.load(open('$OUT/cost.json'))['timings']['cpu_seconds'])"
            done
        done | python3 -c "
import sys, statistics as st
d = {}
for l in sys.stdin:
    b, c = l.split(); d.setdefault(b, []).append(float(c))
o, n = d['$OLD'], d['$NEW']
print('$1 $2 16 spp: alias %.3f s, inversion %.3f s (medians of %d), ratio %.3f' % (st.median(o), st.median(n), len(o), st.median(n) / st.median(o)))"
    done
    exit 0
fi
for mp in "blender-courtyard wu-diffuse cd" "pmndrs-lobby wu-glossy lg" "blender-sunrise wu-diffuse sd"; do
    set -- $mp
    pair "$OLD" $1 $2 $SS $3-strat-alias-$SS $S
    pair "$NEW" $1 $2 $SS $3-strat-inv-$SS $S
    pair "$NEW" $1 $2 $SM $3-mis-$SM $M
done
