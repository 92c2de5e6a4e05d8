#!/usr/bin/env bash
# The pictures of docs/blender.md, rendered headless by blender/docs_images.py (Cycles):
#   scripts/blender-docs-images.sh [OUT_DIR]       (default docs/images)
# Needs blender, data/hdri/blender-sunrise.exr (scripts/fetch-data.sh) and the shared
# libraries in build/ (`make run`).  About a minute on two cores.
set -euo pipefail
ROOT="$(cd "$(dirname "$0")/.." && pwd)"
OUT="$(mkdir -p "${1:-$ROOT/docs/images}" && cd "${1:-$ROOT/docs/images}" && pwd)"
T="$(mktemp -d)"
trap 'rm -rf "$T"' EXIT
"$ROOT/scripts/blender-addon.sh" "$T/lumis_lights.zip" >/dev/null
"$ROOT/build/lumis" convert "$ROOT/data/hdri/blender-sunrise.exr" "$T/sunrise.exr" \
    --resize 512x256 >/dev/null 2>&1
mkdir -p "$T/scripts"
BLENDER_USER_SCRIPTS="$T/scripts" LUMIS_LIBRARY_PATH="${LUMIS_LIBRARY_PATH:-$ROOT/build}" \
    PYTHONDONTWRITEBYTECODE=1 blender -b --factory-startup --python-exit-code 1 \
    --python "$ROOT/blender/docs_images.py" -- --zip "$T/lumis_lights.zip" \
    --map "$T/sunrise.exr" --fixture "$ROOT/tests/data/photometric/luxcore_asa_15m_r2.ies" \
    --lumis-python "$ROOT/python" --out "$OUT" 2>&1 | grep -v '^Fra:\|^Saved:\|^ Time:\|^$'
