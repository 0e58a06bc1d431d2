"""Tests of unimesh.Spacing, unimesh.Features and unimesh.Mesh (plain
unittest; needs numpy).

    UNIMESH_LIBRARY=build/lib/libunimesh.so /usr/bin/python3 -m unittest -v \
        bindings/python/tests/test_mesh.py

Meshes are coarse (2000 km spacing, a few hundred triangles) so the whole
file runs in well under a second. Results are checked against properties
every such mesh has, not against stored answers.
"""

import gc
import json
import os
import sys
import tempfile
import unittest
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parents[1] / "python"))  # the package, when run without PYTHONPATH

import unimesh  # noqa: E402  (path set just above)
from unimesh import (FeatureKind, Features, Mesh, MpasFile, Side, Spacing, Status,  # noqa: E402
                     UnimeshError)

try:
    import numpy
except ImportError:  # pragma: no cover - depends on the installation
    numpy = None

COARSE_KM = 2000.0
RING_LAT = 30.0
ARC_BULGE = 0.03  # degrees: how far a 5-degree arc of the ring rises above RING_LAT


def unit_vectors(lon_deg, lat_deg):
    lon, lat = numpy.radians(lon_deg), numpy.radians(lat_deg)
    return numpy.stack([numpy.cos(lat) * numpy.cos(lon), numpy.cos(lat) * numpy.sin(lon),
                        numpy.sin(lat)], axis=1)


def ring(lat=RING_LAT, n=72):
    """A closed circle of latitude, n points (first not repeated)."""
    lon = numpy.linspace(-180.0, 180.0, n + 1)[:-1]
    return lon, numpy.full(n, lat)


@unittest.skipIf(numpy is None, "numpy is not installed")
class SpacingTests(unittest.TestCase):
    def setUp(self):
        self.ctx = unimesh.Context(threads=2)
        self.addCleanup(self.ctx.close)

    def test_constant_and_preset(self):
        with Spacing.constant(self.ctx, 240) as h:
            values = h.evaluate([[0, 10], [20, 30]], [[0, -45], [89, 90]])
            self.assertEqual(values.shape, (2, 2))
            numpy.testing.assert_array_equal(values, 240.0)
        with Spacing.preset(self.ctx, "qu240") as h:  # prefix case-insensitive
            numpy.testing.assert_array_equal(h.evaluate([0, 100], [0, 60]), 240.0)
        with Spacing.preset(self.ctx, "EC60to30") as h:
            equator, mid = h.evaluate([0, 0], [0, 45])
            self.assertLess(equator, mid)
            self.assertLessEqual(mid, 60.0 + 1e-9)
        self.assertEqual(Spacing.constant(self.ctx, 1).evaluate([], []).shape, (0,))

    def test_grid_clamp_and_gradient_limit(self):
        lon = [-180.0, -90.0, 0.0, 90.0, 180.0]
        lat = [-90.0, 0.0, 90.0]
        width = numpy.full((3, 5), 100.0)
        width[1, 2] = 1000.0  # one high value at (0, 0)
        h = Spacing.grid(self.ctx, lon, lat, width)
        self.assertAlmostEqual(h.evaluate([0.0], [0.0])[0], 1000.0)
        self.assertAlmostEqual(h.evaluate([45.0], [0.0])[0], 550.0)  # bilinear
        h.clamp(150.0, 600.0)
        numpy.testing.assert_allclose(h.evaluate([0.0, 90.0], [0.0, 0.0]), [600.0, 150.0])
        h.limit_gradient(1e-3)  # 1 m per km: at most ~10 km over a 90 degree step
        low, high = h.evaluate([90.0, 0.0], [0.0, 0.0])
        self.assertAlmostEqual(low, 150.0)
        self.assertLess(high, 150.0 + 1e-3 * 10008.0 + 1e-6)
        with self.assertRaises(UnimeshError) as caught:  # only for grids
            Spacing.constant(self.ctx, 10).limit_gradient(0.1)
        self.assertEqual(caught.exception.status, Status.ERR_INVALID_ARGUMENT)
        with self.assertRaisesRegex(ValueError, "cell_width_km must have shape"):
            Spacing.grid(self.ctx, lon, lat, width.T)

    def test_callback_is_kept_alive_by_the_spacing(self):
        h = Spacing.callback(self.ctx, lambda lon, lat: 100.0 + abs(lat))
        gc.collect()  # the lambda has no other reference
        numpy.testing.assert_array_equal(h.evaluate([0, 50, 100], [0, -30, 60]),
                                         [100.0, 130.0, 160.0])

    def test_callback_exception_is_what_the_call_raises(self):
        def spacing(_lon, lat):
            if lat > 50:
                raise ZeroDivisionError("no spacing north of 50")
            return 500.0
        h = Spacing.callback(self.ctx, spacing)
        with self.assertRaisesRegex(ZeroDivisionError, "north of 50"):
            h.evaluate([0, 0, 0], [0, 60, 70])
        self.assertEqual(self.ctx.last_error, "")  # the C message was taken out
        numpy.testing.assert_array_equal(h.evaluate([0], [0]), [500.0])  # usable again

    def test_bad_values_raise_with_the_library_message(self):
        with self.assertRaises(UnimeshError) as caught:
            Spacing.constant(self.ctx, -1.0)
        self.assertEqual(caught.exception.status, Status.ERR_INVALID_ARGUMENT)
        self.assertIn("-1", caught.exception.message)
        with self.assertRaises(UnimeshError) as caught:
            Spacing.callback(self.ctx, lambda lon, lat: 0.0).evaluate([1.0], [2.0])
        self.assertEqual(caught.exception.status, Status.ERR_INVALID_ARGUMENT)
        with self.assertRaises(UnimeshError):
            Spacing.preset(self.ctx, "XY100")
        with self.assertRaises(UnimeshError) as caught:
            Spacing.from_file(self.ctx, os.path.join(tempfile.gettempdir(), "no-such-um.nc"))
        self.assertEqual(caught.exception.status, Status.ERR_IO)
        with self.assertRaises(TypeError):
            Spacing(self.ctx)
        with self.assertRaises(TypeError):
            Spacing.callback(self.ctx, 42)


@unittest.skipIf(numpy is None, "numpy is not installed")
class FeaturesTests(unittest.TestCase):
    def setUp(self):
        self.ctx = unimesh.Context()
        self.addCleanup(self.ctx.close)

    def test_add_counts_and_copies(self):
        with Features(self.ctx) as gamma:
            lon, lat = ring(n=8)
            gamma.add(lon, lat, closed=True, kind=FeatureKind.COASTLINE)
            # Two open parts at once, the first with a repeated point.
            gamma.add([0, 1, 1, 2, 10, 11], [0, 0, 0, 0, 5, 5], offsets=[0, 4, 6],
                      kind=[FeatureKind.RIVER, FeatureKind.WATERSHED], part_id=[70, 71])
            self.assertEqual(gamma.counts(), (3, 8 + 3 + 2, 8 + 2 + 1))
            self.assertEqual(len(gamma), 3)
            parts = gamma.parts()
            numpy.testing.assert_array_equal(parts.offsets, [0, 8, 11, 13])
            numpy.testing.assert_array_equal(parts.closed, [1, 0, 0])
            numpy.testing.assert_array_equal(parts.kind, [1, 3, 4])
            numpy.testing.assert_array_equal(parts.part_id, [0, 70, 71])
            stored_lon, stored_lat = gamma.points()
            numpy.testing.assert_array_equal(stored_lon[8:], [0, 1, 2, 10, 11])
            numpy.testing.assert_array_equal(stored_lat[:8], RING_LAT)

    def test_failing_add_adds_nothing(self):
        gamma = Features(self.ctx)
        with self.assertRaises(UnimeshError) as caught:
            gamma.add([0, 1, 2], [0, 95, 0])
        self.assertEqual(caught.exception.status, Status.ERR_COORDINATE_RANGE)
        self.assertIn("lat_deg[1]", caught.exception.message)
        with self.assertRaises(UnimeshError):
            gamma.add([0, 1], [0, 1], kind=99)
        self.assertEqual(gamma.counts(), (0, 0, 0))
        gamma.close()

    def test_read_geojson(self):
        collection = {"type": "FeatureCollection", "features": [
            {"type": "Feature", "id": 5, "properties": {"kind": "River"},
             "geometry": {"type": "LineString", "coordinates": [[0, 0], [5, 1], [10, 0]]}},
            {"type": "Feature", "properties": {},
             "geometry": {"type": "Polygon",
                          "coordinates": [[[20, 20], [30, 20], [25, 28], [20, 20]]]}}]}
        with tempfile.TemporaryDirectory() as directory:
            path = Path(directory) / "lines.geojson"
            path.write_text(json.dumps(collection))
            gamma = Features(self.ctx)
            with self.assertRaises(UnimeshError) as caught:  # no default kind
                gamma.read_geojson(path)
            self.assertEqual(caught.exception.status, Status.ERR_INPUT)
            self.assertEqual(gamma.counts().n_parts, 0)
            gamma.read_geojson(path, default_kind=FeatureKind.LAKE)
            parts = gamma.parts()
            numpy.testing.assert_array_equal(parts.kind, [FeatureKind.RIVER, FeatureKind.LAKE])
            numpy.testing.assert_array_equal(parts.closed, [0, 1])
            self.assertEqual(parts.part_id[0], 5)
            self.assertEqual(gamma.counts().n_points, 3 + 3)
            with self.assertRaises(UnimeshError) as caught:
                gamma.read_geojson(Path(directory) / "missing.geojson")
            self.assertEqual(caught.exception.status, Status.ERR_IO)


@unittest.skipIf(numpy is None, "numpy is not installed")
class MeshTests(unittest.TestCase):
    def setUp(self):
        self.ctx = unimesh.Context(threads=2)
        self.addCleanup(self.ctx.close)
        self.spacing = Spacing.constant(self.ctx, COARSE_KM)
        self.addCleanup(self.spacing.close)

    def check_closed_surface(self, mesh):
        counts = mesh.counts()
        lon, lat = mesh.vertices()
        triangles = mesh.triangles()
        self.assertEqual(lon.shape, (counts.n_vertices,))
        self.assertEqual(triangles.shape, (counts.n_triangles, 3))
        self.assertEqual(counts.n_triangles, 2 * counts.n_vertices - 4)  # Euler, sphere
        self.assertTrue(numpy.all((lon > -180) & (lon <= 180)))
        self.assertTrue(numpy.all(numpy.abs(lat) <= 90))
        # Every vertex used; counter-clockwise seen from outside.
        self.assertEqual(set(numpy.unique(triangles)), set(range(counts.n_vertices)))
        x = unit_vectors(lon, lat)
        a, b, c = (x[triangles[:, k]] for k in range(3))
        self.assertTrue(numpy.all(numpy.einsum("ij,ij->i", numpy.cross(b - a, c - a), a) > 0))
        numpy.testing.assert_array_equal(mesh.triangles(base=1), triangles + 1)
        return lon, lat, triangles

    def test_refine_without_features(self):
        with Mesh.refine(self.ctx, self.spacing) as mesh:
            lon, lat, triangles = self.check_closed_surface(mesh)
            counts = mesh.counts()
            self.assertGreater(counts.n_vertices, 12)  # more than the icosahedron
            self.assertEqual(counts.n_restricted_edges, 0)
            numpy.testing.assert_array_equal(mesh.vertex_parts(), -1)
            numpy.testing.assert_array_equal(mesh.vertex_sides(), Side.OCEAN)
            numpy.testing.assert_array_equal(mesh.triangle_sides(), Side.OCEAN)
            edges, parts = mesh.restricted_edges()
            self.assertEqual((edges.shape, parts.shape), ((0, 2), (0,)))
            # The edges are near the spacing (alpha = 4/3 bounds them above).
            x = unit_vectors(lon, lat)
            km = 6371.22 * numpy.arccos(numpy.clip(
                numpy.einsum("ij,ij->i", x[triangles[:, 0]], x[triangles[:, 1]]), -1, 1))
            self.assertLess(km.max(), 2 * COARSE_KM)

    def test_refine_with_a_coastline_ring_and_options(self):
        gamma = Features(self.ctx)
        gamma.add(*ring(), closed=True, kind=FeatureKind.COASTLINE)
        options = unimesh.Options(self.ctx, refine_alpha=1.2)
        mesh = Mesh.refine(self.ctx, self.spacing, features=gamma, options=options)
        gamma.close()
        options.close()  # the mesh needs neither any more
        lon, lat, triangles = self.check_closed_surface(mesh)
        counts = mesh.counts()
        self.assertGreater(counts.n_restricted_edges, 0)
        parts = mesh.vertex_parts()
        on_ring = parts == 0
        self.assertTrue(on_ring.any())
        # On the ring's great-circle arcs (5 degrees long: they bulge up to
        # 0.024 degrees poleward of their end points' latitude).
        self.assertTrue(numpy.all((lat[on_ring] > RING_LAT - 1e-9)
                                  & (lat[on_ring] < RING_LAT + ARC_BULGE)))
        numpy.testing.assert_array_equal(mesh.vertex_parts(base=1)[on_ring], 1)
        numpy.testing.assert_array_equal(mesh.vertex_parts(base=1)[~on_ring], -1)
        edges, edge_parts = mesh.restricted_edges()
        self.assertEqual(edges.shape, (counts.n_restricted_edges, 2))
        numpy.testing.assert_array_equal(edge_parts, 0)
        # The ring's smaller side, the northern cap, is land.
        sides = mesh.vertex_sides()
        numpy.testing.assert_array_equal(sides[on_ring], Side.COASTAL)
        self.assertTrue(numpy.all(sides[lat > RING_LAT + ARC_BULGE] != Side.OCEAN))
        self.assertTrue(numpy.all(sides[lat < RING_LAT] != Side.LAND))
        self.assertIn(Side.LAND, sides)
        triangle_sides = mesh.triangle_sides()
        self.assertEqual(triangle_sides.shape, (counts.n_triangles,))
        self.assertTrue(set(numpy.unique(triangle_sides)) <= {Side.OCEAN, Side.LAND})
        self.assertIn(Side.LAND, triangle_sides)
        self.assertIn(Side.OCEAN, triangle_sides)
        mesh.close()

    def test_wgs84_through_the_options(self):
        # The ellipsoid (sphere_radius = a, surface_flattening = f): the ring's
        # vertices at its geodetic latitude (the direction's geocentric one is
        # 0.19 degrees lower), the MPAS cells' areas adding up to WGS84's.
        gamma = Features(self.ctx)
        gamma.add(*ring(), closed=True, kind=FeatureKind.COASTLINE)
        options = unimesh.Options(self.ctx, sphere_radius=6378137.0, surface_flattening=1 / 298.257223563)
        with Mesh.refine(self.ctx, Spacing.constant(self.ctx, 600.0), features=gamma, options=options) as mesh:
            mesh.optimise(options)
            lon, lat = mesh.vertices()
            on_ring = mesh.vertex_parts() == 0
            self.assertTrue(on_ring.any())
            self.assertTrue(numpy.all((lat[on_ring] > RING_LAT - 1e-9) & (lat[on_ring] < RING_LAT + ARC_BULGE)))
            area = mesh.mpas_variable("areaCell")
            self.assertAlmostEqual(area.sum() / 5.100656217240886e14, 1.0, places=10)
        gamma.close()
        options.close()
        with self.assertRaisesRegex(unimesh.UnimeshError, "surface_flattening"):
            unimesh.Options(self.ctx, surface_flattening=0.5)

    def test_optimise_in_place(self):
        # The frontal refinement: a uniform spacing's lattice is well centred already.
        frontal = unimesh.Options(self.ctx, refine_lattice=0)
        with Mesh.refine(self.ctx, Spacing.constant(self.ctx, 600.0), options=frontal) as mesh:
            before = mesh.quality_summary("area_length_ratio")
            _, not_well_centred = mesh.quality_counts()
            self.assertGreater(not_well_centred, 0)
            self.assertIs(mesh.optimise(unimesh.Options(self.ctx, optim_outer_iterations=6)), mesh)
            self.check_closed_surface(mesh)
            self.assertGreater(mesh.quality_summary("area_length_ratio").min, before.min)
            self.assertEqual(mesh.quality_counts()[1], 0)
            report = json.loads(mesh.quality_json())
            self.assertIn("before_optimisation", report)
            self.assertGreaterEqual(report["optimisation"]["outer_iterations"], 1)
            with self.assertRaises(UnimeshError) as caught:
                mesh.optimise(unimesh.Options(self.ctx, optim_weights=1, optim_split_ratio=0.5))
            self.assertEqual(caught.exception.status, Status.ERR_INVALID_ARGUMENT)
            self.assertIn("optim_split_ratio", str(caught.exception))

    def test_mpas_variables_match_the_file(self):
        try:
            import netCDF4  # noqa: F401  (Debian's python3-netcdf4)
        except ImportError:
            self.skipTest("netCDF4 is not installed")
        gamma = Features(self.ctx)
        gamma.add(*ring(), closed=True, kind=FeatureKind.COASTLINE)
        with Mesh.refine(self.ctx, Spacing.constant(self.ctx, 600.0), gamma) as mesh, \
                tempfile.TemporaryDirectory() as tmp:
            mesh.optimise()
            path = os.path.join(tmp, "mesh.nc")
            mesh.write_mpas(path)
            dims = mesh.mpas_dimensions()
            with netCDF4.Dataset(path) as nc:
                self.assertEqual(dims.n_cells, len(nc.dimensions["nCells"]))
                self.assertEqual(dims.max_edges, len(nc.dimensions["maxEdges"]))
                for name, var in nc.variables.items():
                    mine = mesh.mpas_variable(name, base=1)
                    theirs = var[:].data
                    self.assertEqual(mine.shape, theirs.shape, name)
                    numpy.testing.assert_array_equal(mine, theirs, err_msg=name)
            ocean, land = mesh.mpas_variable("cellOceanMask"), mesh.mpas_variable("cellLandMask")
            numpy.testing.assert_array_equal(ocean + land, 1)
            cells_on_edge = mesh.mpas_variable("cellsOnEdge")  # base 0
            self.assertEqual(cells_on_edge.min(), 0)
            self.assertEqual(cells_on_edge.max(), dims.n_cells - 1)
            with self.assertRaises(UnimeshError) as caught:
                mesh.mpas_variable("noSuchVariable")
            self.assertIn("noSuchVariable", str(caught.exception))
            mesh.release_mpas()
            # netCDF-4 on request: the same values in the other container.
            hdf = os.path.join(tmp, "mesh4.nc")
            mesh.write_mpas(hdf, format=MpasFile.NETCDF4)
            with netCDF4.Dataset(path) as nc, netCDF4.Dataset(hdf) as nc4:
                self.assertEqual(nc4.data_model, "NETCDF4")
                for name, var in nc.variables.items():
                    numpy.testing.assert_array_equal(var[:].data, nc4[name][:].data, err_msg=name)
            with self.assertRaises(UnimeshError) as caught:
                mesh.write_mpas(hdf, format=7)
            self.assertIn("format = 7", str(caught.exception))

    def test_components_and_river_report(self):
        gamma = Features(self.ctx)
        gamma.add(*ring(), closed=True, kind=FeatureKind.COASTLINE)
        with Mesh.refine(self.ctx, Spacing.constant(self.ctx, 600.0), gamma) as mesh, \
                tempfile.TemporaryDirectory() as tmp:
            mesh.write_components(tmp)
            names = ("mesh.nc", "ocean.nc", "land.nc", "ocean.graph.info", "land.graph.info",
                     "mesh.scrip.nc", "ocean.scrip.nc", "land.scrip.nc", "mesh.esmf.nc",
                     "ocean.esmf.nc", "land.esmf.nc", "rivers.json")
            for name in names:
                self.assertGreater(os.path.getsize(os.path.join(tmp, name)), 0, name)
            report = json.loads(mesh.river_report_json())
            self.assertEqual(report["river_cells"], 0)
            again = os.path.join(tmp, "again")
            os.mkdir(again)
            self.ctx.write_components(os.path.join(tmp, "mesh.nc"), again)
            for name in names:
                self.assertEqual(Path(tmp, name).read_bytes(), Path(again, name).read_bytes(), name)
            with self.assertRaises(UnimeshError) as caught:
                mesh.write_components(os.path.join(tmp, "no", "such", "directory"))
            self.assertEqual(caught.exception.status, Status.ERR_IO)

    def test_mesh_keeps_a_callback_spacing_alive(self):
        spacing = Spacing.callback(self.ctx, lambda lon, lat: COARSE_KM)
        mesh = Mesh.refine(self.ctx, spacing)
        spacing.close()
        del spacing
        gc.collect()
        # Quality reads the spacing again, through the Python function.
        summary = mesh.quality_summary("edge_spacing_ratio")
        self.assertGreater(summary.min, 0)
        self.assertLessEqual(summary.min, summary.mean)
        self.assertIn("edge_spacing_ratio", mesh.quality_json())
        mesh.close()

    def test_bad_spacing_value_fails_refine(self):
        with self.assertRaises(ValueError):
            Mesh.refine(self.ctx, Spacing.callback(self.ctx, self.raise_value_error))
        self.assertEqual(self.ctx.last_error, "")
        with self.assertRaises(UnimeshError) as caught:
            Mesh.refine(self.ctx, Spacing.callback(self.ctx, lambda lon, lat: float("nan")))
        self.assertEqual(caught.exception.status, Status.ERR_NONFINITE_INPUT)

    @staticmethod
    def raise_value_error(_lon, _lat):
        raise ValueError("no spacing here")


if __name__ == "__main__":
    unittest.main()
