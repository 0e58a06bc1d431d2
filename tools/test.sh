#!/usr/bin/env bash
# Sets up (tools/setup.sh), builds and runs every test through ctest.
#   tools/test.sh                      the normal (Release) build in build/
#   tools/test.sh --sanitize address   the suite under AddressSanitizer + UBSan (build-asan/)
#   tools/test.sh --sanitize thread    the suite under ThreadSanitizer (build-tsan/)
# Extra arguments after -- go to ctest (e.g. tools/test.sh -- -R capi).
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)

sanitize=""
ctest_args=()
while (($#)); do
  case "$1" in
    --sanitize) sanitize=${2:?--sanitize needs address or thread}; shift 2 ;;
    --) shift; ctest_args+=("$@"); break ;;
    *) echo "test.sh: unknown argument '$1' (see the comment at the top of tools/test.sh)" >&2; exit 2 ;;
  esac
done

case "$sanitize" in
  "") export BUILD_DIR=${BUILD_DIR:-$root/build} ;;
  address)
    export BUILD_DIR=${BUILD_DIR:-$root/build-asan}
    export UNIMESH_CMAKE_ARGS="-DUNIMESH_SANITIZE=address -DCMAKE_BUILD_TYPE=RelWithDebInfo"
    export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=1}
    export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1} ;;
  thread)
    export BUILD_DIR=${BUILD_DIR:-$root/build-tsan}
    export UNIMESH_CMAKE_ARGS="-DUNIMESH_SANITIZE=thread -DCMAKE_BUILD_TYPE=RelWithDebInfo"
    export TSAN_OPTIONS=${TSAN_OPTIONS:-halt_on_error=1:second_deadlock_stack=1} ;;
  *) echo "test.sh: --sanitize takes address or thread, not '$sanitize'" >&2; exit 2 ;;
esac
export UNIMESH_SANITIZE_MODE=$sanitize

"$root/tools/setup.sh"
cd "$BUILD_DIR"
ctest --output-on-failure --parallel "$(nproc)" "${ctest_args[@]}"
