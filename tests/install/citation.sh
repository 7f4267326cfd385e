#!/usr/bin/env bash
# install.citation: CITATION.cff carries the project version and names the dissertation whose
# method pnc implements; its licence is the LICENSE file's.
#   citation.sh SOURCE VERSION
set -euo pipefail
cff="$1/CITATION.cff" version=$2
die() {
  echo "FAIL: $cff: $*" >&2
  exit 1
}
grep -qx "version: $version" "$cff" || die "no line 'version: $version' (project(VERSION) in CMakeLists.txt)"
grep -q 'title: "Multiscale simulation of polymer nano-composites using MD and GIMP"' "$cff" ||
  die "the dissertation's title is missing"
grep -q 'family-names: Nair' "$cff" && grep -q 'given-names: A. R.' "$cff" || die "author A. R. Nair missing"
grep -q 'year: 2010' "$cff" || die "year 2010 missing"
grep -q 'thesis-type: "PhD dissertation"' "$cff" || die "thesis type missing"
grep -q 'University of Alabama' "$cff" || die "institution missing"
grep -qx 'license: MIT' "$cff" || die "no 'license: MIT'"
head -1 "$1/LICENSE" | grep -qx 'MIT License' || die "LICENSE is not the MIT licence named in CITATION.cff"
echo "CITATION.cff: version $version, dissertation reference and licence present"
