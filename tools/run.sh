#!/usr/bin/env bash
# The main job: sets up (tools/setup.sh), builds, then meshes the globe to the
# shipped GSHHG coastlines and major rivers at 60 km, writing the MPAS mesh,
# graph.info, the VTK files (--vtu), the component meshes, coupler grids and
# river routing (--components) and the quality report into out/, with the
# time-step floor at 0.7 h (no ocean edge shorter where it can be lifted).
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
export BUILD_DIR=${BUILD_DIR:-$root/build}
"$root/tools/setup.sh"
exec "$BUILD_DIR/tools/unimesh" build \
  --geometry "$root/data/coast_global_l.geojson" \
  --geometry "$root/data/rivers_global_l.geojson" \
  --spacing-km 60 --vtu --components --out "$root/out"
