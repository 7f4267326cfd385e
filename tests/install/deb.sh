#!/usr/bin/env bash
# install.deb: `cpack` builds the Debian package of the installed tree; its Depends must cover
# every shared library its ELF files need (checked against dpkg's own database, independent
# of how CPack derived them) and the run-time tools shlibdeps cannot see; the package is
# unpacked with dpkg -x into a private directory and the unpacked /usr/bin/pnc runs from there.
# (The system-wide `apt install ./pnc_*.deb` is scripts/check_deb.sh: not in the suite.)
#   deb.sh BUILD VERSION
set -euo pipefail
build=$1 version=$2
die() {
  echo "FAIL: $*" >&2
  exit 1
}
work="$(mktemp -d "${TMPDIR:-/tmp}/pnc-deb-test.XXXXXX")"
trap 'rm -rf "$work"' EXIT
cpack --config "$build/CPackConfig.cmake" -B "$work/pkg" >"$work/cpack.log" 2>&1 ||
  { cat "$work/cpack.log" >&2; die "cpack failed"; }
arch="$(dpkg --print-architecture)"
deb="$work/pkg/pnc_${version}_${arch}.deb"
[ -f "$deb" ] || die "cpack did not write $deb ($(ls "$work/pkg"))"
echo "built $(basename "$deb") ($(du -h "$deb" | cut -f1))"
dpkg-deb -I "$deb" >"$work/info.txt"
[ "$(dpkg-deb -f "$deb" Package)" = pnc ] || die "Package is not pnc"
[ "$(dpkg-deb -f "$deb" Version)" = "$version" ] || die "Version is not $version"
depends="$(dpkg-deb -f "$deb" Depends)"
echo "Depends: $depends"
# package names only (drop version constraints and alternatives' extras)
names=" $(sed -e 's/([^)]*)//g' -e 's/[|,]/ /g' <<<"$depends" | tr -s ' ') "
for p in python3 python3-matplotlib; do
  [[ "$names" == *" $p "* ]] || die "Depends lacks $p (the plot scripts)"
done

# the package owning a file; dpkg knows a path as shipped (merged /usr: /lib or /usr/lib,
# the soname link or its target)
owner_of() {
  local c real
  real="$(readlink -f "$1")"
  for c in "$1" "$real" "${1#/usr}" "/usr$1" "${real#/usr}" "$(dirname "$1")/$(basename "$real")"; do
    if dpkg -S "$c" >"$work/owner.txt" 2>/dev/null; then
      sed -n '1s/:.*//p' "$work/owner.txt"
      return
    fi
  done
}

dpkg -x "$deb" "$work/root"
# every NEEDED library of every ELF file: shipped in the package, or provided by a package
# that Depends names
n=0
while IFS= read -r -d '' f; do
  file -b "$f" | grep -q '^ELF' || continue
  for lib in $(readelf -d "$f" | sed -n 's/.*(NEEDED).*\[\(.*\)\]/\1/p'); do
    [ -e "$work/root/usr/lib/$lib" ] && continue # the package's own plugin
    path="$(ldconfig -p | awk -v l="$lib" '$1 == l && /x86-64/ && !p {p = $NF} END {print p}')"
    [ -n "$path" ] || die "$f needs $lib, which is not on this system"
    owner="$(owner_of "$path")"
    [ -n "$owner" ] || die "$f needs $lib ($path), owned by no package"
    [[ "$names" == *" $owner "* ]] || die "$f needs $lib from package $owner, not in Depends"
    n=$((n + 1))
  done
done < <(find "$work/root" -type f -print0)
echo "$n NEEDED entries covered by Depends"

for f in usr/bin/pnc usr/lib/libpnc_material.so.1 usr/lib/pkgconfig/pnc_material.pc \
  usr/lib/cmake/pnc/pncConfig.cmake usr/include/pnc/fe_material/umat.h \
  usr/share/pnc/scripts/plot_figures.py usr/share/doc/pnc/LICENSE; do
  [ -e "$work/root/$f" ] || die "the package lacks /$f"
done
out="$(env -u PNC_SCRIPTS_DIR "$work/root/usr/bin/pnc" --version)"
case "$out" in "pnc $version "*) ;; *) die "unpacked pnc --version: '$out'" ;; esac
echo "unpacked /usr/bin/pnc: $out"
"$work/root/usr/bin/pnc" card tables --model pp --out "$work/pp.h5" >/dev/null 2>"$work/tables.log"
[ -s "$work/pp.h5" ] || die "unpacked pnc wrote no card"
