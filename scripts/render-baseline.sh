#!/usr/bin/env bash
# A fixed set of renders, one per light kind and mode and per built-in scene (fixed seeds,
# --spp, one thread), printed as one line each: the name and the SHA-256 of the EXR's
# pixels (the file's bytes) and of the sidecar's figures that must not move (spp, rays,
# light-set build counts; not timings).  Run it before and after a change that must keep
# every image: `diff` of the two outputs is the comparison.
#
#   scripts/render-baseline.sh [LUMIS] > before.txt   ...   scripts/render-baseline.sh > after.txt
set -euo pipefail
lumis=${1:-build/lumis}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
export LUMIS_NO_CACHE=0 XDG_CACHE_HOME=${XDG_CACHE_HOME:-$PWD/build/test-cache}

run() { # NAME ARGS...
    local name=$1
    shift
    "$lumis" render "$@" --threads 1 --quiet -o "$tmp/$name.exr" >/dev/null
    local img side
    img=$(sha256sum <"$tmp/$name.exr" | cut -c1-16)
    # the sidecar's figures, without what is measured in time (timings: the CPU share
    # varies from run to run) or names this run's files
    side=$(perl -MJSON::PP -0777 -ne '
        sub walk { my ($p, $v) = @_;
            if (ref $v eq "HASH") { walk("$p.$_", $v->{$_}) for sort keys %$v; return }
            if (ref $v eq "ARRAY") { walk("$p\[$_]", $v->[$_]) for 0 .. $#$v; return }
            return if $p =~ /seconds|_ms$|per_second|^\.timings\.|command|outputs|simd_variant|embree_config|lumis_version/;
            print "$p=", (defined $v ? $v : "null"), "\n"; }
        walk("", decode_json($_));' "$tmp/$name.json" | sha256sum | cut -c1-16)
    printf '%-34s image %s  sidecar %s\n' "$name" "$img" "$side"
}

# PCG32 pinned: these images are the renderer's before it had sequences (sobol is the default)
S="--size 48x36 --spp 4 --seed 7 --sequence pcg"
for scene in spheres bunny-plane ward-aniso wu-diffuse wu-satin wu-glossy wu-mixed; do
    run "env-mis-$scene" --scene "$scene" --env sky:128x64 $S
done
run env-light-kdtree --scene spheres --env sky:128x64 --method kdtree --mis none $S
run env-bsdf --scene spheres --env sky:128x64 --method bsdf $S
run env-power --scene spheres --env studio:128x64 --mis power --light-samples 2 $S
run env-paths --scene bunny-plane --env sky:128x64 --bounces 2 $S
for m in median-cut variance-min fhis tmms wu; do
    run "lights-$m" --scene wu-mixed --env sky:128x64 --lights "$m" --lights-k 32 $S
done
run lights-wu-full-res --scene wu-mixed --env sky:128x64 --lights wu --lights-k 32 --upsample 1 $S
for vis in exact approx shadowmap none; do
    run "lum-$vis" --scene headlight-close --luminaire preset:small --visibility "$vis" $S
done
run lum-uniform --scene headlight --luminaire preset:small --lum-strategy uniform $S
run lum-global --scene headlight --luminaire preset:small --lum-strategy global $S
# the other sequences (an option given twice is refused: these spell the rest of $S out)
Q="--size 48x36 --spp 4 --seed 7"
run lum-halton --scene headlight --luminaire preset:small --sequence halton $Q
for q in sobol zsobol pmj02 stratified; do
    run "seq-$q-env" --scene bunny-plane --env sky:128x64 --sequence "$q" $Q
    run "seq-$q-strata" --scene wu-mixed --env sky:128x64 --lights median-cut --lights-mode stratified --sequence "$q" $Q
done
run seq-default-lum --scene headlight-close --luminaire preset:small $Q
# the light kinds' other choices: a light set's strata with MIS variants and paths, the
# luminaires' auto strategy, photometric fixtures (a point, an opening with MIS, a scene
# file's own, with paths) and the sequences under each kind
run strata-wu --scene wu-mixed --env sky:128x64 --lights wu --lights-mode stratified --lights-k 16 $S
run strata-power-paths --scene wu-mixed --env sky:128x64 --lights median-cut --lights-mode stratified --lights-k 16 --mis power --bounces 1 $S
run strata-light-only --scene wu-mixed --env sky:128x64 --lights fhis --lights-mode stratified --lights-k 16 --mis none $S
run lum-auto --scene headlight --luminaire preset:small --lum-strategy auto $S
F=docs/examples/photometric
run fixture-point --scene bunny-plane --fixture $F/spot-cos10.ies --fixture-at 0,3,1 $S
run fixture-area --scene bunny-plane --fixture tests/data/photometric/rp_area_light.ies --fixture-at 0,3,1 --fixture-area $S
run fixture-area-light --scene bunny-plane --fixture tests/data/photometric/rp_area_light.ies --fixture-at 0,3,1 --fixture-area --mis none $S
run fixture-paths --scene spheres --fixture $F/batwing.ies --fixture-at 0,4,2 --fixture-aim 0,0,0 --bounces 1 $S
run fixture-scene "$F/fixtures.json" $S
run seq-zsobol-fixture --scene bunny-plane --fixture $F/spot-cos10.ies --fixture-at 0,3,1 --sequence zsobol $Q
run seq-pmj02-lum --scene headlight-close --luminaire preset:small --sequence pmj02 $Q
run seq-default-lights --scene wu-mixed --env sky:128x64 --lights median-cut --lights-k 16 $Q
