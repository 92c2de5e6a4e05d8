#!/usr/bin/env bash
# CI's cluster stage (docs/cluster.md): a suite as Slurm job arrays on a real Slurm, one
# node of this machine's CPUs (scripts/slurm-local.sh), against the same suite run without
# Slurm.  Checks, in order:
#   1. `lumis bench --slurm` submits 4 reference tasks (2 references split in 2), their
#      merge, 3 items tasks and the report;
#   2. items task 1, killed (scancel) after its first item and before its last, is
#      reported: the report job fails and DIR/slurm/status.txt names task 1;
#   3. resubmitting (DIR/slurm/resubmit.sh) submits task 1 alone, no reference, and the
#      report then finds every item done;
#   4. the merged report equals the single-machine one (scripts/bench-equal.py: the same
#      items, equal-sample renders byte for byte and metrics to 1e-5, identical ranks);
#   5. a second suite with a light-set method and a luminaire scene (headlight-close), its
#      references split in 3 and merged, equals its single-machine run too.
# The daemons are stopped however it ends.  Needs root and scripts/install-deps.sh --slurm.
#
#   scripts/ci-slurm.sh [BUILD_DIR]      (default build)
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
lumis=$(realpath "$build/lumis")
suite=tests/data/slurm-suite.json
tmp=$(mktemp -d /tmp/lumis-slurm.XXXXXX)
cluster="$tmp/cluster"

cleanup() {
    local rc=$?
    scripts/slurm-local.sh stop "$cluster" >/dev/null 2>&1 || true
    if [[ $rc -ne 0 ]]; then
        echo "ci-slurm: FAILED; the daemons' logs:" >&2
        tail -n 30 "$cluster"/slurmctld.log "$cluster"/slurmd.log 2>/dev/null >&2 || true
        for f in "$tmp"/slurm-run/slurm/logs/*.out; do
            [[ -f $f ]] && { echo "--- $f" >&2; tail -n 15 "$f" >&2; }
        done
    fi
    rm -rf "$tmp"
    exit $rc
}
trap cleanup EXIT INT TERM

fail() {
    echo "ci-slurm: $*" >&2
    exit 1
}

# Waits until job $1 (all its array tasks) has left the queue; prints its final state.
wait_job() {
    local id=$1 limit=${2:-300} t=0
    while [[ -n $(squeue -h -j "$id" 2>/dev/null) ]]; do
        sleep 1
        t=$((t + 1))
        [[ $t -lt $limit ]] || fail "job $id still queued after $limit s"
    done
    scontrol -o show job "$id" | sed -n 's/.*JobState=\([A-Z_]*\).*/\1/p' | head -1
}

job_id() { awk -v k="$1" '$1 == k {print $2}' "$2/slurm/jobs.txt"; }

echo "-- a one-node Slurm"
scripts/slurm-local.sh start "$cluster"
eval "$(scripts/slurm-local.sh env "$cluster")"
sinfo

echo "-- the suite on this machine, without Slurm (one core per item, as a task has)"
"$lumis" bench "$suite" --out "$tmp/single" --threads 1

echo "-- the suite as job arrays"
out="$tmp/slurm-run"
"$lumis" bench "$suite" --out "$out" --slurm --tasks 3 --reference-passes 2 | tee "$tmp/submit.txt"
grep -q -- "--array=0-3 " "$out/slurm/submit.sh" || fail "not 4 reference tasks"
grep -q -- "--array=0-2 " "$out/slurm/submit.sh" || fail "not 3 items tasks"
items=$(job_id items "$out")
report=$(job_id report "$out")

echo "-- kill items task 1 (job ${items}_1) after its first item"
# its items are 1, 4 and 7 (every third): wait for one of them, then kill it mid-run
t=0
until ls "$out"/results/*.json >/dev/null 2>&1 &&
    grep -q "^\[" "$out/slurm/logs/items-${items}_1.out" 2>/dev/null; do
    sleep 0.2
    t=$((t + 1))
    [[ $t -lt 1500 ]] || fail "items task 1 never finished an item"
done
scancel "${items}_1"
state=$(wait_job "$report")
echo "report job $report: $state"
[[ $state == FAILED ]] || fail "the report job should fail with task 1 killed, not $state"
cat "$out/slurm/status.txt"
grep -q "^items task 1 of 3:" "$out/slurm/status.txt" || fail "status.txt does not name task 1"
if grep -q "^items task [02] of 3" "$out/slurm/status.txt"; then fail "tasks 0 and 2 finished"; fi

echo "-- resubmit what is missing: task 1 alone"
sh "$out/slurm/resubmit.sh" | tee "$tmp/resubmit.txt"
grep -q -- "--array=1 " "$out/slurm/submit.sh" || fail "the resubmission is not task 1 alone"
if grep -q "references.sbatch\|merge-references.sbatch" "$out/slurm/submit.sh"; then
    fail "the references were resubmitted though they are done"
fi
report=$(job_id report "$out")
state=$(wait_job "$report")
echo "report job $report: $state"
[[ $state == COMPLETED ]] || fail "the second report job ended $state"
grep -q "^all 8 items done" "$out/slurm/status.txt" || fail "status.txt: $(cat "$out/slurm/status.txt")"
[[ -f $out/index.html ]] || fail "no index.html"

echo "-- the cluster's report against the single machine's"
python3 scripts/bench-equal.py "$tmp/single" "$out"

echo "-- light sets and luminaires: a second suite, its references in 3 shares each"
kinds=tests/data/slurm-suite-kinds.json
"$lumis" bench "$kinds" --out "$tmp/kinds-single" --threads 1
"$lumis" bench "$kinds" --out "$tmp/kinds" --slurm --tasks 2 --reference-passes 3
grep -q -- "--array=0-5 " "$tmp/kinds/slurm/submit.sh" || fail "kinds: not 6 reference tasks"
report=$(job_id report "$tmp/kinds")
state=$(wait_job "$report")
echo "report job $report: $state"
[[ $state == COMPLETED ]] || fail "kinds: the report job ended $state (a reference's shares did not merge?)"
grep -q "^all 4 items done" "$tmp/kinds/slurm/status.txt" || fail "kinds: $(cat "$tmp/kinds/slurm/status.txt")"
python3 scripts/bench-equal.py "$tmp/kinds-single" "$tmp/kinds"
echo "ci-slurm: passed"
