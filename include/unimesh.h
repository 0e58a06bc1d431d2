/*
 * unimesh.h -- the one public header of libunimesh.
 *
 * unimesh builds "unified" Laguerre-Power (weighted Delaunay / power diagram)
 * meshes of the sphere for MPAS-type staggered models, as D. Engwirda and
 * C. Liao, "'Unified' Laguerre-Power meshes for coupled earth system
 * modelling", describe them: a restricted triangulation that follows the
 * coastlines and rivers (their section 5), optimised by the weighted
 * primal-dual scheme (section 6, Algorithm 1), judged by the metrics of their
 * Figure 10.
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
 *   - One call at a time per mesh: a call on a mesh while another call uses
 *     it (from inside that call's progress, log or spacing callback, or from
 *     another thread) fails with UM_ERR_USAGE and changes nothing;
 *     um_mesh_destroy then keeps the mesh and records the error.
 *   - Destroying a context while objects created from it are alive is allowed:
 *     the objects keep what they need and stay valid until destroyed.
 *   - Parallel work runs inside the context's own task arena with the number of
 *     threads set by um_context_set_threads. The progress callback and the log
 *     callback are only ever called from the host thread that made the call, never
 *     from a worker thread. A spacing (user) callback may be called from worker
 *     threads concurrently and must be thread-safe.
 *   - Writing an MPAS file of 256 MB of values or more in the classic
 *     formats (64-bit offset, CDF-5: mesh.nc, the component meshes) also
 *     starts one thread of its own for the writes to the device, whatever
 *     um_context_set_threads says: it waits on the device, using no processor
 *     meanwhile, and it has ended when the call returns.
 *   - Only when asked for (um_context_set_worker_placement, or
 *     UNIMESH_WORKER_PLACEMENT=on in the environment; off by default since it
 *     changes the affinity of threads the whole process shares): while a call
 *     runs in parallel (Linux), up to 8 of the worker threads that
 *     ran parts of the context's calls are kept off the CPU the calling thread
 *     is on: their affinity mask loses that CPU for the length of the call and
 *     gets it back when the last call holding it off returns, unless someone
 *     else changed the mask meanwhile (then it is left as they set it); a mask
 *     of one CPU is never narrowed. Best effort: a worker the system refuses
 *     to move stays where it is. Why: a worker woken by a busy thread may otherwise wait behind
 *     it on its CPU for milliseconds (on virtual machines whose kernel packs
 *     threads onto few CPUs, 3-6 ms), which is the whole of a short call. The
 *     workers are oneTBB's, shared by everything in the process that uses
 *     oneTBB: the environment variable UNIMESH_WORKER_PLACEMENT=off (read once
 *     per process) keeps this off whatever a context asks.
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
 * UM_CANCELLED and leaves its handles valid. Stages include "refine",
 * "refine lattice", "refine boundary", "refine surface", "refine relax",
 * "refine tags", "optimise", "quality" (any call that measures the mesh) and
 * "MPAS mesh";
 * every loop that may call a spacing callback reports at least every few
 * seconds of a slow one. */
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

/* on = 1: keep the oneTBB workers off the calling thread's CPU during this
 * context's parallel calls (see Thread rules; it changes their affinity
 * masks for the length of a call); 0 (the default, unless
 * UNIMESH_WORKER_PLACEMENT=on): leave every thread's affinity alone. */
UM_API um_status um_context_set_worker_placement(um_context *ctx, int32_t on);

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
    /* the surface: a sphere, or an ellipsoid ("Surfaces" below) */
    UM_OPT_SPHERE_RADIUS = 1,          /* real, m; default 6371220 (E3SM SHR_CONST_REARTH); an
                                          ellipsoid's semi-major axis a when the flattening > 0 */
    UM_OPT_SURFACE_FLATTENING = 2,     /* real in [0, 0.02]; default 0 (a sphere). WGS84:
                                          sphere_radius 6378137, flattening 1/298.257223563 */
    /* refinement (paper section 5) */
    UM_OPT_REFINE_ALPHA = 100,         /* real; edge/size bound, default 4/3 */
    UM_OPT_REFINE_BETA = 101,          /* real; Hausdorff bound eps < beta*h, default 1/5 */
    UM_OPT_REFINE_RHO = 102,           /* real; radius-edge bound, default 1.05 */
    UM_OPT_REFINE_TOPOLOGY_CHECK = 103,/* int 0/1; default 0. 1: a restricted edge is also
                                          refined when one of its ends has 3 or more restricted
                                          edges of the same feature part (Tri|Gamma is no curve
                                          there), down to the same h/2 filter */
    UM_OPT_REFINE_RELAX = 104,         /* int 0/1; default 1. 1: after refinement, vertices away
                                          from Gamma move (no flips, criteria kept) until their
                                          edges lie within [0.75, 1.35]*h where they can */
    UM_OPT_REFINE_LATTICE = 105,       /* int 0/1; default 1. 1: where the spacing is flat at
                                          its coarsest value h0 (within 1 %), the refinement
                                          starts from the geodesic lattice of h0 (10 n^2 + 2
                                          points, only its 12 corners not six-valent): a
                                          uniform spacing's whole sphere, a graded one's
                                          background; 0: the frontal refinement everywhere */
    UM_OPT_SPACING_GRADIENT = 106,     /* real in [0, 10], km per km; default 0.25. A grid
                                          spacing (also clamped, or a minimum of grids) steeper
                                          than this is meshed gradient-limited to it (as
                                          um_spacing_limit_gradient), so that a feature the
                                          mesh cannot grade to at once (a fine spot in a coarse
                                          background) gets a transition instead of being lost;
                                          the mesh and its report follow the limited spacing.
                                          0: as given. Other kinds are meshed as given */
    /* optimisation (paper section 6, Algorithm 1) */
    UM_OPT_OPTIM_OUTER_ITERATIONS = 200, /* int; N, default 20 */
    UM_OPT_OPTIM_INNER_ITERATIONS = 201, /* int; M, default 8 */
    UM_OPT_OPTIM_TOLERANCE = 202,        /* real; early-stop tolerance, default 1e-4 */
    UM_OPT_OPTIM_WEIGHTS = 203,          /* int 0/1; optimise weights, default 1 */
    UM_OPT_OPTIM_FIX_BOUNDARY = 204,     /* int 0/1; vertices on features stay fixed, default 0 */
    UM_OPT_OPTIM_COLLAPSE_RATIO = 205,   /* real; collapse edges shorter than r*h, default 0.5 */
    UM_OPT_OPTIM_SPLIT_RATIO = 206,      /* real; split edges longer than r*h, default 1.6 */
    UM_OPT_OPTIM_CORNER_VERTICES = 207,  /* int 0/1/2; vertices for obtuse corners on features (2: only where
                                            their cells stay clear of the features), default 1 */
    UM_OPT_OPTIM_CENTROIDAL_SWEEPS = 208,/* int; Lloyd sweeps towards the power cells' centroids
                                            after the shape iterations, default 8 (0: none) */
    UM_OPT_OPTIM_RESEED_ROUNDS = 209,    /* int; at most this many rounds re-seeding the 5-7 defects
                                            in the shape iterations, default 7 (0: none) */
    /* the ocean mesh */
    UM_OPT_OCEAN_FLOOR = 300             /* real in [0, 0.9]; the time-step floor f, default 0.7
                                            (0: none). The refinement puts no vertex on a closed
                                            coastline nearer than f*h to another (narrower detail
                                            is filtered); the optimisation's moves make no edge
                                            between two generators off the land (ocean, or on or
                                            crossed by a coastline: the cells the ocean mesh may
                                            take) shorter than f*h, and a pass takes out a vertex
                                            of each such edge where that keeps Gamma out of more
                                            cells, adds no long edge and (with the weights) no
                                            obtuse or off-centre triangle; the quality report's
                                            "ocean_floor" counts the ocean edges left below. Land
                                            and river edges may be shorter. */
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
 *   exactly coincident points with equal lifted points x / (1 - w/2), so
 *   equal weights (UM_ERR_DUPLICATE_POINTS naming both indices; the caller
 *   removes one - where the weights differ by more than rounding the
 *   lighter one is hidden, its power cell being empty), points that do
 *   not surround the centre of the sphere (all in one hemisphere or on one
 *   great circle: UM_ERR_DEGENERATE_INPUT), n above what int32 indices can
 *   address.
 * Ties (cocircular points) are broken by a symbolic perturbation keyed on the
 * input index, so the result is unique and the same for any thread count.
 * Degrees become unit vectors with sines and cosines reduced in degrees:
 * multiples of 90 give exact axes, a pole is (0, 0, +-1) at any longitude,
 * and longitudes a whole turn apart give the same vector - so two points at
 * one pole, or at longitudes -180 and 180 (0 and 360) with one latitude,
 * are at one place (duplicates, when their weights are equal). */
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

/* ---------------------------------------------- features (polyarc networks) */

/* Polyarc networks Gamma: coastlines, lake shores, rivers and watersheds as
 * polylines ("parts") of longitude/latitude points, in degrees. Each segment
 * is the short great-circle arc between consecutive points, plus the arc from
 * the last point back to the first for a closed part; lines crossing the
 * antimeridian need no special treatment.
 *
 * Adding checks and cleans each part:
 *   - rejected: NaN/Inf coordinates (UM_ERR_NONFINITE_INPUT), |lat| > 90
 *     (UM_ERR_COORDINATE_RANGE), parts with fewer than 2 distinct points
 *     (UM_ERR_TOO_FEW_POINTS; an open UM_FEATURE_PASSAGE may have 1), exactly antipodal consecutive points, whose arc
 *     is undefined (UM_ERR_DEGENERATE_INPUT), kinds other than UM_FEATURE_*,
 *     closed flags other than 0/1 and inconsistent offsets
 *     (UM_ERR_INVALID_ARGUMENT);
 *   - cleaned: consecutive duplicate points are dropped (the first is kept);
 *     a closed part given with its first point repeated at the end stores
 *     that point once. Points are the same when their latitudes are equal and
 *     their longitudes differ by a multiple of 360 (or both are one pole);
 *   - kept as given: self-intersecting, self-touching and overlapping lines
 *     (restricted meshing filters them out where they are smaller than the
 *     spacing), longitudes outside [-180, 180];
 *   - refused (UM_ERR_INPUT): a closed part that repeats a closed ring
 *     already held or given earlier in the call (the same points from any
 *     start, either way round; a file read twice): the land and ocean sides
 *     count the rings around a point, so two copies would cancel.
 * A failing call adds nothing; its message names the argument, the part and
 * the index (for files: the feature and coordinate, as a JSON path). */
typedef struct um_features um_features;

/* Feature kinds: pinned values. */
enum {
    UM_FEATURE_COASTLINE = 1,
    UM_FEATURE_LAKE = 2,
    UM_FEATURE_RIVER = 3,
    UM_FEATURE_WATERSHED = 4,
    UM_FEATURE_OTHER = 5,
    /* Not a feature of the mesh (no vertex is put on it, no edge conforms to
     * it): a critical passage, an open line or a single point, across which
     * the ocean mesh is kept open. Every cell it passes through is in the
     * ocean mesh (cellOceanMask 1) whatever its side, even where that leaves
     * edges below the time-step floor: the quality report lists them as
     * exceptions ("ocean_floor": "kept_open"). */
    UM_FEATURE_PASSAGE = 6,
    /* A closed ring bounding a regional mesh (at least 3 points). With any
     * domain ring the mesh is regional: its cells are those inside the
     * domain, a point being inside when an odd number of rings enclose it
     * (a ring encloses what it encloses drawn in longitude and latitude,
     * whichever way it runs, so a box wider than a hemisphere is that box;
     * a ring round a pole encloses the pole it is nearer, the equator the
     * side on its left; a ring inside
     * another is a hole). The boundary conforms to the rings as a
     * coastline does; outside them the mesh is a coarse cover, growing from
     * the boundary's spacing at 1/4 km per km to 1000 km, that no output
     * holds (section "Regional meshes" below). Rings may cross the
     * antimeridian and hold a pole, but must not cross themselves or each
     * other (UM_ERR_INPUT from um_mesh_refine, naming each ring by its part,
     * id and where it came from - a file's JSON path, or the part in its
     * um_features_add_parts call - and the point where they cross). */
    UM_FEATURE_DOMAIN = 7
};

UM_API um_status um_features_create(um_context *ctx, um_features **out);
UM_API void um_features_destroy(um_features *f); /* NULL-safe */

/* Appends n_parts parts. Part p is points part_offsets[p] .. part_offsets[p+1]-1
 * of lon_deg/lat_deg (part_offsets has n_parts + 1 entries, starting at 0 and
 * ending at n_points). closed[p] is 0 or 1; kind[p] a UM_FEATURE_* value;
 * part_id[p] any int32 the caller wants back (NULL: the part's index in the
 * network, 0-based, counting earlier calls). */
UM_API um_status um_features_add(um_features *f, int64_t n_points, const double *lon_deg,
                                 const double *lat_deg, int64_t n_parts,
                                 const int64_t *part_offsets /* n_parts + 1, from 0 */,
                                 const int32_t *closed /* n_parts, 0/1 */,
                                 const int32_t *kind /* n_parts, UM_FEATURE_* */,
                                 const int32_t *part_id /* n_parts, NULL = index */);

/* Appends the lines of a GeoJSON file: a FeatureCollection, a Feature or a
 * bare geometry; LineString and MultiLineString give open or closed parts,
 * each ring of a Polygon or MultiPolygon a closed part, GeometryCollections
 * their members, each position of a Point or MultiPoint a part of one point
 * (which only a passage may be). A ring of a domain Polygon must end with its
 * first position, as GeoJSON rings do, and a hole of one must lie inside its
 * exterior ring: else UM_ERR_INPUT naming the ring (and the exterior); rings
 * of other kinds given open are closed. Per feature:
 *   kind    the string property kind_property (NULL = "kind"): "coastline",
 *           "lake", "river", "watershed", "other", "passage" or "domain"
 *           (case-insensitive); a
 *           missing or other value takes default_kind (0 = such a feature is
 *           an error, UM_ERR_INPUT);
 *   closed  always for polygon rings; else the boolean property "closed" when
 *           present; else whether the first and last positions are the same;
 *   part_id the feature's numeric "id" member, else its index in the file.
 * Unreadable files give UM_ERR_IO; malformed or truncated JSON and wrong
 * structure (missing "coordinates", non-numbers, positions with fewer than 2
 * numbers) UM_ERR_FILE_FORMAT, with the byte position or the JSON path of the
 * place. All-or-nothing: on any error no part of the file is added. */
UM_API um_status um_features_read_geojson(um_features *f, const char *path,
                                          const char *kind_property /* NULL = "kind" */,
                                          int32_t default_kind /* 0 = error on unknown */);

/* Stored counts (after cleaning); each out-pointer may be NULL. */
UM_API um_status um_features_counts(const um_features *f, int64_t *n_parts, int64_t *n_points,
                                    int64_t *n_segments);
/* The stored points as given (degrees, n_points of each); either array may be
 * NULL (not both); capacity is the elements available in each. */
UM_API um_status um_features_copy_points(const um_features *f, double *lon_deg, double *lat_deg,
                                         int64_t capacity);
/* The stored parts: part_offsets (n_parts + 1, from 0, into the stored
 * points), closed (0/1), kind (UM_FEATURE_*) and part_id (n_parts each). Any
 * array may be NULL (not all); capacity is the elements available in each and
 * must be at least n_parts + 1 when part_offsets is given, n_parts otherwise. */
UM_API um_status um_features_copy_parts(const um_features *f, int64_t *part_offsets,
                                        int32_t *closed, int32_t *kind, int32_t *part_id,
                                        int64_t capacity);

/* ------------------------------------------------------------------ spacing */

/* The mesh spacing h(x): the target edge length, in km, at each point of the
 * sphere. A spacing is created from a context in one of the forms below and
 * then refined in place by um_spacing_limit_gradient and um_spacing_clamp;
 * a failing call leaves it as it was. Distances (for gradients) are measured
 * on a sphere of radius 6371.22 km (the UM_OPT_SPHERE_RADIUS default).
 *
 * Errors common to all: a NULL required pointer (UM_ERR_NULL_ARGUMENT), a
 * context or spacing that is not live (UM_ERR_INVALID_HANDLE), NaN/Inf values
 * (UM_ERR_NONFINITE_INPUT), h <= 0 or values outside their domain
 * (UM_ERR_INVALID_ARGUMENT), latitudes outside [-90, 90]
 * (UM_ERR_COORDINATE_RANGE); the message names the argument, index and
 * value. On error *out is set to NULL. */
typedef struct um_spacing um_spacing;

/* A user spacing: h in km at a longitude/latitude in degrees (longitudes
 * in (-180, 180] when the library asks at mesh points; um_spacing_evaluate
 * passes the caller's values unchanged). Called from worker threads,
 * concurrently: it must be thread-safe. A result that is NaN, Inf or <= 0 is
 * reported as an error by the call that evaluated it, naming the point. */
typedef double (*um_spacing_fn)(void *user_data, double lon_deg, double lat_deg);

/* h = km everywhere (km finite and > 0). */
UM_API um_status um_spacing_create_constant(um_context *ctx, double km, um_spacing **out);

/* A rectilinear lon/lat grid of cell widths in km (the cellWidth(lat, lon)
 * convention of the MPAS mesh tools), read by bilinear interpolation.
 * lon_deg (n_lon >= 2) and lat_deg (n_lat >= 2) are strictly increasing, not
 * necessarily uniform; |lat| <= 90; the longitudes span at most 360 degrees,
 * in any convention (-180..180, 0..360, ...). The grid is periodic in
 * longitude when it goes round the sphere (the gap from the last longitude to
 * the first + 360 is no wider than the widest step: a last column repeating
 * the first has gap 0); a regional grid takes the value of the nearer edge
 * column outside it. Beyond the first/last latitude (towards the poles) the
 * row's value is used. cell_width_km has n_lat rows of n_lon values (lon
 * fastest), each finite and > 0. The arrays are copied. */
UM_API um_status um_spacing_create_grid(um_context *ctx, int64_t n_lon, const double *lon_deg,
                                        int64_t n_lat, const double *lat_deg,
                                        const double *cell_width_km /* n_lat * n_lon */,
                                        um_spacing **out);

/* The same grid from an MPAS-tools spacing file: netCDF with 1-D lon and lat
 * (degrees) and cellWidth(lat, lon) (km). A units attribute, when present,
 * must be km for cellWidth and not radians for lon/lat; cells holding the fill
 * value are missing data. UM_ERR_IO when the file cannot be opened;
 * UM_ERR_FILE_FORMAT when it is not netCDF, is truncated, lacks a variable or
 * holds values a grid rejects (the message names the file and the variable).
 * Classic files are checked before netCDF-C opens them; a netCDF-4 file is
 * read by libhdf5, which a damaged file can crash (no check exists for it):
 * read netCDF-4 files you do not trust in a separate process first, as
 * `unimesh build` does. */
UM_API um_status um_spacing_create_from_file(um_context *ctx, const char *path, um_spacing **out);

/* h from a user function (fn must not be NULL; user_data is passed back). */
UM_API um_status um_spacing_create_callback(um_context *ctx, um_spacing_fn fn, void *user_data,
                                            um_spacing **out);

/* The named spacings of E3SM, with the formulas of MPAS-Tools'
 * mesh_definition_tools:
 *   "QU<km>"        quasi-uniform, e.g. "QU240";
 *   "EC<a>to<b>"    EC_CellWidthVsLat with cellWidthMidLat the larger and
 *                   cellWidthEq the smaller of a and b, other parameters at
 *                   their defaults (cellWidthPole 35), e.g. "EC60to30";
 *   "RRS<a>to<b>"   RRS_CellWidthVsLat with cellWidthEq the larger and
 *                   cellWidthPole the smaller, e.g. "RRS18to6".
 * Prefixes are case-insensitive; numbers are decimal km > 0. Any other name
 * is UM_ERR_INVALID_ARGUMENT. */
UM_API um_status um_spacing_create_preset(um_context *ctx, const char *name, um_spacing **out);

UM_API void um_spacing_destroy(um_spacing *s); /* NULL-safe */

/* Limits the gradient of a grid spacing (from um_spacing_create_grid or
 * _from_file, also after a clamp or in a minimum of grids) to |grad h| <= g, g in km per km (finite,
 * > 0): every grid value becomes min over grid nodes j of (h_j + g * d), with
 * d the geodesic path length along grid neighbours (8 per node, across the
 * longitude wrap when periodic), so neighbouring values differ by at most
 * g times their distance. Other kinds: UM_ERR_INVALID_ARGUMENT. */
UM_API um_status um_spacing_limit_gradient(um_spacing *s, double g);

/* h = min(max(h, km_min), km_max); 0 < km_min <= km_max, both finite. */
UM_API um_status um_spacing_clamp(um_spacing *s, double km_min, double km_max);

/* km_out[i] = h at (lon_deg[i], lat_deg[i]), i < n (n >= 0; the arrays may be
 * NULL when n = 0). Runs in parallel in the context's threads; the values are
 * the same for any thread count. A callback value that is NaN/Inf
 * (UM_ERR_NONFINITE_INPUT) or <= 0 (UM_ERR_INVALID_ARGUMENT) is an error that
 * names the first such point; km_out is then written but not meaningful. */
UM_API um_status um_spacing_evaluate(const um_spacing *s, int64_t n, const double *lon_deg,
                                     const double *lat_deg, double *km_out);

/* What a mesh of spacing s on the Earth is expected to need, before any work:
 * cells (the sphere's area over the area of a cell of spacing h, summed over
 * 180 x 360 bands), refine_bytes (the peak of um_mesh_refine and
 * um_mesh_optimise) and mpas_bytes (what um_mesh_write_mpas adds to the
 * mesh: it streams the file a block of rows at a time, as the MPAS copy-out
 * makes each variable; um_mesh_write_components builds the whole staggered
 * mesh, about 1.6 kB per cell, judged by the cap when it does). These are the estimates
 * the memory cap judges: a caller that will write the MPAS mesh file can
 * refuse a size whose mpas_bytes exceed the cap before refining it.
 * Out-pointers may be NULL. */
UM_API um_status um_spacing_estimate(const um_spacing *s, int64_t *cells, int64_t *refine_bytes,
                                     int64_t *mpas_bytes);

/* --------------------------------------------------------------------- mesh */

/* The restricted triangulation of the sphere (paper section 5): starting from
 * the icosahedron - and, where the spacing is flat at its coarsest value h0
 * (UM_OPT_REFINE_LATTICE, on by default), the geodesic lattice of h0 less its
 * points within h0 of Gamma, so that there the mesh has no 5-7 defects; a
 * uniform spacing's mesh keeps only the twelve pentagons the sphere needs -
 * boundary refinement puts vertices on the features (Gamma)
 * until every restricted edge (an edge whose dual power edge crosses Gamma) is
 * shorter than alpha*h and closer to Gamma than beta*h, leaving out features
 * smaller than the local spacing (no new edge below h/2); surface refinement
 * then adds frontal off-centre points until every triangle has
 * sqrt(3)*circumradius < alpha*h and radius-edge ratio < rho, never inside the
 * surface ball of a restricted edge. Last (UM_OPT_REFINE_RELAX, on by
 * default), an edge-length relaxation moves the vertices away from Gamma,
 * without flips and keeping both surface bounds, until their edges lie within
 * [0.75, 1.35]*h (where fronts met, the surface pass leaves about 2 % of the
 * edges up to 1.54*h); at a crowded spot it removes a vertex or puts it where
 * the hole needs one. Vertices on or near Gamma stay, so the restricted edges
 * and sides are those of the boundary refinement. alpha, beta, rho and the
 * sphere radius come from the options (UM_OPT_REFINE_*, UM_OPT_SPHERE_RADIUS).
 *
 * Mesh vertices are numbered 0..n_vertices-1 (+ base in the copies);
 * triangles are counter-clockwise seen from outside. Deterministic: the same
 * inputs and options give the same mesh for any thread count. */
typedef struct um_mesh um_mesh;

/* Sides of the closed coastlines (parts of kind UM_FEATURE_COASTLINE that are
 * closed): land is inside an odd number of them, the inside of a ring being
 * the smaller region it bounds. */
enum {
    UM_SIDE_OCEAN = 0,
    UM_SIDE_LAND = 1,
    UM_SIDE_COASTAL = 2 /* vertices only: on a coastline, or between sides */
};

/* features and options may be NULL (no Gamma; default options). The spacing
 * is read where the refinement needs it; a value that is not finite and > 0
 * there fails the call, naming the point. */
UM_API um_status um_mesh_refine(um_context *ctx, const um_spacing *spacing,
                                const um_features *features, const um_options *options,
                                um_mesh **out);
UM_API void um_mesh_destroy(um_mesh *m); /* NULL-safe */

/* The weighted primal-dual optimisation (paper section 6, Algorithm 1), in
 * place: UM_OPT_OPTIM_OUTER_ITERATIONS outer iterations, each of
 * UM_OPT_OPTIM_INNER_ITERATIONS sweeps of vertex moves (weighted ODT towards
 * the orthocentres, spacing-weighted areas; vertices on the features slide
 * along them, or stay with UM_OPT_OPTIM_FIX_BOUNDARY) and weight ascent on the
 * worst adjacent Q^P (UM_OPT_OPTIM_WEIGHTS), then flips restoring regularity,
 * then edge collapse (< UM_OPT_OPTIM_COLLAPSE_RATIO * h) and splits
 * (> UM_OPT_OPTIM_SPLIT_RATIO * h), and while the weights are held, a vertex
 * near the circumcentre of a triangle obtuse at a vertex on the features
 * where that lowers the obtuse triangles around (UM_OPT_OPTIM_CORNER_VERTICES;
 * with 2, only where the new cell stays clear of the features), or where no
 * such vertex fits, one of the triangle's vertices on the features taken out
 * when the edge left between its neighbours along the feature still meets
 * the boundary refinement's bounds (UM_OPT_REFINE_ALPHA and _BETA as the
 * mesh was refined) and no more triangles around are obtuse; in the first
 * iterations (at most UM_OPT_OPTIM_RESEED_ROUNDS, while each lowers the
 * defects by a tenth, leaving three to relax), the vertices of degree other
 * than 6 away from the features are taken out with the rings of vertices
 * around them and the holes refilled by the refinement from the regular
 * lattice around (fewer 5-7 defects: where the MPAS divergence, kinetic
 * energy and TRSK errors sit); an update of
 * a vertex is taken only if it lets the features into no more cells of
 * vertices off them around it than before, and only if the worst
 * quality of its triangles improves (or stays, and their mean improves), a
 * weight only if it leaves every adjacent dual edge crossing its primal edge
 * (no vertex can become hidden). Stops early when an outer iteration changes
 * no quality summary by more than UM_OPT_OPTIM_TOLERANCE. The first half of
 * the outer iterations moves vertices and holds the weights; then
 * UM_OPT_OPTIM_CENTROIDAL_SWEEPS Lloyd sweeps move every vertex off the
 * features towards the centroid of its power cell under the density h^-4 (a
 * centroidal Voronoi tessellation: what makes the MPAS operators accurate),
 * each step only as far as it keeps the star valid, lets the features into
 * no more cells and keeps every triangle's area-length ratio at least 0.925,
 * its angles at most 81 degrees and its Q^P at least 0.99 (or as they were); the second half then
 * changes only weights, and only around triangles whose Q^P is below 0.99,
 * each only just past that (or any triangle not holding its orthocentre; weights
 * move xEdge off the primal edge's midpoint, which costs the curl accuracy).
 * After the iterations, two serial joint searches: each triangle not containing its
 * orthocentre gets the weights (and, on the features, the slides) of its
 * vertices searched together, and then each obtuse triangle the positions of
 * its three vertices; a combination is taken only if it leaves fewer such
 * triangles around, no more off-centre ones, and no Q^P, Q^T, angle or edge
 * length past the mesh's own bounds. Sweeps are graph-coloured and run in
 * parallel; the mesh is bit-identical for any thread count. options may be NULL (defaults); ctx is the mesh's context.
 * Progress: stage "optimise", once per outer iteration; cancelling there (or
 * any error) leaves m exactly as it was. Afterwards the quality report holds
 * the refined mesh's metrics too ("before_optimisation") and the counts and
 * times of the optimisation ("optimisation"). Optimising twice continues
 * from the optimised mesh. */
UM_API um_status um_mesh_optimise(um_mesh *m, const um_options *options);

/* n_restricted_edges: edges of Tri|Gamma; n_filtered: bad restricted edges
 * left unrefined because their feature is smaller than the spacing. */
UM_API um_status um_mesh_counts(const um_mesh *m, int64_t *n_vertices, int64_t *n_triangles,
                                int64_t *n_restricted_edges, int64_t *n_filtered);
/* Vertex positions in degrees (lon in (-180, 180]); capacity >= n_vertices. */
UM_API um_status um_mesh_copy_vertices(const um_mesh *m, double *lon_deg, double *lat_deg,
                                       int64_t capacity);
/* 3 vertex indices (+ base) per triangle; capacity >= 3 * n_triangles. */
UM_API um_status um_mesh_copy_triangles(const um_mesh *m, int32_t base, int32_t *out,
                                        int64_t capacity);
/* Per vertex: the features part (+ base) it was placed on, or -1 (whatever
 * the base) when it is not on Gamma; capacity >= n_vertices. */
UM_API um_status um_mesh_copy_vertex_parts(const um_mesh *m, int32_t base, int32_t *out,
                                           int64_t capacity);
/* Per restricted edge: its two vertices (+ base) and the part (+ base) whose
 * segment its dual edge crosses; capacity >= n_restricted_edges. */
UM_API um_status um_mesh_copy_restricted_edges(const um_mesh *m, int32_t base,
                                               int32_t *vertices /* 2 per edge */,
                                               int32_t *parts, int64_t capacity);
/* UM_SIDE_* per vertex (capacity >= n_vertices) and per triangle (of its
 * orthocentre; capacity >= n_triangles). */
UM_API um_status um_mesh_copy_vertex_sides(const um_mesh *m, int32_t *out, int64_t capacity);
UM_API um_status um_mesh_copy_triangle_sides(const um_mesh *m, int32_t *out, int64_t capacity);

/* Quality (the paper's Figure 10 metrics, DESIGN.md section 5): per triangle
 * the area-length ratio Q^T (1 = equilateral), the primal-dual staggering Q^P
 * (eq. 1), the smallest and largest angles (degrees), and per edge its length
 * over the spacing at its midpoint (h_r). Arc lengths and geodesic areas on
 * the sphere. The JSON report holds, for each metric, min / 1st percentile /
 * mean / max and a 50-bin histogram, and the counts of obtuse triangles and
 * of triangles that do not contain their orthocentre; it is copied out as
 * strings are.
 * Its "operator_diagnostics" certify the mesh for the MPAS operators, whose
 * errors these offsets drive (divergence and kinetic energy: the dual-edge
 * offset; curl: the primal-edge offset; TRSK: the centroid offset). With
 * xEdge where the dual arc of an edge crosses its primal arc:
 *   "centroid_offset"     per cell, arc(xCell, centroid of the cell) /
 *                         sqrt(areaCell): rms and max;
 *   "dual_edge_offset"    per edge, arc(xEdge, midpoint of the dual arc) /
 *                         dvEdge: rms and max (a dual edge of no length
 *                         counts as 2^-52 rad long: an offset of ~1e16);
 *   "primal_edge_offset"  per edge, arc(xEdge, midpoint of the primal arc) /
 *                         dcEdge: rms and max (0 on a Voronoi mesh);
 *   "cell_spacing_ratio"  per edge, dcEdge / h(xEdge): min, max, mean, std.
 * Its "ocean_floor" certifies the time step (UM_OPT_OCEAN_FLOOR): "floor" (the
 * floor the mesh was built to), "ocean_edges" (edges between two cells of the
 * ocean mesh, the cellOceanMask rule), "min_ratio" (their least dcEdge /
 * h(xEdge)), "all_edges_min_ratio", "below_floor" (ocean edges below the
 * floor) and "regions": {"count", "largest": [[cells, lon, lat], ...]}, the
 * connected regions of the ocean mesh, largest first (at most 100 listed),
 * each at its cell of the lowest slot: compare with a build without the floor
 * to see a channel it closed.
 * A mesh of an ellipsoid ("Surfaces") adds "geodesic", measured on the
 * ellipsoid with GeographicLib: "ellipsoid" {"semi_major_axis_m",
 * "flattening"}, "edges" and "length_over_h" {min, mean, max} (each edge's
 * geodesic length between the geodetic lon/lat of its ends over h in
 * geodesic km at its midpoint), "cells" and "cell_area_m2" (the sum of the
 * power cells' geodesic polygon areas) beside "ellipsoid_area_m2"; made
 * when this report is first asked for (about 4 us a cell on 2 threads), so
 * the "before_optimisation" report has it only when the report of the mesh
 * was asked for before um_mesh_optimise.
 * The summary takes a metric name: "area_length_ratio", "primal_dual",
 * "angle_min_deg", "angle_max_deg", "edge_spacing_ratio", or one of the four
 * operator diagnostics above, and gives its min, 1st percentile (over the
 * cells, or the edges), mean and max; the rms and std are in the JSON report
 * only (out-pointers may be NULL). */
UM_API um_status um_mesh_quality_json(const um_mesh *m, char *buf, int64_t capacity,
                                      int64_t *needed);
UM_API um_status um_mesh_quality_summary(const um_mesh *m, const char *metric, double *min,
                                         double *p1, double *mean, double *max);
UM_API um_status um_mesh_quality_counts(const um_mesh *m, int64_t *obtuse,
                                        int64_t *not_well_centred);

/* ---------------------------------------------------------------- Surfaces */

/* With UM_OPT_SURFACE_FLATTENING f > 0, um_mesh_refine meshes the ellipsoid
 * of semi-major axis a = UM_OPT_SPHERE_RADIUS and flattening f (WGS84: a =
 * 6378137 m, f = 1/298.257223563; f at most 0.02) instead of the sphere.
 * Longitudes and latitudes (features, spacing grids and callbacks) are
 * geodetic; spacing in km is geodesic km on the ellipsoid. The
 * triangulation is the same lifted hull of unit directions, each direction
 * standing for the ellipsoid point along it (DESIGN.md section 3);
 * um_mesh_copy_vertices gives the vertices' geodetic lon/lat. The radial map is conformal to within f^2, so the quality metrics (all
 * ratios of lengths and angles) are the ellipsoid's to that accuracy.
 * Distances inside the spacing kinds (feature-distance ramps, the gradient
 * limit) are measured at geodetic lon/lat on the sphere of radius a: within
 * 2f of geodesic.
 * Outputs: MPAS assumes a sphere, so the MPAS mesh (file and copy-out) puts
 * every generator (xCell) at the geodetic lat/lon of its ellipsoid point on
 * the sphere of the ellipsoid's authalic radius (sphere_radius; the cells'
 * areas add up to the ellipsoid's area) and is the power diagram of the
 * generators so placed, with their weights: vertices at its power vertices,
 * orthogonal, every length, area and weight of that sphere (where the move,
 * at most 2f off conformal, breaks regularity, as near-cocircular
 * triangles of an unoptimised mesh may, an edge is flipped, losing its
 * feature and river tags); the file's global attributes surface = "ellipsoid",
 * ellipsoid_semi_major_axis, ellipsoid_flattening and surface_note say so.
 * The JIGSAW file and the CLI's VTU files put their points on the
 * ellipsoid. With f = 0 (the default) every result is bit for bit the
 * sphere's. */

/* --------------------------------------------------------- Regional meshes */

/* Features holding UM_FEATURE_DOMAIN rings make um_mesh_refine build a
 * regional mesh. Its edges are straight in longitude and latitude, as
 * GeoJSON draws them (divided into great arcs of at most 0.25 degrees), so a
 * box of longitudes and latitudes is that box (an edge to or from a pole
 * runs along the other end's meridian: a pole has no longitude); each edge goes the shorter
 * way round in longitude (160 to -160 crosses the antimeridian, as 160 to
 * 200 does), so an edge of 180 degrees of longitude or more needs points
 * between (a ring around a pole: points along its parallel) - except an
 * edge of 360 degrees or more (-180 to 180), which runs that far: a ring
 * with one is read as GIS tools draw a polar cap (along the pole, along
 * the antimeridian and round the sphere, [[-180, -90], [180, -90], [180,
 * -60], [-180, -60], [-180, -90]] for the cap south of 60 S) and stands for
 * the ring round that pole, refused (UM_ERR_INPUT) when it is no such cap
 * or a cap larger than a hemisphere; a ring that crosses itself or
 * another is refused (UM_ERR_INPUT), as is a domain holding fewer than 7
 * cells at the spacing ("it must be larger than the spacing"). The mesh's
 * boundary conforms to the rings the way it conforms to a coastline (the
 * restricted edges and their alpha/beta bounds; ring vertices slide along
 * the rings in the optimisation). The triangulation still covers the sphere:
 * outside the domain a coarse cover, growing from the boundary's spacing at
 * 1/4 km per km to 1000 km, which costs about the perimeter over the spacing
 * in cells (10 to 15 % more than the domain holds at 30 km); the counts and
 * copies of um_mesh_counts, um_mesh_copy_vertices, um_mesh_copy_triangles
 * and the other um_mesh_copy_* of the triangulation include it.
 * The MPAS mesh (um_mesh_write_mpas, um_mesh_mpas_dimensions,
 * um_mesh_copy_mpas_*) holds the domain only: the cells inside the domain
 * whose neighbours are all inside or on a ring (each cell then lies within
 * the domain), cut as MPAS-Tools culls cells (0 for the missing neighbour in
 * cellsOnCell, cellsOnEdge, cellsOnVertex; boundaryVertex 1), plus the
 * limited-area layers bdyMaskCell (7 on cells with a missing neighbour, 6
 * on their neighbours, ... down to 1, 0 inside: MPAS-Atmosphere's
 * specified zone 6-7 and relaxation zone 1-5), bdyMaskEdge and
 * bdyMaskVertex (the least of their cells'). It is streamed as a global
 * mesh is (never held whole), its rows the region's elements in the order
 * of the whole triangulation's numbering. The quality report counts the
 * domain's cells and the triangles and edges between them only,
 * um_mesh_write_jigsaw writes those cells and the triangles between three
 * of them, and um_mesh_write_components splits the domain's MPAS mesh (the
 * components keep the base's bdyMask*; a river network that reaches no
 * ocean cell inside the domain drains to where its lines leave it across
 * the boundary: rivers.json's and um_mesh_river_report_json's
 * "boundary_outlets"; the mesh's own downstreamCell and
 * edgeRiverDownstream route the same way). */

/* -------------------------------------------------------------- MPAS output */

/* Writes the MPAS staggered mesh of m to a netCDF file at path (created or
 * overwritten), in the form MPAS-Tools' MpasMeshConverter.x writes:
 *   cells     the power cells of the mesh vertices (xCell = the generator);
 *   vertices  the triangles, at their orthocentres (power vertices), not
 *             their circumcentres;
 *   edges     one per triangle edge: the primal (cell-cell) arc and the dual
 *             (vertex-vertex) arc, orthogonal; xEdge is where they cross.
 * Every variable of the MPAS mesh specification (dimensions nCells, nEdges,
 * nVertices, maxEdges, maxEdges2, TWO, vertexDegree = 3, Time), int32
 * connectivity 1-based with 0 padding, doubles for the rest; orderings
 * counter-clockwise seen from outside; n_e from cellsOnEdge(e,1) to (e,2),
 * k x n_e from verticesOnEdge(e,1) to (e,2); signed geodesic areas and kites;
 * TRSK weightsOnEdge (Thuburn et al. 2009); exact angleEdge; lat/lon in
 * radians, longitudes in (-pi, pi]; lengths in m and areas in m^2 on the
 * sphere of radius UM_OPT_SPHERE_RADIUS given to um_mesh_refine (an
 * ellipsoid's authalic radius: "Surfaces" above);
 * meshDensity = (min h / h)^4 from the spacing h the mesh was refined to, at
 * the generators (the minimum over the cells). Unified tags: cellSide (per
 * cell) and vertexSide (per vertex), UM_SIDE_* values with flag_values /
 * flag_meanings attributes.
 * Global attributes on_a_sphere = "YES", sphere_radius, is_periodic = "NO",
 * mesh_spec = "1.0", Conventions = "MPAS", source = "unimesh <version>" and a
 * file_id hashed from the content.
 *
 * Cells, edges and vertices are numbered along a space-filling curve so that
 * neighbours have nearby indices. The file is netCDF classic 64-bit offset,
 * or CDF-5 when a variable is too large for it (meshes of about 8 million
 * cells and more). The same mesh gives the same bytes for any thread count.
 * The file is streamed: made and written a block of rows at a time, so that
 * it needs about 160 bytes per cell beyond the mesh (280 with features,
 * while the rivers are routed) and two blocks of rows (the staggered mesh
 * whole would be about 1.2 kB per cell). The progress callback sees stage
 * "MPAS mesh" before the numbering and after each block; cancelling at any
 * of them leaves path as it was.
 * The file is written under a temporary name in path's directory (".NAME.part-
 * PID-N"), flushed to disk and renamed over path only when complete: a failed
 * or interrupted write leaves whatever was at path as it was (and removes its
 * temporary file). A path that names a directory, a device, a FIFO or a
 * socket is refused before anything is written.
 * Errors: UM_ERR_IO naming the file,
 * UM_ERR_LIMIT when a count does not fit int32, UM_ERR_MEMORY_CAP, and the
 * spacing's errors if a callback spacing gives a value that is not finite
 * and > 0 at a generator. */
UM_API um_status um_mesh_write_mpas(const um_mesh *m, const char *path);
/* um_mesh_write_mpas in the container asked for: UM_MPAS_FILE_AUTO (what
 * um_mesh_write_mpas writes) or UM_MPAS_FILE_NETCDF4 (netCDF-4/HDF5, for
 * tools and I/O layers that want it; the same variables and attributes, the
 * same bytes for any thread count). UM_ERR_INVALID_ARGUMENT for another
 * format, naming it. */
enum { UM_MPAS_FILE_AUTO = 0, UM_MPAS_FILE_NETCDF4 = 1 };
UM_API um_status um_mesh_write_mpas_as(const um_mesh *m, const char *path, int32_t format);

/* The same staggered mesh in memory, variable by variable, so that a model
 * builds its arrays without a file. Every variable of the file is there by
 * its netCDF name (e.g. "cellsOnEdge", "edgesOnCell", "dcEdge", "dvEdge",
 * "areaCell", "weightsOnEdge", the tags "cellOceanMask", "edgeFeatureKind",
 * ...). The staggered mesh is never held whole: the first call numbers it
 * (about 160 bytes per cell, 280 while the rivers of a mesh with features
 * are routed, 48 more for a regional mesh's rows) and that numbering is kept with m until um_mesh_release_mpas,
 * um_mesh_optimise or um_mesh_destroy; each copy makes its variable's
 * values a block of rows at a time straight into out. A copy therefore
 * costs about as much time as making that variable's share of the file:
 * copying every variable takes longer than writing the file once (about
 * 1.4 times at 30 km), with nothing held but the numbering and one block.
 *
 * A variable of n_rows x n_columns values (n_columns = 1 for one
 * dimension) is copied row after row: out[r * n_columns + c] is the file's
 * var(r, c), which a Fortran caller sees as var(c + 1, r + 1), MPAS's own
 * layout (e.g. cellsOnEdge(2, nEdges)). Index variables (cellsOnEdge,
 * edgesOnCell, ..., indexToCellID) get base added: base 1 gives the file's
 * 1-based values with 0 padding, base 0 gives 0-based values with -1
 * padding; other integers (nEdgesOnCell, the tags) are copied as they are.
 * type: UM_MPAS_REAL (copy with um_mesh_copy_mpas_real) or UM_MPAS_INT
 * (um_mesh_copy_mpas_int). Errors: UM_ERR_INVALID_ARGUMENT for a name that
 * is not a variable of this mesh or a copy of the other type (naming both),
 * UM_ERR_BUFFER_TOO_SMALL when capacity < n_rows * n_columns. */
enum { UM_MPAS_REAL = 1, UM_MPAS_INT = 2 };
UM_API um_status um_mesh_mpas_dimensions(const um_mesh *m, int64_t *n_cells, int64_t *n_edges,
                                         int64_t *n_vertices, int64_t *max_edges);
UM_API um_status um_mesh_mpas_variable(const um_mesh *m, const char *name, int32_t *type,
                                       int64_t *n_rows, int64_t *n_columns);
UM_API um_status um_mesh_copy_mpas_real(const um_mesh *m, const char *name, double *out,
                                        int64_t capacity);
UM_API um_status um_mesh_copy_mpas_int(const um_mesh *m, const char *name, int32_t base,
                                       int32_t *out, int64_t capacity);
/* The triangulation in JIGSAW's .msh format (MSHID=3;EUCLIDEAN-MESH, for
 * interchange with the JIGSAW tools): POINT x;y;z of the generators on the
 * sphere (m), POWER their weights (m^2), TRIA3 the triangles (0-based, the
 * order of um_mesh_copy_triangles). Of a regional mesh, the cells of its
 * MPAS mesh (numbered in the vertex order without the others) and the
 * triangles between three of them. Written and renamed into place as
 * um_mesh_write_mpas does. UM_ERR_IO naming the file. */
UM_API um_status um_mesh_write_jigsaw(const um_mesh *m, const char *path);

/* Frees the numbering kept by the calls above (m stays valid). */
UM_API um_status um_mesh_release_mpas(um_mesh *m);

/* -------------------------------------------------------- component meshes */

/* One unified mesh, every component's files. The cells of a mesh made with
 * closed coastlines split into the ocean mesh (cellOceanMask = 1) and the
 * land mesh (cellLandMask = 1: land and river cells); every cell is in
 * exactly one. Each component is a valid MPAS mesh with a boundary, cut out
 * the way MPAS-Tools' cell culler cuts: its cells, every edge and vertex of
 * theirs, numbered 1.. in the base mesh's order; 0 in cellsOnCell,
 * cellsOnEdge(2, e), cellsOnVertex and edgesOnVertex where the neighbour is
 * in the other component; boundaryVertex = 1 at the vertices of the cut.
 * cellsOnEdge(1, e) is always a cell of the component: an edge whose first
 * cell is cut off is turned around with its vertices, angleEdge and river
 * direction. Areas, lengths and kites are the base mesh's; weightsOnEdge
 * keeps the TRSK stencil of the edge's cells in the component. Each
 * component has baseCellId, baseEdgeId and baseVertexId (the base mesh's
 * ids); the base gets oceanCellId, landCellId, oceanEdgeId, landEdgeId,
 * oceanVertexId and landVertexId (0 where an element is not in that
 * component; an edge or vertex of the cut is in both).
 *
 * River routing (in every MPAS mesh with rivers, and carried into the land
 * mesh): edgeOnRiver marks the edges a river's line crosses (the cells
 * along each river segment, in order); per cell downstreamCell (the cell its
 * river drains to, 0 none) and riverCellKind (0 no river, 1 routed, 2
 * outlet, 3 inland). The direction comes from the network's topology: the
 * cells from which a river crosses into an ocean cell are its outlets (for a
 * network whose lines end short of the sea, its cells beside the ocean), and
 * every other river cell drains along the shortest path of river edges to
 * the nearest outlet of its network. Networks that reach no coast (inland)
 * and networks with cycles are reported.
 *
 * um_mesh_write_components writes into directory (which must exist):
 *   mesh.nc                 the base MPAS mesh (as um_mesh_write_mpas) with
 *                           the maps to the components;
 *   ocean.nc, land.nc       the component MPAS meshes;
 *   ocean.graph.info, land.graph.info   their METIS graphs (for gpmetis);
 *   mesh.scrip.nc, ocean.scrip.nc, land.scrip.nc   SCRIP grids (grid_center_
 *                           lat/lon, grid_corner_lat/lon in degrees from the
 *                           cells' vertices, grid_area in radians^2,
 *                           grid_imask, grid_dims), as CDO and
 *                           ESMF_RegridWeightGen read them;
 *   mesh.esmf.nc, ocean.esmf.nc, land.esmf.nc   ESMF unstructured meshes
 *                           (nodeCoords, elementConn, numElementConn,
 *                           centerCoords, elementArea, elementMask);
 *   rivers.json             the river report (um_mesh_river_report_json).
 * The files are written into a new directory inside directory and renamed
 * into it together when all are complete: a failure leaves the set there
 * before as it was.
 * um_mpas_file_write_components does the same from an MPAS mesh file (ours,
 * with cellOceanMask and cellLandMask; the river routing is made again from
 * its edgeFeatureKind); it reads netCDF-4 files in-process, with netCDF-C.
 * Errors: UM_ERR_INVALID_ARGUMENT for a mesh without the cell masks or with
 * an empty component; UM_ERR_IO naming the file or directory;
 * UM_ERR_FILE_FORMAT naming what is wrong in mesh_path; UM_ERR_MEMORY_CAP. */
UM_API um_status um_mesh_write_components(const um_mesh *m, const char *directory);
UM_API um_status um_mpas_file_write_components(um_context *ctx, const char *mesh_path,
                                               const char *directory);
/* The river routing report as JSON: {"networks", "river_cells",
 * "routed_cells", "outlets", "boundary_outlets" (of the outlets, those
 * where a regional mesh's river leaves it across its boundary), "bridges"
 * (gaps joined where the mesh has no edgeOnRiver), "inland_cells",
 * "inland_networks": [...],
 * "networks_with_cycles": [...]}, each listed network as {"network",
 * "cells", "cycles", "cell" (its lowest 1-based MPAS cell id), "lat", "lon"
 * (degrees)}. Copied out as um_mesh_quality_json does. */
UM_API um_status um_mesh_river_report_json(const um_mesh *m, char *buf, int64_t capacity,
                                           int64_t *needed);

#ifdef __cplusplus
} /* extern "C" */
#endif

#endif /* UNIMESH_H */
