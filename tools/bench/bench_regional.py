#!/usr/bin/env python3
"""The regional benchmark: what a regional mesh (`unimesh build --domain`)
costs per cell against a global mesh of the same spacing, each run in a
process of its own with the command line's default outputs; and, with
--surfaces sphere,wgs84, what the same cases cost on the WGS84 ellipsoid
(`--surface wgs84`). Cases, at the spacing H (default 30 km, 2 threads):

    global           uniform H over the sphere
    atlantic         the North Atlantic box (lon -80..-5, lat 10..65), uniform H
    pacific          a box across the antimeridian (lon 160..-160, lat -20..20)
    global coast     the shipped coastlines (data/coast_global_l.geojson) at H
    atlantic coast   the North Atlantic box with the same coastlines
    pacific coast    the Pacific box with the same coastlines (its islands)
    small            a 4 x 4 degree box (lon -40..-36, lat 20..24), uniform H
                     (about 250 cells at 30 km: run it with --km 2, say)
    midatlantic      the shipped data's Mid-Atlantic box (lon -78.5..-73.5, lat
                     36.5..41) with its full-resolution coast and rivers, uniform H
                     (run it with --km 1)

For each it prints the cells of mesh.nc (and of the whole triangulation,
with the cover outside the domain), how many of the cells away from the
boundary (bdyMaskCell 0) are not hexagons (the lattice's defects: 12 on a
global mesh; read with python3-netcdf4 when installed), the refinement,
optimisation and MPAS stage in seconds, the wall time, and the mesh's time
(refine + optimise) and
the wall per cell of mesh.nc, with their ratio to the global case of the same
features. With --match-cells each box is run once more at the spacing that
gives it about as many cells as its global case (rows "... as global"): the
cost per cell at the same size, without the fixed costs a small mesh spreads
over few cells (starting the process and the pictures' Python).

    cmake --build build --target unimesh_cli
    tools/bench/bench_regional.py [--km 30] [--threads 2] [--cases atlantic,pacific] [--surfaces sphere,wgs84]
                                  [--match-cells]
"""
import argparse
import json
import os
import re
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
COAST = [os.path.join(ROOT, "data", "coast_global_l.geojson")]
MIDATLANTIC = [os.path.join(ROOT, "data", name) for name in ("coast_midatlantic_f.geojson", "rivers_midatlantic_f.geojson")]
BOXES = {"atlantic": [[-80, 10], [-5, 10], [-5, 65], [-80, 65], [-80, 10]],
         "pacific": [[160, -20], [-160, -20], [-160, 20], [160, 20], [160, -20]],
         "small": [[-40, 20], [-36, 20], [-36, 24], [-40, 24], [-40, 20]],
         "midatlantic": [[-78.5, 36.5], [-73.5, 36.5], [-73.5, 41], [-78.5, 41], [-78.5, 36.5]]}
# Each case: its box (None: global) and its lines; the global case of the same
# lines (with lines: "global coast") is what its cost per cell is set against.
CASES = {"global": (None, []), "atlantic": ("atlantic", []), "pacific": ("pacific", []),
         "global coast": (None, COAST), "atlantic coast": ("atlantic", COAST), "pacific coast": ("pacific", COAST),
         "small": ("small", []), "midatlantic": ("midatlantic", MIDATLANTIC)}


def not_hexagons(mesh_nc):
    """Cells away from the boundary with other than six sides, or None
    without python3-netcdf4."""
    try:
        from netCDF4 import Dataset
    except ImportError:
        return None
    with Dataset(mesh_nc) as d:
        sides = d["nEdgesOnCell"][:]
        inside = d["bdyMaskCell"][:] == 0 if "bdyMaskCell" in d.variables else sides == sides
        return int((sides[inside] != 6).sum())


def run_case(cli, km, threads, box, lines, surface, folder):
    args = [cli, "build", "--spacing-km", str(km), "--threads", str(threads), "--surface", surface,
            "--out", os.path.join(folder, "out")]
    if box:
        domain = os.path.join(folder, box + ".geojson")
        with open(domain, "w") as f:
            json.dump({"type": "Feature", "properties": {"kind": "domain"},
                       "geometry": {"type": "Polygon", "coordinates": [BOXES[box]]}}, f)
        args += ["--domain", domain]
    for line_file in lines:
        args += ["--geometry", line_file]
    start = time.monotonic()
    r = subprocess.run(args, capture_output=True, text=True)
    wall = time.monotonic() - start
    if r.returncode != 0:
        return {"error": r.stderr.strip().splitlines()[-1] if r.stderr.strip() else f"exit {r.returncode}"}
    mesh = re.search(r"^mesh: (\d+) cells(?: \((\d+) with the cover outside the domain\))?.*"
                     r"refined in ([\d.]+) s, optimised in ([\d.]+) s", r.stdout, re.M)
    mpas = re.search(r"MPAS mesh ([\d.]+) s", r.stdout)
    cells = int(mesh.group(1))
    return {"cells": cells, "all": int(mesh.group(2) or cells), "refine": float(mesh.group(3)),
            "optimise": float(mesh.group(4)), "mpas": float(mpas.group(1)), "wall": wall,
            "not_hexagons": not_hexagons(os.path.join(folder, "out", "mesh.nc"))}


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--cli", default=os.path.join(ROOT, "build", "tools", "unimesh"))
    parser.add_argument("--km", type=float, default=30)
    parser.add_argument("--threads", type=int, default=2)
    parser.add_argument("--cases", default=",".join(CASES), help="comma-separated: " + ", ".join(CASES))
    parser.add_argument("--surfaces", default="sphere", help="comma-separated: sphere, wgs84")
    parser.add_argument("--match-cells", action="store_true",
                        help="also run each box at the spacing giving its global case's cell count")
    args = parser.parse_args()
    if not os.access(args.cli, os.X_OK):
        sys.exit(f"bench_regional: no command line at {args.cli} (cmake --build build --target unimesh_cli)")
    km = int(args.km) if args.km == int(args.km) else args.km
    results = {}
    for surface in args.surfaces.split(","):
        for name in args.cases.split(","):
            box, lines = CASES[name]
            print(f"bench_regional: {name} on the {surface} at {km} km ...", file=sys.stderr, flush=True)
            with tempfile.TemporaryDirectory() as folder:
                results[(surface, name)] = run_case(args.cli, km, args.threads, box, lines, surface, folder)
        if args.match_cells:
            for name in args.cases.split(","):
                box, lines = CASES[name]
                mine, base = results[(surface, name)], results.get((surface, "global coast" if lines else "global"))
                if not box or not base or "error" in mine or "error" in base:
                    continue
                # Cells go as 1 / h^2 (the cover's share shrinks a little as h does).
                matched = round(km * (mine["cells"] / base["cells"]) ** 0.5, 2)
                print(f"bench_regional: {name} on the {surface} at {matched} km ...", file=sys.stderr, flush=True)
                with tempfile.TemporaryDirectory() as folder:
                    r = run_case(args.cli, matched, args.threads, box, lines, surface, folder)
                results[(surface, f"{name} at {matched} km, as global")] = r
    print(f"regional against global meshes at {km} km, {args.threads} threads")
    print("| surface | case | cells | with the cover | not hexagons | refine | optimise | MPAS | wall | mesh per cell "
          "| wall per cell |")
    print("| --- | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |")
    for (surface, name), r in results.items():
        if "error" in r:
            print(f"| {surface} | {name} | {r['error']} | | | | | | | | |")
            continue
        defects = "-" if r["not_hexagons"] is None else f"{r['not_hexagons']:,}"
        mesh_us = 1e6 * (r["refine"] + r["optimise"]) / r["cells"]
        wall_us = 1e6 * r["wall"] / r["cells"]
        case = name.split(" at ")[0]
        base = results.get((surface, "global coast" if CASES[case][1] else "global"))
        ratio = lambda mine, key: (f" ({mine / key(base):.1f}x)"
                                   if base and "error" not in base and base is not r else "")
        mesh_of = lambda b: 1e6 * (b["refine"] + b["optimise"]) / b["cells"]
        wall_of = lambda b: 1e6 * b["wall"] / b["cells"]
        print(f"| {surface} | {name} | {r['cells']:,} | {r['all']:,} | {defects} | {r['refine']:.2f} s | "
              f"{r['optimise']:.2f} s | "
              f"{r['mpas']:.2f} s | {r['wall']:.2f} s | {mesh_us:.1f} us{ratio(mesh_us, mesh_of)} | "
              f"{wall_us:.1f} us{ratio(wall_us, wall_of)} |")


if __name__ == "__main__":
    main()
