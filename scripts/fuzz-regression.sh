#!/usr/bin/env bash
# SPDX-License-Identifier: Zlib
# The gating fuzz stage (scripts/test.sh runs it after scripts/fuzz-build.sh): for each fuzz target,
#  1. replays every input kept in fuzz/corpus/<target>/ once (the seeds and every crash reproducer
#     found so far, named after what it found), and
#  2. runs a fixed number of generated inputs from a fixed seed, mutating that corpus
#     (-runs, not a time), with nothing written back.
# libFuzzer learns from the values the code compares, pointers among them, so one seed takes the
# same paths only where every address is the same: the targets run without address-space
# randomisation (setarch -R), in a fixed environment (the stack sits below it), from the repository
# root with relative paths (no clone's path reaches a target), and the corpus is handed over as a
# sorted list of files (-seed_inputs) and nothing else. libFuzzer does not name the functions an
# input newly reaches (-print_funcs=0): naming one symbolizes it in the process, and the strings it
# keeps hold the clone's absolute path (the debug info's), which moved every later heap address by
# the path's length, so that two clones' fuzz_scene runs parted after about 10,000 inputs (cov
# 32876 in one, 33034 in another, same commit). So two clones of one commit run the same
# inputs in the same order and get the same answer on any machine, however fast. Exploratory fuzzing (random seed, for a time) is scripts/fuzz.sh, by hand.
# A crash, leak, sanitizer report, timeout or out-of-memory fails the run and leaves the input in
# build-fuzz/artifacts/ (reproduce with: build-fuzz/fuzz/<target> <file>).
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/fuzz-env.sh
# Generated inputs per target, from seed 1: about a minute each on a 2-core machine under the
# sanitizers (fuzz_mesh runs assimp's readers, the bake and hydrostatics; fuzz_scene parses JSON
# scenes and steps small worlds).
declare -A generated_runs=([fuzz_mesh]=${FUZZ_RUNS_MESH:-6000} [fuzz_scene]=${FUZZ_RUNS_SCENE:-100000})
seed=1
fixed_layout=(setarch "$(uname -m)" -R)
if ! "${fixed_layout[@]}" true 2>/dev/null; then
  echo "fuzz-regression: warning: setarch -R is refused here; generated inputs may differ from another machine's" >&2
  fixed_layout=()
fi
mkdir -p build-fuzz/artifacts
status=0
for target in "${fuzz_targets[@]}"; do
  binary=build-fuzz/fuzz/$target
  corpus=fuzz/corpus/${target#fuzz_}
  mapfile -t inputs < <(find "$corpus" -maxdepth 1 -type f | LC_ALL=C sort)
  echo "fuzz-regression: $target replays ${#inputs[@]} kept inputs"
  if ! "${fuzz_environment[@]}" "$binary" "${fuzz_limits[@]}" -artifact_prefix=build-fuzz/artifacts/"$target"- "${inputs[@]}" \
       >build-fuzz/"$target"-replay.log 2>&1; then
    tail -n 40 build-fuzz/"$target"-replay.log >&2
    echo "fuzz-regression: $target failed on a kept input (log: build-fuzz/$target-replay.log)" >&2
    status=1
    continue
  fi
  runs=${generated_runs[$target]}
  echo "fuzz-regression: $target runs $runs generated inputs from seed $seed"
  seed_list=$(IFS=,; echo "${inputs[*]}")
  if ! "${fuzz_environment[@]}" "${fixed_layout[@]}" "$binary" "${fuzz_limits[@]}" -seed="$seed" -runs="$runs" -seed_inputs="$seed_list" -print_funcs=0 -print_final_stats=1 \
       -artifact_prefix=build-fuzz/artifacts/"$target"- >build-fuzz/"$target"-generated.log 2>&1; then
    grep -v '^#[0-9]' build-fuzz/"$target"-generated.log | tail -n 60 >&2
    echo "fuzz-regression: $target failed on a generated input (log: build-fuzz/$target-generated.log)" >&2
    status=1
    continue
  fi
  # The figures two clones must agree on: inputs run, coverage and features reached, inputs kept.
  grep -E '^(stat::number_of_executed_units|stat::new_units_added)' build-fuzz/"$target"-generated.log | tr '\n' ' '
  grep -E '^#[0-9]+[[:space:]]+DONE' build-fuzz/"$target"-generated.log | sed -E 's/[[:space:]]+lim:.*//; s/[[:space:]]+/ /g' || true
  echo
done
exit "$status"
