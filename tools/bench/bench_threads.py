#!/usr/bin/env python3
"""The thread benchmark: what a second thread gains a whole `unimesh build`
run (default outputs), against what the machine gives two runs that share
nothing. Three setups, each run `--repeats` times, interleaved:

    one thread       --threads 1, alone on the machine
    two threads      --threads 2, alone
    two one-thread   two --threads 1 runs at once, into folders of their own

It prints each setup's wall times and their medians, the two-thread
speed-up (one thread / two threads) and the machine's ceiling for it:
2 x (one thread alone) / (two one-thread runs at once), the speed-up a
program would reach with no serial part and no overhead, given what two
processes sharing its cores, caches and memory bandwidth get done.

    cmake --build build --target unimesh_cli
    tools/bench/bench_threads.py [--km 30] [--repeats 2] [-- extra build flags]
"""
import argparse
import os
import statistics
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def build_args(cli, km, threads, out, extra):
    return [cli, "build", "--spacing-km", str(km), "--threads", str(threads), "--out", out, *extra]


def timed(commands):
    """Runs the commands at once; the wall time until the last one ends."""
    start = time.monotonic()
    children = [subprocess.Popen(c, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True) for c in commands]
    for child, command in zip(children, commands):
        _, err = child.communicate()
        if child.returncode != 0:
            for other in children:  # none left writing into the folder about to go
                other.kill()
                other.wait()
            sys.exit(f"bench_threads: {' '.join(command)} failed: {err.strip()}")
    return time.monotonic() - start


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--cli", default=os.path.join(ROOT, "build", "tools", "unimesh"))
    parser.add_argument("--km", type=float, default=30)
    parser.add_argument("--repeats", type=int, default=2)
    parser.add_argument("extra", nargs="*", help="further flags for every build (after --)")
    args = parser.parse_args()
    if not os.access(args.cli, os.X_OK):
        sys.exit(f"bench_threads: no command line at {args.cli} (cmake --build build --target unimesh_cli)")
    km = int(args.km) if args.km == int(args.km) else args.km
    walls = {"one thread": [], "two threads": [], "two one-thread runs at once": []}
    with tempfile.TemporaryDirectory() as folder:
        def out(name, k):
            return os.path.join(folder, f"{name}-{k}")

        for k in range(args.repeats):
            print(f"bench_threads: round {k + 1} of {args.repeats} ...", file=sys.stderr, flush=True)
            walls["one thread"].append(timed([build_args(args.cli, km, 1, out("one", k), args.extra)]))
            walls["two threads"].append(timed([build_args(args.cli, km, 2, out("two", k), args.extra)]))
            walls["two one-thread runs at once"].append(
                timed([build_args(args.cli, km, 1, out(f"pair{p}", k), args.extra) for p in (0, 1)]))
    median = {name: statistics.median(w) for name, w in walls.items()}
    print(" ".join(["unimesh build --spacing-km", str(km), *args.extra]) + f": {args.repeats} runs each")
    print("| setup | wall (s) | median |")
    print("| --- | --- | ---: |")
    for name, w in walls.items():
        print(f"| {name} | {', '.join(f'{x:.2f}' for x in w)} | {median[name]:.2f} s |")
    speedup = median["one thread"] / median["two threads"]
    ceiling = 2 * median["one thread"] / median["two one-thread runs at once"]
    print(f"two-thread speed-up {speedup:.2f}x; the machine's ceiling for it {ceiling:.2f}x "
          f"(two one-thread runs at once against one alone)")


if __name__ == "__main__":
    main()
