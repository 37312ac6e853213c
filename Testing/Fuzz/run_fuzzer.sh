#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Runs one fuzz target for a given time (docs/fuzzing.md):
#
#   Testing/Fuzz/run_fuzzer.sh TARGET DURATION [BUILD_DIR]
#
# TARGET: kernel, filters or cad; DURATION: 60s, 10m, 2h (a plain number is minutes); BUILD_DIR:
# the sanitizer build with CTSPLINES_BUILD_FUZZERS=ON (default build-asan). The seed corpus is
# written by make_seed_corpus.py into BUILD_DIR/fuzz/seeds; inputs libFuzzer finds interesting go
# to BUILD_DIR/fuzz/corpus/TARGET (kept between runs) and a crashing, leaking, hanging or
# out-of-memory input to BUILD_DIR/fuzz/artifacts/TARGET. Exit status: 0 when the time ran out
# without a finding, non-zero (libFuzzer's) on the first one. Extra libFuzzer flags can be given
# in FUZZ_FLAGS (e.g. FUZZ_FLAGS="-fork=1 -ignore_crashes=1" for a campaign that goes on).
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
if [ $# -lt 2 ]; then
  sed -n '3,13p' "$0" | sed 's/^# \{0,1\}//'
  exit 2
fi
target=$1
duration=$2
build=${3:-$root/build-asan}
case "$duration" in
  *s) seconds=${duration%s} ;;
  *m) seconds=$(( ${duration%m} * 60 )) ;;
  *h) seconds=$(( ${duration%h} * 3600 )) ;;
  *) seconds=$(( duration * 60 )) ;;
esac
binary=$build/Testing/Fuzz/ctsplines_fuzz_$target
if [ ! -x "$binary" ]; then
  echo "run_fuzzer.sh: $binary not built (configure $build with -DCTSPLINES_BUILD_FUZZERS=ON)" >&2
  exit 2
fi
case "$target" in
  cad) limits=(-max_len=262144 -timeout=120) ;;
  *) limits=(-max_len=8192 -timeout=60) ;;
esac

work=$build/fuzz
# CAD seeds: the model the tests write (box with a hole) and those they fetched, if any.
mkdir -p "$work/models"
writer=$build/IOCAD/Testing/ctsplines_write_test_model
[ -x "$writer" ] && "$writer" "$work/models/box_with_hole.step" > /dev/null 2>&1 || true
step_args=(--step "$work/models")
for models in "$build/IOCAD/Testing/models" "$root/build/IOCAD/Testing/models"; do
  [ -d "$models" ] && step_args+=(--step "$models")
done
python3 "$here/make_seed_corpus.py" "$work/seeds" "${step_args[@]}" > /dev/null
mkdir -p "$work/corpus/$target" "$work/artifacts/$target"

# What OpenCASCADE, VTK and TBB keep until exit is not a leak of ours.
export LSAN_OPTIONS=${LSAN_OPTIONS:-suppressions=$root/.ci/lsan.supp}
echo "== fuzz $target for ${seconds}s ($binary)"
# -print_final_stats: the closing stat::number_of_executed_units line is the execution count.
# shellcheck disable=SC2086
"$binary" -max_total_time="$seconds" "${limits[@]}" -rss_limit_mb=4096 -print_final_stats=1 \
  -print_funcs=0 -artifact_prefix="$work/artifacts/$target/" ${FUZZ_FLAGS:-} \
  "$work/corpus/$target" "$work/seeds/$target"
