#!/usr/bin/env bash
# The whole test suite (what CI runs): install missing packages, build, run ctest; then the
# sanitizer and fuzzing step (scripts/sanitize.sh: the libraries that need no LAMMPS built with
# ASan + UBSan and their tests, then every libFuzzer target for PNC_FUZZ_SECONDS each).
# Fails when either fails. The last line counts both ctest runs:
#   "tests: N passed, M failed"
# Developers who want only the normal suite set PNC_SKIP_SANITIZE=1 (the last line then says
# that the sanitizer step did not run; CI never sets it).
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
pnc_install_missing
pnc_configure_and_build

logdir="$PNC_BUILD/test-logs"
mkdir -p "$logdir"

# "X% tests passed, F tests failed out of T" -> "passed failed" (0 0 when absent)
ctest_counts() {
  local line
  line="$(grep -E '^[0-9]+% tests passed, [0-9]+ tests? failed out of [0-9]+' "$1" | tail -n 1)"
  if [ -z "$line" ]; then
    echo "0 0"
    return
  fi
  local failed total
  failed="$(sed -E 's/.* ([0-9]+) tests? failed out of ([0-9]+).*/\1/' <<<"$line")"
  total="$(sed -E 's/.* failed out of ([0-9]+).*/\1/' <<<"$line")"
  echo "$((total - failed)) $failed"
}

rc=0
(cd "$PNC_BUILD" && ctest --output-on-failure -j"$(nproc)" --timeout 900) 2>&1 |
  tee "$logdir/ctest.log" || rc=$?
read -r passed failed < <(ctest_counts "$logdir/ctest.log")
[ "$rc" -eq 0 ] || [ "$failed" -gt 0 ] || failed=1 # ctest failed without a summary line

if [ "${PNC_SKIP_SANITIZE:-0}" = 1 ]; then
  echo "pnc test: PNC_SKIP_SANITIZE=1: the sanitizer and fuzzing step (scripts/sanitize.sh) did NOT run" >&2
else
  src=0
  bash "$PNC_ROOT/scripts/sanitize.sh" 2>&1 | tee "$logdir/sanitize.log" || src=$?
  read -r sp sf < <(ctest_counts "$logdir/sanitize.log")
  passed=$((passed + sp))
  failed=$((failed + sf))
  if [ "$src" -ne 0 ]; then
    rc=$src
    [ "$sf" -gt 0 ] || failed=$((failed + 1)) # a fuzz target or the build failed
  fi
fi
echo "tests: $passed passed, $failed failed"
[ "$rc" -eq 0 ] && [ "$failed" -eq 0 ]
