#!/usr/bin/env bash
# Regenerates docs/results/wu/figures: the light distributions of Wu's Fig. 4-5 (and the
# cut variants of Fig. 6) drawn by `lumis lights --png`, K = 64, for Wu's method, Wu with
# the original (variance-only) cut, median cut and variance minimisation, on three maps of
# data/hdri and the procedural sky, and FHIS and TMMS on the sunset; and figures/summary.txt, what each run printed (counts
# of EnvDirects and EnvIndirects, emissive pixels, L_T) without the build time.
# Every method is deterministic (fixed seeds), so a re-run writes the same files.
#
#   docs/results/wu/make-figures.sh          (after building ./build/lumis)
#   LUMIS=path/to/lumis docs/results/wu/make-figures.sh
set -euo pipefail

ROOT="$(cd "$(dirname "$0")/../../.." && pwd)"
LUMIS="${LUMIS:-$ROOT/build/lumis}"
OUT="$ROOT/docs/results/wu/figures"
K=64
WIDTH=512 # photographs at 1024 x 512 make 1.3 MB PNGs; 512 wide keeps each under 400 KB
MAPS=(blender-forest blender-sunset blender-interior)
METHODS=(wu wu-original-cut median-cut variance-min)
EXTRA_METHODS=(fhis tmms)

if [ ! -x "$LUMIS" ]; then
    echo "make-figures: no $LUMIS; build first (cmake -S . -B build && cmake --build build)" >&2
    exit 1
fi
for m in "${MAPS[@]}"; do
    [ -f "$ROOT/data/hdri/$m.exr" ] || "$ROOT/scripts/fetch-data.sh"
done

mkdir -p "$OUT"
summary="$OUT/summary.txt"
: >"$summary"
for m in "${MAPS[@]}" sky; do
    if [ "$m" = sky ]; then map="sky:1024x512"; else map="data/hdri/$m.exr"; fi
    for method in "${METHODS[@]}"; do
        png="$OUT/$m-$method.png"
        # map named relative to the repository, so that summary.txt is the same anywhere
        (cd "$ROOT" && "$LUMIS" lights "$map" --method "$method" -k "$K" \
            --png "$png" --png-width "$WIDTH") |
            sed -n '1,/^total power/p' | sed 's/, built in [0-9.]* ms//' >>"$summary"
        echo "make-figures: $(basename "$png") $(wc -c <"$png") bytes"
    done
done
# FHIS and TMMS, the other rows of Table 1, on the sunset only
for method in "${EXTRA_METHODS[@]}"; do
    m=blender-sunset
    png="$OUT/$m-$method.png"
    (cd "$ROOT" && "$LUMIS" lights "data/hdri/$m.exr" --method "$method" -k "$K" \
        --png "$png" --png-width "$WIDTH") |
        sed -n '1,/^total power/p' | sed 's/, built in [0-9.]* ms//' >>"$summary"
    echo "make-figures: $(basename "$png") $(wc -c <"$png") bytes"
done
