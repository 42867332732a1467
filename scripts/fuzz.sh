#!/usr/bin/env bash
# Builds the libFuzzer targets (fuzz/) with clang-14, AddressSanitizer and UBSan into build-fuzz
# (static libraries: clang links the sanitizer runtimes into executables only),
# and runs each for FUZZ_SECONDS (default 60) on its corpus: the seeds in fuzz/corpus/<target>
# (read only) plus what earlier runs found in build-fuzz/corpus/<target>. A crash, leak, sanitizer
# report, timeout (10 s for one input) or out-of-memory fails the run and leaves the input in
# build-fuzz/artifacts/ (reproduce with: build-fuzz/fuzz/<target> <file>).
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${FUZZ_SECONDS:-60}
# A fixed seed makes CI's run reproducible (the same inputs in the same order; only how far it gets
# in the time depends on the machine); FUZZ_SEED=0 lets libFuzzer pick one for exploratory runs.
seed=${FUZZ_SEED:-1}
start=$(date +%s)
# ccache (when installed) makes a rebuild in a fresh clone cheap: paths are taken relative to here.
launcher=()
if command -v ccache >/dev/null; then
  export CCACHE_BASEDIR="$(pwd)"
  launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
fi
cmake -S . -B build-fuzz "${launcher[@]}" -DCMAKE_CXX_COMPILER=clang++-14 -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_FLAGS_RELEASE="-O1 -g" \
  -DHYDROTEX_FUZZ=ON -DHYDROTEX_SANITIZE=ON -DHYDROTEX_BUILD_TESTS=OFF -DHYDROTEX_BUILD_DEMOS=OFF \
  -DHYDROTEX_BUILD_GPU=OFF -DBUILD_SHARED_LIBS=OFF >/dev/null
targets=(fuzz_mesh fuzz_scene)
cmake --build build-fuzz -j "$(nproc)" --target "${targets[@]}"
built=$(date +%s)
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1"
# The same leak suppressions as the sanitizer suite (third-party code only; see the file).
export LSAN_OPTIONS="suppressions=$(pwd)/scripts/sanitizers/lsan.supp:print_suppressions=0"
mkdir -p build-fuzz/artifacts
for target in "${targets[@]}"; do
  corpus=${target#fuzz_}
  mkdir -p "build-fuzz/corpus/$corpus"
  echo "fuzz: $target for $seconds s"
  build-fuzz/fuzz/"$target" -max_total_time="$seconds" -seed="$seed" -timeout=10 -rss_limit_mb=2048 -max_len=8192 \
    -print_final_stats=1 -artifact_prefix=build-fuzz/artifacts/"$target"- \
    "build-fuzz/corpus/$corpus" "fuzz/corpus/$corpus" 2>&1 | grep -v '^#[0-9]' || { echo "fuzz: $target failed" >&2; exit 1; }
done
echo "fuzz: build $((built - start)) s, fuzzing $(($(date +%s) - built)) s"
