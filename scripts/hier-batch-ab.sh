#!/bin/sh
# Hierarchical warping's batch path against its scalar path, two builds in turn (issue 39
# item 5): 3 rounds of `lumis bench-samplers sky:2048x1024` (medians of 5 runs of 10^6
# samples each) on CPU 1, printing samples/s of lumis_sampler_sample and
# lumis_sampler_sample_n and their ratio per binary and round (inversion beside it).
#   scripts/hier-batch-ab.sh OLD/lumis NEW/lumis
for r in 1 2 3; do for b in "$@"; do
  taskset -c 1 "$b" bench-samplers sky:2048x1024 --methods hierarchical,inversion --runs 5 \
      --samples 1000000 --json 2>/dev/null |
  python3 -c "
import json, sys
for m in json.load(sys.stdin):
    print('%-28s %-13s scalar %.3g batch %.3g ratio %.2f' % (sys.argv[1], m['method'],
          m['samples_per_second'], m['batch_samples_per_second'],
          m['batch_samples_per_second'] / m['samples_per_second']))" "$b"
done; done
