"""Python binding of libunimesh (ctypes; numpy for array arguments).

    import unimesh

    with unimesh.Context(threads=4) as ctx:
        with unimesh.Options(ctx, refine_alpha=1.3, optim_outer_iterations=8) as opts:
            opts["refine_rho"] = 1.1
            print(opts["refine_alpha"], opts.get(unimesh.Option.OPTIM_WEIGHTS))
        with unimesh.Triangulation(ctx, lon_deg, lat_deg) as tri:  # numpy arrays
            triangles = tri.triangles()  # (n_triangles, 3) int32, input indices

Every failure raises UnimeshError(status, message). The message is the one
the context recorded (it names the argument and the value); it is moved into
the exception, i.e. the context's kept error is cleared, so every exception
carries its own message rather than the first one of the context's life.

The library is found through $UNIMESH_LIBRARY, else next to this package or in
the source tree's build/lib, else where the loader finds libunimesh.so.0 (an
installed prefix; see _capi.py). `pip install bindings/python` installs it.
Objects are released by close() or a with-block; garbage collection closes
them as a last resort.
"""

import enum
import operator
import os
import weakref
from collections import namedtuple
from ctypes import byref, c_double, c_int32, c_int64, c_void_p, create_string_buffer

from . import _arrays
from ._capi import C, LOG_FN, PROGRESS_FN, SPACING_FN, library_path, missing_functions

__all__ = [
    "VERSION_MAJOR", "VERSION_MINOR", "VERSION_PATCH", "VERSION_NUMBER", "VERSION_STRING",
    "Status", "Option", "OptionType", "FeatureKind", "Side", "LogLevel", "ErrorMode", "OptionInfo", "UnimeshError",
    "Context", "Options", "Triangulation", "TriangulationCounts", "Features", "FeaturesCounts",
    "FeatureParts", "Spacing", "Mesh", "MeshCounts", "QualitySummary", "QualityCounts", "MeshEstimate", "MpasType", "MpasFile", "MpasDimensions",
    "version", "version_number",
    "version_string", "status_string", "status_class", "option_info", "option_name",
    "option_key", "library_path", "missing_functions",
]

# ----------------------------------------------------------------- constants
# Transcribed from include/unimesh.h; the tests compare them with it.

VERSION_MAJOR = 0
VERSION_MINOR = 1
VERSION_PATCH = 0
VERSION_NUMBER = VERSION_MAJOR * 10000 + VERSION_MINOR * 100 + VERSION_PATCH
VERSION_STRING = "0.1.0"
__version__ = VERSION_STRING


class Status(enum.IntEnum):
    """um_status: 0 ok; bands 100 usage, 200 input data, 300 numerical,
    400 resources, 500 I/O, 600 interrupted, 900 internal."""
    OK = 0
    ERR_USAGE = 100
    ERR_NULL_ARGUMENT = 101
    ERR_INVALID_HANDLE = 102
    ERR_INVALID_ARGUMENT = 103
    ERR_UNKNOWN_OPTION = 104
    ERR_OPTION_TYPE = 105
    ERR_BUFFER_TOO_SMALL = 106
    ERR_WRONG_ORDER = 107
    ERR_INPUT = 200
    ERR_NONFINITE_INPUT = 201
    ERR_COORDINATE_RANGE = 202
    ERR_DUPLICATE_POINTS = 203
    ERR_TOO_FEW_POINTS = 204
    ERR_DEGENERATE_INPUT = 205
    ERR_NUMERICAL = 300
    ERR_OUT_OF_MEMORY = 400
    ERR_MEMORY_CAP = 401
    ERR_LIMIT = 402
    ERR_IO = 500
    ERR_FILE_FORMAT = 501
    CANCELLED = 600
    ERR_INTERNAL = 900


class Option(enum.IntEnum):
    """um_option keys (UM_OPT_*)."""
    SPHERE_RADIUS = 1
    SURFACE_FLATTENING = 2
    REFINE_ALPHA = 100
    REFINE_BETA = 101
    REFINE_RHO = 102
    REFINE_TOPOLOGY_CHECK = 103
    REFINE_RELAX = 104
    REFINE_LATTICE = 105
    SPACING_GRADIENT = 106
    OPTIM_OUTER_ITERATIONS = 200
    OPTIM_INNER_ITERATIONS = 201
    OPTIM_TOLERANCE = 202
    OPTIM_WEIGHTS = 203
    OPTIM_FIX_BOUNDARY = 204
    OPTIM_COLLAPSE_RATIO = 205
    OPTIM_SPLIT_RATIO = 206
    OPTIM_CORNER_VERTICES = 207
    OPTIM_CENTROIDAL_SWEEPS = 208
    OPTIM_RESEED_ROUNDS = 209
    OCEAN_FLOOR = 300


class OptionType(enum.IntEnum):
    INT = 1
    REAL = 2


class FeatureKind(enum.IntEnum):
    """Kinds of features parts (UM_FEATURE_*)."""
    COASTLINE = 1
    LAKE = 2
    RIVER = 3
    WATERSHED = 4
    OTHER = 5
    PASSAGE = 6  # not Gamma: a line or point where the ocean mesh is kept open
    DOMAIN = 7  # a closed ring bounding a regional mesh


class Side(enum.IntEnum):
    """Sides of the closed coastlines (UM_SIDE_*); COASTAL for vertices only."""
    OCEAN = 0
    LAND = 1
    COASTAL = 2


class MpasType(enum.IntEnum):
    """Value types of the MPAS variables (UM_MPAS_*)."""
    REAL = 1
    INT = 2


MPAS_REAL = MpasType.REAL


class MpasFile(enum.IntEnum):
    """Containers of the MPAS mesh file (UM_MPAS_FILE_*)."""
    AUTO = 0
    NETCDF4 = 1


class LogLevel(enum.IntEnum):
    DEBUG = 10
    INFO = 20
    WARNING = 30
    ERROR = 40


class ErrorMode(enum.IntEnum):
    """Kept for completeness: this binding reports errors by exceptions, so
    it never switches a context to ABORT mode."""
    RETURN = 0
    ABORT = 1


OptionInfo = namedtuple("OptionInfo", "type min max default")
TriangulationCounts = namedtuple("TriangulationCounts", "n_vertices n_triangles n_hidden")
FeaturesCounts = namedtuple("FeaturesCounts", "n_parts n_points n_segments")
FeatureParts = namedtuple("FeatureParts", "offsets closed kind part_id")
MeshCounts = namedtuple("MeshCounts", "n_vertices n_triangles n_restricted_edges n_filtered")
QualitySummary = namedtuple("QualitySummary", "min p1 mean max")
QualityCounts = namedtuple("QualityCounts", "obtuse not_well_centred")
MeshEstimate = namedtuple("MeshEstimate", "cells refine_bytes mpas_bytes")
MpasDimensions = namedtuple("MpasDimensions", "n_cells n_edges n_vertices max_edges")


def _enum_or_int(enum_type, value):
    """A member when the value is known, else the plain int (a newer library
    may return values this binding predates)."""
    try:
        return enum_type(value)
    except ValueError:
        return int(value)


def _text(raw):
    return raw.decode("utf-8", "replace") if raw else ""


# -------------------------------------------------------------------- errors

class UnimeshError(Exception):
    """A failed libunimesh call: .status (a Status when known) and .message."""

    def __init__(self, status, message):
        super().__init__(status, message)  # args as given, so the error pickles
        self.status = _enum_or_int(Status, status)
        self.message = message

    @property
    def status_class(self):
        """The band: 0, 100, 200, ..., 900."""
        return status_class(self.status)

    def __str__(self):
        name = self.status.name if isinstance(self.status, Status) else "status"
        return f"{self.message} [{name} = {int(self.status)}]"


def _raise_for(status, context=None, what=None):
    """Raises UnimeshError unless status is UM_OK. The message is the one
    `context` recorded for this status (taken out of it), else the status
    text prefixed by `what` (calls without a context have nowhere to keep a
    message)."""
    if status == Status.OK:
        return
    message = context._take_error(status) if context is not None else ""
    if not message:
        message = status_string(status)
        if what:
            message = f"{what}: {message}"
    raise UnimeshError(status, message)


def _copy_out(function, *leading, what, context=None):
    """A string from a C function with the (buf, capacity, needed) protocol:
    ask for the length, then copy into a buffer of exactly that size."""
    needed = c_int64(0)
    status = function(*leading, None, 0, byref(needed))
    if status not in (Status.OK, Status.ERR_BUFFER_TOO_SMALL):
        _raise_for(status, context, what)
    buffer = create_string_buffer(max(needed.value, 1))
    _raise_for(function(*leading, buffer, len(buffer), byref(needed)), context, what)
    return _text(buffer.value)


# ---------------------------------------------------------- version, status

def version():
    """(major, minor, patch) of the loaded library."""
    parts = c_int32(), c_int32(), c_int32()
    C.um_version(*(byref(p) for p in parts))
    return tuple(p.value for p in parts)


def version_number():
    """MAJOR*10000 + MINOR*100 + PATCH of the loaded library."""
    return C.um_version_number()


def version_string():
    return _text(C.um_version_string())


def status_string(status):
    """A short description of a status ("unknown status" if not one)."""
    return _text(C.um_status_string(int(status)))


def status_class(status):
    """The band of a status: 0, 100, 200, ..., 900."""
    return C.um_status_class(int(status))


# The signatures of a library with another major version may differ from the
# table: refuse it rather than call it wrongly.
if version()[0] != VERSION_MAJOR:
    raise ImportError(f"unimesh: {library_path} is version {version_string()}, this binding "
                      f"needs major version {VERSION_MAJOR}")


# ------------------------------------------------------------- option table

def option_key(name):
    """The Option of a name as used in "name=value" strings."""
    key = c_int32(0)
    _raise_for(C.um_option_key(str(name).encode(), byref(key)), what=f"option_key({name!r})")
    return _enum_or_int(Option, key.value)


def _key(key):
    """An option key from an Option, an int or a name."""
    return option_key(key) if isinstance(key, str) else _enum_or_int(Option, operator.index(key))


def option_name(key):
    """The name of an option key, as used in "name=value" strings."""
    key = _key(key)
    return _copy_out(C.um_option_name, int(key), what=f"option_name({key!r})")


def option_info(key):
    """OptionInfo(type, min, max, default) of an option; bounds are inclusive."""
    key = _key(key)
    kind, low, high, default = c_int32(), c_double(), c_double(), c_double()
    _raise_for(C.um_option_info(int(key), byref(kind), byref(low), byref(high), byref(default)),
               what=f"option_info({key!r})")
    kind = _enum_or_int(OptionType, kind.value)
    if kind == OptionType.INT:
        return OptionInfo(kind, int(low.value), int(high.value), int(default.value))
    return OptionInfo(kind, low.value, high.value, default.value)


# ------------------------------------------------------------------ handles

class _Handle:
    """What every wrapped object shares: the C pointer, close() with its
    destroy function, the with-statement, and a closed check."""

    _destroy = None  # the C destroy function, set by each subclass
    _ptr = None

    @property
    def closed(self):
        return self._ptr is None

    @property
    def _handle(self):
        if self._ptr is None:
            raise UnimeshError(Status.ERR_INVALID_HANDLE, f"the {type(self).__name__} is closed")
        return self._ptr

    def close(self):
        """Destroys the C object; closing twice is fine."""
        ptr, self._ptr = self._ptr, None
        if ptr is not None:
            type(self)._destroy(ptr)

    def __enter__(self):
        return self

    def __exit__(self, *exc_info):
        self.close()

    def __del__(self):
        # Last resort only: at interpreter exit the module may be half gone.
        try:
            self.close()
        except Exception:
            pass


class Context(_Handle):
    """A um_context: thread count, memory cap, error state and callbacks.

    One thread at a time may use a context and the objects made from it.
    """

    _destroy = staticmethod(C.um_context_destroy)

    def __init__(self, threads=None, memory_cap=None):
        # Callback objects must live as long as C may call them.
        self._callbacks = {}
        self._callback_error = None
        ptr = c_void_p()
        _raise_for(C.um_context_create(byref(ptr)), what="um_context_create")
        self._ptr = ptr.value
        try:
            if threads is not None:
                self.threads = threads
            if memory_cap is not None:
                self.memory_cap = memory_cap
        except BaseException:
            self.close()
            raise

    def close(self):
        super().close()
        self._callbacks.clear()

    def _check(self, status, what=None):
        """Raises for a failed call on this context; an exception raised by a
        Python callback during the call wins, being the real cause."""
        pending, self._callback_error = self._callback_error, None
        if pending is not None:
            if status != Status.OK:
                self._take_error(status)  # the C side only saw a cancellation
            raise pending
        _raise_for(status, self, what)

    def _take_error(self, status):
        """The kept message if it belongs to `status`, then cleared ("" if the
        context is closed or holds an older error of another status)."""
        if self._ptr is None or C.um_context_last_status(self._ptr) != int(status):
            return ""
        message = self.last_error
        C.um_context_clear_error(self._ptr)
        return message

    @property
    def threads(self):
        """Threads for parallel work; setting 0 means all cores (reading gives
        the resolved count)."""
        n = c_int32(0)
        self._check(C.um_context_get_threads(self._handle, byref(n)))
        return n.value

    @threads.setter
    def threads(self, n):
        self._check(C.um_context_set_threads(self._handle, operator.index(n)))

    @property
    def memory_cap(self):
        """Cap in bytes on the large allocations of this context's work (0 = none)."""
        cap = c_int64(0)
        self._check(C.um_context_get_memory_cap(self._handle, byref(cap)))
        return cap.value

    @memory_cap.setter
    def memory_cap(self, n_bytes):
        self._check(C.um_context_set_memory_cap(self._handle, operator.index(n_bytes)))

    def set_worker_placement(self, on):
        """Keep oneTBB's workers off the calling thread's CPU during this
        context's parallel calls (it changes their affinity masks; off by
        default)."""
        self._check(C.um_context_set_worker_placement(self._handle, 1 if on else 0))

    @property
    def last_error(self):
        """The kept error message ("" when none). Failed calls made through
        this binding raise and clear it; it is only set by raw C calls."""
        return _copy_out(C.um_context_copy_last_error, self._handle,
                         what="um_context_copy_last_error")

    @property
    def last_status(self):
        return _enum_or_int(Status, C.um_context_last_status(self._handle))

    def clear_error(self):
        self._check(C.um_context_clear_error(self._handle))

    def write_components(self, mesh_path, directory):
        """The component meshes and coupler grids of an MPAS mesh file with
        the ocean and land cell masks, written into an existing directory
        (see um_mpas_file_write_components and Mesh.write_components)."""
        self._check(C.um_mpas_file_write_components(self._handle, os.fsencode(mesh_path), os.fsencode(directory)))

    def set_log(self, callback, min_level=LogLevel.WARNING):
        """callback(level: LogLevel, message: str) for messages at min_level
        or above, called on this thread; None removes it. An exception in the
        callback is raised by the call that logged."""
        c_function = LOG_FN()  # NULL: ctypes wants a function-pointer instance, not None
        if callback is not None:
            owner = weakref.ref(self)  # no cycle through the callback

            def trampoline(_user_data, level, message):
                try:
                    callback(_enum_or_int(LogLevel, level), _text(message))
                except BaseException as error:  # must not unwind through C
                    _record_callback_error(owner, error)
            c_function = LOG_FN(trampoline)
        self._check(C.um_context_set_log(self._handle, c_function, None, int(min_level)))
        self._callbacks["log"] = c_function

    def set_progress(self, callback):
        """callback(stage: str, fraction: float) during long calls; a true
        return value cancels the call (it raises UnimeshError CANCELLED).
        An exception in the callback cancels too, and is what the call raises.
        None removes it."""
        c_function = PROGRESS_FN()  # NULL
        if callback is not None:
            owner = weakref.ref(self)

            def trampoline(_user_data, stage, fraction):
                try:
                    return 1 if callback(_text(stage), fraction) else 0
                except BaseException as error:
                    _record_callback_error(owner, error)
                    return 1
            c_function = PROGRESS_FN(trampoline)
        self._check(C.um_context_set_progress(self._handle, c_function, None))
        self._callbacks["progress"] = c_function

    def __repr__(self):
        return "<unimesh.Context closed>" if self.closed else \
            f"<unimesh.Context threads={self.threads}>"


def _record_callback_error(owner, error):
    context = owner()
    if context is not None and context._callback_error is None:
        context._callback_error = error


class Options(_Handle):
    """A um_options object: typed, bounds-checked settings.

        opts = Options(ctx, "refine_alpha=1.3", optim_outer_iterations=8)
        opts["refine_rho"] = 1.1          # by name
        opts.set(Option.OPTIM_WEIGHTS, 0)  # or by key
        opts.get("refine_alpha")          # int or float by the option's type

    Keyword and string settings are all-or-nothing. The options stay usable
    after their context is closed (errors then carry only the status text).
    """

    _destroy = staticmethod(C.um_options_destroy)

    def __init__(self, context, assignments=None, **values):
        self._context = context
        ptr = c_void_p()
        context._check(C.um_options_create(context._handle, byref(ptr)))
        self._ptr = ptr.value
        try:
            if assignments:
                self.set_string(assignments)
            if values:
                self.update(values)
        except BaseException:
            self.close()
            raise

    def _check(self, status):
        self._context._check(status)

    # Typed access, as in C.
    def set_double(self, key, value):
        self._check(C.um_options_set_double(self._handle, int(_key(key)), float(value)))

    def set_int(self, key, value):
        self._check(C.um_options_set_int(self._handle, int(_key(key)), operator.index(value)))

    def get_double(self, key):
        value = c_double(0)
        self._check(C.um_options_get_double(self._handle, int(_key(key)), byref(value)))
        return value.value

    def get_int(self, key):
        value = c_int64(0)
        self._check(C.um_options_get_int(self._handle, int(_key(key)), byref(value)))
        return value.value

    def set_string(self, assignments):
        """Sets options from "name=value;name=value" (all-or-nothing)."""
        self._check(C.um_options_set_string(self._handle, str(assignments).encode()))

    # Access by the option's own type.
    def set(self, key, value):
        key = _key(key)
        if option_info(key).type == OptionType.INT:
            self.set_int(key, value)  # a float is refused, not truncated
        else:
            self.set_double(key, value)

    def get(self, key):
        key = _key(key)
        return self.get_int(key) if option_info(key).type == OptionType.INT \
            else self.get_double(key)

    __setitem__ = set
    __getitem__ = get

    def update(self, values=(), **more):
        """Sets several options by name or key, all-or-nothing (one
        um_options_set_string call)."""
        items = list(dict(values).items()) + list(more.items())
        self.set_string(";".join(f"{_name_of(k)}={_format_value(v)}" for k, v in items))

    def to_dict(self):
        """{name: value} of every option this binding knows."""
        return {option_name(key): self.get(key) for key in Option}

    def __repr__(self):
        return "<unimesh.Options closed>" if self.closed else f"<unimesh.Options {self.to_dict()}>"


class Triangulation(_Handle):
    """The Laguerre (weighted Delaunay) triangulation of points on the unit
    sphere, from longitudes and latitudes in degrees or from vectors:

        tri = Triangulation(ctx, lon_deg, lat_deg)            # 1-D, n each
        tri = Triangulation(ctx, xyz=points, weights=w)       # (n, 3); n weights

    Weights are in units of R^2 (squared chords of the unit sphere), each
    below 2; None means all 0, the Delaunay triangulation. A point whose
    power cell is empty is hidden: it is no vertex and hidden() lists it.
    Inputs may be any arrays of real numbers (lists, float32, strided
    views, Fortran order): they are converted to contiguous float64; complex
    or non-numeric arrays raise TypeError, wrong shapes ValueError.

    Outputs are new numpy arrays (or `out=` arrays filled in place), with
    INPUT point indices plus `base` (0, or 1 for Fortran/MPAS). Library
    errors raise UnimeshError with the library's message, which names the
    argument, its 0-based index and the value ("lat_deg[4] = nan ...").

    The triangulation stays usable after its context is closed (errors
    then carry only the status text).
    """

    _destroy = staticmethod(C.um_triangulation_destroy)

    def __init__(self, context, lon_deg=None, lat_deg=None, *, xyz=None, weights=None):
        self._context = context
        if xyz is None:
            if lon_deg is None or lat_deg is None:
                raise TypeError("Triangulation needs lon_deg and lat_deg, or xyz=")
            lon = _arrays.input_array(lon_deg, c_double, (-1,), "lon_deg")
            lat = _arrays.input_array(lat_deg, c_double, (-1,), "lat_deg")
            if lat.shape != lon.shape:
                raise ValueError(f"lat_deg has {lat.size} elements and lon_deg {lon.size}: "
                                 "they must have one per point")
            n = lon.size
        else:
            if lon_deg is not None or lat_deg is not None:
                raise TypeError("Triangulation takes lon_deg and lat_deg, or xyz=, not both")
            points = _arrays.input_array(xyz, c_double, (-1, 3), "xyz")
            n = points.shape[0]
        w = None if weights is None else _arrays.input_array(weights, c_double, (n,), "weights")
        ptr = c_void_p()
        if xyz is None:
            status = C.um_triangulation_create(context._handle, n, _arrays.pointer(lon, c_double),
                                               _arrays.pointer(lat, c_double),
                                               _arrays.pointer(w, c_double), byref(ptr))
        else:
            status = C.um_triangulation_create_xyz(context._handle, n,
                                                   _arrays.pointer(points, c_double),
                                                   _arrays.pointer(w, c_double), byref(ptr))
        context._check(status)
        self._ptr = ptr.value

    def _check(self, status):
        self._context._check(status)

    def counts(self):
        """TriangulationCounts(n_vertices, n_triangles, n_hidden)."""
        counts = c_int64(0), c_int64(0), c_int64(0)
        self._check(C.um_triangulation_counts(self._handle, *(byref(c) for c in counts)))
        return TriangulationCounts(*(c.value for c in counts))

    def _per_corner(self, function, base, out):
        base = _base(base)
        out = _arrays.output_array(c_int32, (self.counts().n_triangles, 3), out)
        self._check(function(self._handle, base, _arrays.pointer(out, c_int32),
                             _arrays.capacity(out)))
        return out

    def triangles(self, base=0, out=None):
        """(n_triangles, 3) int32: the vertices of each triangle (input point
        indices + base), counter-clockwise seen from outside the sphere."""
        return self._per_corner(C.um_triangulation_copy_triangles, base, out)

    def neighbours(self, base=0, out=None):
        """(n_triangles, 3) int32: neighbours[t, k] is the triangle (+ base)
        across the edge of t opposite its vertex triangles()[t, k]."""
        return self._per_corner(C.um_triangulation_copy_neighbours, base, out)

    def orthocentres(self, out=None):
        """(n_triangles, 3) float64: the orthocentre (power vertex) of each
        triangle, a unit vector."""
        out = _arrays.output_array(c_double, (self.counts().n_triangles, 3), out)
        self._check(C.um_triangulation_copy_orthocentres(
            self._handle, _arrays.pointer(out, c_double), _arrays.capacity(out)))
        return out

    def hidden(self, base=0, out=None):
        """(n_hidden,) int32: the hidden points (input indices + base), ascending."""
        base = _base(base)
        out = _arrays.output_array(c_int32, (self.counts().n_hidden,), out)
        self._check(C.um_triangulation_copy_hidden(self._handle, base,
                                                   _arrays.pointer(out, c_int32),
                                                   _arrays.capacity(out)))
        return out

    def check(self):
        """Re-checks every invariant with exact predicates; raises UnimeshError
        (ERR_INTERNAL, naming the first violation) if one fails."""
        self._check(C.um_triangulation_check(self._handle))

    def __repr__(self):
        if self.closed:
            return "<unimesh.Triangulation closed>"
        counts = self.counts()
        return (f"<unimesh.Triangulation n_vertices={counts.n_vertices} "
                f"n_triangles={counts.n_triangles} n_hidden={counts.n_hidden}>")


class Features(_Handle):
    """A polyarc network (um_features): coastlines, lake shores, rivers and
    watersheds as polylines ("parts") of longitudes/latitudes in degrees.

        gamma = Features(ctx)
        gamma.add(lon, lat, closed=True, kind=FeatureKind.COASTLINE)   # one part
        gamma.add(lon, lat, offsets=[0, 10, 25], closed=[1, 0],
                  kind=FeatureKind.RIVER, part_id=[7, 8])               # two parts
        gamma.read_geojson("coast.geojson", default_kind=FeatureKind.COASTLINE)
        gamma.counts(); gamma.points(); gamma.parts()

    closed, kind and part_id take one value per part or one for all. The
    library cleans what it stores (consecutive duplicates dropped, a repeated
    closing point stored once); points() and parts() give the stored form.
    A failing call adds nothing.
    """

    _destroy = staticmethod(C.um_features_destroy)

    def __init__(self, context):
        self._context = context
        ptr = c_void_p()
        context._check(C.um_features_create(context._handle, byref(ptr)))
        self._ptr = ptr.value

    def _check(self, status):
        self._context._check(status)

    def add(self, lon_deg, lat_deg, offsets=None, closed=False, kind=FeatureKind.OTHER,
            part_id=None):
        """Appends parts: part p is points offsets[p]..offsets[p+1]-1 (offsets
        has n_parts + 1 entries from 0 to n_points; None = one part of all
        the points). part_id None numbers parts by their index in the network."""
        numpy = _arrays._numpy()
        lon = _arrays.input_array(lon_deg, c_double, (-1,), "lon_deg")
        lat = _arrays.input_array(lat_deg, c_double, (lon.size,), "lat_deg")
        if offsets is None:
            offsets = (0, lon.size)
        offs = _arrays.input_array(offsets, c_int64, (-1,), "offsets")
        if offs.size < 1:
            raise ValueError("offsets must have n_parts + 1 entries")
        n_parts = offs.size - 1

        def per_part(values, name):
            array = numpy.asarray(values)
            if array.ndim == 0:
                array = numpy.full(n_parts, array)
            return _arrays.input_array(array, c_int32, (n_parts,), name)
        closed_ = per_part(numpy.asarray(closed).astype(numpy.int64)
                           if numpy.asarray(closed).dtype == bool else closed, "closed")
        kind_ = per_part(kind, "kind")
        ids = None if part_id is None else per_part(part_id, "part_id")
        self._check(C.um_features_add(
            self._handle, lon.size, _arrays.pointer(lon, c_double),
            _arrays.pointer(lat, c_double), n_parts, _arrays.pointer(offs, c_int64),
            _arrays.pointer(closed_, c_int32), _arrays.pointer(kind_, c_int32),
            _arrays.pointer(ids, c_int32)))

    def read_geojson(self, path, kind_property=None, default_kind=0):
        """Appends the lines of a GeoJSON file (all-or-nothing). kind_property
        names the string property giving the kind (None = "kind");
        default_kind is used for features without a known kind (0 = error)."""
        prop = None if kind_property is None else str(kind_property).encode()
        self._check(C.um_features_read_geojson(self._handle, os.fsencode(path), prop,
                                               operator.index(default_kind)))

    def counts(self):
        """FeaturesCounts(n_parts, n_points, n_segments) of what is stored."""
        counts = c_int64(0), c_int64(0), c_int64(0)
        self._check(C.um_features_counts(self._handle, *(byref(c) for c in counts)))
        return FeaturesCounts(*(c.value for c in counts))

    def points(self):
        """(lon_deg, lat_deg): the stored points, float64 arrays."""
        n = self.counts().n_points
        lon = _arrays.output_array(c_double, (n,))
        lat = _arrays.output_array(c_double, (n,))
        self._check(C.um_features_copy_points(self._handle, _arrays.pointer(lon, c_double),
                                              _arrays.pointer(lat, c_double), n))
        return lon, lat

    def parts(self):
        """FeatureParts(offsets (n_parts + 1,) int64, closed, kind, part_id
        (n_parts,) int32 each) of the stored parts."""
        n = self.counts().n_parts
        offsets = _arrays.output_array(c_int64, (n + 1,))
        # One capacity for all four arrays: n + 1 elements each.
        rest = [_arrays.output_array(c_int32, (n + 1,)) for _ in range(3)]
        self._check(C.um_features_copy_parts(self._handle, _arrays.pointer(offsets, c_int64),
                                             *(_arrays.pointer(a, c_int32) for a in rest),
                                             n + 1))
        closed, kind, part_id = (a[:n].copy() for a in rest)
        return FeatureParts(offsets, closed, kind, part_id)

    def __len__(self):
        return self.counts().n_parts

    def __repr__(self):
        if self.closed:
            return "<unimesh.Features closed>"
        counts = self.counts()
        return (f"<unimesh.Features n_parts={counts.n_parts} n_points={counts.n_points} "
                f"n_segments={counts.n_segments}>")


class _SpacingCallback:
    """A Python spacing function as C calls it: the ctypes function object
    (which must live as long as any C spacing that may call it, including
    the copy a Mesh keeps) and the first exception the function raised."""

    def __init__(self, function):
        self.error = None

        def trampoline(_user_data, lon_deg, lat_deg):
            if self.error is not None:
                return float("nan")  # already failed: finish quickly
            try:
                return float(function(lon_deg, lat_deg))
            except BaseException as error:  # must not unwind through C
                if self.error is None:
                    self.error = error
                return float("nan")  # the call then fails, naming the point
        self.c_function = SPACING_FN(trampoline)

    def take_error(self):
        error, self.error = self.error, None
        return error


def _check_with_callback(context, callback, status):
    """context._check(status), except that an exception raised by a Python
    spacing function during the call is raised instead, being the cause."""
    pending = callback.take_error() if callback is not None else None
    if pending is not None:
        try:
            context._check(status)
        except UnimeshError:
            pass  # the C side only saw a bad value
        raise pending
    context._check(status)


class Spacing(_Handle):
    """The mesh spacing h(x), in km (um_spacing). Made by the class methods:

        Spacing.constant(ctx, 240.0)
        Spacing.grid(ctx, lon_deg, lat_deg, cell_width_km)  # (n_lat, n_lon) widths
        Spacing.from_file(ctx, "cellWidth.nc")             # MPAS-tools netCDF
        Spacing.preset(ctx, "EC60to30")                    # QU<km>, EC<a>to<b>, RRS<a>to<b>
        Spacing.callback(ctx, lambda lon, lat: 100 + abs(lat))

    then refined in place by limit_gradient() and clamp(), and read by
    evaluate(). A callback is called from the library's worker threads
    (serialised by the GIL); an exception in it fails the call that
    evaluated it and is what that call raises.
    """

    _destroy = staticmethod(C.um_spacing_destroy)

    def __init__(self, *_args, **_kwargs):
        raise TypeError("make a Spacing with Spacing.constant, .grid, .from_file, .preset "
                        "or .callback")

    @classmethod
    def _create(cls, context, function, *args, callback=None):
        self = object.__new__(cls)
        self._context = context
        self._callback = callback
        ptr = c_void_p()
        _check_with_callback(context, callback, function(context._handle, *args, byref(ptr)))
        self._ptr = ptr.value
        return self

    @classmethod
    def constant(cls, context, km):
        """h = km everywhere."""
        return cls._create(context, C.um_spacing_create_constant, float(km))

    @classmethod
    def grid(cls, context, lon_deg, lat_deg, cell_width_km):
        """Bilinear interpolation in a lon/lat grid of cell widths in km:
        cell_width_km has shape (n_lat, n_lon) (MPAS cellWidth(lat, lon))."""
        lon = _arrays.input_array(lon_deg, c_double, (-1,), "lon_deg")
        lat = _arrays.input_array(lat_deg, c_double, (-1,), "lat_deg")
        width = _arrays.input_array(cell_width_km, c_double, (lat.size, lon.size),
                                    "cell_width_km")
        return cls._create(context, C.um_spacing_create_grid, lon.size,
                           _arrays.pointer(lon, c_double), lat.size,
                           _arrays.pointer(lat, c_double), _arrays.pointer(width, c_double))

    @classmethod
    def from_file(cls, context, path):
        """The grid of an MPAS-tools spacing file (netCDF lon, lat, cellWidth)."""
        return cls._create(context, C.um_spacing_create_from_file, os.fsencode(path))

    @classmethod
    def preset(cls, context, name):
        """A named E3SM spacing: "QU240", "EC60to30", "RRS18to6", ..."""
        return cls._create(context, C.um_spacing_create_preset, str(name).encode())

    @classmethod
    def callback(cls, context, function):
        """h = function(lon_deg, lat_deg) in km. The Spacing (and any Mesh
        made from it) keeps the function alive."""
        if not callable(function):
            raise TypeError(f"Spacing.callback needs a callable, not {type(function).__name__}")
        holder = _SpacingCallback(function)
        return cls._create(context, C.um_spacing_create_callback, holder.c_function, None,
                           callback=holder)

    def _check(self, status):
        _check_with_callback(self._context, self._callback, status)

    def limit_gradient(self, g):
        """Limits |grad h| to g km per km (grid spacings only)."""
        self._check(C.um_spacing_limit_gradient(self._handle, float(g)))
        return self

    def clamp(self, km_min, km_max):
        """h = min(max(h, km_min), km_max)."""
        self._check(C.um_spacing_clamp(self._handle, float(km_min), float(km_max)))
        return self

    def estimate(self):
        """MeshEstimate(cells, refine_bytes, mpas_bytes): what a mesh of this
        spacing is expected to need (see um_spacing_estimate)."""
        values = c_int64(0), c_int64(0), c_int64(0)
        self._check(C.um_spacing_estimate(self._handle, *(byref(v) for v in values)))
        return MeshEstimate(*(v.value for v in values))

    def evaluate(self, lon_deg, lat_deg, out=None):
        """h in km at the points: a float64 array of the inputs' shape."""
        lon = _arrays.input_array(lon_deg, c_double, None, "lon_deg")
        lat = _arrays.input_array(lat_deg, c_double, lon.shape, "lat_deg")
        out = _arrays.output_array(c_double, lon.shape, out)
        self._check(C.um_spacing_evaluate(self._handle, lon.size, _arrays.pointer(lon, c_double),
                                          _arrays.pointer(lat, c_double),
                                          _arrays.pointer(out, c_double)))
        return out

    def __call__(self, lon_deg, lat_deg):
        return self.evaluate(lon_deg, lat_deg)

    def __repr__(self):
        return "<unimesh.Spacing closed>" if self.closed else "<unimesh.Spacing>"


class Mesh(_Handle):
    """The restricted triangulation of the sphere (um_mesh):

        mesh = Mesh.refine(ctx, spacing, features=None, options=None)
        lon, lat = mesh.vertices()
        triangles = mesh.triangles()   # (n_triangles, 3) int32 (+ base)

    Vertices are numbered 0..n_vertices-1 (+ base); triangles are
    counter-clockwise seen from outside. The mesh stays usable after the
    context, spacing, features and options are closed.
    """

    _destroy = staticmethod(C.um_mesh_destroy)

    def __init__(self, context, spacing, features=None, options=None):
        self._context = context
        # The C mesh keeps the spacing (quality reads it): so must we keep a
        # Python spacing function.
        self._callback = spacing._callback
        ptr = c_void_p()
        status = C.um_mesh_refine(context._handle, spacing._handle,
                                  None if features is None else features._handle,
                                  None if options is None else options._handle, byref(ptr))
        _check_with_callback(context, self._callback, status)
        self._ptr = ptr.value

    @classmethod
    def refine(cls, context, spacing, features=None, options=None):
        """Refines the spacing's mesh from the icosahedron (or a uniform
        spacing's geodesic lattice), with vertices placed on the features
        when given (see um_mesh_refine)."""
        return cls(context, spacing, features, options)

    def _check(self, status):
        _check_with_callback(self._context, self._callback, status)

    def optimise(self, options=None):
        """The weighted primal-dual optimisation, in place (see
        um_mesh_optimise); options None = the defaults. Returns self. On an
        error (raised) the mesh is left as it was."""
        self._check(C.um_mesh_optimise(self._handle,
                                       None if options is None else options._handle))
        return self

    def counts(self):
        """MeshCounts(n_vertices, n_triangles, n_restricted_edges, n_filtered)."""
        counts = c_int64(0), c_int64(0), c_int64(0), c_int64(0)
        self._check(C.um_mesh_counts(self._handle, *(byref(c) for c in counts)))
        return MeshCounts(*(c.value for c in counts))

    def vertices(self):
        """(lon_deg, lat_deg) of the vertices, float64 (lon in (-180, 180])."""
        n = self.counts().n_vertices
        lon = _arrays.output_array(c_double, (n,))
        lat = _arrays.output_array(c_double, (n,))
        self._check(C.um_mesh_copy_vertices(self._handle, _arrays.pointer(lon, c_double),
                                            _arrays.pointer(lat, c_double), n))
        return lon, lat

    def triangles(self, base=0, out=None):
        """(n_triangles, 3) int32: the vertices (+ base) of each triangle."""
        base = _base(base)
        out = _arrays.output_array(c_int32, (self.counts().n_triangles, 3), out)
        self._check(C.um_mesh_copy_triangles(self._handle, base, _arrays.pointer(out, c_int32),
                                             _arrays.capacity(out)))
        return out

    def vertex_parts(self, base=0, out=None):
        """(n_vertices,) int32: the features part (+ base) each vertex lies on,
        -1 (whatever the base) when it is not on a feature."""
        base = _base(base)
        out = _arrays.output_array(c_int32, (self.counts().n_vertices,), out)
        self._check(C.um_mesh_copy_vertex_parts(self._handle, base,
                                                _arrays.pointer(out, c_int32),
                                                _arrays.capacity(out)))
        return out

    def restricted_edges(self, base=0):
        """(vertices (n, 2) int32, parts (n,) int32): each restricted edge's
        two vertices (+ base) and the part (+ base) its dual edge crosses."""
        base = _base(base)
        n = self.counts().n_restricted_edges
        vertices = _arrays.output_array(c_int32, (n, 2))
        parts = _arrays.output_array(c_int32, (n,))
        self._check(C.um_mesh_copy_restricted_edges(self._handle, base,
                                                    _arrays.pointer(vertices, c_int32),
                                                    _arrays.pointer(parts, c_int32), n))
        return vertices, parts

    def vertex_sides(self, out=None):
        """(n_vertices,) int32 Side values (OCEAN, LAND or COASTAL)."""
        out = _arrays.output_array(c_int32, (self.counts().n_vertices,), out)
        self._check(C.um_mesh_copy_vertex_sides(self._handle, _arrays.pointer(out, c_int32),
                                                _arrays.capacity(out)))
        return out

    def triangle_sides(self, out=None):
        """(n_triangles,) int32 Side values (OCEAN or LAND) of the orthocentres."""
        out = _arrays.output_array(c_int32, (self.counts().n_triangles,), out)
        self._check(C.um_mesh_copy_triangle_sides(self._handle, _arrays.pointer(out, c_int32),
                                                  _arrays.capacity(out)))
        return out

    def _json(self, function):
        needed = c_int64(0)
        status = function(self._handle, None, 0, byref(needed))
        if status != Status.ERR_BUFFER_TOO_SMALL:
            self._check(status)
        buffer = create_string_buffer(max(needed.value, 1))
        self._check(function(self._handle, buffer, len(buffer), byref(needed)))
        return _text(buffer.value)

    def quality_json(self):
        """The quality report (see um_mesh_quality_json) as JSON text."""
        return self._json(C.um_mesh_quality_json)

    def river_report_json(self):
        """The river routing report (see um_mesh_river_report_json) as JSON text."""
        return self._json(C.um_mesh_river_report_json)

    def quality_summary(self, metric):
        """QualitySummary(min, p1, mean, max) of a metric: "area_length_ratio",
        "primal_dual", "angle_min_deg", "angle_max_deg", "edge_spacing_ratio",
        or an operator diagnostic: "centroid_offset", "dual_edge_offset",
        "primal_edge_offset" or "cell_spacing_ratio" (dcEdge / h). Their rms
        and std are in quality_json()'s "operator_diagnostics"."""
        values = c_double(), c_double(), c_double(), c_double()
        self._check(C.um_mesh_quality_summary(self._handle, str(metric).encode(),
                                              *(byref(v) for v in values)))
        return QualitySummary(*(v.value for v in values))

    def quality_counts(self):
        """QualityCounts(obtuse, not_well_centred) triangles."""
        counts = c_int64(0), c_int64(0)
        self._check(C.um_mesh_quality_counts(self._handle, *(byref(c) for c in counts)))
        return QualityCounts(*(c.value for c in counts))

    def write_mpas(self, path, format=MpasFile.AUTO):
        """Writes the MPAS mesh file (netCDF) of this mesh: format AUTO (64-bit
        offset, CDF-5 for large meshes) or NETCDF4."""
        self._check(C.um_mesh_write_mpas_as(self._handle, os.fsencode(path), int(format)))

    def write_components(self, directory):
        """Writes the component meshes and coupler grids into an existing
        directory (see um_mesh_write_components): mesh.nc with the maps,
        ocean.nc, land.nc, their graph.info files, SCRIP and ESMF grids of all
        three, rivers.json."""
        self._check(C.um_mesh_write_components(self._handle, os.fsencode(directory)))

    def write_jigsaw(self, path):
        """Writes the triangulation in JIGSAW's .msh format (points, power
        weights, triangles)."""
        self._check(C.um_mesh_write_jigsaw(self._handle, os.fsencode(path)))

    def mpas_dimensions(self):
        """MpasDimensions(n_cells, n_edges, n_vertices, max_edges) of the
        staggered mesh (its numbering made on first use and kept, see
        release_mpas; each variable is made when it is copied)."""
        values = c_int64(0), c_int64(0), c_int64(0), c_int64(0)
        self._check(C.um_mesh_mpas_dimensions(self._handle, *(byref(v) for v in values)))
        return MpasDimensions(*(v.value for v in values))

    def mpas_variable(self, name, base=0):
        """An MPAS variable by its netCDF name, as the file holds it: float64
        or int32, shape (n_rows,) or (n_rows, n_columns). Index variables get
        base added (0: 0-based with -1 padding; 1: MPAS's 1-based with 0)."""
        kind, rows, columns = c_int32(0), c_int64(0), c_int64(0)
        encoded = name.encode() if isinstance(name, str) else name
        self._check(C.um_mesh_mpas_variable(self._handle, encoded, byref(kind), byref(rows),
                                            byref(columns)))
        shape = (rows.value,) if columns.value == 1 else (rows.value, columns.value)
        if kind.value == MPAS_REAL:
            out = _arrays.output_array(c_double, shape)
            self._check(C.um_mesh_copy_mpas_real(self._handle, encoded,
                                                 _arrays.pointer(out, c_double), out.size))
        else:
            out = _arrays.output_array(c_int32, shape)
            self._check(C.um_mesh_copy_mpas_int(self._handle, encoded, _base(base),
                                                _arrays.pointer(out, c_int32), out.size))
        return out

    def release_mpas(self):
        """Frees the numbering kept by mpas_dimensions / mpas_variable."""
        self._check(C.um_mesh_release_mpas(self._handle))

    def __repr__(self):
        if self.closed:
            return "<unimesh.Mesh closed>"
        counts = self.counts()
        return (f"<unimesh.Mesh n_vertices={counts.n_vertices} "
                f"n_triangles={counts.n_triangles} "
                f"n_restricted_edges={counts.n_restricted_edges}>")


def _base(base):
    """An index base for C: 0 or 1. Checked here because ctypes would wrap an
    int beyond int32 into range instead of refusing it."""
    base = operator.index(base)
    if base not in (0, 1):
        raise UnimeshError(Status.ERR_INVALID_ARGUMENT, f"base = {base} is not 0 or 1")
    return base


def _name_of(key):
    return key if isinstance(key, str) else option_name(key)


def _format_value(value):
    """A value as C parses it: integers as digits, reals round-tripping."""
    if isinstance(value, bool):
        return "1" if value else "0"
    try:
        return str(operator.index(value))  # int and numpy integers
    except TypeError:
        return repr(float(value))  # shortest text that reads back the same double
