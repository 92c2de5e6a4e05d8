#!/usr/bin/env bash
# The Blender add-on's test (docs/blender.md, "Test"):
#
#   tests/blender/run.sh LUMIS_CLI [DATA_DIR]
#
# Builds the add-on's zip (scripts/blender-addon.sh), resamples data/hdri/blender-sunrise.exr
# (a low sun) to 256 x 128 with `lumis convert`, and runs addon_test.py in Blender headless,
# the add-on installed into a temporary BLENDER_USER_SCRIPTS (the user's own Blender
# configuration untouched).  The add-on loads the lumis Python package from the source
# tree's python/ and the libraries from LUMIS_LIBRARY_PATH (set by ctest).
# Then fixture_test.py imports tests/data/photometric/luxcore_asa_15m_r2.ies as a lamp over
# a white floor ("Import Photometric Fixture").
# Exit 77 (a ctest skip) without blender or the data; in CI (CI=true) a failure instead.
set -euo pipefail
HERE="$(cd "$(dirname "$0")" && pwd)"
ROOT="$(cd "$HERE/../.." && pwd)"
L="${1:-}"
DATA="${2:-$ROOT/data}"
[ -x "$L" ] || { echo "usage: $0 LUMIS_CLI [DATA_DIR]" >&2; exit 2; }
skip() {
    case "${CI:-}" in
    "" | 0 | false) echo "SKIP: $*"; exit 77 ;;
    *) echo "FAIL: $* (CI=$CI: the add-on's test must run in CI)"; exit 1 ;;
    esac
}
command -v blender >/dev/null || skip "no blender (scripts/install-deps.sh --dev)"
MAP="$DATA/hdri/blender-sunrise.exr"
[ -r "$MAP" ] || skip "no $MAP (scripts/fetch-data.sh)"
T="$(mktemp -d)"
trap 'rm -rf "$T"' EXIT
"$ROOT/scripts/blender-addon.sh" "$T/lumis_lights.zip" >/dev/null
"$L" convert "$MAP" "$T/sunrise.exr" --resize 256x128 >/dev/null 2>&1
mkdir -p "$T/scripts"
status=0
BLENDER_USER_SCRIPTS="$T/scripts" blender -b --factory-startup --python-exit-code 1 \
    --python "$HERE/addon_test.py" -- --zip "$T/lumis_lights.zip" --map "$T/sunrise.exr" \
    --lumis-python "$ROOT/python" >"$T/blender.log" 2>&1 || status=$?
# Blender's own lines (render progress) left out
grep -v '^Fra:\|^Saved:\|^ Time:\|^$' "$T/blender.log" || true
# "Import Photometric Fixture": a road light (IES, type C, asymmetric) over a white floor
fstatus=0
BLENDER_USER_SCRIPTS="$T/scripts" blender -b --factory-startup --python-exit-code 1 \
    --python "$HERE/fixture_test.py" -- --zip "$T/lumis_lights.zip" \
    --file "$ROOT/tests/data/photometric/luxcore_asa_15m_r2.ies" \
    --lumis-python "$ROOT/python" >"$T/fixture.log" 2>&1 || fstatus=$?
grep -v '^Fra:\|^Saved:\|^ Time:\|^$' "$T/fixture.log" || true
[ "$status" -ne 0 ] || status=$fstatus
exit $status
