# Sourced by the fuzz scripts: the fuzz targets, and the sanitizer options every run of them uses.
fuzz_targets=(fuzz_mesh fuzz_scene)
# halt_on_error: the first UB report fails the input. The same leak suppressions as the sanitizer
# suite (third-party code only; see the file).
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1"
export LSAN_OPTIONS="suppressions=$(pwd)/scripts/sanitizers/lsan.supp:print_suppressions=0"
# Limits for one input: 10 s, 2 GiB (a larger allocation is a finding: our guards must refuse
# what would ask for it), 8 KiB of input.
fuzz_limits=(-timeout=10 -rss_limit_mb=2048 -max_len=8192)
