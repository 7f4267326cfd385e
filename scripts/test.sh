#!/usr/bin/env bash
# The whole test suite: install missing packages, build, run ctest; then the sanitizer and
# fuzzing step (scripts/sanitize.sh, docs/hardening-fuzz.md). Either failing fails the script.
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
pnc_install_missing
pnc_configure_and_build
cd "$PNC_BUILD"
ctest --output-on-failure -j"$(nproc)" --timeout 900

echo "pnc test: step 2 of 2: sanitizer build (build-asan), sanitized tests, fuzz targets" >&2
bash "$PNC_ROOT/scripts/sanitize.sh"
