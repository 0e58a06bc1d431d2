"""Rounds of one measurement over several builds of the library, shared by
the benchmarks that compare builds in one run (bench_quality.py,
bench_mpas_write.py): their common options, the refined mesh a child
measures, the rounds and the table.

Each round runs every build once, in a process of its own (the library
chosen with $UNIMESH_LIBRARY), in an order that rotates from round to round.
The child prints one line, "<seconds> <digest>"; the table gives each
build's times, their median, the median of its per-round ratio to the first
build, and the digests it printed (builds that compute the same result
print the same digest).
"""
import argparse
import os
import statistics
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
COAST = os.path.join(ROOT, "data", "coast_global_l.geojson")


def add_common_arguments(parser):
    parser.add_argument("libraries", nargs="*", help="builds of libunimesh.so (default: this tree's)")
    parser.add_argument("--km", type=float, default=30.0, help="uniform spacing (default 30)")
    parser.add_argument("--threads", type=int, default=2, help="threads (default 2)")
    parser.add_argument("--rounds", type=int, default=3, help="rounds (default 3)")
    parser.add_argument("--coast", action="store_true", help="with the shipped coastlines")
    parser.add_argument("--child", action="store_true", help=argparse.SUPPRESS)


def libraries_of(args):
    return args.libraries or [os.path.join(ROOT, "build", "lib", "libunimesh.so")]


def child_command(script, args, extra=()):
    """The command line that runs script's child with args's common options."""
    return ([sys.executable, os.path.abspath(script), "--child", "--km", str(args.km), "--threads", str(args.threads)]
            + (["--coast"] if args.coast else []) + list(extra))


def refined_mesh(km, threads, coast):
    """In a child: the refined global mesh of uniform spacing km (with the
    shipped coastlines if coast), through the Python binding of the build
    $UNIMESH_LIBRARY names."""
    sys.path.insert(0, os.path.join(ROOT, "bindings", "python"))
    import unimesh as um
    ctx = um.Context(threads=threads)
    features = None
    if coast:
        features = um.Features(ctx)
        features.read_geojson(COAST, default_kind=um.FeatureKind.COASTLINE)
    return um.Mesh.refine(ctx, um.Spacing.constant(ctx, km), features)


def run_rounds(name, child_command, libraries, rounds):
    """{library: [seconds]} and {library: {digest}}, or None on a failure
    (reported on stderr)."""
    times = {lib: [] for lib in libraries}
    digests = {lib: set() for lib in libraries}
    for r in range(rounds):
        print(f"{name}: round {r + 1} of {rounds} ...", file=sys.stderr)
        order = libraries[r % len(libraries):] + libraries[:r % len(libraries)]
        for lib in order:
            out = subprocess.run(child_command, env=dict(os.environ, UNIMESH_LIBRARY=lib),
                                 capture_output=True, text=True)
            if out.returncode != 0:
                print(f"{name}: {lib} failed:\n{out.stderr}", file=sys.stderr)
                return None
            seconds, digest = out.stdout.split()
            times[lib].append(float(seconds))
            digests[lib].add(digest)
    return times, digests


def print_table(libraries, times, digests, what):
    first = times[libraries[0]]
    print(f"| build | seconds | median | median ratio to the first | {what} digest |")
    print("| --- | --- | ---: | ---: | --- |")
    for lib in libraries:
        ratio = statistics.median(t / f for t, f in zip(times[lib], first))
        print(f"| {lib} | {', '.join(f'{t:.3f}' for t in times[lib])} | {statistics.median(times[lib]):.3f} | "
              f"{ratio:.3f} | {', '.join(sorted(digests[lib]))} |")
