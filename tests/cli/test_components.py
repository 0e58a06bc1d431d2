"""`unimesh build --components` and `unimesh components` as a coupled-model
workflow runs them: the ocean and land meshes pass `unimesh check`, CDO
remaps a field conservatively from the ocean's SCRIP grid, gpmetis
partitions each component's graph.info, and the ESMF files describe the
same cells as the SCRIP files.

    UNIMESH_CLI=build/tools/unimesh UNIMESH_DATA=data python3 -m unittest test_components
"""
import filecmp
import json
import os
import shutil
import subprocess
import tempfile
import unittest

import numpy as np
import netCDF4

CLI = os.environ["UNIMESH_CLI"]
DATA = os.environ["UNIMESH_DATA"]
COAST = os.path.join(DATA, "coast_global_l.geojson")
RIVERS = os.path.join(DATA, "rivers_global_l.geojson")
COMPONENT_FILES = ("ocean.nc", "land.nc", "ocean.graph.info", "land.graph.info", "mesh.scrip.nc",
                   "ocean.scrip.nc", "land.scrip.nc", "mesh.esmf.nc", "ocean.esmf.nc", "land.esmf.nc",
                   "rivers.json")


def run(*args, **kwargs):
    return subprocess.run([CLI, *args], capture_output=True, text=True, timeout=600, **kwargs)


class Components(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory()
        cls.out = os.path.join(cls.tmp.name, "out")
        r = run("build", "--geometry", COAST, "--geometry", RIVERS, "--spacing-km", "240", "--threads", "2",
                "--components", "--out", cls.out)
        assert r.returncode == 0, r.stderr
        cls.stdout = r.stdout

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def path(self, name):
        return os.path.join(self.out, name)

    def test_every_file_is_written_and_each_mesh_passes_check(self):
        with open(self.path("manifest.json")) as f:
            listed = {entry["name"] for entry in json.load(f)["files"]}
        for name in ("mesh.nc", "graph.info") + COMPONENT_FILES:
            self.assertGreater(os.path.getsize(self.path(name)), 0, name)
            self.assertIn(name, listed)
        for name in ("mesh.nc", "ocean.nc", "land.nc"):
            check = run("check", self.path(name))
            self.assertEqual(check.returncode, 0, check.stdout + check.stderr)
            self.assertNotIn("FAIL", check.stdout)
        self.assertIn("rivers: ", self.stdout)

    def test_cdo_remaps_the_ocean_conservatively(self):
        grid = netCDF4.Dataset(self.path("ocean.scrip.nc"))
        lat, lon = np.radians(grid["grid_center_lat"][:]), np.radians(grid["grid_center_lon"][:])
        values = 2 + np.cos(lat) ** 2 * np.cos(2 * lon) + np.sin(lat)
        source_integral = float(np.sum(values * grid["grid_area"][:]))
        grid.close()
        with tempfile.TemporaryDirectory() as work:
            field, remapped = os.path.join(work, "field.nc"), os.path.join(work, "remapped.nc")
            with netCDF4.Dataset(field, "w") as f:
                f.createDimension("ncells", len(values))
                f.createVariable("f", "f8", ("ncells",))[:] = values
            env = dict(os.environ, CDO_REMAP_NORM="destarea")
            r = subprocess.run(["cdo", "-s", "-f", "nc", "remapcon,r360x180",
                                "-setgrid," + self.path("ocean.scrip.nc"), field, remapped],
                               capture_output=True, text=True, env=env, timeout=600)
            self.assertEqual(r.returncode, 0, r.stderr)
            with netCDF4.Dataset(remapped) as f:
                out = np.ma.filled(f["f"][:], 0.0).reshape(180, 360)
        edges = np.radians(np.linspace(-90, 90, 181))
        area = (np.sin(edges[1:]) - np.sin(edges[:-1]))[:, None] * np.radians(1.0)
        remapped_integral = float(np.sum(out * area))
        self.assertLess(abs(remapped_integral / source_integral - 1), 1e-9,
                        (source_integral, remapped_integral))

    def test_gpmetis_partitions_each_component(self):
        with tempfile.TemporaryDirectory() as work:
            for name in ("ocean", "land"):
                graph = os.path.join(work, name + ".graph.info")
                shutil.copy(self.path(name + ".graph.info"), graph)
                r = subprocess.run(["gpmetis", graph, "4"], capture_output=True, text=True, timeout=600)
                self.assertEqual(r.returncode, 0, r.stdout + r.stderr)
                with open(graph + ".part.4") as f:
                    parts = [int(line) for line in f]
                with netCDF4.Dataset(self.path(name + ".nc")) as mesh:
                    self.assertEqual(len(parts), len(mesh.dimensions["nCells"]))
                self.assertEqual(set(parts), {0, 1, 2, 3})

    def test_esmf_files_describe_the_scrip_cells(self):
        for name in ("mesh", "ocean", "land"):
            with netCDF4.Dataset(self.path(name + ".scrip.nc")) as s, \
                    netCDF4.Dataset(self.path(name + ".esmf.nc")) as e:
                self.assertEqual(e.gridType, "unstructured mesh")
                conn, count = e["elementConn"][:], e["numElementConn"][:]
                nodes = e["nodeCoords"][:]
                self.assertTrue(np.allclose(e["elementArea"][:], s["grid_area"][:], rtol=0, atol=0))
                corner_lon, corner_lat = s["grid_corner_lon"][:], s["grid_corner_lat"][:]
                for c in range(0, len(count), 97):
                    k = int(count[c])
                    ids = np.asarray(conn[c, :k]) - 1
                    self.assertTrue(np.array_equal(nodes[ids, 0], corner_lon[c, :k]), (name, c))
                    self.assertTrue(np.array_equal(nodes[ids, 1], corner_lat[c, :k]), (name, c))
                    self.assertTrue(np.all(corner_lat[c, k:] == corner_lat[c, k - 1]))
        with netCDF4.Dataset(self.path("mesh.scrip.nc")) as s, netCDF4.Dataset(self.path("mesh.nc")) as m:
            self.assertAlmostEqual(float(np.sum(s["grid_area"][:])) / (4 * np.pi), 1, places=12)
            self.assertEqual(len(s.dimensions["grid_size"]), len(m.dimensions["nCells"]))

    def test_river_report_accounts_for_every_river_cell(self):
        with open(self.path("rivers.json")) as f:
            report = json.load(f)
        self.assertEqual(report["routed_cells"] + report["outlets"] + report["inland_cells"],
                         report["river_cells"])
        self.assertEqual(sum(n["cells"] for n in report["inland_networks"]), report["inland_cells"])
        with netCDF4.Dataset(self.path("land.nc")) as land, netCDF4.Dataset(self.path("mesh.nc")) as base:
            kind, down = land["riverCellKind"][:], land["downstreamCell"][:]
            self.assertEqual(int(np.count_nonzero(kind)), report["river_cells"])
            routed = np.nonzero(kind == 1)[0]
            self.assertTrue(np.all(down[routed] > 0))
            # The land mesh's routing is the base's, renumbered.
            base_of = land["baseCellId"][:] - 1
            base_down = base["downstreamCell"][:]
            self.assertTrue(np.array_equal(base_of[down[routed] - 1] + 1, base_down[base_of[routed]]))

    def test_components_command_gives_the_same_files(self):
        with tempfile.TemporaryDirectory() as again:
            r = run("components", self.path("mesh.nc"), "--out", again)
            self.assertEqual(r.returncode, 0, r.stderr)
            self.assertIn("rivers: ", r.stdout)
            for name in ("mesh.nc",) + COMPONENT_FILES:
                self.assertTrue(filecmp.cmp(self.path(name), os.path.join(again, name), shallow=False), name)


    def test_components_command_keeps_only_the_files_of_its_mesh(self):
        with tempfile.TemporaryDirectory() as work:
            own, other = os.path.join(work, "own"), os.path.join(work, "other")
            for out in (own, other):
                r = run("build", "--geometry", COAST, "--spacing-km", "900", "--out", out)
                self.assertEqual(r.returncode, 0, r.stderr)
            # Into the folder of the mesh it reads: the build's files stay.
            r = run("components", os.path.join(own, "mesh.nc"), "--out", own)
            self.assertEqual(r.returncode, 0, r.stderr)
            for name in ("graph.info", "quality.json", "ocean.nc"):
                self.assertTrue(os.path.exists(os.path.join(own, name)), name)
            # Another mesh replaces the folder's mesh.nc: its graph.info and report go.
            r = run("components", self.path("mesh.nc"), "--out", other)
            self.assertEqual(r.returncode, 0, r.stderr)
            for name in ("graph.info", "quality.json"):
                self.assertFalse(os.path.exists(os.path.join(other, name)), name)
            self.assertTrue(filecmp.cmp(self.path("ocean.nc"), os.path.join(other, "ocean.nc"), shallow=False))


class Refused(unittest.TestCase):
    def test_a_mesh_without_coastlines_has_no_components(self):
        with tempfile.TemporaryDirectory() as out:
            r = run("build", "--spacing-km", "900", "--components", "--out", out)
            self.assertEqual(r.returncode, 1)
            self.assertIn("land component has no cells", r.stderr)
            self.assertFalse(os.path.exists(os.path.join(out, "mesh.nc")))
            r = run("build", "--spacing-km", "900", "--out", out)
            self.assertEqual(r.returncode, 0, r.stderr)
            r = run("components", os.path.join(out, "mesh.nc"), "--out", os.path.join(out, "parts"))
            self.assertEqual(r.returncode, 1)
            self.assertIn("land component has no cells", r.stderr)
            self.assertFalse(os.path.exists(os.path.join(out, "parts", "ocean.nc")))

    def test_a_file_that_is_no_mesh(self):
        with tempfile.TemporaryDirectory() as out:
            text = os.path.join(out, "notes.nc")
            with open(text, "w") as f:
                f.write("not a mesh\n")
            r = run("components", text, "--out", os.path.join(out, "parts"))
            self.assertEqual(r.returncode, 1)
            self.assertIn("MPAS mesh file", r.stderr)
            self.assertIn("notes.nc", r.stderr)
            self.assertEqual(len(r.stderr.strip().splitlines()), 1, r.stderr)

    def test_a_later_build_without_components_removes_them(self):
        with tempfile.TemporaryDirectory() as out:
            r = run("build", "--geometry", COAST, "--spacing-km", "900", "--components", "--out", out)
            self.assertEqual(r.returncode, 0, r.stderr)
            self.assertTrue(os.path.exists(os.path.join(out, "ocean.nc")))
            r = run("build", "--geometry", COAST, "--spacing-km", "900", "--out", out)
            self.assertEqual(r.returncode, 0, r.stderr)
            for name in COMPONENT_FILES:
                self.assertFalse(os.path.exists(os.path.join(out, name)), name)
            with netCDF4.Dataset(os.path.join(out, "mesh.nc")) as m:
                self.assertNotIn("oceanCellId", m.variables)


class RegionalComponents(unittest.TestCase):
    """The components of a regional mesh (the North Atlantic box with its
    coastlines and rivers): each passes the check and keeps the base's
    limited-area layers; rivers that leave the box without reaching the sea
    inside drain across its boundary, in the mesh's own file too; the
    components command gives the same files from the regional mesh.nc."""

    def test_a_regional_mesh_splits_into_its_components(self):
        with tempfile.TemporaryDirectory() as tmp:
            domain = os.path.join(tmp, "atlantic.geojson")
            with open(domain, "w") as f:
                json.dump({"type": "Feature", "properties": {"kind": "domain"}, "geometry": {
                    "type": "Polygon", "coordinates": [[[-80, 10], [-5, 10], [-5, 65], [-80, 65], [-80, 10]]]}}, f)
            out = os.path.join(tmp, "out")
            r = run("build", "--domain", domain, "--geometry", COAST, "--geometry", RIVERS, "--spacing-km", "120",
                    "--threads", "2", "--components", "--out", out)
            self.assertEqual(r.returncode, 0, r.stderr)
            for name in ("mesh.nc", "ocean.nc", "land.nc"):
                check = run("check", os.path.join(out, name))
                self.assertEqual(check.returncode, 0, check.stdout + check.stderr)
            with netCDF4.Dataset(os.path.join(out, "mesh.nc")) as base:
                base_layers = base["bdyMaskCell"][:]
                self.assertEqual(sorted(set(base_layers.tolist())), list(range(8)))
                cells = base.dimensions["nCells"].size
                for name in ("ocean.nc", "land.nc"):
                    with netCDF4.Dataset(os.path.join(out, name)) as part:
                        base_of = part["baseCellId"][:] - 1
                        self.assertTrue(np.array_equal(part["bdyMaskCell"][:], base_layers[base_of]), name)
                        cells -= part.dimensions["nCells"].size
                self.assertEqual(cells, 0)
            with open(os.path.join(out, "rivers.json")) as f:
                report = json.load(f)
            self.assertEqual(report["routed_cells"] + report["outlets"] + report["inland_cells"], report["river_cells"])
            self.assertTrue(0 < report["boundary_outlets"] < report["outlets"], report)
            self.assertIn(" on the domain's boundary)", r.stdout)
            # The mesh's own file routes its rivers as its components do: within
            # the domain, every routed cell with a downstream cell.
            plain = os.path.join(tmp, "plain")
            r = run("build", "--domain", domain, "--geometry", COAST, "--geometry", RIVERS, "--spacing-km", "120",
                    "--threads", "2", "--out", plain)
            self.assertEqual(r.returncode, 0, r.stderr)
            with netCDF4.Dataset(os.path.join(plain, "mesh.nc")) as own, \
                    netCDF4.Dataset(os.path.join(out, "mesh.nc")) as base:
                for name in ("riverCellKind", "downstreamCell", "edgeRiverDownstream"):
                    self.assertTrue(np.array_equal(own[name][:], base[name][:]), name)
                kind, down = own["riverCellKind"][:], own["downstreamCell"][:]
                self.assertTrue(np.all(down[kind == 1] > 0))
            again = os.path.join(tmp, "again")
            r = run("components", os.path.join(out, "mesh.nc"), "--out", again)
            self.assertEqual(r.returncode, 0, r.stderr)
            for name in ("mesh.nc",) + COMPONENT_FILES:
                self.assertTrue(filecmp.cmp(os.path.join(out, name), os.path.join(again, name), shallow=False), name)


if __name__ == "__main__":
    unittest.main()
