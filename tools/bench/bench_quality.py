#!/usr/bin/python3
"""The quality report's cost: the seconds a mesh's first um_mesh_quality_json
call takes (every metric over the triangles, edges and cells, the ocean
edges against the floor, the coastline fidelity), on a refined global mesh,
for one or more builds of the library compared in the same run.

Each round runs every build once, in a process of its own (the library
chosen with $UNIMESH_LIBRARY), in an order that rotates from round to round;
a run refines the mesh, then times the report alone. It prints each build's
times, their median, the median of its per-round ratio to the first build,
and a digest of the report (builds that measure the same mesh the same way
print the same digest).

    cmake --build build --target unimesh
    tools/bench/bench_quality.py                               # this build, 30 km
    tools/bench/bench_quality.py --coast --rounds 5 /tmp/before/libunimesh.so.0 build/lib/libunimesh.so.0

--coast adds the shipped coastlines (data/coast_global_l.geojson): the
ocean edges and the coastline fidelity are then measured too.
"""
import argparse
import hashlib
import sys
import time

import builds_ab


def run_once(km, threads, coast):
    """In the child: refine, then time the first quality report; one line."""
    mesh = builds_ab.refined_mesh(km, threads, coast)
    start = time.monotonic()
    report = mesh.quality_json()
    seconds = time.monotonic() - start
    print(f"{seconds:.4f} {hashlib.sha256(report.encode()).hexdigest()[:16]}")


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    builds_ab.add_common_arguments(parser)
    args = parser.parse_args()
    if args.child:
        run_once(args.km, args.threads, args.coast)
        return 0
    libraries = builds_ab.libraries_of(args)
    command = builds_ab.child_command(__file__, args)
    result = builds_ab.run_rounds("bench_quality", command, libraries, args.rounds)
    if result is None:
        return 1
    print(f"quality report of a refined {args.km:g} km global mesh{' with coastlines' if args.coast else ''}, "
          f"{args.threads} threads, {args.rounds} rounds")
    builds_ab.print_table(libraries, *result, "report")
    return 0


if __name__ == "__main__":
    sys.exit(main())
