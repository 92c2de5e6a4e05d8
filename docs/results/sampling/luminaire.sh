#!/usr/bin/env bash
# Sample sequences on a light-field luminaire: headlight-close lit by the preset "small"
# luminaire (restricted sampling, exact visibility), 160x120, one thread, relMSE against a
# 4096-spp reference (Halton, an independent seed), at 4, 16, 64 and 256 spp for each
# sequence.  Prints "sequence spp relmse seconds" lines.
#
#   docs/results/sampling/luminaire.sh [LUMIS] > docs/results/sampling/luminaire.txt
set -euo pipefail
L=${1:-build/lumis}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
R=(--scene headlight-close --luminaire preset:small --size 160x120 --quiet)
"$L" render "${R[@]}" --spp 4096 --threads 2 --seed 999 --sequence halton -o "$tmp/ref.exr"
for q in pcg halton sobol zsobol pmj02; do
    for n in 4 16 64 256; do
        "$L" render "${R[@]}" --spp "$n" --threads 1 --sequence "$q" -o "$tmp/t.exr"
        e=$("$L" compare "$tmp/ref.exr" "$tmp/t.exr" --json --no-hdr-flip |
            sed -n 's/.*"relmse":\([^,}]*\).*/\1/p')
        t=$(sed -n 's/.*"render_seconds":[[:space:]]*\([0-9.e+-]*\).*/\1/p' "$tmp/t.json" | head -1)
        echo "$q $n $e $t"
    done
done
