#!/usr/bin/env bash
# install.layout: what `cmake --install` put into STAGE (docs/install.md "What is installed").
#   layout.sh STAGE SOURCE BUILD VERSION HAVE_SERVER(0|1)
set -euo pipefail
stage=$1 src=$2 build=$3 version=$4 have_server=$5
die() {
  echo "FAIL: $*" >&2
  exit 1
}
cd "$stage"
abi="$(sed -n 's/^#define PNC_MATERIAL_ABI_VERSION \([0-9]*\)$/\1/p' "$src/fe_material/include/pnc/fe_material/pnc_material.h")"
[ -n "$abi" ] || die "no PNC_MATERIAL_ABI_VERSION in pnc_material.h"
want=(bin/pnc "lib/libpnc_material.so.$abi" lib/libpnc_material.so
  include/pnc/fe_material/pnc_material.h include/pnc/fe_material/umat.h
  include/pnc/fe_material/material.hpp include/pnc/fe_material/material_api.hpp
  lib/cmake/pnc/pncConfig.cmake lib/cmake/pnc/pncConfigVersion.cmake lib/cmake/pnc/pncTargets.cmake
  lib/pkgconfig/pnc_material.pc
  share/pnc/scripts/plot_figures.py share/pnc/scripts/plot_thermo.py share/pnc/scripts/plot_escm.py
  share/pnc/scripts/plot_energy.py share/pnc/scripts/plot_G.py
  share/doc/pnc/README.md share/doc/pnc/LICENSE share/doc/pnc/CITATION.cff
  share/doc/pnc/docs/install.md share/doc/pnc/docs/plugin.md share/doc/pnc/examples
  share/doc/pnc/docs/schemas/fit.schema.json share/doc/pnc/docs/schemas/common.schema.json)
[ "$have_server" = 1 ] && want+=(libexec/pnc/pnc_lammps_server)
for f in "${want[@]}"; do
  [ -e "$f" ] || die "$stage/$f is missing"
done
echo "all ${#want[@]} expected paths present"

# the headers are the source tree's, byte for byte
for h in pnc_material.h umat.h material.hpp material_api.hpp; do
  cmp -s "include/pnc/fe_material/$h" "$src/fe_material/include/pnc/fe_material/$h" ||
    die "installed $h differs from the source"
done

# the ABI version written once: soname and symbol version follow the header
soname="$(readelf -d "lib/libpnc_material.so.$abi" | sed -n 's/.*(SONAME).*\[\(.*\)\]/\1/p')"
[ "$soname" = "libpnc_material.so.$abi" ] || die "soname '$soname', want libpnc_material.so.$abi"
# (the symbol table is read once: `readelf | grep -q` under pipefail fails when grep stops
# reading early and readelf gets SIGPIPE)
syms="$(readelf --dyn-syms -W "lib/libpnc_material.so.$abi")"
grep -q " pnc_material_integrate@@PNC_MATERIAL_$abi\$" <<<"$syms" ||
  die "pnc_material_integrate is not exported with symbol version PNC_MATERIAL_$abi"
grep -q " umat_@@PNC_MATERIAL_$abi\$" <<<"$syms" ||
  die "umat_ is not exported with symbol version PNC_MATERIAL_$abi"
# ABI minor m: the library file is .so.<abi>.<m>, and the functions added in 1.1 carry
# PNC_MATERIAL_<abi>.1, the batched entry of 1.2 PNC_MATERIAL_<abi>.2, the damage query of
# 1.3 PNC_MATERIAL_<abi>.3 (D213, D260, D340)
minor="$(sed -n 's/^#define PNC_MATERIAL_ABI_VERSION_MINOR \([0-9]*\)$/\1/p' "$src/fe_material/include/pnc/fe_material/pnc_material.h")"
[ -n "$minor" ] || die "no PNC_MATERIAL_ABI_VERSION_MINOR in pnc_material.h"
[ -f "lib/libpnc_material.so.$abi.$minor" ] || die "lib/libpnc_material.so.$abi.$minor is missing"
if [ "$minor" -ge 1 ]; then
  grep -q " pnc_material_integrate2@@PNC_MATERIAL_$abi.1\$" <<<"$syms" ||
    die "pnc_material_integrate2 is not exported with symbol version PNC_MATERIAL_$abi.1"
fi
if [ "$minor" -ge 2 ]; then
  grep -q " pnc_material_integrate_batch@@PNC_MATERIAL_$abi.2\$" <<<"$syms" ||
    die "pnc_material_integrate_batch is not exported with symbol version PNC_MATERIAL_$abi.2"
fi
if [ "$minor" -ge 3 ]; then
  grep -q " pnc_material_damage_of_stretch@@PNC_MATERIAL_$abi.3\$" <<<"$syms" ||
    die "pnc_material_damage_of_stretch is not exported with symbol version PNC_MATERIAL_$abi.3"
fi

# the plugin links only HDF5, fmt and the C/C++ runtime: no LAMMPS (GPL-2.0), deal.II or
# Ceres (D150, D154)
for lib in $(readelf -d "lib/libpnc_material.so.$abi" | sed -n 's/.*(NEEDED).*\[\(.*\)\]/\1/p'); do
  case "$lib" in
    libhdf5_serial.so.* | libhdf5_serial_cpp.so.* | libhdf5.so.* | libhdf5_cpp.so.* | libfmt.so.* | \
      libstdc++.so.* | libgcc_s.so.* | libm.so.* | libc.so.*) ;;
    *) die "libpnc_material.so.$abi depends on $lib (allowed: HDF5, fmt, C/C++ runtime; D154)" ;;
  esac
done

# the project version written once: .pc, pncConfigVersion.cmake, pnc --version
grep -qx "Version: $version" lib/pkgconfig/pnc_material.pc || die "pnc_material.pc lacks 'Version: $version'"
grep -qx "abi_version=$abi" lib/pkgconfig/pnc_material.pc || die "pnc_material.pc lacks abi_version=$abi"
grep -q "set(PACKAGE_VERSION \"$version\")" lib/cmake/pnc/pncConfigVersion.cmake ||
  die "pncConfigVersion.cmake does not say $version"
grep -q "PNC_MATERIAL_ABI_VERSION $abi)" lib/cmake/pnc/pncConfig.cmake || die "pncConfig.cmake lacks the ABI version"
grep -qx "abi_version_minor=$minor" lib/pkgconfig/pnc_material.pc ||
  die "pnc_material.pc lacks abi_version_minor=$minor"
grep -q "PNC_MATERIAL_ABI_VERSION_MINOR $minor)" lib/cmake/pnc/pncConfig.cmake ||
  die "pncConfig.cmake lacks the ABI minor version"
out="$(bin/pnc --version)"
case "$out" in "pnc $version "*) ;; *) die "pnc --version: '$out'" ;; esac

# relocatable: no installed file names the source or build tree (plot script and server
# paths used to be compiled into pnc), and executables find libraries through $ORIGIN
bad="$(grep -rlF -e "$src/" -e "$build/" . || true)"
[ -z "$bad" ] || die "installed files that name the source or build tree: $bad"
for exe in bin/pnc libexec/pnc/pnc_lammps_server; do
  [ -e "$exe" ] || continue
  rp="$(readelf -d "$exe" | sed -n 's/.*(R\(UN\)\{0,1\}PATH).*\[\(.*\)\]/\2/p')"
  case "$rp" in '' | '$ORIGIN/'*) ;; *) die "$exe has RPATH '$rp' (want \$ORIGIN-relative)" ;; esac
done
echo "layout ok: version $version, ABI $abi, no source/build paths in $(find . -type f | wc -l) files"
