#!/usr/bin/env bash
# The system-wide check of the Debian package (docs/install.md "The Debian package"): build the
# .deb with cpack, `apt-get install ./pnc_<version>_<arch>.deb` (pulling its dependencies from
# the Debian archive), run /usr/bin/pnc --version and `pnc fit` with plots, build and run the C
# consumer of tests/install against /usr through pkg-config, then remove the package again.
# Needs root and changes the system: not part of scripts/test.sh, whose install.deb test only
# unpacks the package (dpkg -x). Refuses to run when a package `pnc` is already installed.
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
[ "$(id -u)" = 0 ] || { echo "check_deb: needs root (apt-get install)" >&2; exit 1; }
if dpkg-query -W -f='${Status}' pnc 2>/dev/null | grep -q "install ok installed"; then
  echo "check_deb: a package 'pnc' is installed already; remove it first" >&2
  exit 1
fi
pnc_install_missing
pnc_configure_and_build
work="$(mktemp -d)"
installed=0
cleanup() {
  [ "$installed" = 1 ] && DEBIAN_FRONTEND=noninteractive apt-get purge -y -qq pnc >&2
  rm -rf "$work"
}
trap cleanup EXIT
cpack --config "$PNC_BUILD/CPackConfig.cmake" -B "$work/pkg" >&2
deb=("$work"/pkg/pnc_*_"$(dpkg --print-architecture)".deb)
chmod 755 "$work" "$work/pkg" # apt's download user reads the local file
DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "${deb[0]}" >&2
installed=1
echo "check_deb: $(dpkg-query -W -f='${Package} ${Version} ${Status}' pnc)"
cd "$work"
/usr/bin/pnc --version
/usr/bin/pnc synth --model pnc --points 60 --seed 1 --out cases.h5 >/dev/null
/usr/bin/pnc fit --data cases.h5 --model pnc --out card.h5 --plots plots >/dev/null
ls plots/fit.png card_report.html card_report.md
echo "check_deb: pkg-config pnc_material $(pkg-config --modversion pnc_material)"
cc -std=c99 -O2 "$PNC_ROOT/tests/install/consumers/c/consumer.c" -o consumer \
  $(pkg-config --cflags --libs pnc_material) -lm
/usr/bin/pnc card tables --model pnc --out pnc.h5 >/dev/null 2>&1
./consumer pnc.h5
DEBIAN_FRONTEND=noninteractive apt-get purge -y -qq pnc >&2
installed=0
[ ! -e /usr/bin/pnc ] || { echo "check_deb: /usr/bin/pnc still there after removal" >&2; exit 1; }
echo "check_deb: installed, used and removed ${deb[0]##*/}"
