#!/usr/bin/env bash
# Fill data/ with the real CC0 test data (18 HDR environment maps, 3 meshes),
# copied from a local shared copy or rebuilt from Debian/npm packages (--help).
set -euo pipefail

ROOT="$(cd "$(dirname "$0")/.." && pwd)"
SHARED="${LUMIS_SHARED_DATA:-$ROOT/../shared/data}"
OUT="${LUMIS_DATA_DIR:-$ROOT/data}"
PMNDRS_VERSION=1.7.0
BUNNY_VERSION=1.0.1

BLENDER_MAPS=(city courtyard forest interior night studio sunrise sunset)
PMNDRS_MAPS=(apartment city dawn forest lobby night studio sunrise sunset venice)
PMNDRS_MESHES=(bunny suzi)
# Sizes of the known-good files: lets a re-run skip complete files without any
# download while still replacing truncated or stale ones.
declare -A SIZE=(
    [blender-city.exr]=213545 [blender-courtyard.exr]=270418 [blender-forest.exr]=513764
    [blender-interior.exr]=202262 [blender-night.exr]=148071 [blender-studio.exr]=97867
    [blender-sunrise.exr]=260454 [blender-sunset.exr]=170385 [pmndrs-apartment.exr]=100399
    [pmndrs-city.exr]=133404 [pmndrs-dawn.exr]=182198 [pmndrs-forest.exr]=312862
    [pmndrs-lobby.exr]=158693 [pmndrs-night.exr]=154431 [pmndrs-studio.exr]=110735
    [pmndrs-sunrise.exr]=168542 [pmndrs-sunset.exr]=148357 [pmndrs-venice.exr]=184307
    [bunny.glb]=18808 [bunny.obj]=110430 [suzi.glb]=31340
)

usage() {
    cat <<EOF
Usage: $(basename "$0") [--force] [--help]

Fill $OUT with the lumis test data:
  hdri/blender-{$(IFS=,; echo "${BLENDER_MAPS[*]}")}.exr
  hdri/pmndrs-{$(IFS=,; echo "${PMNDRS_MAPS[*]}")}.exr
  meshes/bunny.obj meshes/bunny.glb meshes/suzi.glb

If \$LUMIS_SHARED_DATA (default: <repo>/../shared/data) holds hdri/ and
meshes/, missing or differing files are copied from there. Otherwise they are
fetched from the Debian package blender-data (apt-get download, no install) and
the npm packages @pmndrs/assets@$PMNDRS_VERSION and bunny@$BUNNY_VERSION.

  --force   re-fetch files that are already present with the expected size
  --help    show this help

Environment: LUMIS_SHARED_DATA, LUMIS_DATA_DIR (output dir, default <repo>/data).
EOF
}

FORCE=0
for arg in "$@"; do
    case "$arg" in
        --force) FORCE=1 ;;
        -h|--help) usage; exit 0 ;;
        *) echo "fetch-data: unknown argument '$arg' (try --help)" >&2; exit 2 ;;
    esac
done

die() { echo "fetch-data: error: $*" >&2; exit 1; }

mkdir -p "$OUT/hdri" "$OUT/meshes"

# Path 1: a local copy of the data exists (CI, shared workspace): copy it.
if [[ -d "$SHARED/hdri" && -d "$SHARED/meshes" ]]; then
    for sub in hdri meshes; do
        for src in "$SHARED/$sub"/*; do
            [[ -f "$src" ]] || continue
            dst="$OUT/$sub/$(basename "$src")"
            # cmp -s keeps re-runs cheap and leaves identical files untouched.
            if [[ $FORCE -eq 1 ]] || ! cmp -s "$src" "$dst"; then
                cp -f "$src" "$dst" || die "cannot copy $src to $dst"
                chmod u+w "$dst"   # shared copies may be read-only
            fi
        done
    done
    echo "fetch-data: copied data from $SHARED to $OUT"
    exit 0
fi

# Path 2: fetch from the package registries.
for tool in apt-get dpkg-deb npm node base64 tar; do
    command -v "$tool" >/dev/null || die "'$tool' is required to fetch the data but is not installed"
done

TMP="$(mktemp -d)"
trap 'rm -rf "$TMP"' EXIT

# True if $1 still has to be produced: --force, absent, or not the expected size.
needed() {
    [[ $FORCE -eq 1 || ! -f "$1" || "$(stat -c %s "$1")" != "${SIZE[$(basename "$1")]}" ]]
}

# Write dst atomically so an interrupted run never leaves a truncated file
# that a later run would skip.
install_file() { mv -f "$1.part" "$1" || die "cannot write $1"; echo "fetch-data: wrote $1"; }

# The @pmndrs/assets files are one line: export default 'data:<mime>;base64,...'
decode_data_url() {
    [[ -f "$1" ]] || die "$1 not found in @pmndrs/assets@$PMNDRS_VERSION"
    sed -e 's/^.*;base64,//' "$1" | tr -cd 'A-Za-z0-9+/=' | base64 -d > "$2.part" \
        || die "cannot decode the base64 data URL in $1"
    install_file "$2"
}

need_blender=0
for m in "${BLENDER_MAPS[@]}"; do needed "$OUT/hdri/blender-$m.exr" && need_blender=1; done
if [[ $need_blender -eq 1 ]]; then
    echo "fetch-data: downloading Debian package blender-data (~31 MB)"
    mkdir "$TMP/deb"
    # The package lists may be missing or stale in fresh containers; refresh only then.
    if ! (cd "$TMP/deb" && apt-get download blender-data >/dev/null 2>&1); then
        apt-get update >/dev/null || die "apt-get update failed"
        (cd "$TMP/deb" && apt-get download blender-data) || die "apt-get download blender-data failed"
    fi
    dpkg-deb -x "$TMP"/deb/blender-data_*.deb "$TMP/deb/x" || die "dpkg-deb could not extract blender-data"
    world="$TMP/deb/x/usr/share/blender/datafiles/studiolights/world"
    for m in "${BLENDER_MAPS[@]}"; do
        dst="$OUT/hdri/blender-$m.exr"
        needed "$dst" || continue
        # Names in the package are already lowercase (city.exr, ...); look up
        # case-insensitively in case a later package version changes that.
        src="$(find "$world" -maxdepth 1 -iname "$m.exr" | head -n 1)"
        [[ -n "$src" ]] || die "$m.exr not found in blender-data ($world)"
        cp "$src" "$dst.part" || die "cannot copy $src"
        install_file "$dst"
    done
fi

need_pmndrs=0
for m in "${PMNDRS_MAPS[@]}"; do needed "$OUT/hdri/pmndrs-$m.exr" && need_pmndrs=1; done
for m in "${PMNDRS_MESHES[@]}"; do needed "$OUT/meshes/$m.glb" && need_pmndrs=1; done
if [[ $need_pmndrs -eq 1 ]]; then
    echo "fetch-data: downloading npm package @pmndrs/assets@$PMNDRS_VERSION (~14 MB)"
    mkdir "$TMP/pmndrs"
    (cd "$TMP/pmndrs" && npm pack --silent "@pmndrs/assets@$PMNDRS_VERSION" >/dev/null) \
        || die "npm pack @pmndrs/assets@$PMNDRS_VERSION failed"
    tar -xzf "$TMP"/pmndrs/*.tgz -C "$TMP/pmndrs" || die "cannot unpack @pmndrs/assets"
    pkg="$TMP/pmndrs/package"
    # "needed || continue" rather than "needed && decode": bash ignores set -e
    # inside a function called on the left of &&.
    for m in "${PMNDRS_MAPS[@]}"; do
        needed "$OUT/hdri/pmndrs-$m.exr" || continue
        decode_data_url "$pkg/hdri/$m.exr.js" "$OUT/hdri/pmndrs-$m.exr"
    done
    for m in "${PMNDRS_MESHES[@]}"; do
        needed "$OUT/meshes/$m.glb" || continue
        decode_data_url "$pkg/models/$m.glb.js" "$OUT/meshes/$m.glb"
    done
fi

if needed "$OUT/meshes/bunny.obj"; then
    echo "fetch-data: downloading npm package bunny@$BUNNY_VERSION"
    mkdir "$TMP/bunny"
    (cd "$TMP/bunny" && npm pack --silent "bunny@$BUNNY_VERSION" >/dev/null) \
        || die "npm pack bunny@$BUNNY_VERSION failed"
    tar -xzf "$TMP"/bunny/*.tgz -C "$TMP/bunny" || die "cannot unpack bunny"
    # Same format as the shared bunny.obj: header comment, JS number formatting,
    # 1-based face indices; the counts guard against a changed package.
    node -e '
        const m = require(process.argv[1]);
        if (m.positions.length !== 1839 || m.cells.length !== 3674)
            throw new Error("expected 1839 vertices, 3674 triangles; got " + m.positions.length + ", " + m.cells.length);
        const out = ["# Stanford bunny (Stanford 3D Scanning Repository), from the npm package bunny@1.0.1"];
        for (const p of m.positions) out.push("v " + p.join(" "));
        for (const c of m.cells) out.push("f " + c.map(i => i + 1).join(" "));
        process.stdout.write(out.join("\n") + "\n");
    ' "$TMP/bunny/package" > "$OUT/meshes/bunny.obj.part" || die "cannot convert bunny@$BUNNY_VERSION to OBJ"
    install_file "$OUT/meshes/bunny.obj"
fi

echo "fetch-data: data ready in $OUT"
