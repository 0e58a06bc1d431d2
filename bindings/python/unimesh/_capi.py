"""libunimesh through ctypes: finding the library and its one signature table.

Every C function is declared once, in SIGNATURES, and bound in one loop. A
function ctypes calls without a declared restype returns a C int, which
silently truncates 64-bit pointers: so the rest of the package calls C only
through the namespace `C` built here, which holds table functions and
nothing else. tests/test_unimesh_python.py checks the table against
include/unimesh.h, name by name and type by type.
"""

import ctypes
import ctypes.util
import os
import sys
import types
from ctypes import CFUNCTYPE, POINTER, c_char, c_char_p, c_double, c_int32, c_int64, c_void_p
from pathlib import Path

# ------------------------------------------------------------------ ABI types

status_t = c_int32  # um_status
option_t = c_int32  # um_option
handle_t = c_void_p  # um_context *, um_options *, ...: opaque, never dereferenced here
handle_out_t = POINTER(c_void_p)  # um_x **out
string_in_t = c_char_p  # const char * (NUL-terminated bytes)
buffer_out_t = POINTER(c_char)  # char *buf of `capacity` bytes, written by C

# The header's callback typedefs. Strings arrive as bytes.
PROGRESS_FN = CFUNCTYPE(c_int32, c_void_p, c_char_p, c_double)  # um_progress_fn
LOG_FN = CFUNCTYPE(None, c_void_p, c_int32, c_char_p)  # um_log_fn
ABORT_FN = CFUNCTYPE(None, c_void_p, status_t, c_char_p)  # um_abort_fn
# Called from worker threads, concurrently (ctypes takes the GIL for each call).
SPACING_FN = CFUNCTYPE(c_double, c_void_p, c_double, c_double)  # um_spacing_fn
CALLBACK_TYPES = {"um_progress_fn": PROGRESS_FN, "um_log_fn": LOG_FN, "um_abort_fn": ABORT_FN,
                  "um_spacing_fn": SPACING_FN}

_i32p, _i64p, _f64p = POINTER(c_int32), POINTER(c_int64), POINTER(c_double)

# (name, restype, argtypes), in the order of the header.
SIGNATURES = (
    # version
    ("um_version_number", c_int32, ()),
    ("um_version", None, (_i32p, _i32p, _i32p)),
    ("um_version_string", c_char_p, ()),
    # status
    ("um_status_string", c_char_p, (status_t,)),
    ("um_status_class", c_int32, (status_t,)),
    # context
    ("um_context_create", status_t, (handle_out_t,)),
    ("um_context_destroy", None, (handle_t,)),
    ("um_context_set_threads", status_t, (handle_t, c_int32)),
    ("um_context_get_threads", status_t, (handle_t, _i32p)),
    ("um_context_set_progress", status_t, (handle_t, PROGRESS_FN, c_void_p)),
    ("um_context_set_log", status_t, (handle_t, LOG_FN, c_void_p, c_int32)),
    ("um_context_set_memory_cap", status_t, (handle_t, c_int64)),
    ("um_context_set_worker_placement", status_t, (handle_t, c_int32)),
    ("um_context_get_memory_cap", status_t, (handle_t, _i64p)),
    ("um_context_set_error_mode", status_t, (handle_t, c_int32, ABORT_FN, c_void_p)),
    ("um_context_last_error", c_char_p, (handle_t,)),
    ("um_context_last_status", status_t, (handle_t,)),
    ("um_context_copy_last_error", status_t, (handle_t, buffer_out_t, c_int64, _i64p)),
    ("um_context_clear_error", status_t, (handle_t,)),
    # options
    ("um_options_create", status_t, (handle_t, handle_out_t)),
    ("um_options_destroy", None, (handle_t,)),
    ("um_options_set_double", status_t, (handle_t, option_t, c_double)),
    ("um_options_set_int", status_t, (handle_t, option_t, c_int64)),
    ("um_options_get_double", status_t, (handle_t, option_t, _f64p)),
    ("um_options_get_int", status_t, (handle_t, option_t, _i64p)),
    ("um_options_set_string", status_t, (handle_t, string_in_t)),
    ("um_option_info", status_t, (option_t, _i32p, _f64p, _f64p, _f64p)),
    ("um_option_name", status_t, (option_t, buffer_out_t, c_int64, _i64p)),
    ("um_option_key", status_t, (string_in_t, POINTER(option_t))),
    # triangulation
    ("um_triangulation_create", status_t,
     (handle_t, c_int64, _f64p, _f64p, _f64p, handle_out_t)),
    ("um_triangulation_create_xyz", status_t, (handle_t, c_int64, _f64p, _f64p, handle_out_t)),
    ("um_triangulation_destroy", None, (handle_t,)),
    ("um_triangulation_counts", status_t, (handle_t, _i64p, _i64p, _i64p)),
    ("um_triangulation_copy_triangles", status_t, (handle_t, c_int32, _i32p, c_int64)),
    ("um_triangulation_copy_neighbours", status_t, (handle_t, c_int32, _i32p, c_int64)),
    ("um_triangulation_copy_orthocentres", status_t, (handle_t, _f64p, c_int64)),
    ("um_triangulation_copy_hidden", status_t, (handle_t, c_int32, _i32p, c_int64)),
    ("um_triangulation_check", status_t, (handle_t,)),
    # features (polyarc networks)
    ("um_features_create", status_t, (handle_t, handle_out_t)),
    ("um_features_destroy", None, (handle_t,)),
    ("um_features_add", status_t,
     (handle_t, c_int64, _f64p, _f64p, c_int64, _i64p, _i32p, _i32p, _i32p)),
    ("um_features_read_geojson", status_t, (handle_t, string_in_t, string_in_t, c_int32)),
    ("um_features_counts", status_t, (handle_t, _i64p, _i64p, _i64p)),
    ("um_features_copy_points", status_t, (handle_t, _f64p, _f64p, c_int64)),
    ("um_features_copy_parts", status_t, (handle_t, _i64p, _i32p, _i32p, _i32p, c_int64)),
    # spacing
    ("um_spacing_create_constant", status_t, (handle_t, c_double, handle_out_t)),
    ("um_spacing_create_grid", status_t,
     (handle_t, c_int64, _f64p, c_int64, _f64p, _f64p, handle_out_t)),
    ("um_spacing_create_from_file", status_t, (handle_t, string_in_t, handle_out_t)),
    ("um_spacing_create_callback", status_t, (handle_t, SPACING_FN, c_void_p, handle_out_t)),
    ("um_spacing_create_preset", status_t, (handle_t, string_in_t, handle_out_t)),
    ("um_spacing_destroy", None, (handle_t,)),
    ("um_spacing_limit_gradient", status_t, (handle_t, c_double)),
    ("um_spacing_clamp", status_t, (handle_t, c_double, c_double)),
    ("um_spacing_evaluate", status_t, (handle_t, c_int64, _f64p, _f64p, _f64p)),
    ("um_spacing_estimate", status_t, (handle_t, _i64p, _i64p, _i64p)),
    # mesh
    ("um_mesh_refine", status_t, (handle_t, handle_t, handle_t, handle_t, handle_out_t)),
    ("um_mesh_optimise", status_t, (handle_t, handle_t)),
    ("um_mesh_destroy", None, (handle_t,)),
    ("um_mesh_counts", status_t, (handle_t, _i64p, _i64p, _i64p, _i64p)),
    ("um_mesh_copy_vertices", status_t, (handle_t, _f64p, _f64p, c_int64)),
    ("um_mesh_copy_triangles", status_t, (handle_t, c_int32, _i32p, c_int64)),
    ("um_mesh_copy_vertex_parts", status_t, (handle_t, c_int32, _i32p, c_int64)),
    ("um_mesh_copy_restricted_edges", status_t, (handle_t, c_int32, _i32p, _i32p, c_int64)),
    ("um_mesh_copy_vertex_sides", status_t, (handle_t, _i32p, c_int64)),
    ("um_mesh_copy_triangle_sides", status_t, (handle_t, _i32p, c_int64)),
    ("um_mesh_quality_json", status_t, (handle_t, buffer_out_t, c_int64, _i64p)),
    ("um_mesh_quality_summary", status_t, (handle_t, string_in_t, _f64p, _f64p, _f64p, _f64p)),
    ("um_mesh_quality_counts", status_t, (handle_t, _i64p, _i64p)),
    # MPAS output
    ("um_mesh_write_mpas", status_t, (handle_t, string_in_t)),
    ("um_mesh_write_mpas_as", status_t, (handle_t, string_in_t, c_int32)),
    ("um_mesh_mpas_dimensions", status_t, (handle_t, _i64p, _i64p, _i64p, _i64p)),
    ("um_mesh_mpas_variable", status_t, (handle_t, string_in_t, _i32p, _i64p, _i64p)),
    ("um_mesh_copy_mpas_real", status_t, (handle_t, string_in_t, _f64p, c_int64)),
    ("um_mesh_copy_mpas_int", status_t, (handle_t, string_in_t, c_int32, _i32p, c_int64)),
    ("um_mesh_write_jigsaw", status_t, (handle_t, string_in_t)),
    ("um_mesh_release_mpas", status_t, (handle_t,)),
    # Component meshes
    ("um_mesh_write_components", status_t, (handle_t, string_in_t)),
    ("um_mpas_file_write_components", status_t, (handle_t, string_in_t, string_in_t)),
    ("um_mesh_river_report_json", status_t, (handle_t, buffer_out_t, c_int64, _i64p)),
)

# ----------------------------------------------------------- finding the library

_LIBRARY_NAMES = {
    "win32": ("unimesh.dll", "libunimesh.dll"),
    "darwin": ("libunimesh.0.dylib", "libunimesh.dylib"),
}.get(sys.platform, ("libunimesh.so.0", "libunimesh.so"))


def _candidates():
    """Where to look, in order: $UNIMESH_LIBRARY alone when set (a wrong
    path should fail, not fall back to some other build); else next to this
    package, the source tree's build/lib (bindings/python/unimesh -> the
    repository root is three levels up), then the system search path: the
    library's own names, which the loader resolves through LD_LIBRARY_PATH
    and its cache (an installed prefix), then ctypes' search."""
    explicit = os.environ.get("UNIMESH_LIBRARY")
    if explicit:
        return [explicit]
    here = Path(__file__).resolve().parent
    directories = [here, here.parents[2] / "build" / "lib"]
    found = [str(d / name) for d in directories for name in _LIBRARY_NAMES if (d / name).exists()]
    system = ctypes.util.find_library("unimesh")
    return found + list(_LIBRARY_NAMES) + ([system] if system else [])


def _load():
    tried = []
    for path in _candidates():
        try:
            return ctypes.CDLL(path), path
        except OSError as error:
            tried.append(f"{path}: {error}")
    raise OSError("unimesh: cannot load libunimesh; set UNIMESH_LIBRARY to its path. Tried:\n  "
                  + ("\n  ".join(tried) if tried else "(no candidate found)"))


def _missing(name, path):
    """Stands in for a function the loaded library lacks (an older build):
    the package still imports, and only calls that need it fail."""
    def call(*_args):
        raise NotImplementedError(f"{name} is not in {path}: the binding is newer than the "
                                  "library; rebuild or point UNIMESH_LIBRARY at a newer one")
    call.__name__ = name
    return call


def _bind(library, path):
    functions, missing = {}, []
    for name, restype, argtypes in SIGNATURES:
        function = getattr(library, name, None)
        if function is None:
            missing.append(name)
            functions[name] = _missing(name, path)
            continue
        function.restype = restype
        function.argtypes = argtypes
        functions[name] = function
    return types.SimpleNamespace(**functions), missing


library, library_path = _load()
C, missing_functions = _bind(library, library_path)
