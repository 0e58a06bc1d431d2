#!/usr/bin/env bash
# The main job: sets up (tools/setup.sh), builds, then runs the default job.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
export BUILD_DIR=${BUILD_DIR:-$root/build}
"$root/tools/setup.sh"
exec "$BUILD_DIR/tools/unimesh" demo --out "$root/out"
