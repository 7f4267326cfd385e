# Shared by scripts/main.sh and scripts/test.sh: install what is missing (Debian 12),
# configure and build. Source it; do not run it.
set -euo pipefail

PNC_ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
PNC_BUILD="${PNC_BUILD:-$PNC_ROOT/build}"

# The project's system dependencies (Debian 12 package names).
PNC_PACKAGES=(
  g++ cmake ninja-build pkg-config git
  libeigen3-dev libceres-dev libhdf5-dev libfmt-dev nlohmann-json3-dev libcli11-dev libtoml11-dev
  liblammps-dev lammps libdeal.ii-dev
  libgtest-dev googletest libbenchmark-dev
  clang llvm # scripts/sanitize.sh: ASan/UBSan build and libFuzzer targets (fuzz/)
  python3 python3-matplotlib python3-numpy python3-vtk9 # python3-vtk9: tests read VTU/PVD with VTK (Vtu.*)
  python3-jsonschema # tests only: --json outputs checked against docs/schemas/ (docs.json_schemas)
  python3-h5py       # tests only: docs.json_schemas writes a box file for `pnc thermo work`
  gfortran make dpkg-dev file # tests/install: Fortran UMAT host, C host, cpack .deb (shlibdeps)
  chromium # tests only: report.html rendered in a real headless browser (Report.*, rve tests)
  slurm-wlm munge # tests/rve/slurm: a one-node Slurm cluster for the Slurm executor's tests
)

pnc_install_missing() {
  local missing=()
  for p in "${PNC_PACKAGES[@]}"; do
    if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
      missing+=("$p")
    fi
  done
  if [ "${#missing[@]}" -gt 0 ]; then
    echo "pnc: installing missing packages: ${missing[*]}" >&2
    local sudo=""
    [ "$(id -u)" -ne 0 ] && sudo="sudo"
    $sudo apt-get update -qq
    DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >&2
  fi
}

pnc_configure_and_build() {
  local gen=()
  command -v ninja >/dev/null 2>&1 && gen=(-G Ninja)
  if [ ! -f "$PNC_BUILD/CMakeCache.txt" ]; then
    cmake -S "$PNC_ROOT" -B "$PNC_BUILD" "${gen[@]}" -DCMAKE_BUILD_TYPE=Release \
      -DPNC_BUILD_TESTS=ON -DPNC_BUILD_BENCH=ON -DPNC_WITH_DEALII=ON "$@" >&2
  fi
  cmake --build "$PNC_BUILD" -j"$(nproc)" >&2
}
