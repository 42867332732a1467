#!/usr/bin/env bash
# SPDX-License-Identifier: Zlib
# Exploratory fuzzing, run by hand and never by the gating run (that is scripts/fuzz-regression.sh):
# builds the targets (scripts/fuzz-build.sh), then fuzzes each for FUZZ_SECONDS (default 600) from
# a random seed (FUZZ_SEED to pick one), starting from the kept corpus fuzz/corpus/<target>/ (read
# only) plus what earlier runs found in build-fuzz/corpus/<target>/. FUZZ_TARGETS narrows the list.
# Run it for a while in every session that touches input parsing or repair.
#
# A finding stops the target and leaves its input in build-fuzz/artifacts/; reproduce it with
# build-fuzz/fuzz/<target> <file>. Fix it, then copy the input into fuzz/corpus/<corpus>/ under a
# name that says what it found (e.g. ply-huge-list-count-oom.bin) in the same commit as the fix:
# from then on the gating run replays it.
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/fuzz-env.sh
seconds=${FUZZ_SECONDS:-600}
seed=${FUZZ_SEED:-0}
read -r -a targets <<<"${FUZZ_TARGETS:-${fuzz_targets[*]}}"
scripts/fuzz-build.sh
mkdir -p build-fuzz/artifacts
status=0
for target in "${targets[@]}"; do
  corpus=${target#fuzz_}
  mkdir -p "build-fuzz/corpus/$corpus"
  echo "fuzz: $target for $seconds s (seed ${seed}; 0 = random)"
  build-fuzz/fuzz/"$target" "${fuzz_limits[@]}" -max_total_time="$seconds" -seed="$seed" -print_final_stats=1 \
    -artifact_prefix=build-fuzz/artifacts/"$target"- \
    "build-fuzz/corpus/$corpus" "fuzz/corpus/$corpus" 2>&1 | grep -v '^#[0-9]' || { echo "fuzz: $target found something (build-fuzz/artifacts/)" >&2; status=1; }
done
exit "$status"
