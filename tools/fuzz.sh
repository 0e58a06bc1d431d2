#!/usr/bin/env bash
# Builds the libFuzzer targets with clang (into build-fuzz/) and runs each
# for SECONDS (default 60) on its seed corpus fuzz/corpus/<target>; new
# interesting inputs go to build-fuzz/corpus/<target>, crashing inputs to
# build-fuzz/findings/<target>/ (crash-*, timeout-*, oom-*, leak-*); exit 1 if any.
#   tools/fuzz.sh [SECONDS] [TARGET...]    targets: geojson spacing_file case_file capi mpas_file
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
seconds=${1:-60}
shift || true
targets=("$@")
((${#targets[@]})) || targets=(geojson spacing_file case_file capi mpas_file)

"$root/tools/setup.sh" >/dev/null  # the project's packages (and a normal build)
missing=()
for p in clang libclang-rt-14-dev; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  sudo_cmd=()
  [ "$(id -u)" -eq 0 ] || sudo_cmd=(sudo)
  "${sudo_cmd[@]}" apt-get update -qq
  DEBIAN_FRONTEND=noninteractive "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

build=$root/build-fuzz
generator=()
[ -f "$build/CMakeCache.txt" ] || generator=(-G Ninja)
cmake -S "$root" -B "$build" "${generator[@]}" -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ \
  -DCMAKE_BUILD_TYPE=RelWithDebInfo -DUNIMESH_FUZZ=ON -DUNIMESH_BUILD_TESTS=OFF \
  -DUNIMESH_BUILD_BENCHMARKS=OFF >"$build.configure.log" 2>&1 || { cat "$build.configure.log"; exit 1; }
cmake --build "$build" --parallel "$(nproc)" --target "${targets[@]/#/fuzz_}"

# netCDF-C allocates whatever a corrupt header claims (15 GB seen, in
# nc_open, before unimesh sees a value): allocations above 2 GB return NULL,
# which netCDF reports as an error, and the reader must then refuse the file.
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=1:allocator_may_return_null=1:max_allocation_size_mb=2048}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
export LSAN_OPTIONS=${LSAN_OPTIONS:-suppressions=$root/fuzz/lsan.supp}
status=0
for t in "${targets[@]}"; do
  mkdir -p "$build/corpus/$t" "$build/findings/$t"
  echo "fuzz: $t for ${seconds} s"
  limit=()
  [ "$t" = spacing_file ] && limit=(-malloc_limit_mb=4096)  # see max_allocation_size_mb above
  [ "$t" = mpas_file ] && limit=(-close_fd_mask=1)  # check's and quality's reports
  (cd "$build/findings/$t" && "$build/fuzz/fuzz_$t" -max_total_time="$seconds" -timeout=30 -rss_limit_mb=3072 \
      "${limit[@]}" -print_final_stats=1 "$build/corpus/$t" "$root/fuzz/corpus/$t") 2>&1 |
    grep -E "^(stat::number_of_executed_units|stat::peak_rss_mb|==[0-9]+==ERROR|SUMMARY|Test unit written)" || true
  for found in "$build/findings/$t"/{crash,timeout,oom,leak}-*; do
    [ -e "$found" ] && { echo "fuzz: $t found $found"; status=1; }
  done
done
exit $status
