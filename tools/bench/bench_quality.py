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
import os
import statistics
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
COAST = os.path.join(ROOT, "data", "coast_global_l.geojson")


def run_once(km, threads, coast):
    """In the child: refine, then time the first quality report; one line."""
    sys.path.insert(0, os.path.join(ROOT, "bindings", "python"))
    import unimesh as um
    ctx = um.Context(threads=threads)
    features = None
    if coast:
        features = um.Features(ctx)
        features.read_geojson(COAST, default_kind=um.FeatureKind.COASTLINE)
    mesh = um.Mesh.refine(ctx, um.Spacing.constant(ctx, km), features)
    start = time.monotonic()
    report = mesh.quality_json()
    seconds = time.monotonic() - start
    print(f"{seconds:.4f} {hashlib.sha256(report.encode()).hexdigest()[:16]}")


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("libraries", nargs="*", help="builds of libunimesh.so (default: this tree's)")
    parser.add_argument("--km", type=float, default=30.0, help="uniform spacing (default 30)")
    parser.add_argument("--threads", type=int, default=2, help="threads (default 2)")
    parser.add_argument("--rounds", type=int, default=3, help="rounds (default 3)")
    parser.add_argument("--coast", action="store_true", help="with the shipped coastlines")
    parser.add_argument("--child", action="store_true", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.child:
        run_once(args.km, args.threads, args.coast)
        return 0
    libraries = args.libraries or [os.path.join(ROOT, "build", "lib", "libunimesh.so")]
    times = {lib: [] for lib in libraries}
    digests = {lib: set() for lib in libraries}
    for r in range(args.rounds):
        print(f"bench_quality: round {r + 1} of {args.rounds} ...", file=sys.stderr)
        order = libraries[r % len(libraries):] + libraries[:r % len(libraries)]
        for lib in order:
            command = [sys.executable, os.path.abspath(__file__), "--child", "--km", str(args.km),
                       "--threads", str(args.threads)] + (["--coast"] if args.coast else [])
            out = subprocess.run(command, env=dict(os.environ, UNIMESH_LIBRARY=lib), capture_output=True, text=True)
            if out.returncode != 0:
                print(f"bench_quality: {lib} failed:\n{out.stderr}", file=sys.stderr)
                return 1
            seconds, digest = out.stdout.split()
            times[lib].append(float(seconds))
            digests[lib].add(digest)
    first = times[libraries[0]]
    print(f"quality report of a refined {args.km:g} km global mesh{' with coastlines' if args.coast else ''}, "
          f"{args.threads} threads, {args.rounds} rounds")
    print("| build | seconds | median | median ratio to the first | report digest |")
    print("| --- | --- | ---: | ---: | --- |")
    for lib in libraries:
        ratio = statistics.median(t / f for t, f in zip(times[lib], first))
        print(f"| {lib} | {', '.join(f'{t:.3f}' for t in times[lib])} | {statistics.median(times[lib]):.3f} | "
              f"{ratio:.3f} | {', '.join(sorted(digests[lib]))} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
