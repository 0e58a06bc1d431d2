#!/usr/bin/env python3
"""The scale benchmark: `unimesh build --spacing-km H` on uniform global meshes,
each in a process of its own, with the command line's default outputs (mesh.nc,
graph.info, quality.json, the pictures). For each size it prints the time of
each phase (refinement, optimisation, the MPAS mesh with mesh.nc, every other
output) in seconds and in microseconds per cell, the wall time, the peak
resident memory of the process in bytes per cell, and the size of mesh.nc.

    cmake --build build --target unimesh_cli
    tools/bench/bench_scale.py                      # 30, 10 and 5 km on 2 threads
    tools/bench/bench_scale.py --sizes 30,10,5,3    # and 3 km (about 66 M cells)
    tools/bench/bench_scale.py --sizes 30 --threads 1

A size that does not fit the machine is refused by the command line's memory
cap before or during the run; the benchmark prints the reason and goes on.
"""
import argparse
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def run_case(cli, km, threads, out_dir):
    start = time.monotonic()
    os.makedirs(out_dir, exist_ok=True)
    with open(os.path.join(out_dir, "stdout.txt"), "w+") as out, open(os.path.join(out_dir, "stderr.txt"), "w+") as err:
        proc = subprocess.Popen([cli, "build", "--spacing-km", str(km), "--threads", str(threads), "--out", out_dir],
                                stdout=out, stderr=err)
        # wait4: this child's own peak resident memory (not the largest of all children so far).
        _, status, usage = os.wait4(proc.pid, 0)
        proc.returncode = os.waitstatus_to_exitcode(status)
        out.seek(0), err.seek(0)
        stdout_text, stderr_text = out.read(), err.read()
    wall = time.monotonic() - start
    result = {"km": km, "wall": wall, "rss": usage.ru_maxrss * 1024, "code": proc.returncode}
    if proc.returncode != 0:
        lines = [line for line in stderr_text.splitlines() if line.startswith("unimesh")]
        result["error"] = lines[-1] if lines else stderr_text.strip()[-200:]
        return result
    mesh = re.search(r"^mesh: (\d+) cells.*refined in ([\d.]+) s, optimised in ([\d.]+) s", stdout_text, re.M)
    outputs = re.search(r"^outputs: (.*)$", stdout_text, re.M)
    result["cells"] = int(mesh.group(1))
    result["refine"], result["optimise"] = float(mesh.group(2)), float(mesh.group(3))
    result["outputs"] = {name: float(seconds)
                         for name, seconds in re.findall(r"([^,]+?) ([\d.]+) s(?:, |$)", outputs.group(1))}
    result["mesh_nc"] = os.path.getsize(os.path.join(out_dir, "mesh.nc"))
    return result


def per_cell_us(seconds, cells):
    return 1e6 * seconds / cells


def print_table(results, threads):
    print(f"\nuniform global meshes, `unimesh build --spacing-km H --threads {threads}`, default outputs")
    print("| H km | cells | refine s (µs/cell) | optimise s (µs/cell) | MPAS mesh + mesh.nc s (µs/cell) "
          "| other outputs s | wall s | MPAS share of wall | peak RSS GB (B/cell) | mesh.nc GB |")
    print("| ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |")
    for r in results:
        if r["code"] != 0:
            print(f"| {r['km']} | — | refused after {r['wall']:.0f} s: {r['error']} | | | | | | "
                  f"{r['rss'] / 2**30:.2f} | |")
            continue
        n = r["cells"]
        mpas = r["outputs"].get("MPAS mesh", 0.0)
        other = sum(v for k, v in r["outputs"].items() if k != "MPAS mesh")
        print(f"| {r['km']} | {n:,} | {r['refine']:.1f} ({per_cell_us(r['refine'], n):.1f}) "
              f"| {r['optimise']:.1f} ({per_cell_us(r['optimise'], n):.1f}) "
              f"| {mpas:.1f} ({per_cell_us(mpas, n):.1f}) | {other:.1f} | {r['wall']:.1f} "
              f"| {100 * mpas / r['wall']:.0f} % | {r['rss'] / 2**30:.2f} ({r['rss'] / n:.0f}) "
              f"| {r['mesh_nc'] / 2**30:.2f} |")
    for r in results:
        if r["code"] == 0:
            detail = ", ".join(f"{k} {v:.2f} s" for k, v in r["outputs"].items())
            print(f"{r['km']} km outputs: {detail}")


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--cli", default=os.path.join(ROOT, "build", "tools", "unimesh"))
    parser.add_argument("--sizes", default="30,10,5", help="spacings in km, comma-separated")
    parser.add_argument("--threads", type=int, default=2)
    parser.add_argument("--out", help="keep each case's files in OUT/<km>km (default: a temporary folder, "
                                      "emptied after each case)")
    args = parser.parse_args()
    if not os.access(args.cli, os.X_OK):
        sys.exit(f"bench_scale: no command line at {args.cli} (cmake --build build --target unimesh_cli)")
    results = []
    with tempfile.TemporaryDirectory() as scratch:
        for km in [float(s) if "." in s else int(s) for s in args.sizes.split(",")]:
            out_dir = os.path.join(args.out or scratch, f"{km}km")
            print(f"bench_scale: {km} km ...", file=sys.stderr, flush=True)
            results.append(run_case(args.cli, km, args.threads, out_dir))
            if not args.out:
                shutil.rmtree(out_dir)  # a 3 km mesh.nc is about 65 GB: one case on disk at a time
    print_table(results, args.threads)


if __name__ == "__main__":
    main()
