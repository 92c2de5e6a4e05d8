#!/bin/sh
# Equal-CPU measurements of docs/results/sun/README.md, section "2026-11-28".  From the
# repository's root after building and scripts/fetch-data.sh:
#   docs/results/sun/measure-alloc.sh OUT_DIR
# Each configuration twice at a fixed spp (seeds 11 and 12), one thread, default sequence
# (Sobol'); the relMSE of one image is (A - B)^2 / 2 over (ref^2 + 0.01), ref a 64-spp
# render of the strata (K = 32, seed 3) used only as the denominator; the cost is the mean
# of the sidecars' cpu_seconds.  The ratio to MIS in the README is relMSE x CPU over MIS's.
set -e
OUT=${1:?usage: measure-alloc.sh OUT_DIR}
L=${LUMIS:-./build/lumis}
mkdir -p "$OUT"
S="--lights median-cut --lights-mode stratified"
one() { # MAP SCENE SPP LABEL ARGS...
    MAP=$1 SC=$2 SPP=$3 T=$4
    shift 4
    O="$OUT/$MAP-$SC"
    mkdir -p "$O"
    [ -f "$O/ref.pfm" ] || "$L" render --scene "$SC" --env "data/hdri/$MAP.exr" --spp 64 \
        --size 160x120 --threads 1 --seed 3 $S --lights-k 32 -o "$O/ref.pfm" >/dev/null 2>&1
    for s in 11 12; do
        "$L" render --scene "$SC" --env "data/hdri/$MAP.exr" --spp "$SPP" --size 160x120 \
            --threads 1 --seed $s "$@" -o "$O/$T-$s.pfm" >/dev/null 2>&1
    done
    python3 - "$O" "$T" "$MAP $SC $T spp $SPP" <<'PY'
import json, struct, sys
o, t, what = sys.argv[1:]
def read(p):
    b = open(p, 'rb').read().split(b'\n', 3)
    w, h = map(int, b[1].split())
    n = 3 * w * h
    return struct.unpack(('<' if float(b[2]) < 0 else '>') + 'f' * n, b[3][:4 * n])
ref, a, b = read(o + '/ref.pfm'), read(o + '/%s-11.pfm' % t), read(o + '/%s-12.pfm' % t)
r = sum((x - y) ** 2 / (z * z + 1e-2) for x, y, z in zip(a, b, ref)) / len(ref) / 2
c = sum(json.load(open(o + '/%s-%d.json' % (t, s)))['timings']['cpu_seconds'] for s in (11, 12)) / 2
print('%s relmse %.3g cpu %.3f rel*cpu %.3g' % (what, r, c, r * c))
PY
}
for MAP in blender-sunrise pmndrs-studio; do
    for SC in wu-diffuse wu-glossy; do
        one $MAP $SC 160 mis --method inversion --mis balance
        one $MAP $SC 32 k32 $S --lights-k 32
        one $MAP $SC 16 k32rd64 $S --lights-k 32 --lights-region-draws 64
        one $MAP $SC 20 k32rd48 $S --lights-k 32 --lights-region-draws 48
        one $MAP $SC 48 k16 $S --lights-k 16
        one $MAP $SC 48 k32d16 $S --lights-k 32 --lights-draws 16
        one $MAP $SC 32 k32sun $S --lights-k 32 --sun
    done
done
