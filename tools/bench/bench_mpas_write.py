#!/usr/bin/python3
"""The MPAS stage's cost: the seconds um_mesh_write_mpas_as takes to number
the staggered mesh of a refined global mesh, make its rows block by block
and write mesh.nc, for one or more builds of the library compared in the
same run.

A run refines the mesh, then writes mesh.nc into a temporary directory,
once by default: the command line's one write, whose first touches of the
memory it takes are part of its cost (later writes in the same process find
much of it mapped). --writes N writes it N times and reports the median. A
run prints a digest of the file's bytes: builds that write the same file
print the same digest. Rounds and builds as bench_quality.py runs them
(builds_ab.py).

    cmake --build build --target unimesh
    tools/bench/bench_mpas_write.py                            # this build, 30 km
    tools/bench/bench_mpas_write.py --rounds 5 /tmp/before/libunimesh.so.0 build/lib/libunimesh.so.0

--coast adds the shipped coastlines (data/coast_global_l.geojson): the
ocean and land tags and the feature of each edge are then written too.
--cpu times the processor seconds of the process (every thread's) instead
of the wall: the work, less disturbed by other load on the machine.
"""
import argparse
import hashlib
import os
import statistics
import sys
import tempfile
import time

import builds_ab


def run_once(km, threads, coast, writes, cpu):
    """In the child: refine, then time the writes of mesh.nc; one line."""
    mesh = builds_ab.refined_mesh(km, threads, coast)
    seconds = []
    clock = time.process_time if cpu else time.monotonic
    with tempfile.TemporaryDirectory() as directory:
        path = os.path.join(directory, "mesh.nc")
        for _ in range(writes):
            start = clock()
            mesh.write_mpas(path)
            seconds.append(clock() - start)
        with open(path, "rb") as f:
            digest = hashlib.sha256(f.read()).hexdigest()[:16]
    print(f"{statistics.median(seconds):.4f} {digest}")


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--writes", type=int, default=1, help="writes of mesh.nc per run (default 1)")
    parser.add_argument("--cpu", action="store_true",
                        help="the process's processor seconds (every thread's) instead of the wall's")
    builds_ab.add_common_arguments(parser)
    args = parser.parse_args()
    if args.writes < 1 or args.rounds < 1:
        parser.error(f"--writes {args.writes} and --rounds {args.rounds}: both must be at least 1")
    if args.child:
        run_once(args.km, args.threads, args.coast, args.writes, args.cpu)
        return 0
    libraries = builds_ab.libraries_of(args)
    command = builds_ab.child_command(__file__, args, ["--writes", str(args.writes)] + (["--cpu"] if args.cpu else []))
    result = builds_ab.run_rounds("bench_mpas_write", command, libraries, args.rounds)
    if result is None:
        return 1
    print(f"mesh.nc of a refined {args.km:g} km global mesh{' with coastlines' if args.coast else ''}, "
          f"{args.threads} threads, median of {args.writes} writes a run, {args.rounds} rounds"
          f"{', processor seconds' if args.cpu else ''}")
    builds_ab.print_table(libraries, *result, "mesh.nc")
    return 0


if __name__ == "__main__":
    sys.exit(main())
