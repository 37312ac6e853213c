#!/bin/sh
# SPDX-License-Identifier: GPL-3.0-or-later
# Mutation campaign of the CAD import through the command line:
#   cad_mutant_campaign.sh BUILD_DIR OUT_DIR SEED JOBS COUNT:FILE...
# writes COUNT seeded mutants of each FILE (ctsplines_cad_mutants of BUILD_DIR) to OUT_DIR/mutants
# and runs `python3 -m ctsplines convert MUTANT --tolerance 1e-2 --read-timeout 30` on each
# (JOBS at a time, each killed after 300 s). Outcome per mutant in OUT_DIR/results.tsv
# (file, kind, exit code, outcome, first error line); counts in OUT_DIR/summary.txt:
#   success  exit 0
#   error    exit 1 or 3 with an "error:" message (a clean error)
#   hang     killed after 300 s
#   crash    killed by a signal, or a Python traceback
#   other    anything else (exit 1 or 3 without a message, ...)
# PYTHON (default /usr/bin/python3) must import the installed ctsplines package.
set -eu
# One mutant: its outcome line (tab-separated).
run_one() {
  m=$1
  base=$(basename "$m")
  work="$OUT/runs/$base"
  mkdir -p "$work"
  set +e
  timeout -s KILL 300 "$PYTHON" -m ctsplines convert "$m" -o "$work/out.vtm" --tolerance 1e-2 \
    --read-timeout 30 >"$work/stdout" 2>"$work/stderr"
  code=$?
  set -e
  if [ $code -eq 0 ]; then
    outcome=success
  elif [ $code -eq 137 ]; then
    outcome=hang
  elif [ $code -gt 128 ] || grep -q "^Traceback" "$work/stderr"; then
    outcome=crash
  elif { [ $code -eq 1 ] || [ $code -eq 3 ]; } && grep -q "^error: ." "$work/stderr"; then
    outcome=error
  else
    outcome=other
  fi
  kind=$(echo "$base" | awk -F. '{print $(NF-1)}')
  message=$(grep -A 1 -m 1 "^error:" "$work/stderr" | tr '\n\t' '  ' | cut -c1-400 || true)
  printf '%s\t%s\t%s\t%s\t%s\n' "$base" "$kind" "$code" "$outcome" "$message"
  rm -rf "$work/out" "$work/out.vtm" "$work/out.vtu"
}
if [ "${1:-}" = "--one" ]; then
  run_one "$2"
  exit 0
fi
if [ $# -lt 5 ]; then
  echo "usage: $0 BUILD_DIR OUT_DIR SEED JOBS COUNT:FILE..." >&2
  exit 2
fi
build=$1 out=$2 seed=$3 jobs=$4
shift 4
python=${PYTHON:-/usr/bin/python3}
mutants="$out/mutants"
rm -rf "$mutants" "$out/runs"
mkdir -p "$mutants" "$out/runs"
for spec in "$@"; do
  "$build/IOCAD/Testing/ctsplines_cad_mutants" "$mutants" "$seed" "${spec%%:*}" "${spec#*:}"
done

export OUT="$out" PYTHON="$python"
ls "$mutants"/* | xargs -P "$jobs" -n 1 sh "$0" --one >"$out/results.tsv"

{
  echo "mutants: $(wc -l <"$out/results.tsv")"
  for o in success error hang crash other; do
    printf '%s: %s\n' "$o" "$(awk -F'\t' -v o=$o '$4 == o' "$out/results.tsv" | wc -l)"
  done
  echo "by input (success error hang crash other):"
  awk -F'\t' '{split($1, a, "."); n[a[1]]++; c[a[1], $4]++}
    END {for (f in n) printf "  %s: %d (%d %d %d %d %d)\n", f, n[f], c[f, "success"], c[f, "error"],
      c[f, "hang"], c[f, "crash"], c[f, "other"]}' "$out/results.tsv" | sort
} >"$out/summary.txt"
cat "$out/summary.txt"
