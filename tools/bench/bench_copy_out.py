#!/usr/bin/python3
"""The MPAS copy-out against the file: every variable of a uniform global mesh
taken into numpy arrays through the Python binding (Mesh.mpas_variable, one
variable at a time, each made from the mesh's numbering), and the same
variables through the file (Mesh.write_mpas, then netCDF4 reads them back),
what a model without the copy-out would do. Each method runs in a process of
its own, which refines and optimises the mesh first; the benchmark prints the
seconds of each method (after the mesh) and the peak resident memory of its
process, and checks that both give the same values.

    cmake --build build --target unimesh
    tools/bench/bench_copy_out.py                  # 30 km, 2 threads
    tools/bench/bench_copy_out.py --km 60 --threads 1

Needs Debian's python3-numpy and python3-netcdf4 (hence /usr/bin/python3).
"""
import argparse
import hashlib
import os
import resource
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "bindings", "python"))


def variables_of(mesh_nc):
    import netCDF4
    with netCDF4.Dataset(mesh_nc) as nc:
        return list(nc.variables)


def run_method(method, km, threads, scratch):
    """In the child: the mesh, then the variables by `method`; prints one line."""
    import numpy as np
    import unimesh as um
    ctx = um.Context(threads=threads)
    mesh = um.Mesh.refine(ctx, um.Spacing.constant(ctx, km))
    mesh.optimise()
    names_file = os.path.join(scratch, "names.txt")
    digest = hashlib.sha256()
    start = time.monotonic()
    if method == "copy-out":
        with open(names_file) as f:
            names = f.read().split()
        for name in names:
            digest.update(np.ascontiguousarray(mesh.mpas_variable(name, base=1)).tobytes())
    else:
        import netCDF4
        path = os.path.join(scratch, "mesh.nc")
        mesh.write_mpas(path)
        with netCDF4.Dataset(path) as nc:
            nc.set_auto_mask(False)
            names = list(nc.variables)
            for name in names:
                digest.update(np.ascontiguousarray(nc.variables[name][...]).tobytes())
            cells = len(nc.dimensions["nCells"])
        with open(names_file, "w") as f:
            f.write("\n".join(names))
    seconds = time.monotonic() - start
    if method == "copy-out":
        cells = mesh.mpas_dimensions().n_cells
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024
    print(f"{method} {cells} {len(names)} {seconds:.3f} {peak} {digest.hexdigest()}")


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--km", type=float, default=30.0, help="uniform spacing (default 30)")
    parser.add_argument("--threads", type=int, default=2, help="threads (default 2)")
    parser.add_argument("--method", help=argparse.SUPPRESS)
    parser.add_argument("--scratch", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.method:
        run_method(args.method, args.km, args.threads, args.scratch)
        return 0
    with tempfile.TemporaryDirectory(prefix="bench_copy_out.") as scratch:
        rows = []
        # The file first: it lists the variables the copy-out then takes.
        for method in ("file", "copy-out"):
            out = subprocess.run([sys.executable, __file__, "--method", method, "--km", str(args.km),
                                  "--threads", str(args.threads), "--scratch", scratch],
                                 capture_output=True, text=True)
            if out.returncode != 0:
                print(out.stderr, file=sys.stderr)
                return 1
            name, cells, count, seconds, peak, digest = out.stdout.split()
            rows.append((name, int(cells), int(count), float(seconds), int(peak), digest))
    print(f"uniform {args.km:g} km, {rows[0][1]:,} cells, {rows[0][2]} variables, {args.threads} threads")
    print("| method | seconds (after the mesh) | peak RSS MB (B/cell) |")
    print("| --- | ---: | ---: |")
    for name, cells, _, seconds, peak, _ in rows:
        label = "write_mpas + netCDF4 read" if name == "file" else "mpas_variable, one by one"
        print(f"| {label} | {seconds:.2f} | {peak / 2**20:.0f} ({peak / cells:.0f}) |")
    same = rows[0][5] == rows[1][5]
    print("values: " + ("the same" if same else "DIFFERENT"))
    return 0 if same else 1


if __name__ == "__main__":
    sys.exit(main())
