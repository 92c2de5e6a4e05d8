#!/bin/sh
# The light-distribution pictures of docs/results/wu/README.md (Wu's Fig. 4-6): each map,
# downscaled to 768x384 first (so the committed PNGs stay small and the 1-pixel markings
# stay sharp), with K = 64 lights of a method drawn on it by `lumis lights --png`.
# Usage: docs/results/wu/make-figures.sh [path/to/lumis]   (from the repository's root,
# after scripts/fetch-data.sh)
set -eu
LUMIS=${1:-./build/lumis}
OUT=docs/results/wu/figures
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
mkdir -p "$OUT"
for map in sky pmndrs-sunset blender-interior; do
    if [ "$map" = sky ]; then
        "$LUMIS" sky --size 768x384 -o "$TMP/$map.exr" >/dev/null
    else
        "$LUMIS" convert "data/hdri/$map.exr" "$TMP/$map.exr" --resize 768x384 >/dev/null
    fi
    for method in wu median-cut variance-min wu-original-cut; do
        "$LUMIS" lights "$TMP/$map.exr" --method "$method" -k 64 --png "$OUT/$map-$method.png" \
            >/dev/null
    done
done
ls -l "$OUT"
