# SPDX-License-Identifier: Zlib
# Sourced by the fuzz scripts: the fuzz targets, and the sanitizer options every run of them uses.
fuzz_targets=(fuzz_mesh fuzz_scene)
# halt_on_error: the first UB report fails the input. The same leak suppressions as the sanitizer
# suite (third-party code only; see the file); relative to the repository root, where the fuzz
# scripts run.
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1"
export LSAN_OPTIONS="suppressions=scripts/sanitizers/lsan.supp:print_suppressions=0"
# Limits for one input: 10 s, 2 GiB (a larger allocation is a finding: our guards must refuse
# what would ask for it), 8 KiB of input.
fuzz_limits=(-timeout=10 -rss_limit_mb=2048 -max_len=8192)
# The environment of a gating run, the same in every clone and shell: the process's stack starts
# below its environment strings, so another environment moves every stack address.
fuzz_environment=(env -i PATH=/usr/bin:/bin "UBSAN_OPTIONS=$UBSAN_OPTIONS" "LSAN_OPTIONS=$LSAN_OPTIONS")
