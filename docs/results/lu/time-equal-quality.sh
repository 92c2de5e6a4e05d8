#!/bin/sh
# Usage (from the repository root, after building): taskset -c 1 docs/results/lu/time-equal-quality.sh
# Equal-quality render time: restricted at 1 spp (K = 32) against global at the spp that
# reaches the same mean Lab (docs/results/lu/README.md), alternating, one thread.
set -eu
mkdir -p bench-out/lu-time
L=${LUMIS:-./build/lumis}
for scene_spp in headlight:105 headlight-close:128; do
  scene=${scene_spp%%:*}; gspp=${scene_spp##*:}
  for r in 1 2 3 4 5; do
    for m in restricted:1 global:$gspp; do
      s=${m%%:*}; n=${m##*:}
      "$L" render --scene $scene --size 256x160 --threads 1 --quiet --lum-budget 32 \
        --lum-strategy $s --spp $n -o bench-out/lu-time/$scene-$s.exr
      python3 -c "import json,sys;print('$scene $s $n', json.load(open('bench-out/lu-time/$scene-$s.json'))['timings']['render_seconds'])"
    done
  done
done
