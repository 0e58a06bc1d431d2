"""The unimesh command-line tool as a mesh builder runs it: build from flags
and from a case file (every promised file written, exit 0), check and
quality on what it wrote, and one-line errors with a non-zero exit for bad
flags, files and case files.

    UNIMESH_CLI=build/tools/unimesh UNIMESH_DATA=data python3 -m unittest test_cli
"""
import fcntl
import json
import os
import resource
import signal
import subprocess
import tempfile
import time
import unittest

CLI = os.environ["UNIMESH_CLI"]
DATA = os.environ["UNIMESH_DATA"]
COAST = os.path.join(DATA, "coast_global_l.geojson")
RIVERS = os.path.join(DATA, "rivers_global_l.geojson")
FILES = ("mesh.nc", "graph.info", "quality.json")  # and the pictures, unless too many cells
EXTRA_FILES = ("mesh.vtu", "triangles.vtu", "mesh.msh")  # on --vtu, --jigsaw


def run(*args):
    return subprocess.run([CLI, *args], capture_output=True, text=True, timeout=600)


class Build(unittest.TestCase):
    def test_flags_write_every_file_and_check_passes(self):
        with tempfile.TemporaryDirectory() as out:
            # The frontal refinement (not the lattice), whose defects are re-seeded.
            r = run("build", "--geometry", COAST, "--geometry", RIVERS, "--spacing-km", "600",
                    "--option", "refine_lattice=0", "--threads", "2", "--vtu", "--jigsaw", "--out", out)
            self.assertEqual(r.returncode, 0, r.stderr)
            for name in FILES + EXTRA_FILES:
                self.assertGreater(os.path.getsize(os.path.join(out, name)), 0, name)
            self.assertIn("optimised quality", r.stdout)
            self.assertIn("optimised operator diagnostics: centroid offset rms ", r.stdout)
            # The pictures (tools/setup.sh installs what draws them): the
            # histograms and the map of the cells and the input lines.
            for name in ("quality.png", "mesh.png"):
                with open(os.path.join(out, name), "rb") as f:
                    self.assertEqual(f.read(8), b"\x89PNG\r\n\x1a\n", name)
                self.assertIn(os.path.join(out, name), r.stdout)
            with open(os.path.join(out, "quality.json")) as f:
                report = json.load(f)
            self.assertIn("before_optimisation", report)
            self.assertGreaterEqual(report["optimisation"]["reseed_rounds"], 1)  # the 5-7 defects re-seeded
            self.assertGreater(report["optimisation"]["reseeded"], 0)
            diagnostics = report["operator_diagnostics"]
            for name in ("centroid_offset", "dual_edge_offset", "primal_edge_offset"):
                self.assertEqual(set(diagnostics[name]), {"rms", "max"}, name)
                self.assertLessEqual(diagnostics[name]["rms"], diagnostics[name]["max"], name)
            self.assertEqual(set(diagnostics["cell_spacing_ratio"]), {"min", "max", "mean", "std"})
            self.assertIn("operator_diagnostics", report["before_optimisation"])
            mesh = os.path.join(out, "mesh.nc")
            check = run("check", mesh)
            self.assertEqual(check.returncode, 0, check.stdout + check.stderr)
            self.assertNotIn("FAIL ", check.stdout)
            quality = run("quality", "--json", mesh)
            self.assertEqual(quality.returncode, 0, quality.stderr)
            from_file = json.loads(quality.stdout)
            self.assertEqual(from_file["triangles"], report["triangles"])
            self.assertEqual(from_file["not_well_centred"], report["not_well_centred"])
            self.assertAlmostEqual(from_file["primal_dual"]["min"], report["primal_dual"]["min"], places=9)

    def test_quality_json_of_a_path_with_quotes(self):
        with tempfile.TemporaryDirectory() as folder:
            out = os.path.join(folder, 'say "hi"\\ there')
            r = run("build", "--spacing-km", "900", "--threads", "1", "--out", out)
            self.assertEqual(r.returncode, 0, r.stderr)
            mesh = os.path.join(out, "mesh.nc")
            quality = run("quality", "--json", mesh)
            self.assertEqual(quality.returncode, 0, quality.stderr)
            self.assertEqual(json.loads(quality.stdout)["file"], mesh)

    def test_default_kind_reads_features_without_one(self):
        with tempfile.TemporaryDirectory() as out:
            with open(COAST) as f:
                collection = json.load(f)
            for feature in collection["features"]:
                feature.get("properties", {}).pop("kind", None)
            plain = os.path.join(out, "no_kind.geojson")
            with open(plain, "w") as f:
                json.dump(collection, f)
            r = run("build", "--spacing-km", "900", "--geometry", plain, "--out", out)
            self.assertNotEqual(r.returncode, 0)
            self.assertIn('no property "kind"', r.stderr)
            r = run("build", "--spacing-km", "900", "--geometry", plain, "--kind", "coastline",
                    "--out", out)
            self.assertEqual(r.returncode, 0, r.stderr)
            self.assertRegex(r.stdout, r"[1-9][0-9]* restricted edges")
            r = run("build", "--spacing-km", "900", "--geometry", plain, "--kind", "sea", "--out", out)
            self.assertNotEqual(r.returncode, 0)
            self.assertIn("--kind sea", r.stderr)
            # The longer spelling of earlier versions still works.
            r = run("build", "--spacing-km", "900", "--geometry", plain, "--default-kind", "river", "--out", out)
            self.assertEqual(r.returncode, 0, r.stderr)
            # A case file says it with `kind`; the flag wins over it.
            case = os.path.join(out, "case.toml")
            with open(case, "w") as f:
                f.write(f'geometry = ["{plain}"]\nkind = "coastline"\nspacing_km = 900\n')
            r = run("build", "--case", case, "--out", out)
            self.assertEqual(r.returncode, 0, r.stderr)
            self.assertRegex(r.stdout, r"[1-9][0-9]* restricted edges")
            r = run("build", "--case", case, "--kind", "sea", "--out", out)
            self.assertIn("--kind sea", r.stderr)

    def test_passages_keep_straits_open(self):
        # Gibraltar and the Turkish straits, far narrower than 300 km cells: the
        # report lists the closures there; drawn as passages (from open water to
        # open water), they are joined.
        straits = [[[-12, 36], [-5.6, 35.95], [0, 36.8], [3, 37.5]],
                   [[25, 39.3], [26.2, 40.1], [27.5, 40.6], [29.0, 41.1], [31, 42.5]]]
        features = [{"type": "Feature", "properties": {"name": str(k)},
                     "geometry": {"type": "LineString", "coordinates": line}} for k, line in enumerate(straits)]

        def near_straits(report):
            return [p for p in report["closed_passages"]["thinnest"]
                    if (-8 < p[0] < 0 and 34 < p[1] < 38) or (25 < p[0] < 31 and 39 < p[1] < 42)]

        with tempfile.TemporaryDirectory() as out:
            def ocean_floor(*extra):
                r = run("build", "--spacing-km", "300", "--geometry", COAST, *extra, "--out", out)
                self.assertEqual(r.returncode, 0, r.stderr)
                self.assertIn("optimised ocean connectivity: ", r.stdout)
                with open(os.path.join(out, "quality.json")) as f:
                    return json.load(f)["ocean_floor"]
            closed = ocean_floor()
            closures = len(near_straits(closed))
            self.assertGreaterEqual(closures, 1, closed["closed_passages"])
            self.assertEqual(closed["kept_open"], {"cells": 0, "below_floor": 0})
            passages = os.path.join(out, "straits.geojson")
            with open(passages, "w") as f:
                json.dump({"type": "FeatureCollection", "features": features}, f)
            kept = ocean_floor("--passages", passages)
            self.assertEqual(near_straits(kept), [], kept["closed_passages"])
            self.assertEqual(kept["regions"]["count"], closed["regions"]["count"] - closures)
            self.assertGreater(kept["kept_open"]["cells"], 0)
            self.assertEqual(kept["below_floor"], 0)
            # A passages file holds passages only.
            features[0]["properties"]["kind"] = "coastline"
            with open(passages, "w") as f:
                json.dump({"type": "FeatureCollection", "features": features}, f)
            r = run("build", "--spacing-km", "300", "--passages", passages, "--out", out)
            self.assertNotEqual(r.returncode, 0)
            self.assertIn("--passages " + passages + ": the feature of id 0 has a kind other than", r.stderr)

    def test_regional_meshes_inside_their_domain(self):
        # The North Atlantic (with the coastlines inside it) and a box across
        # the antimeridian: mesh.nc holds only cells inside the domain, with
        # the limited-area layers, and passes the checker; VTU works on it.
        import netCDF4  # python3-netcdf4 (and numpy), installed by tools/setup.sh
        import numpy as np
        boxes = {"atlantic": ([[-80, 10], [-5, 10], [-5, 65], [-80, 65], [-80, 10]], (-80, -5), ("--geometry", COAST)),
                 "pacific": ([[160, -20], [-160, -20], [-160, 20], [160, 20], [160, -20]], (160, 200), ())}
        with tempfile.TemporaryDirectory() as folder:
            for name, (ring, (lon0, lon1), extra) in boxes.items():
                domain = os.path.join(folder, name + ".geojson")
                with open(domain, "w") as f:
                    json.dump({"type": "Feature", "properties": {"kind": "domain"},
                               "geometry": {"type": "Polygon", "coordinates": [ring]}}, f)
                out = os.path.join(folder, name)
                r = run("build", "--spacing-km", "120", "--domain", domain, *extra, "--vtu", "--out", out)
                self.assertEqual(r.returncode, 0, r.stderr)
                self.assertIn("with the cover outside the domain", r.stdout)
                mesh_nc = os.path.join(out, "mesh.nc")
                r = run("check", mesh_nc)
                self.assertEqual(r.returncode, 0, r.stdout + r.stderr)
                with netCDF4.Dataset(mesh_nc) as m:
                    lat, lon = np.degrees(m["latCell"][:]), np.degrees(m["lonCell"][:])
                    layers = m["bdyMaskCell"][:]
                    on_boundary = (m["cellsOnCell"][:] == 0) & (np.arange(m.dimensions["maxEdges"].size)[None, :]
                                                                < m["nEdgesOnCell"][:][:, None])
                lon = lon0 + np.mod(lon - lon0, 360)
                self.assertTrue(np.all((lat > ring[0][1]) & (lat < ring[2][1])), (lat.min(), lat.max()))
                self.assertTrue(np.all((lon > lon0) & (lon < lon1)), (lon.min(), lon.max()))
                self.assertEqual(sorted(set(layers.tolist())), list(range(8)))
                self.assertTrue(np.array_equal(layers == 7, on_boundary.any(axis=1)))
                with open(os.path.join(out, "quality.json")) as f:
                    report = json.load(f)
                # None in open water; where coastlines below 120 km force a few,
                # no more than globally (at 30 km the Atlantic has 0.005 %).
                self.assertLessEqual(report["obtuse_triangles"], 0.001 * report["triangles"] if extra else 0)
                self.assertTrue(os.path.getsize(os.path.join(out, "mesh.vtu")) > 0)
            # The case file's key.
            case = os.path.join(folder, "case.toml")
            with open(case, "w") as f:
                f.write('domain = ["pacific.geojson"]\nspacing_km = 240\nout = "from_case"\n')
            r = run("build", "--case", case)
            self.assertEqual(r.returncode, 0, r.stderr)
            self.assertIn("with the cover outside the domain", r.stdout)
            # The JIGSAW file holds the domain's cells (mesh.nc's) and the
            # triangles between them.
            out = os.path.join(folder, "with_msh")
            r = run("build", "--spacing-km", "120", "--domain", domain, "--jigsaw", "--out", out)
            self.assertEqual(r.returncode, 0, r.stderr)
            with open(os.path.join(out, "mesh.msh")) as f:
                lines = f.read().splitlines()
            counts = {line.split("=")[0]: int(line.split("=")[1].split(";")[0]) for line in lines if "=" in line}
            first = lines.index("POINT=%d" % counts["POINT"]) + 1
            points = np.array([[float(v) for v in line.split(";")[:3]] for line in lines[first:first + counts["POINT"]]])
            first = lines.index("TRIA3=%d" % counts["TRIA3"]) + 1
            triangles = np.array([[int(v) for v in line.split(";")[:3]] for line in lines[first:first + counts["TRIA3"]]])
            with netCDF4.Dataset(os.path.join(out, "mesh.nc")) as m:
                cells, triangles_nc = m.dimensions["nCells"].size, m.dimensions["nVertices"].size
                xyz = np.stack([m["xCell"][:], m["yCell"][:], m["zCell"][:]], axis=1)
            self.assertEqual(counts["POINT"], cells)
            self.assertTrue(0 < counts["TRIA3"] < triangles_nc, (counts["TRIA3"], triangles_nc))
            self.assertTrue(triangles.min() == 0 and triangles.max() == cells - 1)
            self.assertEqual(sorted(map(tuple, np.round(points, 3))), sorted(map(tuple, np.round(xyz, 3))))
            # A domain file of other kinds is refused.
            r = run("build", "--spacing-km", "120", "--domain", COAST, "--out", out)
            self.assertNotEqual(r.returncode, 0)
            self.assertIn("--domain " + COAST + ": the feature of id", r.stderr)

    def test_a_gis_polar_cap_is_meshed_round_its_pole(self):
        # The cap south of 60 S as GIS tools draw it (along the pole, up the
        # antimeridian, 360 degrees round): a regional mesh of the cap.
        import netCDF4
        import numpy as np
        with tempfile.TemporaryDirectory() as folder:
            domain = os.path.join(folder, "south_of_60.geojson")
            with open(domain, "w") as f:
                json.dump({"type": "Feature", "properties": {"kind": "domain"}, "geometry": {
                    "type": "Polygon", "coordinates": [[[-180, -90], [180, -90], [180, -60], [-180, -60], [-180, -90]]]}}, f)
            out = os.path.join(folder, "cap")
            r = run("build", "--spacing-km", "240", "--domain", domain, "--out", out)
            self.assertEqual(r.returncode, 0, r.stderr)
            mesh_nc = os.path.join(out, "mesh.nc")
            r = run("check", mesh_nc)
            self.assertEqual(r.returncode, 0, r.stdout + r.stderr)
            with netCDF4.Dataset(mesh_nc) as m:
                lat = np.degrees(m["latCell"][:])
                layers = m["bdyMaskCell"][:]
            self.assertTrue(lat.max() < -60 and lat.min() < -88, (lat.min(), lat.max()))
            self.assertEqual(sorted(set(layers.tolist())), list(range(8)))

    def test_wgs84_meshes(self):
        # --surface wgs84: mesh.nc says what it holds (the geodetic lat/lon on
        # the authalic sphere) and passes the checker; mesh.vtu and mesh.msh
        # put their points on the ellipsoid; a regional mesh works on it too.
        import netCDF4  # python3-netcdf4 (and numpy), installed by tools/setup.sh
        import numpy as np
        a, f = 6378137.0, 1 / 298.257223563
        b = a * (1 - f)
        with tempfile.TemporaryDirectory() as folder:
            out = os.path.join(folder, "wgs84")
            r = run("build", "--spacing-km", "240", "--surface", "wgs84", "--vtu", "--jigsaw", "--threads", "2",
                    "--out", out)
            self.assertEqual(r.returncode, 0, r.stderr)
            r = run("check", os.path.join(out, "mesh.nc"))
            self.assertEqual(r.returncode, 0, r.stdout + r.stderr)
            with netCDF4.Dataset(os.path.join(out, "mesh.nc")) as m:
                self.assertEqual(m.surface, "ellipsoid")
                self.assertEqual((m.ellipsoid_semi_major_axis, m.ellipsoid_flattening), (a, f))
                self.assertAlmostEqual(m.sphere_radius, 6371007.181, places=3)
                # The cells' areas add up to the ellipsoid's (5.10065622e14 m^2).
                self.assertAlmostEqual(m["areaCell"][:].sum() / 5.100656217240886e14, 1, places=12)
            # The report's geodesic measures (GeographicLib): edges near h, the
            # cells' geodesic areas tiling the ellipsoid.
            with open(os.path.join(out, "quality.json")) as q:
                geodesic = json.load(q)["geodesic"]
            self.assertEqual(geodesic["ellipsoid"], {"semi_major_axis_m": a, "flattening": f})
            self.assertTrue(0.8 < geodesic["length_over_h"]["min"] <= geodesic["length_over_h"]["max"] < 1.2)
            self.assertAlmostEqual(geodesic["cell_area_m2"] / geodesic["ellipsoid_area_m2"], 1, places=10)
            def on_ellipsoid(points):
                p = np.array(points)
                return np.abs((p[:, 0] ** 2 + p[:, 1] ** 2) / a ** 2 + p[:, 2] ** 2 / b ** 2 - 1).max()
            with open(os.path.join(out, "mesh.msh")) as msh:
                lines = msh.read().splitlines()
            self.assertIn("mesh of the ellipsoid, semi-major axis 6378137 m", lines[0])
            first = lines.index(next(l for l in lines if l.startswith("POINT="))) + 1
            self.assertLess(on_ellipsoid([[float(v) for v in l.split(";")[:3]] for l in lines[first:first + 100]]), 1e-12)
            with open(os.path.join(out, "mesh.vtu")) as vtu:
                text = vtu.read()
            block = text.split('NumberOfComponents="3" format="ascii">\n')[1].split("</DataArray>")[0]
            self.assertLess(on_ellipsoid([[float(v) for v in l.split()] for l in block.splitlines()[:100]]), 1e-8)
            # A regional mesh across the antimeridian on WGS84, from a case file.
            domain = os.path.join(folder, "pacific.geojson")
            with open(domain, "w") as g:
                json.dump({"type": "Feature", "properties": {"kind": "domain"},
                           "geometry": {"type": "Polygon",
                                        "coordinates": [[[160, -20], [-160, -20], [-160, 20], [160, 20], [160, -20]]]}}, g)
            case = os.path.join(folder, "case.toml")
            with open(case, "w") as g:
                g.write('domain = ["pacific.geojson"]\nspacing_km = 240\nsurface = "wgs84"\nout = "pacific"\n')
            r = run("build", "--case", case, "--threads", "2")
            self.assertEqual(r.returncode, 0, r.stderr)
            with netCDF4.Dataset(os.path.join(folder, "pacific", "mesh.nc")) as m:
                self.assertEqual(m.surface, "ellipsoid")
                lat = np.degrees(m["latCell"][:])
                self.assertTrue(np.all(np.abs(lat) < 20), (lat.min(), lat.max()))
            # The same bytes on one thread.
            r = run("build", "--case", case, "--threads", "1", "--out", os.path.join(folder, "pacific1"))
            self.assertEqual(r.returncode, 0, r.stderr)
            for name in ("mesh.nc", "graph.info"):
                with open(os.path.join(folder, "pacific", name), "rb") as two, \
                        open(os.path.join(folder, "pacific1", name), "rb") as one:
                    self.assertTrue(one.read() == two.read(), name)
            # Not optimised (nearly cocircular generators along the coastlines,
            # which the move to the sphere may leave irregular): still a valid
            # MPAS mesh; `unimesh components` keeps what the file says.
            coastal = os.path.join(folder, "coastal")
            r = run("build", "--spacing-km", "240", "--geometry", COAST, "--surface", "wgs84", "--no-optimise",
                    "--threads", "2", "--out", coastal)
            self.assertEqual(r.returncode, 0, r.stderr)
            r = run("check", os.path.join(coastal, "mesh.nc"))
            self.assertEqual(r.returncode, 0, r.stdout + r.stderr)
            r = run("components", os.path.join(coastal, "mesh.nc"), "--out", os.path.join(folder, "parts"))
            self.assertEqual(r.returncode, 0, r.stderr)
            for name in ("mesh.nc", "ocean.nc", "land.nc"):
                with netCDF4.Dataset(os.path.join(folder, "parts", name)) as m:
                    self.assertEqual((m.surface, m.ellipsoid_flattening), ("ellipsoid", f), name)
            # Bad surfaces, named.
            for surface, message in (("ellipsoid:6378137,0.5", "flattening"), ("mars", "not sphere, wgs84"),
                                     ("ellipsoid:-1,0.003", "sphere_radius = -1"), ("ellipsoid:6378137", "not ellipsoid:A,F"),
                                     ("ellipsoid:6378137,1e-400", "out of the range")):
                r = run("build", "--spacing-km", "240", "--surface", surface, "--out", os.path.join(folder, "bad"))
                self.assertNotEqual(r.returncode, 0, surface)
                self.assertIn("--surface " + surface, r.stderr)
                self.assertIn(message, r.stderr)
            # Flags win: --option over the case file's surface.
            r = run("build", "--case", case, "--option", "surface_flattening=0", "--out", os.path.join(folder, "flat"))
            self.assertEqual(r.returncode, 0, r.stderr)
            with netCDF4.Dataset(os.path.join(folder, "flat", "mesh.nc")) as m:
                self.assertNotIn("surface", m.ncattrs())
                self.assertEqual(m.sphere_radius, a)
            with open(case, "w") as g:
                g.write('spacing_km = 240\nsurface = "moon"\nout = "bad"\n')
            r = run("build", "--case", case)
            self.assertNotEqual(r.returncode, 0)
            self.assertIn("case key surface moon: not sphere, wgs84 or ellipsoid:A,F", r.stderr)

    def test_a_fine_spot_in_a_spacing_file_is_meshed(self):
        # 10 km within 100 km of (lon 30, lat 20), 480 km elsewhere: a
        # regional 0.1-degree grid (its edge values beyond). About the disc's
        # area over (sqrt(3) / 2) h^2 cells in it, with the default gradient
        # limit and with a steeper one; as given (0), the refinement still
        # finds it.
        import netCDF4  # python3-netcdf4 (and numpy), installed by tools/setup.sh
        import numpy as np
        with tempfile.TemporaryDirectory() as out:
            path = os.path.join(out, "spot.nc")
            lon, lat = np.linspace(20, 40, 201), np.linspace(10, 30, 201)
            x, y = np.meshgrid(np.radians(lon), np.radians(lat))
            c = (np.radians(30), np.radians(20))
            d = 6371.0 * np.arccos(np.clip(np.sin(y) * np.sin(c[1]) + np.cos(y) * np.cos(c[1]) * np.cos(x - c[0]), -1, 1))
            with netCDF4.Dataset(path, "w", format="NETCDF3_CLASSIC") as f:
                f.createDimension("lon", lon.size)
                f.createDimension("lat", lat.size)
                f.createVariable("lon", "f8", ("lon",))[:] = lon
                f.createVariable("lat", "f8", ("lat",))[:] = lat
                f.createVariable("cellWidth", "f8", ("lat", "lon"))[:] = np.where(d <= 100, 10.0, 480.0)
            expected = np.pi * 100 ** 2 / (np.sqrt(3) / 2 * 10 ** 2)
            for flags in ([], ["--spacing-gradient", "1"], ["--spacing-gradient", "0", "--no-optimise"]):
                with self.subTest(flags=flags):
                    mesh_dir = os.path.join(out, "mesh" + "".join(flags))
                    r = run("build", "--spacing-file", path, *flags, "--threads", "2", "--out", mesh_dir)
                    self.assertEqual(r.returncode, 0, r.stderr)
                    with netCDF4.Dataset(os.path.join(mesh_dir, "mesh.nc")) as m:
                        lon_c, lat_c = m["lonCell"][:], m["latCell"][:]
                    arc = np.arccos(np.clip(np.sin(lat_c) * np.sin(c[1]) + np.cos(lat_c) * np.cos(c[1]) * np.cos(lon_c - c[0]), -1, 1))
                    inside = int(np.count_nonzero(6371.0 * arc <= 100))
                    self.assertGreater(inside, 0.75 * expected, flags)
                    self.assertLess(inside, 1.3 * expected, flags)

    def test_version_flag_and_command(self):
        for args in (["--version"], ["version"]):
            r = run(*args)
            self.assertEqual(r.returncode, 0, r.stderr)
            self.assertRegex(r.stdout, r"^unimesh \S+ \(library \S+\)$")

    def test_vtu_and_jigsaw_files_on_request(self):
        # By default the set is mesh.nc, graph.info, quality.json and the
        # pictures; --vtu and --jigsaw (or the case file's keys) add the
        # others, and a later run without them takes the earlier run's away
        # (the folder holds one run's files).
        with tempfile.TemporaryDirectory() as folder:
            out = os.path.join(folder, "out")
            r = run("build", "--spacing-km", "900", "--threads", "1", "--out", out)
            self.assertEqual(r.returncode, 0, r.stderr)
            self.assertEqual([n for n in EXTRA_FILES if os.path.exists(os.path.join(out, n))], [])
            case = os.path.join(folder, "case.toml")
            with open(case, "w") as f:
                f.write('spacing_km = 900\nthreads = 1\nvtu = true\njigsaw = true\nout = "out"\n')
            r = run("build", "--case", case)
            self.assertEqual(r.returncode, 0, r.stderr)
            for name in EXTRA_FILES:
                self.assertGreater(os.path.getsize(os.path.join(out, name)), 0, name)
                self.assertIn(os.path.join(out, name), r.stdout)
            r = run("build", "--spacing-km", "900", "--threads", "1", "--jigsaw", "--out", out)
            self.assertEqual(r.returncode, 0, r.stderr)
            self.assertTrue(os.path.exists(os.path.join(out, "mesh.msh")))
            self.assertFalse(os.path.exists(os.path.join(out, "mesh.vtu")))
            self.assertFalse(os.path.exists(os.path.join(out, "triangles.vtu")))
            with open(os.path.join(out, "manifest.json")) as f:
                self.assertEqual(sorted(e["name"] for e in json.load(f)["files"]),
                                 sorted(FILES + ("mesh.msh", "quality.png", "mesh.png")))
            with open(case, "w") as f:
                f.write('spacing_km = 900\nvtu = "yes"\n')
            r = run("build", "--case", case)
            self.assertEqual(r.returncode, 1)
            self.assertIn("'vtu' must be true or false", r.stderr)

    def test_netcdf4_mesh_file_on_request(self):
        # --mpas-format netcdf4 (or the case file's key) writes mesh.nc as
        # netCDF-4 with the automatic file's values; check and graph.info
        # read it; the component files have only the automatic format.
        import netCDF4  # python3-netcdf4 (and numpy), installed by tools/setup.sh
        import numpy as np
        with tempfile.TemporaryDirectory() as folder:
            auto, hdf = os.path.join(folder, "auto"), os.path.join(folder, "hdf")
            r = run("build", "--spacing-km", "900", "--threads", "1", "--out", auto)
            self.assertEqual(r.returncode, 0, r.stderr)
            case = os.path.join(folder, "case.toml")
            with open(case, "w") as f:
                f.write('spacing_km = 900\nthreads = 1\nmpas_format = "netcdf4"\nout = "hdf"\n')
            r = run("build", "--case", case)
            self.assertEqual(r.returncode, 0, r.stderr)
            with netCDF4.Dataset(os.path.join(auto, "mesh.nc")) as a, netCDF4.Dataset(os.path.join(hdf, "mesh.nc")) as b:
                self.assertEqual(a.data_model, "NETCDF3_64BIT_OFFSET")
                self.assertEqual(b.data_model, "NETCDF4")
                self.assertEqual(sorted(a.variables), sorted(b.variables))
                for name in a.variables:
                    self.assertTrue(np.array_equal(a[name][:], b[name][:]), name)
                self.assertEqual(a.file_id, b.file_id)
            with open(os.path.join(auto, "graph.info")) as f, open(os.path.join(hdf, "graph.info")) as g:
                self.assertEqual(f.read(), g.read())
            r = run("check", os.path.join(hdf, "mesh.nc"))
            self.assertEqual(r.returncode, 0, r.stdout + r.stderr)
            r = run("build", "--spacing-km", "900", "--mpas-format", "netcdf4", "--components", "--out", hdf)
            self.assertEqual(r.returncode, 1)
            self.assertIn("--mpas-format netcdf4 with --components", r.stderr)
            with open(case, "w") as f:
                f.write('spacing_km = 900\nmpas_format = "hdf5"\n')
            r = run("build", "--case", case)
            self.assertEqual(r.returncode, 1)
            self.assertIn("'mpas_format' must be", r.stderr)

    def test_case_file_and_flags_that_win(self):
        with tempfile.TemporaryDirectory() as folder:
            case = os.path.join(folder, "case.toml")
            with open(case, "w") as f:
                f.write(f'geometry = ["{COAST}"]\nspacing_km = 800\nthreads = 1\noptimise = false\n'
                        'out = "from_case"\n[options]\nrefine_beta = 0.25\n')
            r = run("build", "--case", case)
            self.assertEqual(r.returncode, 0, r.stderr)
            for name in FILES:
                self.assertTrue(os.path.exists(os.path.join(folder, "from_case", name)), name)
            self.assertNotIn("optimised quality", r.stdout)  # optimise = false
            elsewhere = os.path.join(folder, "flags")
            r = run("build", "--case", case, "--out", elsewhere, "--spacing-km", "900")
            self.assertEqual(r.returncode, 0, r.stderr)
            self.assertTrue(os.path.exists(os.path.join(elsewhere, "mesh.nc")))


def snapshot(folder):
    """Every entry of a folder with its bytes (None for a folder)."""
    out = {}
    for name in sorted(os.listdir(folder)):
        path = os.path.join(folder, name)
        if os.path.isfile(path):
            with open(path, "rb") as f:
                out[name] = f.read()
        else:
            out[name] = None
    return out


def plot_processes_on(folder):
    """The command lines of the running processes that draw into folder."""
    found = []
    for pid in filter(str.isdigit, os.listdir("/proc")):
        try:
            with open(f"/proc/{pid}/cmdline", "rb") as f:
                args = f.read().decode(errors="replace").split("\0")
        except OSError:
            continue
        if any(a.endswith(".py") and "plot_" in a for a in args) and any(folder in a for a in args):
            found.append(" ".join(args))
    return found


def limit_file_size(ignore_signal):
    """preexec_fn: files of the child stop at 64 KB (writes fail with EFBIG, or
    SIGXFSZ kills the child mid-write)."""
    def apply():
        if ignore_signal:
            signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
        resource.setrlimit(resource.RLIMIT_FSIZE, (65536, 65536))
    return apply


class Outputs(unittest.TestCase):
    """A run publishes its files as a set: a failed or killed run leaves the
    set before it as it was, manifest.json names the set, and a second run
    into the same folder at once is refused."""

    def build(self, out, km, **kwargs):
        kwargs.setdefault("capture_output", True)
        return subprocess.run([CLI, "build", "--spacing-km", str(km), "--threads", "1", "--out", out],
                              text=True, timeout=600, **kwargs)

    def test_a_failed_or_killed_run_keeps_the_last_set(self):
        with tempfile.TemporaryDirectory() as out:
            r = self.build(out, 900)
            self.assertEqual(r.returncode, 0, r.stderr)
            before = snapshot(out)
            for ignore_signal in (True, False):
                with self.subTest(killed=not ignore_signal):
                    # (Not through pipes: run() would wait for every process
                    # holding them, the pictures' scripts too.)
                    r = self.build(out, 700, preexec_fn=limit_file_size(ignore_signal), capture_output=False,
                                   stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
                    self.assertNotEqual(r.returncode, 0)
                    # The pictures' scripts, started before the files are
                    # written, end with the run (killed: when they find no
                    # one left to tell them to draw).
                    deadline = time.monotonic() + (0 if ignore_signal else 20)
                    while plot_processes_on(out) and time.monotonic() < deadline:
                        time.sleep(0.2)
                    self.assertEqual(plot_processes_on(out), [])
                    after = snapshot(out)
                    stale = [n for n in after if n.startswith(".unimesh-staging-")]
                    if ignore_signal:  # a failure cleans up; a killed run cannot
                        self.assertEqual(stale, [])
                    for name in stale:
                        del after[name]
                    self.assertEqual(after, before)
            self.assertIn("mesh.nc", before)

    def test_manifest_names_the_set(self):
        with tempfile.TemporaryDirectory() as out:
            r = self.build(out, 900)
            self.assertEqual(r.returncode, 0, r.stderr)
            with open(os.path.join(out, "manifest.json")) as f:
                manifest = json.load(f)
            self.assertRegex(manifest["file_id"], "^[0-9a-z]{10}$")
            names = {entry["name"]: entry["bytes"] for entry in manifest["files"]}
            for name in FILES:
                self.assertEqual(names[name], os.path.getsize(os.path.join(out, name)), name)
            self.assertEqual([n for n in os.listdir(out) if n.startswith(".unimesh-staging-")], [])

    def test_a_second_run_into_the_same_folder_is_refused(self):
        with tempfile.TemporaryDirectory() as out:
            with open(os.path.join(out, ".unimesh.lock"), "w") as lock:
                fcntl.flock(lock, fcntl.LOCK_EX)
                r = self.build(out, 900)
            self.assertNotEqual(r.returncode, 0)
            self.assertIn("another unimesh build is writing there", r.stderr)
            self.assertFalse(os.path.exists(os.path.join(out, "mesh.nc")))


class DamagedFiles(unittest.TestCase):
    """check and quality on damaged or hostile MPAS files: a one-line error
    and exit 1, never a crash or a PASS (a cut classic file reads its missing
    tail as zeros)."""

    def test_cut_and_wrong_index_files_are_refused(self):
        import netCDF4  # python3-netcdf4, installed by tools/setup.sh
        with tempfile.TemporaryDirectory() as out:
            r = run("build", "--spacing-km", "900", "--threads", "1", "--out", out)
            self.assertEqual(r.returncode, 0, r.stderr)
            with open(os.path.join(out, "mesh.nc"), "rb") as f:
                data = f.read()
            damaged = {}
            for fraction in (0.5, 0.95, 0.999):
                path = os.path.join(out, f"cut_{fraction}.nc")
                with open(path, "wb") as f:
                    f.write(data[:int(len(data) * fraction)])
                damaged[path] = "truncated"
            # A header whose first dimension's name claims 1.8 GB (found by
            # fuzzing check: netCDF-C would try to read it) and one whose
            # variable count is far beyond the file.
            name_length_at = 16  # magic, numrecs, NC_DIMENSION tag, ndims
            for what, patch in (("name", (name_length_at, b"\x6c\x73\x00\x00")),
                                ("count", (12, b"\x7f\xff\xff\xff"))):
                path = os.path.join(out, f"header_{what}.nc")
                with open(path, "wb") as f:
                    f.write(data[:patch[0]] + patch[1] + data[patch[0] + 4:])
                damaged[path] = "netCDF header is damaged"
            for var, index, value in (("cellsOnVertex", (0, 0), 0), ("nEdgesOnCell", (0,), 100),
                                      ("edgesOnEdge", (0, 0), 10 ** 6), ("cellsOnEdge", (3, 1), -7)):
                path = os.path.join(out, f"{var}.nc")
                with open(path, "wb") as f:
                    f.write(data)
                with netCDF4.Dataset(path, "a") as d:
                    d.variables[var][index] = value
                damaged[path] = var
            for path, word in damaged.items():
                for command in ("check", "quality"):
                    with self.subTest(path=os.path.basename(path), command=command):
                        r = run(command, path)
                        self.assertEqual(r.returncode, 1, r.stdout + r.stderr)
                        self.assertIn(word, r.stderr)


    def test_a_file_declaring_more_than_the_memory_is_refused(self):
        # A netCDF-4 file can declare ten billion cells in kilobytes (its
        # chunks unwritten): refused from its dimensions, before any read.
        import netCDF4
        with tempfile.TemporaryDirectory() as out:
            r = run("build", "--spacing-km", "900", "--threads", "1", "--out", out)
            self.assertEqual(r.returncode, 0, r.stderr)
            huge = os.path.join(out, "huge.nc")
            sizes = {"nCells": 10 ** 10, "nEdges": 3 * 10 ** 10, "nVertices": 2 * 10 ** 10}
            with netCDF4.Dataset(os.path.join(out, "mesh.nc")) as src, netCDF4.Dataset(huge, "w", format="NETCDF4") as dst:
                dst.setncatts({a: src.getncattr(a) for a in src.ncattrs()})
                for name, dim in src.dimensions.items():
                    dst.createDimension(name, sizes.get(name, len(dim)))
                for name, var in src.variables.items():
                    dst.createVariable(name, var.dtype, var.dimensions)
            for command in ("check", "quality"):
                with self.subTest(command=command):
                    r = run(command, huge)
                    self.assertEqual(r.returncode, 1, r.stdout + r.stderr)
                    self.assertIn("more than the available memory", r.stderr)

    def test_netcdf4_mesh_files_are_judged_in_a_trial_process(self):
        # check and quality read a netCDF-4 (HDF5) file in a child (a damaged
        # one may kill libhdf5): a sound one still gets its verdict and report.
        import netCDF4
        with tempfile.TemporaryDirectory() as out:
            r = run("build", "--spacing-km", "900", "--threads", "1", "--out", out)
            self.assertEqual(r.returncode, 0, r.stderr)
            copy = os.path.join(out, "mesh4.nc")
            with netCDF4.Dataset(os.path.join(out, "mesh.nc")) as src, netCDF4.Dataset(copy, "w", format="NETCDF4") as dst:
                dst.setncatts({a: src.getncattr(a) for a in src.ncattrs()})
                for name, dim in src.dimensions.items():
                    dst.createDimension(name, len(dim))
                for name, var in src.variables.items():
                    dst.createVariable(name, var.dtype, var.dimensions)[:] = var[:]
            check = run("check", copy)
            self.assertEqual(check.returncode, 0, check.stdout + check.stderr)
            self.assertIn("PASS (0 failed)", check.stdout)
            quality = run("quality", "--json", copy)
            self.assertEqual(quality.returncode, 0, quality.stderr)
            self.assertEqual(json.loads(quality.stdout)["file"], copy)


class Errors(unittest.TestCase):
    def assert_fails(self, args, *words):
        r = run(*args)
        self.assertNotEqual(r.returncode, 0, r.stdout)
        message = r.stderr.strip().splitlines()[-1] if r.stderr.strip() else ""
        for word in words:
            self.assertIn(word, message)

    def test_bad_flags_and_files(self):
        with tempfile.TemporaryDirectory() as out:
            self.assert_fails(["build", "--spacing-km", "-5", "--out", out], "spacing")
            self.assert_fails(["build", "--spacing-km", "0", "--out", out], "--spacing-km", "0")
            self.assert_fails(["build", "--spacing-km", "nan", "--out", out], "--spacing-km", "nan is not a number")
            # An impossible size is refused up front under the default cap
            # (the available memory), with the estimate; a cap of 1 MiB too.
            self.assert_fails(["build", "--spacing-km", "0.03", "--out", out], "cells needs about", "memory cap")
            self.assert_fails(["build", "--spacing-km", "100", "--memory-cap", "1M", "--out", out], "memory cap")
            # A real size over a small cap: refused before the meshing, not minutes into it.
            started = time.monotonic()
            self.assert_fails(["build", "--spacing-km", "20", "--memory-cap", "300M", "--out", out],
                              "cells needs about", "memory cap")
            self.assertLess(time.monotonic() - started, 20)
            self.assert_fails(["build", "--spacing-km", "100", "--memory-cap", "lots", "--out", out],
                              "--memory-cap", "lots")
            self.assert_fails(["build", "--spacing-km", "100", "--option", "refine_rho=0.5", "--out", out],
                              "refine_rho", "0.5")
            for value in ("-1", "nan", "11"):
                self.assert_fails(["build", "--spacing-km", "100", "--spacing-gradient", value, "--out", out],
                                  "--spacing-gradient", value)
            self.assert_fails(["build", "--spacing-km", "100", "--geometry", "/no/such.geojson"], "no/such")
            bad = os.path.join(out, "bad.geojson")
            with open(bad, "w") as f:
                f.write('{"type": "FeatureCollection", "features": [')
            self.assert_fails(["build", "--spacing-km", "500", "--geometry", bad, "--out", out], "bad.geojson")
            self.assert_fails(["check", bad], "netCDF")
            empty = os.path.join(out, "empty.geojson")
            with open(empty, "w") as f:
                f.write('{"type": "FeatureCollection", "features": []}')
            self.assert_fails(["build", "--spacing-km", "500", "--domain", empty, "--out", out],
                              "--domain " + empty + ": holds no domain feature")
            # A domain ring given open (GeoJSON repeats a ring's first position).
            open_ring = os.path.join(out, "open_ring.geojson")
            with open(open_ring, "w") as f:
                f.write('{"type": "Polygon", "coordinates": [[[-80, 10], [-5, 10], [-5, 65], [-80, 65]]]}')
            self.assert_fails(["build", "--spacing-km", "500", "--domain", open_ring, "--out", out],
                              "--domain " + open_ring, ": coordinates[0] is a domain ring but is open")
            # A run that fails after making its output folder leaves none.
            bowtie = os.path.join(out, "bowtie.geojson")
            with open(bowtie, "w") as f:
                f.write('{"type": "Polygon", "coordinates": [[[0, 0], [10, 10], [10, 0], [0, 10], [0, 0]]]}')
            fresh = os.path.join(out, "fresh")
            self.assert_fails(["build", "--spacing-km", "100", "--domain", bowtie, "--out",
                               os.path.join(fresh, "a", "b")], "crosses itself", bowtie + ": coordinates[0]")
            self.assertFalse(os.path.exists(fresh))
            r = run("build", "--spacing-km", "900", "--geometry", empty, "--out", os.path.join(out, "empty"))
            self.assertEqual(r.returncode, 0, r.stderr)  # no coastlines: a uniform global mesh
            # A damaged netCDF-4 file that kills libhdf5: read in a trial
            # process first, refused (or, where libhdf5 survives it, an error).
            damaged = os.path.join(os.path.dirname(__file__), "..", "data", "netcdf4_damaged.nc")
            self.assert_fails(["build", "--spacing-file", damaged, "--out", out], "--spacing-file", "netcdf4_damaged.nc")
            self.assertEqual(run("build", "--spacing-file", damaged, "--out", out).returncode, 1)
            # One on which libhdf5 loops for ever: the trial read is stopped (20 s).
            loops = os.path.join(os.path.dirname(__file__), "..", "data", "netcdf4_loops.nc")
            self.assert_fails(["build", "--spacing-file", loops, "--out", out], "did not finish in 20 s")

    def test_trial_process_sees_its_child_when_sigchld_is_ignored(self):
        # A parent that ignores SIGCHLD passes that on across exec; the child
        # would then be reaped unseen. The trial still reports how it ended.
        import signal
        damaged = os.path.join(os.path.dirname(__file__), "..", "data", "netcdf4_damaged.nc")
        with tempfile.TemporaryDirectory() as out:
            r = subprocess.run([CLI, "build", "--spacing-file", damaged, "--out", out], capture_output=True,
                               text=True, timeout=600,
                               preexec_fn=lambda: signal.signal(signal.SIGCHLD, signal.SIG_IGN))
            self.assertEqual(r.returncode, 1, r.stdout + r.stderr)
            self.assertIn("killed the HDF5 library", r.stderr)

    def test_bad_case_files(self):
        with tempfile.TemporaryDirectory() as folder:
            cases = {
                'spacing_km = "wide"\n': "spacing_km",
                "spacing_km = 100\ncolour = 3\n": "colour",
                "spacing_km = [\n": "line",
                "spacing_km = 100\n[options]\nno_such_option = 1\n": "no_such_option",
                'spacing_km = 100\ngeometry = "one.geojson"\n': "geometry",
                "spacing_km = 600\noptimise = t\n": "line 2",  # found by fuzzing: a two-line message
                "spacing_km = 600\nthreads = 5.1e27\n": "threads",  # found by fuzzing: UB in toml++
                "spacing_km = 600\n[options]\nrefine_bta = 0.2\n": "options.refine_bta is not a known option",
                'spacing_km = 600\n[options]\n"refine_beta=0.1;refine_rho" = 1.1\n': "is not a known option",
            }
            for text, word in cases.items():
                path = os.path.join(folder, "case.toml")
                with open(path, "w") as f:
                    f.write(text)
                with self.subTest(text=text):
                    self.assert_fails(["build", "--case", path, "--out", folder], word)


if __name__ == "__main__":
    unittest.main()
