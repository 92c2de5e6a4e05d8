#!/bin/sh
# Equal-CPU-time measurements of docs/results/tenth/README.md ("Equal CPU time").  From the
# repository's root, after building: docs/results/tenth/measure.sh OUT_DIR
# Each configuration is rendered twice at a fixed spp, seeds 11 and 12, one thread; the
# relMSE between the two images is twice each image's (no reference needed), and the
# sidecar's cpu_seconds is the cost.  LUMIS selects the binary (for the prototype of
# region-inversion.patch, build it apart and set LUMIS_REGION_INV=1 in the environment).
set -e
OUT=${1:?usage: measure.sh OUT_DIR}
L=${LUMIS:-./build/lumis}
mkdir -p "$OUT"
pair() { # MAP SCENE SPP SEQ LABEL ARGS...
    MAP=$1 SCENE=$2 SPP=$3 SEQ=$4 LABEL=$5
    shift 5
    for s in 11 12; do
        "$L" render --scene "$SCENE" --env "data/hdri/$MAP.exr" --spp "$SPP" --size 160x120 \
            --threads 1 --sequence "$SEQ" --seed $s "$@" -o "$OUT/$LABEL-$s.exr" >/dev/null 2>&1
    done
    r=$("$L" compare "$OUT/$LABEL-11.exr" "$OUT/$LABEL-12.exr" | awk '/^relmse/{print $2}')
    c=$(python3 -c "import json;print(json.load(open('$OUT/$LABEL-11.json'))['timings']['cpu_seconds'])")
    echo "$MAP $SCENE $SPP $SEQ $LABEL relmse_between=$r cpu_s=$c"
}
S="--lights median-cut --lights-mode stratified --lights-k 32"
M="--method inversion --mis balance"
# the sequences' gain at equal spp, courtyard / diffuse
for spp in 16 64; do
    pair blender-courtyard wu-diffuse $spp pcg cd-strat-pcg-$spp $S
    pair blender-courtyard wu-diffuse $spp sobol cd-strat-sobol-$spp $S
    pair blender-courtyard wu-diffuse $spp pcg cd-mis-pcg-$spp $M
    pair blender-courtyard wu-diffuse $spp sobol cd-mis-sobol-$spp $M
done
for seq in pcg sobol; do pair blender-courtyard wu-diffuse 64 $seq cd-alias-$seq-64 --method alias --mis balance; done
# equal CPU time: strata at 64 spp against MIS at 256 (about the same CPU seconds)
for mp in "blender-courtyard wu-diffuse cd" "pmndrs-lobby wu-glossy lg" "blender-sunrise wu-diffuse sd"; do
    set -- $mp
    pair $1 $2 64 pcg $3-strat-pcg-64 $S
    pair $1 $2 64 sobol $3-strat-sobol-64 $S
    pair $1 $2 256 pcg $3-mis-pcg-256 $M
    pair $1 $2 256 sobol $3-mis-sobol-256 $M
    # the prototype of region-inversion.patch: LUMIS=path/to/its/lumis PROTO=1
    if [ -n "$PROTO" ]; then
        export LUMIS_REGION_INV=1
        pair $1 $2 64 sobol $3-strat-inv-sobol-64 $S
        if [ $3 = cd ]; then
            pair $1 $2 16 sobol $3-strat-inv-sobol-16 $S
            pair $1 $2 16 pcg $3-strat-inv-pcg-16 $S
        fi
        unset LUMIS_REGION_INV
    fi
done
