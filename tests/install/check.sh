#!/usr/bin/env bash
# Tests of the installed tree (tests/install/CMakeLists.txt registers them; docs/install.md).
#
#   check.sh TEST STAGE SOURCE BUILD VERSION
#
# TEST: relocated_fit | consumer_c | consumer_cxx | consumer_fortran. STAGE is the prefix that
# the fixture install.stage installed into. Each test copies STAGE to a fresh private
# directory (a moved installation), copies what it needs (this script, the consumer sources)
# next to it, and runs there with every PNC_* variable, CMAKE_PREFIX_PATH, PKG_CONFIG_PATH and
# compiler search path unset. As root with mount namespaces (CI, this machine) the source and
# build trees are covered by empty tmpfs mounts for that run, so nothing in them can be used
# (elsewhere the test says so and relies on the path checks below).
set -euo pipefail

die() {
  echo "FAIL: $*" >&2
  exit 1
}

# ---------------------------------------------------------------- outer part (from ctest)
outer() {
  local test=$1 stage=$2 src=$3 build=$4 version=$5
  [ -x "$stage/bin/pnc" ] || die "$stage/bin/pnc missing (fixture install.stage)"
  work="$(mktemp -d "${TMPDIR:-/tmp}/pnc-install-test.XXXXXX")" # global: the EXIT trap uses it
  trap 'rm -rf "$work"' EXIT
  case "$work/" in "$src"/* | "$build"/*) die "temp dir $work is inside the source or build tree" ;; esac
  cp -a "$stage" "$work/prefix"
  cp -a "$src/tests/install/consumers" "$work/consumers"
  cp "$src/tests/install/check.sh" "$work/check.sh"
  local hidden=0
  if [ "$(id -u)" = 0 ] && unshare -m true 2>/dev/null; then
    hidden=1
  else
    echo "note: not root or no mount namespaces: the source and build trees stay visible;" \
      "relying on the path checks" >&2
  fi
  cd "$work"
  if [ "$hidden" = 1 ]; then
    # private propagation (unshare's default): the mounts never reach the host
    unshare -m --propagation private bash -c '
      src=$1 build=$2; shift 2
      mount -t tmpfs -o size=1m,mode=0755 pnc-hidden "$src" || exit 97
      case "$build/" in "$src"/*) ;; *) mount -t tmpfs -o size=1m,mode=0755 pnc-hidden "$build" || exit 97 ;; esac
      exec "$@"' hide "$src" "$build" \
      bash "$work/check.sh" --inner "$test" "$work" "$src" "$build" "$version" 1
  else
    bash "$work/check.sh" --inner "$test" "$work" "$src" "$build" "$version" 0
  fi
}

# ---------------------------------------------------------------- inner part (moved tree)
clean_env() {
  local v
  for v in $(compgen -e); do
    case "$v" in
      PNC_* | CMAKE_PREFIX_PATH | CMAKE_INCLUDE_PATH | CMAKE_LIBRARY_PATH | PKG_CONFIG_PATH | \
        PKG_CONFIG_LIBDIR | CPATH | C_INCLUDE_PATH | CPLUS_INCLUDE_PATH | LIBRARY_PATH | \
        LD_LIBRARY_PATH | LD_PRELOAD | pnc_DIR | CMAKE_GENERATOR) unset "$v" ;;
    esac
  done
}

# FILE must not mention the source or the build tree
no_tree_paths() {
  local f=$1
  if grep -qF -e "$SRC/" -e "$BUILD/" "$f"; then
    grep -nF -e "$SRC/" -e "$BUILD/" "$f" | head -5 >&2
    die "$f refers to the source or build tree"
  fi
}

generator() {
  if command -v ninja >/dev/null; then echo "-GNinja"; else echo "-GUnix Makefiles"; fi
}

t_relocated_fit() {
  local pnc="$P/bin/pnc" out
  out="$("$pnc" --version)"
  case "$out" in "pnc $VERSION "*) ;; *) die "pnc --version printed '$out', want 'pnc $VERSION ...'" ;; esac
  echo "$out"
  mkdir run && cd run
  "$pnc" synth --model pnc --points 60 --noise-mpa 1 --seed 7 --out cases.h5 >/dev/null
  "$pnc" fit --data cases.h5 --model pnc --out card.h5 --plots plots >fit.log 2>&1 ||
    { cat fit.log >&2; die "pnc fit failed in the moved tree"; }
  [ -s card.h5 ] || die "no card written"
  local png=plots/fit.png # every case in one figure (scripts/plot_figures.py)
  [ -s "$png" ] || die "no plot $png (plots/: $(ls plots))"
  [ "$(head -c 8 "$png" | od -An -tx1 | tr -d ' \n')" = 89504e470d0a1a0a ] || die "$png is not a PNG"
  grep -q 'src="data:image/png;base64,' card_report.html || die "card_report.html embeds no figure"
  echo "pnc fit in the moved tree wrote $(ls plots | tr '\n' ' ') and card_report.html"
  # the documented override is honoured, and a wrong one is named in the error
  mkdir empty
  if PNC_SCRIPTS_DIR="$PWD/empty" "$pnc" fit --data cases.h5 --model pnc --out card2.h5 \
    --plots plots2 >/dev/null 2>err.log; then
    die "pnc fit with PNC_SCRIPTS_DIR=<empty dir> succeeded; the override was not used"
  fi
  grep -q "PNC_SCRIPTS_DIR" err.log || die "error without the variable's name: $(cat err.log)"
  echo "override: $(tail -1 err.log)"
  # the point driver: the moved pnc finds the moved plugin (lib/) and plot script by itself
  local path_file="$P/share/doc/pnc/examples/drive/uniaxial_stress_lur.toml"
  [ -s "$path_file" ] || die "the example path file is not installed: $path_file"
  "$pnc" material drive card.h5 --path "$path_file" --out drive.csv --plot drive.png \
    >drive.log 2>&1 || { cat drive.log >&2; die "pnc material drive failed in the moved tree"; }
  [ "$(grep -vc '^#' drive.csv)" -gt 100 ] || die "drive.csv has too few rows: $(wc -l <drive.csv)"
  [ "$(head -c 8 drive.png | od -An -tx1 | tr -d ' \n')" = 89504e470d0a1a0a ] ||
    die "drive.png is not a PNG"
  echo "pnc material drive in the moved tree: $(grep -vc '^#' drive.csv) lines, drive.png"
  # a LAMMPS stage on 2 ranks: mpirun starts the moved libexec/pnc/pnc_lammps_server (builds
  # without LAMMPS have neither the server nor `pnc rve`; install.layout checks which)
  if [ -e "$P/libexec/pnc/pnc_lammps_server" ]; then
    cat >in.lj <<'LMP'
units lj
atom_style atomic
lattice fcc 0.8442
region box block 0 3 0 3 0 3
create_box 1 box
create_atoms 1 box
mass 1 1.0
pair_style lj/cut 2.5
pair_coeff 1 1 1.0 1.0 2.5
run 20
LMP
    "$pnc" rve lammps in.lj --ranks 2 --log lj.log >lammps.out 2>&1 ||
      { cat lammps.out >&2; die "a stage on 2 ranks failed in the moved tree"; }
    grep -q "on 2 procs for 20 steps" lj.log || die "the stage did not run on 2 ranks: $(tail -3 lj.log)"
    echo "stage on 2 ranks through the moved pnc_lammps_server: $(tail -1 lammps.out)"
  fi
}

t_consumer_c() {
  export PKG_CONFIG_PATH="$P/lib/pkgconfig"
  local v abi want_abi cflags
  v="$(pkg-config --modversion pnc_material)"
  [ "$v" = "$VERSION" ] || die "pkg-config version '$v', want '$VERSION'"
  abi="$(pkg-config --variable=abi_version pnc_material)"
  want_abi="$(sed -n 's/^#define PNC_MATERIAL_ABI_VERSION \([0-9]*\)$/\1/p' \
    "$P/include/pnc/fe_material/pnc_material.h")"
  [ -n "$abi" ] && [ "$abi" = "$want_abi" ] || die "pkg-config abi_version '$abi', header '$want_abi'"
  cflags="$(pkg-config --cflags --libs pnc_material)"
  case "$cflags" in *"$P"/*) ;; *) die "pkg-config flags '$cflags' do not point into the moved prefix" ;; esac
  mkdir build && cp consumers/c/* build/ && cd build
  make -s consumer 2>&1 | tee make.log
  make -n -B consumer >cmd.log
  no_tree_paths cmd.log
  "$P/bin/pnc" card tables --model pnc --out pnc.h5 >/dev/null 2>tables.log
  "$P/bin/pnc" card tables --model pp --out pp.h5 >/dev/null 2>>tables.log
  ./consumer pnc.h5 pp.h5
  local loaded
  loaded="$(ldd ./consumer | awk '$1 ~ /^libpnc_material\.so/ {print $3}')"
  [ -n "$loaded" ] && [ "$(readlink -f "$loaded")" = "$(readlink -f "$P/lib/libpnc_material.so.1")" ] ||
    die "consumer loads '$loaded', not the moved prefix's plugin"
  echo "consumer loads $loaded"
}

t_consumer_cxx() {
  cmake -S consumers/cxx -B build "$(generator)" -DCMAKE_BUILD_TYPE=Release \
    -DCMAKE_PREFIX_PATH="$P" -DPNC_EXPECT_VERSION="$VERSION" \
    -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF -DCMAKE_EXPORT_COMPILE_COMMANDS=ON >configure.log ||
    { cat configure.log >&2; die "configure failed"; }
  grep "consumer: pnc" configure.log
  grep -qF "pnc_DIR:PATH=$P/lib/cmake/pnc" build/CMakeCache.txt || die "pnc_DIR is not the moved prefix"
  cmake --build build >build.log || { cat build.log >&2; die "build failed"; }
  no_tree_paths build/compile_commands.json
  build/consumer build/card.h5
}

t_consumer_fortran() {
  "$P/bin/pnc" card tables --model pnc --out card.h5 >/dev/null 2>tables.log
  # PROPS as a UMAT user would take them from `pnc card show --json` (docs/plugin.md)
  "$P/bin/pnc" card show card.h5 --json >card.json 2>card.txt
  python3 - card.json props.txt <<'PY'
import json, sys
j = json.load(open(sys.argv[1]))
names = ["C11", "C22", "C33", "C12", "C13", "C23", "C44", "C55", "C66", "A1", "A5", "A9", "A10",
         "A11", "A13", "A15", "A17", "A18", "A22", "A24", "A26", "alpha"]
c = j["constants"]
props = [1.0] + [float(c[n]["value"]) for n in names]
with open(sys.argv[2], "w") as f:
    f.write("%d\n" % len(props))
    f.write("\n".join(repr(v) for v in props) + "\n")
PY
  cmake -S consumers/fortran -B build "$(generator)" -DCMAKE_BUILD_TYPE=Release \
    -DCMAKE_PREFIX_PATH="$P" -DPNC_EXPECT_VERSION="$VERSION" \
    -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF -DCMAKE_EXPORT_COMPILE_COMMANDS=ON >configure.log ||
    { cat configure.log >&2; die "configure failed"; }
  grep "consumer: pnc" configure.log
  grep -qF "pnc_DIR:PATH=$P/lib/cmake/pnc" build/CMakeCache.txt || die "pnc_DIR is not the moved prefix"
  cmake --build build >build.log || { cat build.log >&2; die "build failed"; }
  no_tree_paths build/compile_commands.json
  build/consumer props.txt
}

inner() {
  local test=$1 work=$2 hidden=$6
  SRC=$3 BUILD=$4 VERSION=$5 P="$work/prefix"
  clean_env
  cd "$work"
  if [ "$hidden" = 1 ]; then
    [ ! -e "$SRC/CMakeLists.txt" ] && [ ! -e "$BUILD/CMakeCache.txt" ] ||
      die "the source/build tree is still visible"
    echo "source and build trees hidden; installation moved to $P"
  fi
  "t_$test"
}

if [ "${1:-}" = --inner ]; then
  shift
  inner "$@"
else
  [ $# -eq 5 ] || die "usage: check.sh TEST STAGE SOURCE BUILD VERSION"
  outer "$@"
fi
