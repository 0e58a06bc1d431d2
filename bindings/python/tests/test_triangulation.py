"""Tests of unimesh.Triangulation (plain unittest; needs numpy).

    UNIMESH_LIBRARY=build/lib/libunimesh.so /usr/bin/python3 -m unittest -v \
        bindings/python/tests/test_triangulation.py

The results are checked against what holds for any triangulation of the
sphere and against independent brute-force numpy tests of the defining
property -- the triangulation is the convex hull of the lifted points
x_i / (1 - w_i / 2), so no lifted point lies beyond the plane of any
triangle -- not against stored answers.
"""

import gc
import sys
import unittest
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parents[1] / "python"))  # the package, when run without PYTHONPATH

import unimesh  # noqa: E402  (path set just above)
from unimesh import Status, Triangulation, UnimeshError, _capi  # noqa: E402

try:
    import numpy
except ImportError:  # pragma: no cover - depends on the installation
    numpy = None


# ------------------------------------------------------------------ points

def fibonacci(n):
    """n points of a Fibonacci sphere: (lon_deg, lat_deg)."""
    i = numpy.arange(n)
    lat = numpy.degrees(numpy.arcsin(1 - 2 * (i + 0.5) / n))
    golden_angle = 360 * (1 - 2 / (1 + 5 ** 0.5))
    lon = numpy.mod(i * golden_angle, 360.0) - 180
    return lon, lat


def unit_vectors(lon_deg, lat_deg):
    lon, lat = numpy.radians(lon_deg), numpy.radians(lat_deg)
    return numpy.stack([numpy.cos(lat) * numpy.cos(lon), numpy.cos(lat) * numpy.sin(lon),
                        numpy.sin(lat)], axis=1)


def random_points(n, seed):
    """n random unit vectors (uniform on the sphere)."""
    points = numpy.random.default_rng(seed).normal(size=(n, 3))
    return points / numpy.linalg.norm(points, axis=1, keepdims=True)


def octahedron():
    return (numpy.array([0.0, 90, 180, -90, 0, 0]), numpy.array([0.0, 0, 0, 0, 90, -90]))


def canonical(triangles):
    """The set of triangles, each rotated to start at its smallest index
    (orientation kept): equal for the same triangulation in any order."""
    rows = [tuple(numpy.roll(t, -int(numpy.argmin(t)))) for t in triangles]
    return set(rows)


def lifted(points, weights=None):
    if weights is None:
        return points
    return points / (1 - numpy.asarray(weights) / 2)[:, None]


def facet_heights(triangles, lifted_points):
    """For every triangle (rows) and every point (columns): the height of
    the lifted point above the plane of the triangle's lifted vertices, along
    the plane's unit outward normal; -inf where the point is a vertex of the
    triangle. Also returns the normals."""
    a, b, c = (lifted_points[triangles[:, k]] for k in range(3))
    normals = numpy.cross(b - a, c - a)
    normals /= numpy.linalg.norm(normals, axis=1, keepdims=True)
    heights = normals @ lifted_points.T - numpy.sum(normals * a, axis=1)[:, None]
    rows = numpy.repeat(numpy.arange(len(triangles)), 3)
    heights[rows, triangles.ravel()] = -numpy.inf
    return heights, normals


@unittest.skipIf(numpy is None, "numpy is not installed")
class TriangulationCase(unittest.TestCase):
    def setUp(self):
        self.ctx = unimesh.Context()
        self.addCleanup(self.ctx.close)

    def triangulate(self, *args, **kwargs):
        tri = Triangulation(self.ctx, *args, **kwargs)
        self.addCleanup(tri.close)
        return tri

    def assert_triangulation_invariants(self, tri, n_points):
        """What holds for any triangulation of the sphere: counts, shapes and
        dtypes, 0-based indices in range, the vertices being exactly the
        points not hidden, each directed edge once and its reverse once,
        neighbour k across the edge opposite vertex k and pointing back,
        orthocentres of unit length, the library's own check."""
        counts = tri.counts()
        self.assertIsInstance(counts, unimesh.TriangulationCounts)
        self.assertEqual(counts.n_vertices + counts.n_hidden, n_points)
        self.assertEqual(counts.n_triangles, 2 * counts.n_vertices - 4, "Euler")

        triangles, neighbours = tri.triangles(), tri.neighbours()
        centres, hidden = tri.orthocentres(), tri.hidden()
        n_tri = counts.n_triangles
        for array, dtype, shape in ((triangles, numpy.int32, (n_tri, 3)),
                                    (neighbours, numpy.int32, (n_tri, 3)),
                                    (centres, numpy.float64, (n_tri, 3)),
                                    (hidden, numpy.int32, (counts.n_hidden,))):
            self.assertEqual((array.dtype, array.shape), (dtype, shape))
            self.assertTrue(array.flags.c_contiguous)
        self.assertTrue(((triangles >= 0) & (triangles < n_points)).all())
        self.assertTrue(((neighbours >= 0) & (neighbours < n_tri)).all())

        used = numpy.zeros(n_points, bool)
        used[triangles.ravel()] = True
        numpy.testing.assert_array_equal(numpy.flatnonzero(~used), hidden)
        self.assertTrue((numpy.diff(hidden) > 0).all(), "hidden ascending")

        # Directed edges (t[k+1], t[k+2]) opposite vertex k: each once, and
        # the neighbour holds it reversed.
        edges = {}
        for t, row in enumerate(triangles):
            for k in range(3):
                edge = (row[(k + 1) % 3], row[(k + 2) % 3])
                self.assertNotIn(edge, edges, "a directed edge twice")
                edges[edge] = (t, k)
        for (a, b), (t, k) in edges.items():
            self.assertIn((b, a), edges, "an edge without its reverse")
            other, m = edges[(b, a)]
            self.assertEqual(neighbours[t, k], other)
            self.assertEqual(neighbours[other, m], t)

        numpy.testing.assert_allclose(numpy.linalg.norm(centres, axis=1), 1.0, rtol=0,
                                      atol=1e-12)
        self.assertIsNone(tri.check())
        return triangles

    def assert_regular(self, tri, points, weights=None):
        """The brute-force test: no lifted point (hidden ones included) lies
        beyond the plane of any triangle, every triangle faces outwards
        (counter-clockwise seen from outside), and each orthocentre is the
        unit outward normal of its triangle's plane -- the power vertex.
        Tolerances cover this test's own rounding only."""
        q = lifted(points, weights)
        triangles = tri.triangles()
        heights, normals = facet_heights(triangles, q)
        self.assertLess(heights.max(), 1e-13, "a point beyond a triangle's plane")
        offsets = numpy.sum(normals * q[triangles[:, 0]], axis=1)
        self.assertTrue((offsets > 0).all(), "a triangle facing inwards")
        numpy.testing.assert_allclose(tri.orthocentres(), normals, rtol=0, atol=1e-9)


class Octahedron(TriangulationCase):
    def test_six_points_eight_faces(self):
        lon, lat = octahedron()
        tri = self.triangulate(lon, lat)
        self.assertEqual(tri.counts(), (6, 8, 0))
        triangles = self.assert_triangulation_invariants(tri, 6)
        self.assert_regular(tri, unit_vectors(lon, lat))
        # One point of each axis pair per face: +-x (0, 2), +-y (1, 3), +-z (4, 5).
        for pair in ((0, 2), (1, 3), (4, 5)):
            numpy.testing.assert_array_equal(numpy.isin(triangles, pair).sum(axis=1), 1)
        numpy.testing.assert_allclose(abs(tri.orthocentres()), 3 ** -0.5, rtol=0, atol=1e-12)
        self.assertEqual(tri.hidden().shape, (0,))
        self.assertIn("n_triangles=8", repr(tri))

    def test_index_base(self):
        tri = self.triangulate(*octahedron())
        numpy.testing.assert_array_equal(tri.triangles(base=1), tri.triangles() + 1)
        numpy.testing.assert_array_equal(tri.neighbours(1), tri.neighbours(0) + 1)
        for bad in (2, -1, 2 ** 32):
            with self.subTest(base=bad):
                with self.assertRaises(UnimeshError) as caught:
                    tri.triangles(base=bad)
                self.assertEqual(caught.exception.status, Status.ERR_INVALID_ARGUMENT)
                self.assertIn(f"base = {bad}", caught.exception.message)
        with self.assertRaises(TypeError):
            tri.hidden(base=1.0)

    def test_out_arrays_are_filled_in_place(self):
        tri = self.triangulate(*octahedron())
        out = numpy.full((8, 3), -7, dtype=numpy.int32)
        self.assertIs(tri.triangles(out=out), out)
        numpy.testing.assert_array_equal(out, tri.triangles())
        centres = numpy.empty((8, 3))
        self.assertIs(tri.orthocentres(out=centres), centres)
        with self.assertRaises(TypeError):
            tri.neighbours(out=numpy.empty((8, 3), dtype=numpy.int64))
        with self.assertRaises(ValueError):
            tri.triangles(out=numpy.empty((7, 3), dtype=numpy.int32))
        with self.assertRaises(ValueError):
            tri.orthocentres(out=numpy.empty((3, 8)).T)  # right shape, not C-contiguous


class FibonacciSphere(TriangulationCase):
    N = 300

    def test_euler_neighbours_and_orthocentres(self):
        lon, lat = fibonacci(self.N)
        tri = self.triangulate(lon, lat)
        self.assertEqual(tri.counts(), (self.N, 2 * self.N - 4, 0))
        self.assert_triangulation_invariants(tri, self.N)
        self.assert_regular(tri, unit_vectors(lon, lat))

    def test_xyz_gives_the_same_triangles(self):
        lon, lat = fibonacci(self.N)
        from_lonlat = self.triangulate(lon, lat).triangles()
        # Scaled (normalised by the library) and in Fortran order.
        xyz = numpy.asfortranarray(7.5 * unit_vectors(lon, lat))
        self.assertFalse(xyz.flags.c_contiguous)
        tri = self.triangulate(xyz=xyz)
        self.assert_triangulation_invariants(tri, self.N)
        self.assertEqual(canonical(tri.triangles()), canonical(from_lonlat))


class RandomPoints(TriangulationCase):
    """The triangle set against the brute-force hull test, for points with
    no structure at all."""

    def test_delaunay_of_random_points(self):
        points = random_points(300, seed=20240611)
        tri = self.triangulate(xyz=points)
        self.assertEqual(tri.counts(), (300, 596, 0))
        self.assert_triangulation_invariants(tri, 300)
        self.assert_regular(tri, points)

    def test_from_lon_lat_of_random_points(self):
        points = random_points(300, seed=7)
        lon = numpy.degrees(numpy.arctan2(points[:, 1], points[:, 0]))
        lat = numpy.degrees(numpy.arcsin(points[:, 2]))
        tri = self.triangulate(lon, lat)
        self.assert_triangulation_invariants(tri, 300)
        self.assert_regular(tri, unit_vectors(lon, lat))

    def test_regular_triangulation_with_random_weights(self):
        points = random_points(300, seed=11)
        # Of the order of the squared spacing: some points get hidden.
        weights = numpy.random.default_rng(12).uniform(-0.06, 0.02, size=300)
        tri = self.triangulate(xyz=points, weights=weights)
        counts = tri.counts()
        self.assertGreater(counts.n_hidden, 0, "no hidden point: the test tests too little")
        self.assert_triangulation_invariants(tri, 300)
        self.assert_regular(tri, points, weights)

    def test_same_result_for_any_thread_count(self):
        lon, lat = fibonacci(40000)
        weights = 2e-4 * numpy.sin(numpy.arange(40000))
        results = []
        for threads in (1, 2):
            self.ctx.threads = threads
            with Triangulation(self.ctx, lon, lat, weights=weights) as tri:
                results.append((tri.triangles(), tri.neighbours(), tri.orthocentres(),
                                tri.hidden()))
        for one, two in zip(*results):
            numpy.testing.assert_array_equal(one, two)


class Weighted(TriangulationCase):
    SUNK = 7  # 0-based

    def test_a_sunk_point_is_hidden(self):
        # Weight -0.5 lifts the point to 0.8 of the radius, well inside the
        # hull of its neighbours.
        lon, lat = fibonacci(300)
        weights = numpy.zeros(300)
        weights[self.SUNK] = -0.5
        tri = self.triangulate(lon, lat, weights=weights)
        self.assertEqual(tri.counts(), (299, 594, 1))
        numpy.testing.assert_array_equal(tri.hidden(), [self.SUNK])
        numpy.testing.assert_array_equal(tri.hidden(base=1), [self.SUNK + 1])
        self.assertFalse((tri.triangles() == self.SUNK).any())
        self.assert_triangulation_invariants(tri, 300)
        self.assert_regular(tri, unit_vectors(lon, lat), weights)

    def test_zero_weights_are_delaunay(self):
        lon, lat = fibonacci(300)
        plain = self.triangulate(lon, lat).triangles()
        weighted = self.triangulate(lon, lat, weights=numpy.zeros(300)).triangles()
        numpy.testing.assert_array_equal(weighted, plain)


class Inputs(TriangulationCase):
    """Conversions that represent the same values; refusals of the rest."""

    def test_float32_is_converted(self):
        lon, lat = fibonacci(300)
        lon32, lat32 = lon.astype(numpy.float32), lat.astype(numpy.float32)
        tri = self.triangulate(lon32, lat32)
        same = self.triangulate(lon32.astype(numpy.float64), lat32.astype(numpy.float64))
        numpy.testing.assert_array_equal(tri.triangles(), same.triangles())
        xyz32 = unit_vectors(lon, lat).astype(numpy.float32)
        numpy.testing.assert_array_equal(
            self.triangulate(xyz=xyz32).triangles(),
            self.triangulate(xyz=xyz32.astype(numpy.float64)).triangles())

    def test_non_contiguous_views_are_converted(self):
        lon, lat = fibonacci(300)
        wide = numpy.zeros((2, 600))
        wide[0, ::2], wide[1, ::2] = lon, lat
        lon_view, lat_view = wide[0, ::2], wide[1, ::2]
        self.assertFalse(lon_view.flags.c_contiguous)
        weights = numpy.zeros(600)
        weights[1::2] = 1.0  # must not be read
        weights[2 * Weighted.SUNK] = -0.5
        tri = self.triangulate(lon_view, lat_view, weights=weights[::2])
        numpy.testing.assert_array_equal(tri.hidden(), [Weighted.SUNK])
        plain = self.triangulate(lon, lat)
        numpy.testing.assert_array_equal(self.triangulate(lon_view, lat_view).triangles(),
                                         plain.triangles())
        # A transposed (3, n) array seen as (n, 3): not C-contiguous.
        xyz = numpy.ascontiguousarray(unit_vectors(lon, lat).T).T
        self.assertFalse(xyz.flags.c_contiguous)
        self.assertEqual(canonical(self.triangulate(xyz=xyz).triangles()),
                         canonical(plain.triangles()))

    def test_lists_integers_and_other_byte_orders(self):
        lon, lat = octahedron()
        tri = self.triangulate([int(x) for x in lon], list(lat))
        self.assertEqual(tri.counts(), (6, 8, 0))
        swapped = self.triangulate(lon.astype(">f8"), lat.astype(">f8"))
        numpy.testing.assert_array_equal(swapped.triangles(), tri.triangles())

    def test_values_that_would_change_are_refused(self):
        lon, lat = octahedron()
        for bad, name in ((lon + 0j, "lon_deg"), (lat.astype(str), "lat_deg"),
                          (numpy.array([True] * 6), "lon_deg"),
                          (numpy.array([None] * 6), "lat_deg")):
            with self.subTest(dtype=bad.dtype):
                args = (bad, lat) if name == "lon_deg" else (lon, bad)
                with self.assertRaisesRegex(TypeError, f"{name} must hold real numbers"):
                    Triangulation(self.ctx, *args)
        with self.assertRaisesRegex(TypeError, "weights must hold real numbers"):
            Triangulation(self.ctx, lon, lat, weights=numpy.zeros(6, complex))

    def test_wrong_shapes_are_refused(self):
        lon, lat = fibonacci(20)
        xyz = unit_vectors(lon, lat)
        cases = (
            ((lon, lat[:19]), {}, "lat_deg has 19 elements and lon_deg 20"),
            ((lon.reshape(4, 5), lat), {}, r"lon_deg must have shape \(n\)"),
            ((lon, 10.0), {}, r"lat_deg must have shape \(n\)"),
            ((), {"xyz": xyz.T}, r"xyz must have shape \(n, 3\), not \(3, 20\)"),
            ((), {"xyz": xyz.ravel()}, r"xyz must have shape \(n, 3\)"),
            ((lon, lat), {"weights": numpy.zeros(19)}, r"weights must have shape \(20\)"),
            ((), {"xyz": xyz, "weights": numpy.zeros((20, 1))}, r"weights must have shape"),
        )
        for args, kwargs, message in cases:
            with self.subTest(message=message):
                with self.assertRaisesRegex(ValueError, message):
                    Triangulation(self.ctx, *args, **kwargs)

    def test_point_arguments_are_one_form_or_the_other(self):
        lon, lat = fibonacci(20)
        with self.assertRaisesRegex(TypeError, "lon_deg and lat_deg, or xyz"):
            Triangulation(self.ctx)
        with self.assertRaisesRegex(TypeError, "lon_deg and lat_deg, or xyz"):
            Triangulation(self.ctx, lon)
        with self.assertRaisesRegex(TypeError, "not both"):
            Triangulation(self.ctx, lon, lat, xyz=unit_vectors(lon, lat))


class Errors(TriangulationCase):
    """Library errors: UnimeshError with the status and the library's
    message, which names the argument, its (0-based) index and the value."""

    def assert_refused(self, status, texts, *args, **kwargs):
        with self.assertRaises(UnimeshError) as caught:
            Triangulation(self.ctx, *args, **kwargs)
        self.assertEqual(caught.exception.status, status)
        for text in texts:
            self.assertIn(text, caught.exception.message)
        # The message moved into the exception: the context holds none.
        self.assertEqual(self.ctx.last_error, "")
        return caught.exception

    def test_nan_latitude(self):
        lon, lat = fibonacci(12)
        lat[4] = numpy.nan
        error = self.assert_refused(Status.ERR_NONFINITE_INPUT, ["lat_deg[4]", "nan"], lon, lat)
        self.assertIn("lat_deg[4]", str(error))

    def test_bad_coordinates_and_weights(self):
        lon, lat = fibonacci(12)
        lat[2] = 90.5
        self.assert_refused(Status.ERR_COORDINATE_RANGE, ["lat_deg[2] = 90.5"], lon, lat)
        lon, lat = fibonacci(12)
        lon[3] = numpy.inf
        self.assert_refused(Status.ERR_NONFINITE_INPUT, ["lon_deg[3]"], lon, lat)
        weights = numpy.zeros(12)
        weights[6] = 2.0
        self.assert_refused(Status.ERR_INVALID_ARGUMENT, ["weights[6]"], *fibonacci(12),
                            weights=weights)
        weights[6] = numpy.nan
        self.assert_refused(Status.ERR_NONFINITE_INPUT, ["weights[6]"], *fibonacci(12),
                            weights=weights)
        xyz = unit_vectors(*fibonacci(12))
        xyz[5] = 0
        self.assert_refused(Status.ERR_INVALID_ARGUMENT, ["point 5"], xyz=xyz)
        xyz[5] = [0, numpy.nan, 1]
        self.assert_refused(Status.ERR_NONFINITE_INPUT, ["xyz[16]", "point 5"], xyz=xyz)

    def test_degenerate_point_sets(self):
        lon, lat = fibonacci(12)
        lon[9], lat[9] = lon[2], lat[2]
        error = self.assert_refused(Status.ERR_DUPLICATE_POINTS, [], lon, lat)
        self.assertRegex(error.message, r"\b2\b")
        self.assertRegex(error.message, r"\b9\b")
        self.assert_refused(Status.ERR_TOO_FEW_POINTS, ["n = 3"], lon[:3], lat[:3])
        self.assert_refused(Status.ERR_TOO_FEW_POINTS, ["n = 0"], [], [])
        self.assert_refused(Status.ERR_DEGENERATE_INPUT, [], [0, 90, 180, -90, 45],
                            [10, 20, 30, 40, 80])

    def test_each_error_carries_its_own_message(self):
        lon, lat = fibonacci(12)
        lat[4] = numpy.nan
        self.assert_refused(Status.ERR_NONFINITE_INPUT, ["lat_deg[4]"], lon, lat)
        lat[4] = 0
        lat[8] = -95
        error = self.assert_refused(Status.ERR_COORDINATE_RANGE, ["lat_deg[8]"], lon, lat)
        self.assertNotIn("lat_deg[4]", error.message)


class Lifetime(TriangulationCase):
    def test_close_and_with(self):
        with Triangulation(self.ctx, *octahedron()) as tri:
            self.assertFalse(tri.closed)
        self.assertTrue(tri.closed)
        tri.close()  # twice is fine
        self.assertIn("closed", repr(tri))
        for method in (tri.counts, tri.triangles, tri.neighbours, tri.orthocentres,
                       tri.hidden, tri.check):
            with self.subTest(method=method.__name__):
                with self.assertRaises(UnimeshError) as caught:
                    method()
                self.assertEqual(caught.exception.status, Status.ERR_INVALID_HANDLE)

    def test_outlives_its_context(self):
        ctx = unimesh.Context()
        tri = Triangulation(ctx, *fibonacci(50))
        ctx.close()
        self.assertEqual(tri.counts(), (50, 96, 0))
        self.assert_triangulation_invariants(tri, 50)
        with self.assertRaises(UnimeshError) as caught:
            tri.triangles(base=3)
        self.assertEqual(caught.exception.status, Status.ERR_INVALID_ARGUMENT)
        tri.close()
        with self.assertRaises(UnimeshError):
            Triangulation(ctx, *fibonacci(50))  # a closed context

    def test_garbage_collection_closes(self):
        tri = Triangulation(self.ctx, *octahedron())
        handle = tri._handle
        del tri
        gc.collect()
        status = _capi.C.um_triangulation_counts(handle, None, None, None)
        self.assertEqual(status, Status.ERR_INVALID_HANDLE)


if __name__ == "__main__":
    unittest.main()
