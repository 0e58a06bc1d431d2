! unimesh_cint -- the raw C interoperability layer of the Fortran binding.
!
! One bind(c) interface per function of include/unimesh.h and one parameter
! per constant, nothing else: no logic lives here, so this module can be read
! against the header line by line (and bindings/fortran/tests/
! check_fortran_binding.py does exactly that in ctest). Most Fortran code
! should `use unimesh`, the friendly layer built on top of this one.
!
! Conventions of this file (the checker relies on them):
!   - Each interface is named c_<C name> and binds to the C name, so the
!     friendly module can use the C names (um_...) for its own routines.
!   - Dummy arguments have the header's parameter names, so keyword calls
!     read like the C documentation.
!   - Handles are type(c_ptr): `value` for um_x *, by reference for um_x **.
!   - Pointers the header allows to be NULL are `optional` (Fortran 2018
!     passes an absent optional as NULL to a bind(c) procedure).
!   - Returned C strings are type(c_ptr); strings in are NUL-terminated
!     character(kind=c_char) arrays.
module unimesh_cint
  use, intrinsic :: iso_c_binding, only: c_int32_t, c_int64_t, c_double, c_char, c_ptr, c_funptr
  implicit none
  private :: c_int32_t, c_int64_t, c_double, c_char, c_ptr, c_funptr

  ! ------------------------------------------------------------------ version
  integer(c_int32_t), parameter :: UM_VERSION_MAJOR = 0
  integer(c_int32_t), parameter :: UM_VERSION_MINOR = 1
  integer(c_int32_t), parameter :: UM_VERSION_PATCH = 0
  integer(c_int32_t), parameter :: UM_VERSION_NUMBER = &
      UM_VERSION_MAJOR * 10000 + UM_VERSION_MINOR * 100 + UM_VERSION_PATCH
  character(len=*), parameter :: UM_VERSION_STRING = "0.1.0"

  ! ------------------------------------------------------------------ status
  integer(c_int32_t), parameter :: UM_OK = 0

  integer(c_int32_t), parameter :: UM_ERR_USAGE = 100
  integer(c_int32_t), parameter :: UM_ERR_NULL_ARGUMENT = 101
  integer(c_int32_t), parameter :: UM_ERR_INVALID_HANDLE = 102
  integer(c_int32_t), parameter :: UM_ERR_INVALID_ARGUMENT = 103
  integer(c_int32_t), parameter :: UM_ERR_UNKNOWN_OPTION = 104
  integer(c_int32_t), parameter :: UM_ERR_OPTION_TYPE = 105
  integer(c_int32_t), parameter :: UM_ERR_BUFFER_TOO_SMALL = 106
  integer(c_int32_t), parameter :: UM_ERR_WRONG_ORDER = 107

  integer(c_int32_t), parameter :: UM_ERR_INPUT = 200
  integer(c_int32_t), parameter :: UM_ERR_NONFINITE_INPUT = 201
  integer(c_int32_t), parameter :: UM_ERR_COORDINATE_RANGE = 202
  integer(c_int32_t), parameter :: UM_ERR_DUPLICATE_POINTS = 203
  integer(c_int32_t), parameter :: UM_ERR_TOO_FEW_POINTS = 204
  integer(c_int32_t), parameter :: UM_ERR_DEGENERATE_INPUT = 205

  integer(c_int32_t), parameter :: UM_ERR_NUMERICAL = 300

  integer(c_int32_t), parameter :: UM_ERR_OUT_OF_MEMORY = 400
  integer(c_int32_t), parameter :: UM_ERR_MEMORY_CAP = 401
  integer(c_int32_t), parameter :: UM_ERR_LIMIT = 402

  integer(c_int32_t), parameter :: UM_ERR_IO = 500
  integer(c_int32_t), parameter :: UM_ERR_FILE_FORMAT = 501

  integer(c_int32_t), parameter :: UM_CANCELLED = 600

  integer(c_int32_t), parameter :: UM_ERR_INTERNAL = 900

  ! ------------------------------------------------------------------ context
  integer(c_int32_t), parameter :: UM_LOG_DEBUG = 10
  integer(c_int32_t), parameter :: UM_LOG_INFO = 20
  integer(c_int32_t), parameter :: UM_LOG_WARNING = 30
  integer(c_int32_t), parameter :: UM_LOG_ERROR = 40

  integer(c_int32_t), parameter :: UM_ERROR_MODE_RETURN = 0
  integer(c_int32_t), parameter :: UM_ERROR_MODE_ABORT = 1

  ! ------------------------------------------------------------------ options
  integer(c_int32_t), parameter :: UM_OPT_SPHERE_RADIUS = 1
  integer(c_int32_t), parameter :: UM_OPT_SURFACE_FLATTENING = 2
  integer(c_int32_t), parameter :: UM_OPT_REFINE_ALPHA = 100
  integer(c_int32_t), parameter :: UM_OPT_REFINE_BETA = 101
  integer(c_int32_t), parameter :: UM_OPT_REFINE_RHO = 102
  integer(c_int32_t), parameter :: UM_OPT_REFINE_TOPOLOGY_CHECK = 103
  integer(c_int32_t), parameter :: UM_OPT_REFINE_RELAX = 104
  integer(c_int32_t), parameter :: UM_OPT_REFINE_LATTICE = 105
  integer(c_int32_t), parameter :: UM_OPT_SPACING_GRADIENT = 106
  integer(c_int32_t), parameter :: UM_OPT_OPTIM_OUTER_ITERATIONS = 200
  integer(c_int32_t), parameter :: UM_OPT_OPTIM_INNER_ITERATIONS = 201
  integer(c_int32_t), parameter :: UM_OPT_OPTIM_TOLERANCE = 202
  integer(c_int32_t), parameter :: UM_OPT_OPTIM_WEIGHTS = 203
  integer(c_int32_t), parameter :: UM_OPT_OPTIM_FIX_BOUNDARY = 204
  integer(c_int32_t), parameter :: UM_OPT_OPTIM_COLLAPSE_RATIO = 205
  integer(c_int32_t), parameter :: UM_OPT_OPTIM_SPLIT_RATIO = 206
  integer(c_int32_t), parameter :: UM_OPT_OPTIM_CORNER_VERTICES = 207
  integer(c_int32_t), parameter :: UM_OPT_OPTIM_CENTROIDAL_SWEEPS = 208
  integer(c_int32_t), parameter :: UM_OPT_OPTIM_RESEED_ROUNDS = 209
  integer(c_int32_t), parameter :: UM_OPT_OCEAN_FLOOR = 300

  integer(c_int32_t), parameter :: UM_OPTION_TYPE_INT = 1
  integer(c_int32_t), parameter :: UM_OPTION_TYPE_REAL = 2

  ! ---------------------------------------------- features (polyarc networks)
  integer(c_int32_t), parameter :: UM_FEATURE_COASTLINE = 1
  integer(c_int32_t), parameter :: UM_FEATURE_LAKE = 2
  integer(c_int32_t), parameter :: UM_FEATURE_RIVER = 3
  integer(c_int32_t), parameter :: UM_FEATURE_WATERSHED = 4
  integer(c_int32_t), parameter :: UM_FEATURE_OTHER = 5
  integer(c_int32_t), parameter :: UM_FEATURE_PASSAGE = 6
  integer(c_int32_t), parameter :: UM_FEATURE_DOMAIN = 7

  ! --------------------------------------------------------------------- mesh
  integer(c_int32_t), parameter :: UM_SIDE_OCEAN = 0
  integer(c_int32_t), parameter :: UM_SIDE_LAND = 1
  integer(c_int32_t), parameter :: UM_SIDE_COASTAL = 2
  integer(c_int32_t), parameter :: UM_MPAS_REAL = 1
  integer(c_int32_t), parameter :: UM_MPAS_INT = 2
  integer(c_int32_t), parameter :: UM_MPAS_FILE_AUTO = 0
  integer(c_int32_t), parameter :: UM_MPAS_FILE_NETCDF4 = 1

  ! ---------------------------------------------------------- callback types
  ! The header's function-pointer typedefs, for writing callbacks in Fortran:
  ! `procedure(um_log_fn) :: my_log` and pass c_funloc(my_log). Strings
  ! arrive as NUL-terminated C pointers.
  abstract interface
    integer(c_int32_t) function um_progress_fn(user_data, stage, fraction) bind(c)
      import :: c_int32_t, c_ptr, c_double
      type(c_ptr), value :: user_data
      type(c_ptr), value :: stage
      real(c_double), value :: fraction
    end function um_progress_fn

    subroutine um_log_fn(user_data, level, message) bind(c)
      import :: c_int32_t, c_ptr
      type(c_ptr), value :: user_data
      integer(c_int32_t), value :: level
      type(c_ptr), value :: message
    end subroutine um_log_fn

    subroutine um_abort_fn(user_data, status, message) bind(c)
      import :: c_int32_t, c_ptr
      type(c_ptr), value :: user_data
      integer(c_int32_t), value :: status
      type(c_ptr), value :: message
    end subroutine um_abort_fn

    ! A spacing in km at a point in degrees; called from worker threads,
    ! concurrently (it must be thread-safe).
    real(c_double) function um_spacing_fn(user_data, lon_deg, lat_deg) bind(c)
      import :: c_ptr, c_double
      type(c_ptr), value :: user_data
      real(c_double), value :: lon_deg
      real(c_double), value :: lat_deg
    end function um_spacing_fn
  end interface

  interface
    ! ---------------------------------------------------------------- version
    integer(c_int32_t) function c_um_version_number() bind(c, name="um_version_number")
      import :: c_int32_t
    end function c_um_version_number

    subroutine c_um_version(major, minor, patch) bind(c, name="um_version")
      import :: c_int32_t
      integer(c_int32_t), intent(out), optional :: major
      integer(c_int32_t), intent(out), optional :: minor
      integer(c_int32_t), intent(out), optional :: patch
    end subroutine c_um_version

    type(c_ptr) function c_um_version_string() bind(c, name="um_version_string")
      import :: c_ptr
    end function c_um_version_string

    ! ----------------------------------------------------------------- status
    type(c_ptr) function c_um_status_string(status) bind(c, name="um_status_string")
      import :: c_ptr, c_int32_t
      integer(c_int32_t), value :: status
    end function c_um_status_string

    integer(c_int32_t) function c_um_status_class(status) bind(c, name="um_status_class")
      import :: c_int32_t
      integer(c_int32_t), value :: status
    end function c_um_status_class

    ! ---------------------------------------------------------------- context
    integer(c_int32_t) function c_um_context_create(out) bind(c, name="um_context_create")
      import :: c_int32_t, c_ptr
      type(c_ptr), intent(out) :: out
    end function c_um_context_create

    subroutine c_um_context_destroy(ctx) bind(c, name="um_context_destroy")
      import :: c_ptr
      type(c_ptr), value :: ctx
    end subroutine c_um_context_destroy

    integer(c_int32_t) function c_um_context_set_threads(ctx, n_threads) &
        bind(c, name="um_context_set_threads")
      import :: c_int32_t, c_ptr
      type(c_ptr), value :: ctx
      integer(c_int32_t), value :: n_threads
    end function c_um_context_set_threads

    integer(c_int32_t) function c_um_context_get_threads(ctx, n_threads) &
        bind(c, name="um_context_get_threads")
      import :: c_int32_t, c_ptr
      type(c_ptr), value :: ctx
      integer(c_int32_t), intent(out) :: n_threads
    end function c_um_context_get_threads

    integer(c_int32_t) function c_um_context_set_progress(ctx, fn, user_data) &
        bind(c, name="um_context_set_progress")
      import :: c_int32_t, c_ptr, c_funptr
      type(c_ptr), value :: ctx
      type(c_funptr), value :: fn
      type(c_ptr), value :: user_data
    end function c_um_context_set_progress

    integer(c_int32_t) function c_um_context_set_log(ctx, fn, user_data, min_level) &
        bind(c, name="um_context_set_log")
      import :: c_int32_t, c_ptr, c_funptr
      type(c_ptr), value :: ctx
      type(c_funptr), value :: fn
      type(c_ptr), value :: user_data
      integer(c_int32_t), value :: min_level
    end function c_um_context_set_log

    integer(c_int32_t) function c_um_context_set_worker_placement(ctx, on) &
        bind(c, name="um_context_set_worker_placement")
      import :: c_int32_t, c_ptr
      type(c_ptr), value :: ctx
      integer(c_int32_t), value :: on
    end function c_um_context_set_worker_placement

    integer(c_int32_t) function c_um_context_set_memory_cap(ctx, bytes) &
        bind(c, name="um_context_set_memory_cap")
      import :: c_int32_t, c_int64_t, c_ptr
      type(c_ptr), value :: ctx
      integer(c_int64_t), value :: bytes
    end function c_um_context_set_memory_cap

    integer(c_int32_t) function c_um_context_get_memory_cap(ctx, bytes) &
        bind(c, name="um_context_get_memory_cap")
      import :: c_int32_t, c_int64_t, c_ptr
      type(c_ptr), value :: ctx
      integer(c_int64_t), intent(out) :: bytes
    end function c_um_context_get_memory_cap

    integer(c_int32_t) function c_um_context_set_error_mode(ctx, mode, hook, user_data) &
        bind(c, name="um_context_set_error_mode")
      import :: c_int32_t, c_ptr, c_funptr
      type(c_ptr), value :: ctx
      integer(c_int32_t), value :: mode
      type(c_funptr), value :: hook
      type(c_ptr), value :: user_data
    end function c_um_context_set_error_mode

    type(c_ptr) function c_um_context_last_error(ctx) bind(c, name="um_context_last_error")
      import :: c_ptr
      type(c_ptr), value :: ctx
    end function c_um_context_last_error

    integer(c_int32_t) function c_um_context_last_status(ctx) &
        bind(c, name="um_context_last_status")
      import :: c_int32_t, c_ptr
      type(c_ptr), value :: ctx
    end function c_um_context_last_status

    integer(c_int32_t) function c_um_context_copy_last_error(ctx, buf, capacity, needed) &
        bind(c, name="um_context_copy_last_error")
      import :: c_int32_t, c_int64_t, c_ptr, c_char
      type(c_ptr), value :: ctx
      character(kind=c_char), intent(out), optional :: buf(*)
      integer(c_int64_t), value :: capacity
      integer(c_int64_t), intent(out), optional :: needed
    end function c_um_context_copy_last_error

    integer(c_int32_t) function c_um_context_clear_error(ctx) &
        bind(c, name="um_context_clear_error")
      import :: c_int32_t, c_ptr
      type(c_ptr), value :: ctx
    end function c_um_context_clear_error

    ! ---------------------------------------------------------------- options
    integer(c_int32_t) function c_um_options_create(ctx, out) bind(c, name="um_options_create")
      import :: c_int32_t, c_ptr
      type(c_ptr), value :: ctx
      type(c_ptr), intent(out) :: out
    end function c_um_options_create

    subroutine c_um_options_destroy(opts) bind(c, name="um_options_destroy")
      import :: c_ptr
      type(c_ptr), value :: opts
    end subroutine c_um_options_destroy

    integer(c_int32_t) function c_um_options_set_double(opts, key, value) &
        bind(c, name="um_options_set_double")
      import :: c_int32_t, c_double, c_ptr
      type(c_ptr), value :: opts
      integer(c_int32_t), value :: key
      real(c_double), value :: value
    end function c_um_options_set_double

    integer(c_int32_t) function c_um_options_set_int(opts, key, value) &
        bind(c, name="um_options_set_int")
      import :: c_int32_t, c_int64_t, c_ptr
      type(c_ptr), value :: opts
      integer(c_int32_t), value :: key
      integer(c_int64_t), value :: value
    end function c_um_options_set_int

    integer(c_int32_t) function c_um_options_get_double(opts, key, value) &
        bind(c, name="um_options_get_double")
      import :: c_int32_t, c_double, c_ptr
      type(c_ptr), value :: opts
      integer(c_int32_t), value :: key
      real(c_double), intent(out) :: value
    end function c_um_options_get_double

    integer(c_int32_t) function c_um_options_get_int(opts, key, value) &
        bind(c, name="um_options_get_int")
      import :: c_int32_t, c_int64_t, c_ptr
      type(c_ptr), value :: opts
      integer(c_int32_t), value :: key
      integer(c_int64_t), intent(out) :: value
    end function c_um_options_get_int

    integer(c_int32_t) function c_um_options_set_string(opts, assignments) &
        bind(c, name="um_options_set_string")
      import :: c_int32_t, c_ptr, c_char
      type(c_ptr), value :: opts
      character(kind=c_char), intent(in) :: assignments(*)
    end function c_um_options_set_string

    integer(c_int32_t) function c_um_option_info(key, type, min_value, max_value, default_value) &
        bind(c, name="um_option_info")
      import :: c_int32_t, c_double
      integer(c_int32_t), value :: key
      integer(c_int32_t), intent(out), optional :: type
      real(c_double), intent(out), optional :: min_value
      real(c_double), intent(out), optional :: max_value
      real(c_double), intent(out), optional :: default_value
    end function c_um_option_info

    integer(c_int32_t) function c_um_option_name(key, buf, capacity, needed) &
        bind(c, name="um_option_name")
      import :: c_int32_t, c_int64_t, c_char
      integer(c_int32_t), value :: key
      character(kind=c_char), intent(out), optional :: buf(*)
      integer(c_int64_t), value :: capacity
      integer(c_int64_t), intent(out), optional :: needed
    end function c_um_option_name

    integer(c_int32_t) function c_um_option_key(name, key) bind(c, name="um_option_key")
      import :: c_int32_t, c_char
      character(kind=c_char), intent(in) :: name(*)
      integer(c_int32_t), intent(out) :: key
    end function c_um_option_key

    ! ---------------------------------------------------------- triangulation
    ! Arrays are assumed-size: a Fortran xyz(3, n) or out(3, n_triangles)
    ! passes as the flat C buffer by sequence association.
    integer(c_int32_t) function c_um_triangulation_create(ctx, n, lon_deg, lat_deg, weights, out) &
        bind(c, name="um_triangulation_create")
      import :: c_int32_t, c_int64_t, c_double, c_ptr
      type(c_ptr), value :: ctx
      integer(c_int64_t), value :: n
      real(c_double), intent(in) :: lon_deg(*)
      real(c_double), intent(in) :: lat_deg(*)
      real(c_double), intent(in), optional :: weights(*)
      type(c_ptr), intent(out) :: out
    end function c_um_triangulation_create

    integer(c_int32_t) function c_um_triangulation_create_xyz(ctx, n, xyz, weights, out) &
        bind(c, name="um_triangulation_create_xyz")
      import :: c_int32_t, c_int64_t, c_double, c_ptr
      type(c_ptr), value :: ctx
      integer(c_int64_t), value :: n
      real(c_double), intent(in) :: xyz(*)
      real(c_double), intent(in), optional :: weights(*)
      type(c_ptr), intent(out) :: out
    end function c_um_triangulation_create_xyz

    subroutine c_um_triangulation_destroy(t) bind(c, name="um_triangulation_destroy")
      import :: c_ptr
      type(c_ptr), value :: t
    end subroutine c_um_triangulation_destroy

    integer(c_int32_t) function c_um_triangulation_counts(t, n_vertices, n_triangles, n_hidden) &
        bind(c, name="um_triangulation_counts")
      import :: c_int32_t, c_int64_t, c_ptr
      type(c_ptr), value :: t
      integer(c_int64_t), intent(out) :: n_vertices
      integer(c_int64_t), intent(out) :: n_triangles
      integer(c_int64_t), intent(out) :: n_hidden
    end function c_um_triangulation_counts

    integer(c_int32_t) function c_um_triangulation_copy_triangles(t, base, out, capacity) &
        bind(c, name="um_triangulation_copy_triangles")
      import :: c_int32_t, c_int64_t, c_ptr
      type(c_ptr), value :: t
      integer(c_int32_t), value :: base
      integer(c_int32_t), intent(out) :: out(*)
      integer(c_int64_t), value :: capacity
    end function c_um_triangulation_copy_triangles

    integer(c_int32_t) function c_um_triangulation_copy_neighbours(t, base, out, capacity) &
        bind(c, name="um_triangulation_copy_neighbours")
      import :: c_int32_t, c_int64_t, c_ptr
      type(c_ptr), value :: t
      integer(c_int32_t), value :: base
      integer(c_int32_t), intent(out) :: out(*)
      integer(c_int64_t), value :: capacity
    end function c_um_triangulation_copy_neighbours

    integer(c_int32_t) function c_um_triangulation_copy_orthocentres(t, out, capacity) &
        bind(c, name="um_triangulation_copy_orthocentres")
      import :: c_int32_t, c_int64_t, c_double, c_ptr
      type(c_ptr), value :: t
      real(c_double), intent(out) :: out(*)
      integer(c_int64_t), value :: capacity
    end function c_um_triangulation_copy_orthocentres

    integer(c_int32_t) function c_um_triangulation_copy_hidden(t, base, out, capacity) &
        bind(c, name="um_triangulation_copy_hidden")
      import :: c_int32_t, c_int64_t, c_ptr
      type(c_ptr), value :: t
      integer(c_int32_t), value :: base
      integer(c_int32_t), intent(out) :: out(*)
      integer(c_int64_t), value :: capacity
    end function c_um_triangulation_copy_hidden

    integer(c_int32_t) function c_um_triangulation_check(t) bind(c, name="um_triangulation_check")
      import :: c_int32_t, c_ptr
      type(c_ptr), value :: t
    end function c_um_triangulation_check

    ! --------------------------------------------- features (polyarc networks)
    integer(c_int32_t) function c_um_features_create(ctx, out) bind(c, name="um_features_create")
      import :: c_int32_t, c_ptr
      type(c_ptr), value :: ctx
      type(c_ptr), intent(out) :: out
    end function c_um_features_create

    subroutine c_um_features_destroy(f) bind(c, name="um_features_destroy")
      import :: c_ptr
      type(c_ptr), value :: f
    end subroutine c_um_features_destroy

    integer(c_int32_t) function c_um_features_add(f, n_points, lon_deg, lat_deg, n_parts, &
        part_offsets, closed, kind, part_id) bind(c, name="um_features_add")
      import :: c_int32_t, c_int64_t, c_double, c_ptr
      type(c_ptr), value :: f
      integer(c_int64_t), value :: n_points
      real(c_double), intent(in) :: lon_deg(*)
      real(c_double), intent(in) :: lat_deg(*)
      integer(c_int64_t), value :: n_parts
      integer(c_int64_t), intent(in) :: part_offsets(*)
      integer(c_int32_t), intent(in) :: closed(*)
      integer(c_int32_t), intent(in) :: kind(*)
      integer(c_int32_t), intent(in), optional :: part_id(*)
    end function c_um_features_add

    integer(c_int32_t) function c_um_features_read_geojson(f, path, kind_property, &
        default_kind) bind(c, name="um_features_read_geojson")
      import :: c_int32_t, c_ptr, c_char
      type(c_ptr), value :: f
      character(kind=c_char), intent(in) :: path(*)
      character(kind=c_char), intent(in), optional :: kind_property(*)
      integer(c_int32_t), value :: default_kind
    end function c_um_features_read_geojson

    integer(c_int32_t) function c_um_features_counts(f, n_parts, n_points, n_segments) &
        bind(c, name="um_features_counts")
      import :: c_int32_t, c_int64_t, c_ptr
      type(c_ptr), value :: f
      integer(c_int64_t), intent(out), optional :: n_parts
      integer(c_int64_t), intent(out), optional :: n_points
      integer(c_int64_t), intent(out), optional :: n_segments
    end function c_um_features_counts

    integer(c_int32_t) function c_um_features_copy_points(f, lon_deg, lat_deg, capacity) &
        bind(c, name="um_features_copy_points")
      import :: c_int32_t, c_int64_t, c_double, c_ptr
      type(c_ptr), value :: f
      real(c_double), intent(out), optional :: lon_deg(*)
      real(c_double), intent(out), optional :: lat_deg(*)
      integer(c_int64_t), value :: capacity
    end function c_um_features_copy_points

    integer(c_int32_t) function c_um_features_copy_parts(f, part_offsets, closed, kind, &
        part_id, capacity) bind(c, name="um_features_copy_parts")
      import :: c_int32_t, c_int64_t, c_ptr
      type(c_ptr), value :: f
      integer(c_int64_t), intent(out), optional :: part_offsets(*)
      integer(c_int32_t), intent(out), optional :: closed(*)
      integer(c_int32_t), intent(out), optional :: kind(*)
      integer(c_int32_t), intent(out), optional :: part_id(*)
      integer(c_int64_t), value :: capacity
    end function c_um_features_copy_parts

    ! ---------------------------------------------------------------- spacing
    integer(c_int32_t) function c_um_spacing_create_constant(ctx, km, out) &
        bind(c, name="um_spacing_create_constant")
      import :: c_int32_t, c_double, c_ptr
      type(c_ptr), value :: ctx
      real(c_double), value :: km
      type(c_ptr), intent(out) :: out
    end function c_um_spacing_create_constant

    ! cell_width_km(n_lon, n_lat) in Fortran order is the C [n_lat][n_lon].
    integer(c_int32_t) function c_um_spacing_create_grid(ctx, n_lon, lon_deg, n_lat, lat_deg, &
        cell_width_km, out) bind(c, name="um_spacing_create_grid")
      import :: c_int32_t, c_int64_t, c_double, c_ptr
      type(c_ptr), value :: ctx
      integer(c_int64_t), value :: n_lon
      real(c_double), intent(in) :: lon_deg(*)
      integer(c_int64_t), value :: n_lat
      real(c_double), intent(in) :: lat_deg(*)
      real(c_double), intent(in) :: cell_width_km(*)
      type(c_ptr), intent(out) :: out
    end function c_um_spacing_create_grid

    integer(c_int32_t) function c_um_spacing_create_from_file(ctx, path, out) &
        bind(c, name="um_spacing_create_from_file")
      import :: c_int32_t, c_ptr, c_char
      type(c_ptr), value :: ctx
      character(kind=c_char), intent(in) :: path(*)
      type(c_ptr), intent(out) :: out
    end function c_um_spacing_create_from_file

    integer(c_int32_t) function c_um_spacing_create_callback(ctx, fn, user_data, out) &
        bind(c, name="um_spacing_create_callback")
      import :: c_int32_t, c_ptr, c_funptr
      type(c_ptr), value :: ctx
      type(c_funptr), value :: fn
      type(c_ptr), value :: user_data
      type(c_ptr), intent(out) :: out
    end function c_um_spacing_create_callback

    integer(c_int32_t) function c_um_spacing_create_preset(ctx, name, out) &
        bind(c, name="um_spacing_create_preset")
      import :: c_int32_t, c_ptr, c_char
      type(c_ptr), value :: ctx
      character(kind=c_char), intent(in) :: name(*)
      type(c_ptr), intent(out) :: out
    end function c_um_spacing_create_preset

    subroutine c_um_spacing_destroy(s) bind(c, name="um_spacing_destroy")
      import :: c_ptr
      type(c_ptr), value :: s
    end subroutine c_um_spacing_destroy

    integer(c_int32_t) function c_um_spacing_limit_gradient(s, g) &
        bind(c, name="um_spacing_limit_gradient")
      import :: c_int32_t, c_double, c_ptr
      type(c_ptr), value :: s
      real(c_double), value :: g
    end function c_um_spacing_limit_gradient

    integer(c_int32_t) function c_um_spacing_clamp(s, km_min, km_max) &
        bind(c, name="um_spacing_clamp")
      import :: c_int32_t, c_double, c_ptr
      type(c_ptr), value :: s
      real(c_double), value :: km_min
      real(c_double), value :: km_max
    end function c_um_spacing_clamp

    ! The arrays may be absent (NULL) when n = 0.
    integer(c_int32_t) function c_um_spacing_evaluate(s, n, lon_deg, lat_deg, km_out) &
        bind(c, name="um_spacing_evaluate")
      import :: c_int32_t, c_int64_t, c_double, c_ptr
      type(c_ptr), value :: s
      integer(c_int64_t), value :: n
      real(c_double), intent(in), optional :: lon_deg(*)
      real(c_double), intent(in), optional :: lat_deg(*)
      real(c_double), intent(out), optional :: km_out(*)
    end function c_um_spacing_evaluate

    integer(c_int32_t) function c_um_spacing_estimate(s, cells, refine_bytes, mpas_bytes) &
        bind(c, name="um_spacing_estimate")
      import :: c_int32_t, c_int64_t, c_ptr
      type(c_ptr), value :: s
      integer(c_int64_t), intent(out), optional :: cells, refine_bytes, mpas_bytes
    end function c_um_spacing_estimate

    ! ------------------------------------------------------------------- mesh
    ! features and options: pass c_null_ptr for none.
    integer(c_int32_t) function c_um_mesh_refine(ctx, spacing, features, options, out) &
        bind(c, name="um_mesh_refine")
      import :: c_int32_t, c_ptr
      type(c_ptr), value :: ctx
      type(c_ptr), value :: spacing
      type(c_ptr), value :: features
      type(c_ptr), value :: options
      type(c_ptr), intent(out) :: out
    end function c_um_mesh_refine

    integer(c_int32_t) function c_um_mesh_optimise(m, options) bind(c, name="um_mesh_optimise")
      import :: c_int32_t, c_ptr
      type(c_ptr), value :: m
      type(c_ptr), value :: options
    end function c_um_mesh_optimise

    subroutine c_um_mesh_destroy(m) bind(c, name="um_mesh_destroy")
      import :: c_ptr
      type(c_ptr), value :: m
    end subroutine c_um_mesh_destroy

    integer(c_int32_t) function c_um_mesh_counts(m, n_vertices, n_triangles, &
        n_restricted_edges, n_filtered) bind(c, name="um_mesh_counts")
      import :: c_int32_t, c_int64_t, c_ptr
      type(c_ptr), value :: m
      integer(c_int64_t), intent(out) :: n_vertices
      integer(c_int64_t), intent(out) :: n_triangles
      integer(c_int64_t), intent(out) :: n_restricted_edges
      integer(c_int64_t), intent(out) :: n_filtered
    end function c_um_mesh_counts

    integer(c_int32_t) function c_um_mesh_copy_vertices(m, lon_deg, lat_deg, capacity) &
        bind(c, name="um_mesh_copy_vertices")
      import :: c_int32_t, c_int64_t, c_double, c_ptr
      type(c_ptr), value :: m
      real(c_double), intent(out) :: lon_deg(*)
      real(c_double), intent(out) :: lat_deg(*)
      integer(c_int64_t), value :: capacity
    end function c_um_mesh_copy_vertices

    integer(c_int32_t) function c_um_mesh_copy_triangles(m, base, out, capacity) &
        bind(c, name="um_mesh_copy_triangles")
      import :: c_int32_t, c_int64_t, c_ptr
      type(c_ptr), value :: m
      integer(c_int32_t), value :: base
      integer(c_int32_t), intent(out) :: out(*)
      integer(c_int64_t), value :: capacity
    end function c_um_mesh_copy_triangles

    integer(c_int32_t) function c_um_mesh_copy_vertex_parts(m, base, out, capacity) &
        bind(c, name="um_mesh_copy_vertex_parts")
      import :: c_int32_t, c_int64_t, c_ptr
      type(c_ptr), value :: m
      integer(c_int32_t), value :: base
      integer(c_int32_t), intent(out) :: out(*)
      integer(c_int64_t), value :: capacity
    end function c_um_mesh_copy_vertex_parts

    integer(c_int32_t) function c_um_mesh_copy_restricted_edges(m, base, vertices, parts, &
        capacity) bind(c, name="um_mesh_copy_restricted_edges")
      import :: c_int32_t, c_int64_t, c_ptr
      type(c_ptr), value :: m
      integer(c_int32_t), value :: base
      integer(c_int32_t), intent(out) :: vertices(*)
      integer(c_int32_t), intent(out) :: parts(*)
      integer(c_int64_t), value :: capacity
    end function c_um_mesh_copy_restricted_edges

    integer(c_int32_t) function c_um_mesh_copy_vertex_sides(m, out, capacity) &
        bind(c, name="um_mesh_copy_vertex_sides")
      import :: c_int32_t, c_int64_t, c_ptr
      type(c_ptr), value :: m
      integer(c_int32_t), intent(out) :: out(*)
      integer(c_int64_t), value :: capacity
    end function c_um_mesh_copy_vertex_sides

    integer(c_int32_t) function c_um_mesh_copy_triangle_sides(m, out, capacity) &
        bind(c, name="um_mesh_copy_triangle_sides")
      import :: c_int32_t, c_int64_t, c_ptr
      type(c_ptr), value :: m
      integer(c_int32_t), intent(out) :: out(*)
      integer(c_int64_t), value :: capacity
    end function c_um_mesh_copy_triangle_sides

    ! The JSON quality report, copied out as strings are (buf may be absent
    ! with capacity 0 to ask for the length).
    integer(c_int32_t) function c_um_mesh_quality_json(m, buf, capacity, needed) &
        bind(c, name="um_mesh_quality_json")
      import :: c_int32_t, c_int64_t, c_ptr, c_char
      type(c_ptr), value :: m
      character(kind=c_char), intent(out), optional :: buf(*)
      integer(c_int64_t), value :: capacity
      integer(c_int64_t), intent(out), optional :: needed
    end function c_um_mesh_quality_json

    integer(c_int32_t) function c_um_mesh_quality_summary(m, metric, min, p1, mean, max) &
        bind(c, name="um_mesh_quality_summary")
      import :: c_int32_t, c_double, c_ptr, c_char
      type(c_ptr), value :: m
      character(kind=c_char), intent(in) :: metric(*)
      real(c_double), intent(out), optional :: min
      real(c_double), intent(out), optional :: p1
      real(c_double), intent(out), optional :: mean
      real(c_double), intent(out), optional :: max
    end function c_um_mesh_quality_summary

    integer(c_int32_t) function c_um_mesh_quality_counts(m, obtuse, not_well_centred) &
        bind(c, name="um_mesh_quality_counts")
      import :: c_int32_t, c_int64_t, c_ptr
      type(c_ptr), value :: m
      integer(c_int64_t), intent(out) :: obtuse
      integer(c_int64_t), intent(out) :: not_well_centred
    end function c_um_mesh_quality_counts

    ! ------------------------------------------------------------ MPAS output
    integer(c_int32_t) function c_um_mesh_write_mpas(m, path) bind(c, name="um_mesh_write_mpas")
      import :: c_int32_t, c_ptr, c_char
      type(c_ptr), value :: m
      character(kind=c_char), intent(in) :: path(*)
    end function c_um_mesh_write_mpas
    integer(c_int32_t) function c_um_mesh_write_mpas_as(m, path, format) bind(c, name="um_mesh_write_mpas_as")
      import :: c_int32_t, c_ptr, c_char
      type(c_ptr), value :: m
      character(kind=c_char), intent(in) :: path(*)
      integer(c_int32_t), value :: format
    end function c_um_mesh_write_mpas_as

    integer(c_int32_t) function c_um_mesh_mpas_dimensions(m, n_cells, n_edges, n_vertices, &
        max_edges) bind(c, name="um_mesh_mpas_dimensions")
      import :: c_int32_t, c_int64_t, c_ptr
      type(c_ptr), value :: m
      integer(c_int64_t), intent(out) :: n_cells, n_edges, n_vertices, max_edges
    end function c_um_mesh_mpas_dimensions

    integer(c_int32_t) function c_um_mesh_mpas_variable(m, name, type, n_rows, n_columns) &
        bind(c, name="um_mesh_mpas_variable")
      import :: c_int32_t, c_int64_t, c_ptr, c_char
      type(c_ptr), value :: m
      character(kind=c_char), intent(in) :: name(*)
      integer(c_int32_t), intent(out) :: type
      integer(c_int64_t), intent(out) :: n_rows, n_columns
    end function c_um_mesh_mpas_variable

    integer(c_int32_t) function c_um_mesh_copy_mpas_real(m, name, out, capacity) &
        bind(c, name="um_mesh_copy_mpas_real")
      import :: c_int32_t, c_int64_t, c_ptr, c_char, c_double
      type(c_ptr), value :: m
      character(kind=c_char), intent(in) :: name(*)
      real(c_double), intent(out) :: out(*)
      integer(c_int64_t), value :: capacity
    end function c_um_mesh_copy_mpas_real

    integer(c_int32_t) function c_um_mesh_copy_mpas_int(m, name, base, out, capacity) &
        bind(c, name="um_mesh_copy_mpas_int")
      import :: c_int32_t, c_int64_t, c_ptr, c_char
      type(c_ptr), value :: m
      character(kind=c_char), intent(in) :: name(*)
      integer(c_int32_t), value :: base
      integer(c_int32_t), intent(out) :: out(*)
      integer(c_int64_t), value :: capacity
    end function c_um_mesh_copy_mpas_int

    integer(c_int32_t) function c_um_mesh_write_jigsaw(m, path) bind(c, name="um_mesh_write_jigsaw")
      import :: c_int32_t, c_ptr, c_char
      type(c_ptr), value :: m
      character(kind=c_char), intent(in) :: path(*)
    end function c_um_mesh_write_jigsaw

    integer(c_int32_t) function c_um_mesh_release_mpas(m) bind(c, name="um_mesh_release_mpas")
      import :: c_int32_t, c_ptr
      type(c_ptr), value :: m
    end function c_um_mesh_release_mpas

    integer(c_int32_t) function c_um_mesh_write_components(m, directory) &
        bind(c, name="um_mesh_write_components")
      import :: c_int32_t, c_ptr, c_char
      type(c_ptr), value :: m
      character(kind=c_char), intent(in) :: directory(*)
    end function c_um_mesh_write_components

    integer(c_int32_t) function c_um_mpas_file_write_components(ctx, mesh_path, directory) &
        bind(c, name="um_mpas_file_write_components")
      import :: c_int32_t, c_ptr, c_char
      type(c_ptr), value :: ctx
      character(kind=c_char), intent(in) :: mesh_path(*)
      character(kind=c_char), intent(in) :: directory(*)
    end function c_um_mpas_file_write_components

    integer(c_int32_t) function c_um_mesh_river_report_json(m, buf, capacity, needed) &
        bind(c, name="um_mesh_river_report_json")
      import :: c_int32_t, c_int64_t, c_ptr, c_char
      type(c_ptr), value :: m
      character(kind=c_char), intent(out), optional :: buf(*)
      integer(c_int64_t), value :: capacity
      integer(c_int64_t), intent(out), optional :: needed
    end function c_um_mesh_river_report_json
  end interface

end module unimesh_cint
