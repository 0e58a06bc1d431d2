#!/usr/bin/env bash
# Shared set-up for tools/run.sh and tools/test.sh: installs the Debian
# packages unimesh needs (only those missing), then configures and builds
# into BUILD_DIR (default build/). Quick when nothing changed.
#   BUILD_DIR=...          build directory
#   UNIMESH_CMAKE_ARGS=... extra CMake arguments (e.g. -DUNIMESH_SANITIZE=address)
set -euo pipefail

root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build_dir=${BUILD_DIR:-$root/build}

# Why each package is here: see README.md, "Dependencies".
packages=(
  build-essential cmake ninja-build pkg-config gfortran
  libtbb-dev libnetcdf-dev libgeographiclib-dev nlohmann-json3-dev
  libcmocka-dev libcli11-dev libtomlplusplus-dev
  python3 python3-numpy python3-netcdf4 python3-matplotlib python3-pip python3-setuptools python3-wheel
  libcgal-dev libqhull-dev libgmp-dev libmpfr-dev
  cdo metis
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "setup: installing ${missing[*]}"
  sudo_cmd=()
  [ "$(id -u)" -eq 0 ] || sudo_cmd=(sudo)
  "${sudo_cmd[@]}" apt-get update -qq
  DEBIAN_FRONTEND=noninteractive "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends \
    "${missing[@]}" >/dev/null
fi

generator=()
[ -f "$build_dir/CMakeCache.txt" ] || generator=(-G Ninja)
# shellcheck disable=SC2086
cmake -S "$root" -B "$build_dir" "${generator[@]}" -DCMAKE_BUILD_TYPE=Release \
  ${UNIMESH_CMAKE_ARGS:-} >"$build_dir.configure.log" 2>&1 || {
  cat "$build_dir.configure.log"; exit 1; }
cmake --build "$build_dir" --parallel "$(nproc)"
