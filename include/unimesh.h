/*
 * unimesh.h -- the one public header of libunimesh.
 *
 * unimesh builds "unified" Laguerre-Power (weighted Delaunay / power diagram)
 * meshes of the sphere for MPAS-type staggered models.
 *
 * ABI rules
 *   - Pure C99. Every symbol is prefixed um_ / UM_.
 *   - Every entry point returns um_status (0 = UM_OK) unless it is a destroy
 *     function (void, NULL-safe) or a borrowed-string accessor.
 *   - Objects come out through out-parameters; every object is created from a
 *     um_context, has exactly one owner and a NULL-safe um_*_destroy.
 *   - Integer types on the ABI: int32_t indices/flags, int64_t counts, double
 *     reals. No size_t, bool, long or unsigned (Fortran has none).
 *   - Arrays are caller-owned buffers with an explicit capacity (elements) and,
 *     where they hold indices, an explicit index base (0 for C/Python, 1 for
 *     Fortran/MPAS).
 *   - Strings in are NUL-terminated; strings out are copied into a caller
 *     buffer of `capacity` bytes, always NUL-terminated when capacity > 0, and
 *     the length needed (including the NUL) is reported.
 *   - A released signature never changes; a new one gets a _v2 suffix. Enum
 *     values are pinned and never reused.
 *
 * Thread rules
 *   - A context and every object created from it may be used by one host
 *     thread at a time. Separate contexts may be used concurrently from
 *     different host threads.
 *   - Destroying a context while objects created from it are alive is allowed:
 *     the objects keep what they need and stay valid until destroyed.
 *   - Parallel work runs inside the context's own task arena with the number of
 *     threads set by um_context_set_threads. The progress callback and the log
 *     callback are only ever called from the host thread that made the call, never
 *     from a worker thread. A spacing (user) callback may be called from worker
 *     threads concurrently and must be thread-safe.
 *
 * Errors
 *   - Status codes come in numbered bands (see um_status); um_status_class()
 *     gives the band.
 *   - The context keeps the FIRST error message (naming the argument and the
 *     value) until um_context_clear_error(); reading it never clears it.
 *   - A failing call leaves every handle as it was before the call, unless its
 *     documentation says otherwise.
 *   - In UM_ERROR_MODE_ABORT the context calls the caller's abort hook after
 *     recording an error; the library itself never prints, aborts or exits.
 */
#ifndef UNIMESH_H
#define UNIMESH_H

#include <stdint.h>

#if defined(_WIN32)
#  if defined(UNIMESH_BUILDING_LIBRARY)
#    define UM_API __declspec(dllexport)
#  else
#    define UM_API __declspec(dllimport)
#  endif
#elif defined(__GNUC__) || defined(__clang__)
#  define UM_API __attribute__((visibility("default")))
#else
#  define UM_API
#endif

#ifdef __cplusplus
extern "C" {
#endif

/* ------------------------------------------------------------------ version */

#define UM_VERSION_MAJOR 0
#define UM_VERSION_MINOR 1
#define UM_VERSION_PATCH 0
/* MAJOR*10000 + MINOR*100 + PATCH */
#define UM_VERSION_NUMBER (UM_VERSION_MAJOR * 10000 + UM_VERSION_MINOR * 100 + UM_VERSION_PATCH)
#define UM_VERSION_STRING "0.1.0"

/* Run-time version of the library actually loaded (compare to the macros). */
UM_API int32_t um_version_number(void);
UM_API void um_version(int32_t *major, int32_t *minor, int32_t *patch); /* NULLs allowed */
UM_API const char *um_version_string(void);                            /* static string */

/* ------------------------------------------------------------------ status */

/* Bands: 0 ok; 100-199 usage (caller's mistake); 200-299 input data;
 * 300-399 numerical; 400-499 resources and limits; 500-599 I/O and file
 * formats; 600-699 interrupted by the caller; 900-999 internal. */
typedef int32_t um_status;
enum {
    UM_OK = 0,

    UM_ERR_USAGE = 100,             /* generic misuse */
    UM_ERR_NULL_ARGUMENT = 101,     /* a required pointer was NULL */
    UM_ERR_INVALID_HANDLE = 102,    /* not a live handle of the expected kind */
    UM_ERR_INVALID_ARGUMENT = 103,  /* a value outside its domain (NaN, range, enum) */
    UM_ERR_UNKNOWN_OPTION = 104,    /* option key or name not known */
    UM_ERR_OPTION_TYPE = 105,       /* integer option set as real or vice versa */
    UM_ERR_BUFFER_TOO_SMALL = 106,  /* output capacity below what is needed */
    UM_ERR_WRONG_ORDER = 107,       /* call made before what it depends on */

    UM_ERR_INPUT = 200,             /* generic bad input data */
    UM_ERR_NONFINITE_INPUT = 201,   /* NaN or Inf in input data */
    UM_ERR_COORDINATE_RANGE = 202,  /* |lat| > 90 or similar */
    UM_ERR_DUPLICATE_POINTS = 203,  /* exactly coincident points */
    UM_ERR_TOO_FEW_POINTS = 204,    /* not enough distinct points */
    UM_ERR_DEGENERATE_INPUT = 205,  /* e.g. all points on one great circle */

    UM_ERR_NUMERICAL = 300,         /* a numerical procedure failed */

    UM_ERR_OUT_OF_MEMORY = 400,     /* allocation failed */
    UM_ERR_MEMORY_CAP = 401,        /* request exceeds the context's memory cap */
    UM_ERR_LIMIT = 402,             /* a size limit (e.g. int32 indices) exceeded */

    UM_ERR_IO = 500,                /* reading or writing a file failed */
    UM_ERR_FILE_FORMAT = 501,       /* file readable but not of the expected form */

    UM_CANCELLED = 600,             /* the progress callback asked to stop */

    UM_ERR_INTERNAL = 900           /* a bug in unimesh: please report */
};

/* Static, never NULL: a short description of a status ("unknown status" if not one). */
UM_API const char *um_status_string(um_status status);
/* The band of a status: 0, 100, 200, ..., 900 (status / 100 * 100; negative -> 900). */
UM_API int32_t um_status_class(um_status status);

/* ------------------------------------------------------------------ context */

typedef struct um_context um_context;

/* Progress: called from the host thread with a stage name and a fraction in
 * [0, 1]. Return non-zero to cancel: the running call then returns
 * UM_CANCELLED and leaves its handles valid. */
typedef int32_t (*um_progress_fn)(void *user_data, const char *stage, double fraction);

/* Log levels. */
enum {
    UM_LOG_DEBUG = 10,
    UM_LOG_INFO = 20,
    UM_LOG_WARNING = 30,
    UM_LOG_ERROR = 40
};
typedef void (*um_log_fn)(void *user_data, int32_t level, const char *message);

/* Error modes. */
enum {
    UM_ERROR_MODE_RETURN = 0, /* record the error and return the status (default) */
    UM_ERROR_MODE_ABORT = 1   /* also call the caller's abort hook */
};
/* Called (from the host thread) after an error is recorded in abort mode. If it
 * returns, the failing call returns its status as usual. */
typedef void (*um_abort_fn)(void *user_data, um_status status, const char *message);

UM_API um_status um_context_create(um_context **out);
UM_API void um_context_destroy(um_context *ctx); /* NULL-safe */

/* Threads used by parallel work: 0 = all cores; 1..1024 otherwise. */
UM_API um_status um_context_set_threads(um_context *ctx, int32_t n_threads);
/* The effective thread count (after resolving 0). */
UM_API um_status um_context_get_threads(const um_context *ctx, int32_t *n_threads);

UM_API um_status um_context_set_progress(um_context *ctx, um_progress_fn fn, void *user_data);
UM_API um_status um_context_set_log(um_context *ctx, um_log_fn fn, void *user_data,
                                    int32_t min_level);

/* Memory cap in bytes for the large allocations of this context's work
 * (0 = no cap). Requests whose estimate exceeds it fail with UM_ERR_MEMORY_CAP
 * before allocating. */
UM_API um_status um_context_set_memory_cap(um_context *ctx, int64_t bytes);
UM_API um_status um_context_get_memory_cap(const um_context *ctx, int64_t *bytes);

/* mode is UM_ERROR_MODE_RETURN or UM_ERROR_MODE_ABORT; abort mode needs a hook. */
UM_API um_status um_context_set_error_mode(um_context *ctx, int32_t mode, um_abort_fn hook,
                                           void *user_data);

/* The first error message kept by the context: borrowed, valid until the next
 * call on the context; "" when none (and for a NULL or invalid context). */
UM_API const char *um_context_last_error(const um_context *ctx);
/* The status that went with the kept message (UM_OK when none). */
UM_API um_status um_context_last_status(const um_context *ctx);
/* Copies the kept message into buf (capacity bytes, may be 0 with buf NULL);
 * *needed (may be NULL) receives strlen + 1. Returns UM_ERR_BUFFER_TOO_SMALL
 * when truncated (the buffer then holds a NUL-terminated prefix). */
UM_API um_status um_context_copy_last_error(const um_context *ctx, char *buf, int64_t capacity,
                                            int64_t *needed);
UM_API um_status um_context_clear_error(um_context *ctx);

/* ------------------------------------------------------------------ options */

typedef struct um_options um_options;

/* Option keys: pinned values, never reused. Each key is either real (set with
 * um_options_set_double) or integer (um_options_set_int). um_option_info
 * gives its type, bounds and default. */
typedef int32_t um_option;
enum {
    /* sphere */
    UM_OPT_SPHERE_RADIUS = 1,          /* real, m; default 6371220 (E3SM SHR_CONST_REARTH) */
    /* refinement (paper section 5) */
    UM_OPT_REFINE_ALPHA = 100,         /* real; edge/size bound, default 4/3 */
    UM_OPT_REFINE_BETA = 101,          /* real; Hausdorff bound eps < beta*h, default 1/5 */
    UM_OPT_REFINE_RHO = 102,           /* real; radius-edge bound, default 1.05 */
    UM_OPT_REFINE_TOPOLOGY_CHECK = 103,/* int 0/1; default 0 */
    /* optimisation (paper section 6, Algorithm 1) */
    UM_OPT_OPTIM_OUTER_ITERATIONS = 200, /* int; N, default 16 */
    UM_OPT_OPTIM_INNER_ITERATIONS = 201, /* int; M, default 8 */
    UM_OPT_OPTIM_TOLERANCE = 202,        /* real; early-stop tolerance, default 1e-4 */
    UM_OPT_OPTIM_WEIGHTS = 203,          /* int 0/1; optimise weights, default 1 */
    UM_OPT_OPTIM_FIX_BOUNDARY = 204,     /* int 0/1; vertices on features stay fixed, default 0 */
    UM_OPT_OPTIM_COLLAPSE_RATIO = 205,   /* real; collapse edges shorter than r*h, default 0.5 */
    UM_OPT_OPTIM_SPLIT_RATIO = 206       /* real; split edges longer than r*h, default 1.6 */
};
enum {
    UM_OPTION_TYPE_INT = 1,
    UM_OPTION_TYPE_REAL = 2
};

UM_API um_status um_options_create(um_context *ctx, um_options **out);
UM_API void um_options_destroy(um_options *opts); /* NULL-safe */

UM_API um_status um_options_set_double(um_options *opts, um_option key, double value);
UM_API um_status um_options_set_int(um_options *opts, um_option key, int64_t value);
UM_API um_status um_options_get_double(const um_options *opts, um_option key, double *value);
UM_API um_status um_options_get_int(const um_options *opts, um_option key, int64_t *value);
/* Sets several options from "name=value;name=value" (spaces around names and
 * values ignored; empty items skipped). Names are the keys' lower-case names
 * without UM_OPT_ (e.g. "refine_alpha=1.3;optim_outer_iterations=8").
 * All-or-nothing: on any error no option is changed. */
UM_API um_status um_options_set_string(um_options *opts, const char *assignments);

/* Bounds query (no context needed): type (UM_OPTION_TYPE_*), inclusive bounds
 * and default, each out-pointer may be NULL. */
UM_API um_status um_option_info(um_option key, int32_t *type, double *min_value,
                                double *max_value, double *default_value);
/* The key's name as used by um_options_set_string, copied out as for strings. */
UM_API um_status um_option_name(um_option key, char *buf, int64_t capacity, int64_t *needed);
/* The key of a name; UM_ERR_UNKNOWN_OPTION if none. */
UM_API um_status um_option_key(const char *name, um_option *key);

/* ------------------------------------------------------------ triangulation */

/* The Laguerre (regular, weighted Delaunay) triangulation of points on the
 * unit sphere: the convex hull of the lifted points x_i / (1 - w_i / 2).
 * Weights are in units of R^2 (squared chord lengths on the unit sphere) and
 * must be < 2; 0 gives the Delaunay triangulation. A point whose power cell is
 * empty is "hidden": it is not a vertex and is listed by
 * um_triangulation_copy_hidden.
 *
 * Vertex indices in every output are INPUT indices (plus the base).
 * Triangles are counter-clockwise seen from outside the sphere; neighbour k of
 * a triangle lies across the edge opposite its vertex k.
 *
 * Rejected input (the message names the argument, index and value):
 *   n < 4, NaN/Inf coordinates or weights, |lat| > 90, weights >= 2,
 *   exactly coincident points (UM_ERR_DUPLICATE_POINTS naming both indices;
 *   the caller removes one), points that do not surround the centre of the
 *   sphere (all in one hemisphere or on one great circle:
 *   UM_ERR_DEGENERATE_INPUT), n above what int32 indices can address.
 * Ties (cocircular points) are broken by a symbolic perturbation keyed on the
 * input index, so the result is unique and the same for any thread count. */
typedef struct um_triangulation um_triangulation;

UM_API um_status um_triangulation_create(um_context *ctx, int64_t n, const double *lon_deg,
                                         const double *lat_deg,
                                         const double *weights /* NULL = 0 */,
                                         um_triangulation **out);
/* The same from unit vectors (3 per point, x y z; normalised on input). */
UM_API um_status um_triangulation_create_xyz(um_context *ctx, int64_t n, const double *xyz,
                                             const double *weights /* NULL = 0 */,
                                             um_triangulation **out);
UM_API void um_triangulation_destroy(um_triangulation *t); /* NULL-safe */

UM_API um_status um_triangulation_counts(const um_triangulation *t, int64_t *n_vertices,
                                         int64_t *n_triangles, int64_t *n_hidden);
/* 3 vertex indices (+ base) per triangle; capacity in elements. */
UM_API um_status um_triangulation_copy_triangles(const um_triangulation *t, int32_t base,
                                                 int32_t *out /* 3 per triangle */,
                                                 int64_t capacity);
/* 3 triangle indices (+ base) per triangle: across the edge opposite vertex k. */
UM_API um_status um_triangulation_copy_neighbours(const um_triangulation *t, int32_t base,
                                                  int32_t *out /* 3 per triangle */,
                                                  int64_t capacity);
/* The orthocentre (power vertex) of each triangle as a unit vector (3 per triangle). */
UM_API um_status um_triangulation_copy_orthocentres(const um_triangulation *t,
                                                    double *out /* 3 per triangle */,
                                                    int64_t capacity);
/* Input indices (+ base) of the hidden points, ascending (n_hidden of them). */
UM_API um_status um_triangulation_copy_hidden(const um_triangulation *t, int32_t base,
                                              int32_t *out, int64_t capacity);
/* Re-checks every invariant with exact predicates (links, Euler characteristic,
 * orientation, local regularity of every edge, hidden points inside the hull).
 * UM_OK when all hold, UM_ERR_INTERNAL with the first violation otherwise. */
UM_API um_status um_triangulation_check(const um_triangulation *t);

#ifdef __cplusplus
} /* extern "C" */
#endif

#endif /* UNIMESH_H */
