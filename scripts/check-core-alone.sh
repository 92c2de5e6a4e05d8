#!/usr/bin/env bash
# The core builds alone (issue 38): configure lumis with LUMIS_BUILD_IO, _RENDER and _CLI
# OFF in a fresh build directory, as a host without Embree, assimp, OpenEXR, libpng, stb,
# cJSON or OpenMP would, then build it and run the core's own tests.
#
#   scripts/check-core-alone.sh [BUILD_DIR]      (default build-core; removed first)
#
# CI has those packages installed, so the script takes them away from the build instead:
#   - find_package of Embree and OpenMP is disabled (CMake refuses a REQUIRED one);
#   - pkg-config sees cmocka only (the tests' framework), so any other module fails;
#   - a folder of poisoned headers comes first on the include path: a core file that
#     includes Embree, assimp, libpng or OpenMP headers stops the build with #error (the
#     others are not on the default include path at all);
# and it checks that no compile or link command names one of them.
set -euo pipefail
cd "$(dirname "$0")/.."
build="${1:-build-core}"
case $build in /*) ;; *) build="$PWD/$build" ;; esac # absolute, for the flags below
jobs="${JOBS:-2}"
rm -rf "$build"
mkdir -p "$build/sandbox/pkgconfig" "$build/sandbox/include/embree3" "$build/sandbox/include/assimp"

cmocka_pc="$(pkg-config --variable=pcfiledir cmocka)/cmocka.pc"
cp "$cmocka_pc" "$build/sandbox/pkgconfig/"
poison() { printf '#error "%s: the core (lumis) is C11 and libm only (ARCHITECTURE.md)"\n' "$1" > "$2"; }
for h in rtcore.h rtcore_ray.h rtcore_scene.h rtcore_geometry.h rtcore_device.h; do
    poison "embree3/$h" "$build/sandbox/include/embree3/$h"
done
for h in cimport.h scene.h postprocess.h; do poison "assimp/$h" "$build/sandbox/include/assimp/$h"; done
for h in png.h omp.h cJSON.h stb_image.h stb_image_write.h ImfInputFile.h; do
    poison "$h" "$build/sandbox/include/$h"
done

echo "-- configure: the core alone"
env -u PKG_CONFIG_PATH PKG_CONFIG_LIBDIR="$build/sandbox/pkgconfig" \
    cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DLUMIS_WERROR=ON \
    -DLUMIS_BUILD_IO=OFF -DLUMIS_BUILD_RENDER=OFF -DLUMIS_BUILD_CLI=OFF \
    -DCMAKE_DISABLE_FIND_PACKAGE_embree=ON -DCMAKE_DISABLE_FIND_PACKAGE_OpenMP=ON \
    -DCMAKE_C_FLAGS="-I$build/sandbox/include" -DCMAKE_CXX_FLAGS="-I$build/sandbox/include" \
    >"$build/configure.log" || { cat "$build/configure.log"; exit 1; }

echo "-- build"
cmake --build "$build" -j"$jobs"
for t in lumis-io lumis-render lumis-cli; do
    if cmake --build "$build" --target help | grep -q "^\.\.\. $t\$"; then
        echo "check-core-alone: target $t exists in a core-only build" >&2
        exit 1
    fi
done

echo "-- no compile or link command names a dependency of lumis-io or lumis-render"
# (the sandbox's own path names none of them)
# shellcheck disable=SC2046 # one word per file
if grep -niE 'embree|assimp|openexr|imath|libpng|png16|cjson|stb|openmp|fopenmp|-lgomp' \
    "$build/compile_commands.json" $(find "$build" -name link.txt -o -name flags.make); then
    echo "check-core-alone: a core-only build refers to a library the core must not need" >&2
    exit 1
fi

echo "-- the core's tests"
ctest --test-dir "$build" --output-on-failure -j"$jobs"
echo "check-core-alone: lumis builds and passes its tests alone"
