#!/usr/bin/env bash
# The whole test suite: install missing packages, build, run ctest.
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
pnc_install_missing
pnc_configure_and_build
cd "$PNC_BUILD"
ctest --output-on-failure -j"$(nproc)" --timeout 900
