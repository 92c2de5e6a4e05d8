#!/usr/bin/env bash
# Selected draws against one draw in every region, at equal CPU time on one core (issue 39
# item 2; README.md here).  Run from the repository's root after a build:
#   docs/results/selected-draws/measure.sh OUT_DIR
# References: the stratified median cut (K 32, one draw per region) at 256 spp, seed 99
# (512 for the courtyard's, made first), on core 1; the renders at 8 and 32 spp, seed 3,
# on core 0, each timed (user + system CPU seconds).
set -euo pipefail
B=build/lumis; D=data/hdri; O=${1:-bench-out/selected-draws}; mkdir -p "$O"
MAPS="blender-courtyard pmndrs-lobby blender-sunrise blender-sunset pmndrs-apartment"
common="--lights median-cut --lights-mode stratified --size 160x120 --sequence pcg"
for m in $MAPS; do for s in wu-diffuse wu-glossy; do
    [ -f "$O/ref_${m}_$s.exr" ] && continue
    taskset -c 1 $B render --scene $s --env $D/$m.exr $common --lights-k 32 --spp 256 \
        --seed 99 -o "$O/ref_${m}_$s.exr" >/dev/null 2>&1 &
done; done
for spp in 8 32; do for m in $MAPS; do for s in wu-diffuse wu-glossy; do
    for c in 32:0 32:8 64:16 128:32; do
        K=${c%:*}; N=${c#*:}; opt=""; [ "$N" -gt 0 ] && opt="--lights-draws $N"
        /usr/bin/time -f "%U %S" -o "$O/tm" taskset -c 0 $B render --scene $s --env $D/$m.exr \
            $common --lights-k $K $opt --spp $spp --seed 3 -o "$O/t_${m}_${s}_${K}_${N}_$spp.exr" \
            >/dev/null 2>&1
        echo "$m $s $K $N $spp $(cat "$O/tm")" >>"$O/cpu-times.txt"
    done
done; done; done
wait
# relMSE a / spp + r at spp samples (r: the reference's own error); from the two budgets
# a = (e8 - e32) 32 / 3; relMSE at 1 s of one core = a x (CPU seconds per spp at 32 spp)
while read -r m s K N spp u sy; do
    [ "$spp" = 32 ] || continue
    e8=$($B compare "$O/ref_${m}_$s.exr" "$O/t_${m}_${s}_${K}_${N}_8.exr" | awk '/^relmse/{print $2}')
    e32=$($B compare "$O/ref_${m}_$s.exr" "$O/t_${m}_${s}_${K}_${N}_32.exr" | awk '/^relmse/{print $2}')
    awk -v m="$m" -v s="$s" -v K="$K" -v N="$N" -v e8="$e8" -v e32="$e32" -v t="$u" -v t2="$sy" \
        'BEGIN { print m, s, K, N, e8, e32, (e8 - e32) * 32 / 3 * (t + t2) / 32 }'
done <"$O/cpu-times.txt"
