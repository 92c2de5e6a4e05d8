#!/usr/bin/env bash
# lumis's light exports tested in their consumers (docs/lights-export.md, "Tests in the
# consumers"):
#
#   tests/consumers/run.sh validator|threejs|blender LUMIS_CLI [DATA_DIR]
#
# The HDRI data/hdri/blender-sunrise.exr (a low sun: 61 % of its power in 0.1 % of its
# pixels) is resampled to 256 x 128 with `lumis convert` (power-preserving, Radiance .hdr,
# which both consumers read), and `lumis lights --method wu -k 16` exports it as
# engine.gltf / engine.glb (the default frame) and lumis.gltf (--frame lumis, the frame of
# issue 35's bug).  Then:
#   validator  the Khronos glTF validator (npm gltf-validator): no error or warning, a .glb
#              read as the binary container;
#   threejs    three.js in headless Chromium (threejs_lights.mjs): engine.gltf and
#              engine.glb line up with the HDRI (as .hdr and as .exr), lumis.gltf must not;
#   blender    Blender headless with its glTF importer and Cycles (blender_lights.py): the
#              same.
# Exit 77 (a ctest skip) when a tool is missing: chromium, blender (scripts/install-deps.sh
# --dev), node_modules (npm ci --prefix tests/consumers) or the data (scripts/fetch-data.sh);
# in CI (CI=true) a missing tool is a failure instead, so that the tests cannot pass by
# skipping.
set -euo pipefail
HERE="$(cd "$(dirname "$0")" && pwd)"
KIND="${1:-}"
L="${2:-}"
DATA="${3:-$HERE/../../data}"
[ -n "$KIND" ] && [ -x "$L" ] || { echo "usage: $0 validator|threejs|blender LUMIS_CLI [DATA_DIR]" >&2; exit 2; }

skip() {
    case "${CI:-}" in
    "" | 0 | false) echo "SKIP: $*"; exit 77 ;;
    *) echo "FAIL: $* (CI=$CI: the consumer tests must run in CI)"; exit 1 ;;
    esac
}
need_node() {
    command -v node >/dev/null || skip "no node (scripts/install-deps.sh --dev installs nodejs)"
    for m in "$@"; do
        [ -d "$HERE/node_modules/$m" ] || skip "no $m in tests/consumers/node_modules (npm ci --prefix tests/consumers)"
    done
}

MAP="$DATA/hdri/blender-sunrise.exr"
[ -r "$MAP" ] || skip "no $MAP (scripts/fetch-data.sh)"
case "$KIND" in
validator) need_node gltf-validator ;;
threejs)
    need_node three playwright-core
    [ -x "${LUMIS_CHROMIUM:-/usr/bin/chromium}" ] || skip "no chromium (scripts/install-deps.sh --dev)" ;;
blender) command -v blender >/dev/null || skip "no blender (scripts/install-deps.sh --dev)" ;;
*) echo "run.sh: unknown consumer '$KIND'" >&2; exit 2 ;;
esac

T="$(mktemp -d)"
trap 'rm -rf "$T"' EXIT
"$L" convert "$MAP" "$T/sunrise.hdr" --resize 256x128 >/dev/null 2>&1
lights() { "$L" lights "$T/sunrise.hdr" --method wu -k 16 "$@" >/dev/null; }
lights --gltf "$T/engine.gltf"
lights --gltf "$T/engine.glb"
lights --gltf "$T/lumis.gltf" --frame lumis

case "$KIND" in
validator)
    "$L" lights sky:64x32 --method median-cut -k 8 --gltf "$T/sky.glb" >/dev/null
    "$L" lights sky:64x32 --method variance-min -k 3 --gltf "$T/sky.gltf" --frame lumis >/dev/null
    node "$HERE/validate_gltf.mjs" "$T/engine.gltf" "$T/engine.glb" "$T/lumis.gltf" "$T/sky.glb" \
        "$T/sky.gltf"
    ;;
threejs)
    # the map as Radiance HDR (HDRLoader) and as OpenEXR (EXRLoader), which store their
    # rows in opposite orders
    "$L" convert "$T/sunrise.hdr" "$T/sunrise.exr" >/dev/null
    node "$HERE/threejs_lights.mjs" --hdr "$T/sunrise.hdr" --hdr "$T/sunrise.exr" \
        --expect-pass "$T/engine.gltf" --expect-pass "$T/engine.glb" --expect-fail "$T/lumis.gltf"
    ;;
blender)
    # Blender's own messages (render progress, saved files) stay in a log shown on failure
    set +e
    blender -b --factory-startup --python-exit-code 1 --python "$HERE/blender_lights.py" -- \
        --hdr "$T/sunrise.hdr" --expect-pass "$T/engine.gltf" --expect-pass "$T/engine.glb" \
        --expect-fail "$T/lumis.gltf" >"$T/blender.log" 2>&1
    rc=$?
    set -e
    if [ $rc = 77 ]; then skip "$(grep '^SKIP' "$T/blender.log" | head -1)"; fi
    if [ $rc = 0 ]; then grep -E '^(Blender|  |PASS|FAIL)|suns\)' "$T/blender.log"; else cat "$T/blender.log"; fi
    exit $rc
    ;;
esac
