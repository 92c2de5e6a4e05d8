#!/usr/bin/env bash
# The Blender add-on as the zip Blender's preferences install (Edit > Preferences > Add-ons
# > Install...): blender/lumis_lights/ at the zip's top (docs/blender.md).
#   scripts/blender-addon.sh [OUT.zip]     (default build/lumis_lights.zip)
set -euo pipefail
ROOT="$(cd "$(dirname "$0")/.." && pwd)"
OUT="${1:-$ROOT/build/lumis_lights.zip}"
mkdir -p "$(dirname "$OUT")"
OUT="$(cd "$(dirname "$OUT")" && pwd)/$(basename "$OUT")"
rm -f "$OUT"
# python3's zipfile: no zip(1) needed; __pycache__ left out
cd "$ROOT/blender"
python3 - "$OUT" <<'PY'
import os, sys, zipfile
with zipfile.ZipFile(sys.argv[1], "w", zipfile.ZIP_DEFLATED) as z:
    for d, dirs, files in os.walk("lumis_lights"):
        dirs[:] = sorted(x for x in dirs if x != "__pycache__")
        for f in sorted(files):
            if f.endswith(".py"):
                z.write(os.path.join(d, f))
PY
echo "$OUT"
