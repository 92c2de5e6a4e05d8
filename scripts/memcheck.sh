#!/usr/bin/env bash
# valgrind's memcheck over one tiny run of every light kind and every sampler (CI's memcheck
# stage).  valgrind emulates an AVX2 CPU, so Embree runs its AVX2 kernels and lumis its AVX2
# variants here even on an AVX-512 machine.  Any error fails the run (exit 1), with the log.
#
#   scripts/memcheck.sh [BUILD_DIR]      (default: build)
set -euo pipefail
cd "$(dirname "$0")/.."
B=${1:-build}
L="$B/lumis"
[ -x "$L" ] || { echo "memcheck: no $L (build first: make build)" >&2; exit 2; }
command -v valgrind >/dev/null || { echo "memcheck: valgrind is not installed" >&2; exit 2; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail=0 runs=0
vg() { # NAME ARGS...: one run under memcheck
    local name=$1
    shift
    runs=$((runs + 1))
    if valgrind -q --error-exitcode=99 --track-origins=yes --leak-check=no \
        --log-file="$tmp/$name.log" "$L" "$@" >"$tmp/$name.out" 2>&1 && [ ! -s "$tmp/$name.log" ]; then
        printf '  %-28s clean\n' "$name"
    else
        printf '  %-28s FAILED: lumis %s\n' "$name" "$*"
        sed -n '1,60p' "$tmp/$name.log" "$tmp/$name.out"
        fail=1
    fi
}
R=(--size 12x9 --spp 1 --threads 2 --quiet --no-sidecar)
echo "memcheck: renders (environment map with MIS, the automatic estimator, every light set, Wu with upsampling, strata)"
vg env-mis render --scene spheres --env sky:64x32 --no-auto "${R[@]}" -o "$tmp/a.exr"
# the default: the automatic estimator, its pilots (32 spp: a render big enough for them)
vg env-auto render --scene spheres --env sky:64x32 --size 12x9 --spp 32 --threads 2 --quiet \
    --no-sidecar -o "$tmp/a.exr"
vg env-mis-power render --scene bunny-plane --env sky:64x32 --mis power "${R[@]}" -o "$tmp/a.exr"
for q in pcg halton stratified zsobol pmj02; do # (sobol: the default, every other run)
    vg "sequence-$q" render --scene bunny-plane --env sky:64x32 --bounces 1 --sequence "$q" \
        "${R[@]}" -o "$tmp/a.exr"
done
for m in median-cut variance-min fhis tmms; do
    vg "lights-$m" render --scene spheres --env sky:64x32 --lights "$m" --lights-k 20 "${R[@]}" \
        -o "$tmp/a.exr"
done
vg lights-wu-upsample render --scene wu-diffuse --env sky:128x64 --lights wu --lights-k 24 \
    --upsample 2 "${R[@]}" -o "$tmp/a.exr"
# the stratified mode: region samplers, batched draws, MIS per region, Wu's two layers
vg lights-stratified render --scene bunny-plane --env sky:64x32 --lights median-cut \
    --lights-mode stratified --lights-k 12 "${R[@]}" -o "$tmp/a.exr"
vg lights-wu-stratified render --scene wu-glossy --env sky:128x64 --lights wu \
    --lights-mode stratified --lights-k 24 --upsample 2 "${R[@]}" -o "$tmp/a.exr"
echo "memcheck: the headlight luminaire, each visibility (a small luminaire made natively)"
"$L" luminaire create "$tmp/lum.json" --preset small >/dev/null
for v in exact approx shadowmap none; do
    vg "luminaire-$v" render --scene headlight --luminaire "$tmp/lum.json" --visibility "$v" \
        --lum-budget 8 "${R[@]}" -o "$tmp/a.exr"
done
echo "memcheck: photometric files and fixtures (points and openings, MIS), their light field"
P="$(cd "$(dirname "$0")/.." && pwd)/docs/examples/photometric"
vg photometric-info info "$P/road-asymmetric.ies" --svg "$tmp/p.svg"
vg photometric-fixtures render "$P/fixtures.json" "${R[@]}" -o "$tmp/a.exr"
vg photometric-light-field luminaire create "$tmp/lf.json" --from "$P/spot-cos10.ies" \
    --grid 3x3 --size 16x16
echo "memcheck: which strategy pays (the prediction, auto with bands)"
vg luminaire-predict luminaire predict "$tmp/lf.json" --distance 0.2,2 --bands 2 --probes 32
vg luminaire-auto render --scene headlight --luminaire "$tmp/lum.json" --lum-strategy auto \
    --lum-auto-bands --lum-budget 8 "${R[@]}" -o "$tmp/a.exr"
echo "memcheck: every sampler"
for m in inversion inversion-guided alias kdtree kdtree-exact hierarchical uniform; do
    vg "sample-$m" sample sky:64x32 --method "$m" -n 200
done
vg lights-export lights sky:64x32 --method wu -k 16 --json "$tmp/l.json" --gltf "$tmp/l.gltf"
if [ "$fail" -ne 0 ]; then
    echo "memcheck: FAILED (logs above)"
    exit 1
fi
echo "memcheck: $runs runs, no errors"
