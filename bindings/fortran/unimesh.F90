! unimesh -- the friendly Fortran layer over unimesh_cint.
!
!   use unimesh
!   type(um_context_t) :: ctx
!   type(um_options_t) :: opts
!   integer :: ierr
!   call um_context_create(ctx)
!   call um_options_create(ctx, opts)
!   call um_options_set_double(opts, UM_OPT_REFINE_ALPHA, 1.25d0, ierr)
!   if (ierr /= UM_OK) print *, um_context_last_error(ctx)
!   call um_options_destroy(opts)
!
!   type(um_triangulation_t) :: tri
!   integer, allocatable :: triangles(:, :)       ! (3, n_triangles), 1-based
!   call um_triangulation_create(ctx, lon_deg, lat_deg, tri)   ! real(real64)(:)
!   call um_triangulation_get_triangles(tri, triangles)
!   call um_triangulation_destroy(tri)
!   call um_context_destroy(ctx)
!
! Routines carry the C names and take Fortran types: handles wrapped in small
! derived types, default-kind integers (int64 overloads where the ABI is
! int64), real(real64) reals and ordinary character strings. The one
! exception is um_version, which also returns what um_version_number and
! um_version_string give in C: Fortran names ignore case, so functions of
! those names would clash with the UM_VERSION_* constants.
!
! Errors. Every routine has an `optional, intent(out) :: ierr`. When it is
! present it receives the status (UM_OK = 0 on success) and the caller reads
! the message with um_context_last_error; the context keeps the FIRST message
! until um_context_clear_error, exactly as in C. When ierr is absent a failure
! goes to the abort hook with the routine name and the message: by default it
! prints to error_unit and stops with `error stop`; um_set_abort_hook installs
! another (e.g. the model's own abort). If a user hook returns, the routine
! returns with its outputs undefined. The hook is process-wide state.
!
! Handles are destroyed explicitly (um_*_destroy); there are no FINAL
! procedures because derived types are copied freely in Fortran (assignment,
! intent(out), function results) and a finaliser on a copy would destroy the
! one C object every copy shares.
!
! Adding a handle type follows um_options_t (um_triangulation_t is another
! example): a type holding the C pointer plus the borrowed context pointer its
! errors are recorded in, create/destroy routines, and
! `call finish(status, h%ctx, ...)` after every C call. Array results are
! allocatable dummies allocated to the size the C counts give, indices 1-based
! (see the triangulation section).
module unimesh
  use, intrinsic :: iso_c_binding, only: c_ptr, c_null_ptr, c_associated, c_f_pointer, c_loc, &
      c_char, c_null_char, c_int32_t, c_int64_t, c_double, c_size_t, c_funloc, c_funptr, &
      c_null_funptr
  use, intrinsic :: iso_fortran_env, only: error_unit, int64, real64
  use unimesh_cint
  implicit none
  private

  ! Constants of the header, re-exported so `use unimesh` is all a caller
  ! needs (check_fortran_binding.py verifies that none is missing here).
  public :: UM_VERSION_MAJOR, UM_VERSION_MINOR, UM_VERSION_PATCH, UM_VERSION_NUMBER, &
      UM_VERSION_STRING
  public :: UM_OK, UM_ERR_USAGE, UM_ERR_NULL_ARGUMENT, UM_ERR_INVALID_HANDLE, &
      UM_ERR_INVALID_ARGUMENT, UM_ERR_UNKNOWN_OPTION, UM_ERR_OPTION_TYPE, &
      UM_ERR_BUFFER_TOO_SMALL, UM_ERR_WRONG_ORDER, UM_ERR_INPUT, UM_ERR_NONFINITE_INPUT, &
      UM_ERR_COORDINATE_RANGE, UM_ERR_DUPLICATE_POINTS, UM_ERR_TOO_FEW_POINTS, &
      UM_ERR_DEGENERATE_INPUT, UM_ERR_NUMERICAL, UM_ERR_OUT_OF_MEMORY, UM_ERR_MEMORY_CAP, &
      UM_ERR_LIMIT, UM_ERR_IO, UM_ERR_FILE_FORMAT, UM_CANCELLED, UM_ERR_INTERNAL
  public :: UM_LOG_DEBUG, UM_LOG_INFO, UM_LOG_WARNING, UM_LOG_ERROR
  public :: UM_ERROR_MODE_RETURN, UM_ERROR_MODE_ABORT
  public :: UM_OPT_SPHERE_RADIUS, UM_OPT_SURFACE_FLATTENING, UM_OPT_REFINE_ALPHA, UM_OPT_REFINE_BETA, UM_OPT_REFINE_RHO, &
      UM_OPT_REFINE_TOPOLOGY_CHECK, UM_OPT_REFINE_RELAX, UM_OPT_REFINE_LATTICE, UM_OPT_SPACING_GRADIENT, &
      UM_OPT_OPTIM_OUTER_ITERATIONS, UM_OPT_OPTIM_INNER_ITERATIONS, UM_OPT_OPTIM_TOLERANCE, UM_OPT_OPTIM_WEIGHTS, &
      UM_OPT_OPTIM_FIX_BOUNDARY, UM_OPT_OPTIM_COLLAPSE_RATIO, UM_OPT_OPTIM_SPLIT_RATIO, &
      UM_OPT_OPTIM_CORNER_VERTICES, UM_OPT_OPTIM_CENTROIDAL_SWEEPS, UM_OPT_OPTIM_RESEED_ROUNDS, &
      UM_OPT_OCEAN_FLOOR
  public :: UM_OPTION_TYPE_INT, UM_OPTION_TYPE_REAL
  public :: UM_FEATURE_COASTLINE, UM_FEATURE_LAKE, UM_FEATURE_RIVER, UM_FEATURE_WATERSHED, &
      UM_FEATURE_OTHER, UM_FEATURE_PASSAGE, UM_FEATURE_DOMAIN
  public :: UM_SIDE_OCEAN, UM_SIDE_LAND, UM_SIDE_COASTAL
  public :: UM_MPAS_REAL, UM_MPAS_INT, UM_MPAS_FILE_AUTO, UM_MPAS_FILE_NETCDF4

  ! ------------------------------------------------------------------ handles

  !> A um_context: the root object; create it first, destroy it last.
  type, public :: um_context_t
    type(c_ptr) :: ptr = c_null_ptr
  end type um_context_t

  !> A um_options object. ctx is borrowed from the context it was created
  !> from: the C library records this object's errors there. After that
  !> context is destroyed the options stay usable, but failures then report
  !> only the status text.
  type, public :: um_options_t
    type(c_ptr) :: ptr = c_null_ptr
    type(c_ptr) :: ctx = c_null_ptr
  end type um_options_t

  !> A um_triangulation: the Laguerre (weighted Delaunay) triangulation of
  !> points on the unit sphere. ctx is borrowed as for um_options_t; the
  !> triangulation stays valid (and its getters work) after the context is
  !> destroyed.
  type, public :: um_triangulation_t
    type(c_ptr) :: ptr = c_null_ptr
    type(c_ptr) :: ctx = c_null_ptr
  end type um_triangulation_t

  !> A um_features polyarc network (coastlines, rivers, ...). ctx is borrowed
  !> as for um_options_t.
  type, public :: um_features_t
    type(c_ptr) :: ptr = c_null_ptr
    type(c_ptr) :: ctx = c_null_ptr
  end type um_features_t

  !> A um_spacing: the target edge length h(x) in km. ctx is borrowed as for
  !> um_options_t.
  type, public :: um_spacing_t
    type(c_ptr) :: ptr = c_null_ptr
    type(c_ptr) :: ctx = c_null_ptr
  end type um_spacing_t

  !> A um_mesh: the restricted triangulation made by um_mesh_refine. ctx is
  !> borrowed as for um_options_t; the mesh stays valid after the context,
  !> spacing, features and options are destroyed (a callback spacing's
  !> function and user data must stay valid while the mesh lives: the mesh
  !> keeps the spacing).
  type, public :: um_mesh_t
    type(c_ptr) :: ptr = c_null_ptr
    type(c_ptr) :: ctx = c_null_ptr
  end type um_mesh_t

  ! -------------------------------------------------------------- abort hook

  abstract interface
    !> What um_set_abort_hook accepts: called on a failure in a routine whose
    !> ierr was absent, with the status and "<routine>: <message>".
    subroutine um_abort_handler(status, message)
      integer, intent(in) :: status
      character(len=*), intent(in) :: message
    end subroutine um_abort_handler
  end interface
  public :: um_abort_handler, um_set_abort_hook, um_default_abort_hook

  procedure(um_abort_handler), pointer, save :: abort_hook => um_default_abort_hook

  ! --------------------------------------------------------------- routines

  public :: um_version
  public :: um_status_string, um_status_class
  public :: um_context_create, um_context_destroy, um_context_set_threads, &
      um_context_get_threads, um_context_set_memory_cap, um_context_get_memory_cap, &
      um_context_set_worker_placement, &
      um_context_last_error, um_context_last_status, um_context_clear_error
  public :: um_options_create, um_options_destroy, um_options_set_double, um_options_set_int, &
      um_options_get_double, um_options_get_int, um_options_set_string
  public :: um_option_info, um_option_name, um_option_key
  public :: um_triangulation_create, um_triangulation_create_xyz, um_triangulation_destroy, &
      um_triangulation_counts, um_triangulation_get_triangles, um_triangulation_get_neighbours, &
      um_triangulation_get_orthocentres, um_triangulation_get_hidden, um_triangulation_check
  public :: um_spacing_fn, um_progress_fn, um_log_fn
  public :: um_context_set_progress, um_context_set_log
  public :: um_features_create, um_features_destroy, um_features_add_part, &
      um_features_read_geojson, um_features_counts, um_features_get_points, um_features_get_parts
  public :: um_spacing_create_constant, um_spacing_create_grid, um_spacing_create_preset, &
      um_spacing_create_from_file, um_spacing_create_callback, um_spacing_destroy, &
      um_spacing_limit_gradient, um_spacing_clamp, um_spacing_evaluate, um_spacing_estimate
  public :: um_mesh_refine, um_mesh_optimise, um_mesh_destroy, um_mesh_counts, um_mesh_get_vertices, &
      um_mesh_get_triangles, um_mesh_get_vertex_parts, um_mesh_get_restricted_edges, &
      um_mesh_get_vertex_sides, um_mesh_get_triangle_sides
  public :: um_mesh_quality_summary, um_mesh_quality_counts, um_mesh_quality_json
  public :: um_mesh_write_mpas, um_mesh_write_mpas_as, um_mesh_write_jigsaw, um_mesh_mpas_dimensions, um_mesh_get_mpas, &
      um_mesh_release_mpas
  public :: um_mesh_write_components, um_mpas_file_write_components, um_mesh_river_report_json

  ! An MPAS variable by its netCDF name into an allocatable array: rank 1
  ! for variables of one dimension (areaCell(nCells)), rank 2 in MPAS's own
  ! layout for the others (cellsOnEdge(2, nEdges)); real(real64) for reals,
  ! default integers (indices 1-based, 0 padding) for the rest.
  interface um_mesh_get_mpas
    module procedure mesh_get_mpas_real_1d, mesh_get_mpas_real_2d, mesh_get_mpas_int_1d, &
        mesh_get_mpas_int_2d
  end interface um_mesh_get_mpas

  ! Where the ABI takes int64 the routine accepts default integers (the
  ! common case) and int64 (for values a default integer cannot hold).
  interface um_context_set_memory_cap
    module procedure context_set_memory_cap, context_set_memory_cap_int64
  end interface um_context_set_memory_cap
  interface um_context_get_memory_cap
    module procedure context_get_memory_cap, context_get_memory_cap_int64
  end interface um_context_get_memory_cap
  interface um_options_set_int
    module procedure options_set_int, options_set_int_int64
  end interface um_options_set_int
  interface um_options_get_int
    module procedure options_get_int, options_get_int_int64
  end interface um_options_get_int
  interface um_triangulation_counts
    module procedure triangulation_counts, triangulation_counts_int64
  end interface um_triangulation_counts

  ! The C functions that copy out a mesh's JSON report (um_mesh_quality_json,
  ! um_mesh_river_report_json), for the one routine that sizes and copies.
  abstract interface
    integer(c_int32_t) function mesh_json_fn(m, buf, capacity, needed) bind(c)
      import :: c_int32_t, c_int64_t, c_ptr, c_char
      type(c_ptr), value :: m
      character(kind=c_char), intent(out), optional :: buf(*)
      integer(c_int64_t), value :: capacity
      integer(c_int64_t), intent(out), optional :: needed
    end function mesh_json_fn
  end interface

  ! C's strlen, to size the Fortran copy of a borrowed C string.
  interface
    integer(c_size_t) function c_strlen(s) bind(c, name="strlen")
      import :: c_ptr, c_size_t
      type(c_ptr), value :: s
    end function c_strlen
  end interface

contains

  ! ==================================================================== errors

  !> Installs hook as the abort hook; without hook (or with a disassociated
  !> procedure pointer) restores um_default_abort_hook.
  subroutine um_set_abort_hook(hook, ierr)
    procedure(um_abort_handler), optional :: hook
    integer, optional, intent(out) :: ierr
    if (present(hook)) then
      abort_hook => hook
    else
      abort_hook => um_default_abort_hook
    end if
    if (present(ierr)) ierr = UM_OK
  end subroutine um_set_abort_hook

  !> The default abort hook: reports on error_unit and stops the program.
  subroutine um_default_abort_hook(status, message)
    integer, intent(in) :: status
    character(len=*), intent(in) :: message
    write (error_unit, '(a, i0, 4a)') 'unimesh: error ', status, ' (', &
        status_text(int(status, c_int32_t)), ') in ', message
    ! error_unit may be buffered when not a terminal: show the message before
    ! the runtime's own ERROR STOP text.
    flush (error_unit)
    error stop 'unimesh: stopping after an error (see the message above)'
  end subroutine um_default_abort_hook

  !> The end of every routine: hands the status to ierr when the caller gave
  !> one, otherwise sends a failure to the abort hook. ctx is the context the
  !> C call recorded its message in (may be null); message, when given,
  !> replaces the context's (for failures found in this binding).
  subroutine finish(status, ctx, routine, ierr, message)
    integer(c_int32_t), intent(in) :: status
    type(c_ptr), intent(in) :: ctx
    character(len=*), intent(in) :: routine
    integer, optional, intent(out) :: ierr
    character(len=*), optional, intent(in) :: message
    if (present(ierr)) ierr = int(status)
    if (status == UM_OK .or. present(ierr)) return
    if (present(message)) then
      call abort_hook(int(status), routine // ': ' // message)
    else
      call abort_hook(int(status), routine // ': ' // error_text(status, ctx))
    end if
  end subroutine finish

  !> The best description of a failure with this status: the context's message
  !> when the context holds one for this status, else the status text. (The
  !> context keeps the FIRST error, so an older uncleared error of another
  !> status must not be reported as this one.)
  function error_text(status, ctx) result(text)
    integer(c_int32_t), intent(in) :: status
    type(c_ptr), intent(in) :: ctx
    character(len=:), allocatable :: text
    if (c_associated(ctx)) then
      if (c_um_context_last_status(ctx) == status) then
        text = context_message(ctx)
        if (len(text) > 0) return
      end if
    end if
    text = status_text(status)
  end function error_text

  !> The context's kept message, copied out with the length C reports as
  !> needed; "" when there is none or ctx is not a live context.
  function context_message(ctx, status) result(text)
    type(c_ptr), intent(in) :: ctx
    integer(c_int32_t), optional, intent(out) :: status
    character(len=:), allocatable :: text
    character(kind=c_char), allocatable :: buf(:)
    integer(c_int64_t) :: capacity, needed
    integer(c_int32_t) :: s
    text = ''
    needed = 0
    ! Sizing call: capacity 0 with no buffer only reports the length needed.
    s = c_um_context_copy_last_error(ctx, capacity=0_c_int64_t, needed=needed)
    if (s == UM_ERR_BUFFER_TOO_SMALL) then
      capacity = needed
      allocate (buf(capacity))
      s = c_um_context_copy_last_error(ctx, buf, capacity, needed)
      if (s == UM_OK) text = from_c_chars(buf, int(needed) - 1)
    end if
    if (present(status)) status = s
  end function context_message

  function status_text(status) result(text)
    integer(c_int32_t), intent(in) :: status
    character(len=:), allocatable :: text
    text = string_from_c(c_um_status_string(status))
  end function status_text

  ! =================================================================== strings

  !> A Fortran string as a NUL-terminated C string. Trailing blanks are
  !> padding in Fortran, never part of a name or value, so they are dropped.
  pure function to_c(text) result(c)
    character(len=*), intent(in) :: text
    character(kind=c_char, len=:), allocatable :: c
    c = trim(text) // c_null_char
  end function to_c

  !> The first n characters of a C character buffer as a Fortran string.
  pure function from_c_chars(chars, n) result(text)
    character(kind=c_char), intent(in) :: chars(*)
    integer, intent(in) :: n
    character(len=:), allocatable :: text
    integer :: i
    allocate (character(len=max(n, 0)) :: text)
    do i = 1, n
      text(i:i) = chars(i)
    end do
  end function from_c_chars

  !> A copy of a borrowed NUL-terminated C string ("" for NULL).
  function string_from_c(p) result(text)
    type(c_ptr), intent(in) :: p
    character(len=:), allocatable :: text
    character(kind=c_char), pointer :: chars(:)
    integer :: n
    if (.not. c_associated(p)) then
      text = ''
      return
    end if
    n = int(c_strlen(p))
    call c_f_pointer(p, chars, [n])
    text = from_c_chars(chars, n)
  end function string_from_c

  !> Narrows an int64 from C to a default integer, or fails with UM_ERR_LIMIT
  !> (a binding-level failure: the context holds no message for it).
  subroutine narrow(value64, value, ctx, routine, ierr)
    integer(int64), intent(in) :: value64
    integer, intent(out) :: value
    type(c_ptr), intent(in) :: ctx
    character(len=*), intent(in) :: routine
    integer, optional, intent(out) :: ierr
    character(len=24) :: digits
    if (value64 >= int(-huge(value), int64) .and. value64 <= int(huge(value), int64)) then
      value = int(value64)
      call finish(UM_OK, ctx, routine, ierr)
    else
      value = 0
      write (digits, '(i0)') value64
      call finish(UM_ERR_LIMIT, ctx, routine, ierr, 'value ' // trim(digits) // &
          ' does not fit a default integer: pass an integer(int64) instead')
    end if
  end subroutine narrow

  ! =========================================================== version, status

  !> The version of the library actually loaded, to compare with the
  !> UM_VERSION_* constants this binding was built with. (One routine with
  !> optional outputs because Fortran names are case-insensitive: functions
  !> um_version_number/um_version_string would clash with the constants.)
  subroutine um_version(major, minor, patch, number, string, ierr)
    integer, optional, intent(out) :: major, minor, patch
    integer, optional, intent(out) :: number
    character(len=:), allocatable, optional, intent(out) :: string
    integer, optional, intent(out) :: ierr
    integer(c_int32_t) :: c_major, c_minor, c_patch
    call c_um_version(c_major, c_minor, c_patch)
    if (present(major)) major = int(c_major)
    if (present(minor)) minor = int(c_minor)
    if (present(patch)) patch = int(c_patch)
    if (present(number)) number = int(c_um_version_number())
    if (present(string)) string = string_from_c(c_um_version_string())
    if (present(ierr)) ierr = UM_OK
  end subroutine um_version

  !> A short description of a status ("unknown status" if not one).
  function um_status_string(status, ierr) result(text)
    integer, intent(in) :: status
    integer, optional, intent(out) :: ierr
    character(len=:), allocatable :: text
    text = status_text(int(status, c_int32_t))
    if (present(ierr)) ierr = UM_OK
  end function um_status_string

  !> The band of a status: 0, 100, 200, ..., 900.
  integer function um_status_class(status, ierr)
    integer, intent(in) :: status
    integer, optional, intent(out) :: ierr
    um_status_class = int(c_um_status_class(int(status, c_int32_t)))
    if (present(ierr)) ierr = UM_OK
  end function um_status_class

  ! =================================================================== context

  subroutine um_context_create(ctx, ierr)
    type(um_context_t), intent(out) :: ctx
    integer, optional, intent(out) :: ierr
    call finish(c_um_context_create(ctx%ptr), c_null_ptr, 'um_context_create', ierr)
  end subroutine um_context_create

  !> Destroys the context (objects created from it stay valid) and nulls the
  !> handle; a null handle is fine.
  subroutine um_context_destroy(ctx, ierr)
    type(um_context_t), intent(inout) :: ctx
    integer, optional, intent(out) :: ierr
    call c_um_context_destroy(ctx%ptr)
    ctx%ptr = c_null_ptr
    if (present(ierr)) ierr = UM_OK
  end subroutine um_context_destroy

  !> Threads for parallel work: 0 = all cores, 1..1024 otherwise.
  subroutine um_context_set_threads(ctx, n_threads, ierr)
    type(um_context_t), intent(in) :: ctx
    integer, intent(in) :: n_threads
    integer, optional, intent(out) :: ierr
    call finish(c_um_context_set_threads(ctx%ptr, int(n_threads, c_int32_t)), ctx%ptr, &
        'um_context_set_threads', ierr)
  end subroutine um_context_set_threads

  !> The effective thread count (0 resolved to the number of cores).
  subroutine um_context_get_threads(ctx, n_threads, ierr)
    type(um_context_t), intent(in) :: ctx
    integer, intent(out) :: n_threads
    integer, optional, intent(out) :: ierr
    integer(c_int32_t) :: n
    n = 0
    call finish(c_um_context_get_threads(ctx%ptr, n), ctx%ptr, 'um_context_get_threads', ierr)
    n_threads = int(n)
  end subroutine um_context_get_threads

  !> Keep oneTBB's workers off the calling thread's CPU during the context's
  !> parallel calls (changes their affinity; off by default).
  subroutine um_context_set_worker_placement(ctx, on, ierr)
    type(um_context_t), intent(in) :: ctx
    logical, intent(in) :: on
    integer, optional, intent(out) :: ierr
    call finish(c_um_context_set_worker_placement(ctx%ptr, merge(1_c_int32_t, 0_c_int32_t, on)), ctx%ptr, &
        'um_context_set_worker_placement', ierr)
  end subroutine um_context_set_worker_placement

  !> Memory cap in bytes for the context's large allocations (0 = no cap).
  subroutine context_set_memory_cap(ctx, bytes, ierr)
    type(um_context_t), intent(in) :: ctx
    integer, intent(in) :: bytes
    integer, optional, intent(out) :: ierr
    call context_set_memory_cap_int64(ctx, int(bytes, int64), ierr)
  end subroutine context_set_memory_cap

  subroutine context_set_memory_cap_int64(ctx, bytes, ierr)
    type(um_context_t), intent(in) :: ctx
    integer(int64), intent(in) :: bytes
    integer, optional, intent(out) :: ierr
    call finish(c_um_context_set_memory_cap(ctx%ptr, int(bytes, c_int64_t)), ctx%ptr, &
        'um_context_set_memory_cap', ierr)
  end subroutine context_set_memory_cap_int64

  subroutine context_get_memory_cap(ctx, bytes, ierr)
    type(um_context_t), intent(in) :: ctx
    integer, intent(out) :: bytes
    integer, optional, intent(out) :: ierr
    integer(int64) :: bytes64
    integer :: status
    bytes = 0
    call context_get_memory_cap_int64(ctx, bytes64, status)
    if (status == UM_OK) then
      call narrow(bytes64, bytes, ctx%ptr, 'um_context_get_memory_cap', ierr)
    else
      call finish(int(status, c_int32_t), ctx%ptr, 'um_context_get_memory_cap', ierr)
    end if
  end subroutine context_get_memory_cap

  subroutine context_get_memory_cap_int64(ctx, bytes, ierr)
    type(um_context_t), intent(in) :: ctx
    integer(int64), intent(out) :: bytes
    integer, optional, intent(out) :: ierr
    integer(c_int64_t) :: b
    b = 0
    call finish(c_um_context_get_memory_cap(ctx%ptr, b), ctx%ptr, 'um_context_get_memory_cap', &
        ierr)
    bytes = int(b, int64)
  end subroutine context_get_memory_cap_int64

  !> The first error message kept by the context ("" when none). Reading it
  !> does not clear it: see um_context_clear_error.
  function um_context_last_error(ctx, ierr) result(text)
    type(um_context_t), intent(in) :: ctx
    integer, optional, intent(out) :: ierr
    character(len=:), allocatable :: text
    integer(c_int32_t) :: status
    text = context_message(ctx%ptr, status)
    ! The sizing call's "too small" is the expected path, not a failure.
    if (status == UM_ERR_BUFFER_TOO_SMALL) status = UM_OK
    call finish(status, ctx%ptr, 'um_context_last_error', ierr)
  end function um_context_last_error

  !> The status that went with the kept message (UM_OK when none).
  integer function um_context_last_status(ctx, ierr)
    type(um_context_t), intent(in) :: ctx
    integer, optional, intent(out) :: ierr
    um_context_last_status = int(c_um_context_last_status(ctx%ptr))
    if (present(ierr)) ierr = UM_OK
  end function um_context_last_status

  subroutine um_context_clear_error(ctx, ierr)
    type(um_context_t), intent(in) :: ctx
    integer, optional, intent(out) :: ierr
    call finish(c_um_context_clear_error(ctx%ptr), ctx%ptr, 'um_context_clear_error', ierr)
  end subroutine um_context_clear_error

  !> Progress reports of long calls: fn (interface um_progress_fn, bind(c):
  !> user_data, a C string stage, a fraction in [0, 1]) is called from the
  !> host thread and returns 0 to go on, non-zero to cancel. fn absent: none.
  subroutine um_context_set_progress(ctx, fn, user_data, ierr)
    type(um_context_t), intent(in) :: ctx
    procedure(um_progress_fn), optional :: fn
    type(c_ptr), optional, intent(in) :: user_data
    integer, optional, intent(out) :: ierr
    type(c_funptr) :: f
    type(c_ptr) :: data
    f = c_null_funptr
    data = c_null_ptr
    if (present(fn)) f = c_funloc(fn)
    if (present(user_data)) data = user_data
    call finish(c_um_context_set_progress(ctx%ptr, f, data), ctx%ptr, 'um_context_set_progress', ierr)
  end subroutine um_context_set_progress

  !> Log messages of min_level (UM_LOG_*) and above to fn (interface
  !> um_log_fn, bind(c): user_data, level, a C string), from the host
  !> thread. fn absent: none.
  subroutine um_context_set_log(ctx, fn, min_level, user_data, ierr)
    type(um_context_t), intent(in) :: ctx
    procedure(um_log_fn), optional :: fn
    integer, optional, intent(in) :: min_level
    type(c_ptr), optional, intent(in) :: user_data
    integer, optional, intent(out) :: ierr
    type(c_funptr) :: f
    type(c_ptr) :: data
    integer(c_int32_t) :: level
    f = c_null_funptr
    data = c_null_ptr
    level = UM_LOG_WARNING
    if (present(fn)) f = c_funloc(fn)
    if (present(user_data)) data = user_data
    if (present(min_level)) level = int(min_level, c_int32_t)
    call finish(c_um_context_set_log(ctx%ptr, f, data, level), ctx%ptr, 'um_context_set_log', ierr)
  end subroutine um_context_set_log

  ! =================================================================== options

  subroutine um_options_create(ctx, opts, ierr)
    type(um_context_t), intent(in) :: ctx
    type(um_options_t), intent(out) :: opts
    integer, optional, intent(out) :: ierr
    integer(c_int32_t) :: status
    status = c_um_options_create(ctx%ptr, opts%ptr)
    if (status == UM_OK) opts%ctx = ctx%ptr
    call finish(status, ctx%ptr, 'um_options_create', ierr)
  end subroutine um_options_create

  subroutine um_options_destroy(opts, ierr)
    type(um_options_t), intent(inout) :: opts
    integer, optional, intent(out) :: ierr
    call c_um_options_destroy(opts%ptr)
    opts%ptr = c_null_ptr
    opts%ctx = c_null_ptr
    if (present(ierr)) ierr = UM_OK
  end subroutine um_options_destroy

  !> Sets a real option (UM_OPT_*); out-of-range values fail and change nothing.
  subroutine um_options_set_double(opts, key, value, ierr)
    type(um_options_t), intent(in) :: opts
    integer, intent(in) :: key
    real(real64), intent(in) :: value
    integer, optional, intent(out) :: ierr
    call finish(c_um_options_set_double(opts%ptr, int(key, c_int32_t), real(value, c_double)), &
        opts%ctx, 'um_options_set_double', ierr)
  end subroutine um_options_set_double

  subroutine options_set_int(opts, key, value, ierr)
    type(um_options_t), intent(in) :: opts
    integer, intent(in) :: key
    integer, intent(in) :: value
    integer, optional, intent(out) :: ierr
    call options_set_int_int64(opts, key, int(value, int64), ierr)
  end subroutine options_set_int

  subroutine options_set_int_int64(opts, key, value, ierr)
    type(um_options_t), intent(in) :: opts
    integer, intent(in) :: key
    integer(int64), intent(in) :: value
    integer, optional, intent(out) :: ierr
    call finish(c_um_options_set_int(opts%ptr, int(key, c_int32_t), int(value, c_int64_t)), &
        opts%ctx, 'um_options_set_int', ierr)
  end subroutine options_set_int_int64

  subroutine um_options_get_double(opts, key, value, ierr)
    type(um_options_t), intent(in) :: opts
    integer, intent(in) :: key
    real(real64), intent(out) :: value
    integer, optional, intent(out) :: ierr
    real(c_double) :: v
    v = 0
    call finish(c_um_options_get_double(opts%ptr, int(key, c_int32_t), v), opts%ctx, &
        'um_options_get_double', ierr)
    value = real(v, real64)
  end subroutine um_options_get_double

  subroutine options_get_int(opts, key, value, ierr)
    type(um_options_t), intent(in) :: opts
    integer, intent(in) :: key
    integer, intent(out) :: value
    integer, optional, intent(out) :: ierr
    integer(int64) :: value64
    integer :: status
    value = 0
    call options_get_int_int64(opts, key, value64, status)
    if (status == UM_OK) then
      call narrow(value64, value, opts%ctx, 'um_options_get_int', ierr)
    else
      call finish(int(status, c_int32_t), opts%ctx, 'um_options_get_int', ierr)
    end if
  end subroutine options_get_int

  subroutine options_get_int_int64(opts, key, value, ierr)
    type(um_options_t), intent(in) :: opts
    integer, intent(in) :: key
    integer(int64), intent(out) :: value
    integer, optional, intent(out) :: ierr
    integer(c_int64_t) :: v
    v = 0
    call finish(c_um_options_get_int(opts%ptr, int(key, c_int32_t), v), opts%ctx, &
        'um_options_get_int', ierr)
    value = int(v, int64)
  end subroutine options_get_int_int64

  !> Sets several options from "name=value;name=value" (names as returned by
  !> um_option_name). All-or-nothing: on any error no option changes.
  subroutine um_options_set_string(opts, assignments, ierr)
    type(um_options_t), intent(in) :: opts
    character(len=*), intent(in) :: assignments
    integer, optional, intent(out) :: ierr
    call finish(c_um_options_set_string(opts%ptr, to_c(assignments)), opts%ctx, &
        'um_options_set_string', ierr)
  end subroutine um_options_set_string

  ! ============================================================= triangulation
  ! Arrays in are assumed-shape and may be sections with strides (the
  ! compiler hands C a contiguous copy when needed); lon_deg/lat_deg/weights
  ! have one element per point, xyz is xyz(3, n). Arrays out are allocatable
  ! and allocated here to their exact size (left unallocated on failure).
  ! Vertex indices are INPUT point indices and, like triangle indices, are
  ! 1-based.
  !
  ! Messages. The C library's messages name the argument, the index and the
  ! value, with C's 0-based index in brackets: "lat_deg[4] = nan" is the
  ! Fortran lat_deg(5). Sizes that disagree (lat_deg or weights against
  ! lon_deg, a first dimension of xyz other than 3) are found by this
  ! binding: UM_ERR_INVALID_ARGUMENT, described in the abort hook's message
  ! (the context holds no message for them, as for other binding-level
  ! failures).

  !> The triangulation of points given by longitude and latitude in degrees.
  !> weights (units of R^2, each below 2; absent = all 0, the Delaunay
  !> triangulation) make it the Laguerre triangulation: a point whose power
  !> cell is empty is hidden (see um_triangulation_get_hidden).
  subroutine um_triangulation_create(ctx, lon_deg, lat_deg, tri, weights, ierr)
    type(um_context_t), intent(in) :: ctx
    real(real64), intent(in) :: lon_deg(:), lat_deg(:)
    type(um_triangulation_t), intent(out) :: tri
    real(real64), optional, intent(in) :: weights(:)
    integer, optional, intent(out) :: ierr
    character(len=*), parameter :: routine = 'um_triangulation_create'
    character(len=:), allocatable :: problem
    integer(c_int32_t) :: status
    problem = size_problem('lat_deg', size(lat_deg, kind=int64), 'lon_deg', &
        size(lon_deg, kind=int64))
    if (len(problem) == 0 .and. present(weights)) problem = size_problem('weights', &
        size(weights, kind=int64), 'lon_deg', size(lon_deg, kind=int64))
    if (len(problem) > 0) then
      call finish(UM_ERR_INVALID_ARGUMENT, ctx%ptr, routine, ierr, problem)
      return
    end if
    status = c_um_triangulation_create(ctx%ptr, size(lon_deg, kind=c_int64_t), lon_deg, &
        lat_deg, weights, tri%ptr)
    if (status == UM_OK) tri%ctx = ctx%ptr
    call finish(status, ctx%ptr, routine, ierr)
  end subroutine um_triangulation_create

  !> The same from vectors xyz(:, i) (normalised by the library; not zero).
  subroutine um_triangulation_create_xyz(ctx, xyz, tri, weights, ierr)
    type(um_context_t), intent(in) :: ctx
    real(real64), intent(in) :: xyz(:, :)
    type(um_triangulation_t), intent(out) :: tri
    real(real64), optional, intent(in) :: weights(:)
    integer, optional, intent(out) :: ierr
    character(len=*), parameter :: routine = 'um_triangulation_create_xyz'
    character(len=:), allocatable :: problem
    integer(c_int32_t) :: status
    problem = ''
    if (size(xyz, 1) /= 3) then
      problem = 'xyz has ' // int_text(size(xyz, 1, kind=int64)) // &
          ' rows: it must be xyz(3, n), one column per point'
    else if (present(weights)) then
      problem = size_problem('weights', size(weights, kind=int64), 'the columns of xyz', &
          size(xyz, 2, kind=int64))
    end if
    if (len(problem) > 0) then
      call finish(UM_ERR_INVALID_ARGUMENT, ctx%ptr, routine, ierr, problem)
      return
    end if
    status = c_um_triangulation_create_xyz(ctx%ptr, size(xyz, 2, kind=c_int64_t), xyz, &
        weights, tri%ptr)
    if (status == UM_OK) tri%ctx = ctx%ptr
    call finish(status, ctx%ptr, routine, ierr)
  end subroutine um_triangulation_create_xyz

  !> Destroys the triangulation and nulls the handle; a null handle is fine.
  subroutine um_triangulation_destroy(tri, ierr)
    type(um_triangulation_t), intent(inout) :: tri
    integer, optional, intent(out) :: ierr
    call c_um_triangulation_destroy(tri%ptr)
    tri%ptr = c_null_ptr
    tri%ctx = c_null_ptr
    if (present(ierr)) ierr = UM_OK
  end subroutine um_triangulation_destroy

  !> Vertices (input points that are not hidden), triangles and hidden points.
  subroutine triangulation_counts(tri, n_vertices, n_triangles, n_hidden, ierr)
    type(um_triangulation_t), intent(in) :: tri
    integer, intent(out) :: n_vertices, n_triangles, n_hidden
    integer, optional, intent(out) :: ierr
    character(len=*), parameter :: routine = 'um_triangulation_counts'
    integer(int64) :: v, t, h, largest
    integer :: status, unused
    n_vertices = 0
    n_triangles = 0
    n_hidden = 0
    call triangulation_counts_int64(tri, v, t, h, status)
    if (status /= UM_OK) then
      call finish(int(status, c_int32_t), tri%ctx, routine, ierr)
      return
    end if
    ! One check for the three (all >= 0), so that one failure is reported once.
    largest = max(v, t, h)
    if (largest <= int(huge(n_vertices), int64)) then
      n_vertices = int(v)
      n_triangles = int(t)
      n_hidden = int(h)
    end if
    call narrow(largest, unused, tri%ctx, routine, ierr)
  end subroutine triangulation_counts

  subroutine triangulation_counts_int64(tri, n_vertices, n_triangles, n_hidden, ierr)
    type(um_triangulation_t), intent(in) :: tri
    integer(int64), intent(out) :: n_vertices, n_triangles, n_hidden
    integer, optional, intent(out) :: ierr
    integer(c_int64_t) :: v, t, h
    v = 0
    t = 0
    h = 0
    call finish(c_um_triangulation_counts(tri%ptr, v, t, h), tri%ctx, &
        'um_triangulation_counts', ierr)
    n_vertices = int(v, int64)
    n_triangles = int(t, int64)
    n_hidden = int(h, int64)
  end subroutine triangulation_counts_int64

  !> triangles(:, j): the three vertices of triangle j (1-based input point
  !> indices), counter-clockwise seen from outside the sphere.
  subroutine um_triangulation_get_triangles(tri, triangles, ierr)
    type(um_triangulation_t), intent(in) :: tri
    integer, allocatable, intent(out) :: triangles(:, :)
    integer, optional, intent(out) :: ierr
    call get_per_corner(tri, c_um_triangulation_copy_triangles, triangles, &
        'um_triangulation_get_triangles', ierr)
  end subroutine um_triangulation_get_triangles

  !> neighbours(k, j): the triangle (1-based) across the edge of triangle j
  !> opposite its vertex triangles(k, j).
  subroutine um_triangulation_get_neighbours(tri, neighbours, ierr)
    type(um_triangulation_t), intent(in) :: tri
    integer, allocatable, intent(out) :: neighbours(:, :)
    integer, optional, intent(out) :: ierr
    call get_per_corner(tri, c_um_triangulation_copy_neighbours, neighbours, &
        'um_triangulation_get_neighbours', ierr)
  end subroutine um_triangulation_get_neighbours

  !> xyz(:, j): the orthocentre (power vertex) of triangle j, a unit vector.
  subroutine um_triangulation_get_orthocentres(tri, xyz, ierr)
    type(um_triangulation_t), intent(in) :: tri
    real(real64), allocatable, intent(out) :: xyz(:, :)
    integer, optional, intent(out) :: ierr
    character(len=*), parameter :: routine = 'um_triangulation_get_orthocentres'
    integer(c_int64_t) :: n_vertices, n_triangles, n_hidden
    integer(c_int32_t) :: status
    integer :: alloc_status
    status = c_um_triangulation_counts(tri%ptr, n_vertices, n_triangles, n_hidden)
    if (status == UM_OK) then
      allocate (xyz(3, n_triangles), stat=alloc_status)
      if (alloc_status /= 0) then
        call finish(UM_ERR_OUT_OF_MEMORY, tri%ctx, routine, ierr, no_memory(3 * n_triangles))
        return
      end if
      status = c_um_triangulation_copy_orthocentres(tri%ptr, xyz, 3 * n_triangles)
      if (status /= UM_OK) deallocate (xyz)
    end if
    call finish(status, tri%ctx, routine, ierr)
  end subroutine um_triangulation_get_orthocentres

  !> The hidden points (1-based input indices, ascending); size 0 when none.
  subroutine um_triangulation_get_hidden(tri, hidden, ierr)
    type(um_triangulation_t), intent(in) :: tri
    integer, allocatable, intent(out) :: hidden(:)
    integer, optional, intent(out) :: ierr
    character(len=*), parameter :: routine = 'um_triangulation_get_hidden'
    integer(c_int64_t) :: n_vertices, n_triangles, n_hidden
    integer(c_int32_t) :: status
    integer :: alloc_status
    status = c_um_triangulation_counts(tri%ptr, n_vertices, n_triangles, n_hidden)
    if (status == UM_OK) then
      allocate (hidden(n_hidden), stat=alloc_status)
      if (alloc_status /= 0) then
        call finish(UM_ERR_OUT_OF_MEMORY, tri%ctx, routine, ierr, no_memory(n_hidden))
        return
      end if
      status = copy_indices(c_um_triangulation_copy_hidden, tri%ptr, hidden, n_hidden)
      if (status /= UM_OK) deallocate (hidden)
    end if
    call finish(status, tri%ctx, routine, ierr)
  end subroutine um_triangulation_get_hidden

  !> Re-checks every invariant with exact predicates: UM_OK when all hold,
  !> UM_ERR_INTERNAL naming the first violation otherwise.
  subroutine um_triangulation_check(tri, ierr)
    type(um_triangulation_t), intent(in) :: tri
    integer, optional, intent(out) :: ierr
    call finish(c_um_triangulation_check(tri%ptr), tri%ctx, 'um_triangulation_check', ierr)
  end subroutine um_triangulation_check

  ! ================================================================== features
  ! Messages name C's 0-based indices, as for the triangulation.

  subroutine um_features_create(ctx, features, ierr)
    type(um_context_t), intent(in) :: ctx
    type(um_features_t), intent(out) :: features
    integer, optional, intent(out) :: ierr
    integer(c_int32_t) :: status
    status = c_um_features_create(ctx%ptr, features%ptr)
    if (status == UM_OK) features%ctx = ctx%ptr
    call finish(status, ctx%ptr, 'um_features_create', ierr)
  end subroutine um_features_create

  !> Destroys the network and nulls the handle; a null handle is fine.
  subroutine um_features_destroy(features, ierr)
    type(um_features_t), intent(inout) :: features
    integer, optional, intent(out) :: ierr
    call c_um_features_destroy(features%ptr)
    features%ptr = c_null_ptr
    features%ctx = c_null_ptr
    if (present(ierr)) ierr = UM_OK
  end subroutine um_features_destroy

  !> Appends one part: the polyline through (lon_deg(i), lat_deg(i)), closed
  !> back to its first point when closed is true. kind is a UM_FEATURE_*
  !> value; part_id is the caller's own label kept with the part (absent:
  !> the part's 0-based index in the network). Mesh getters name parts by
  !> their 1-based position in the network, not by part_id.
  subroutine um_features_add_part(features, lon_deg, lat_deg, closed, kind, part_id, ierr)
    type(um_features_t), intent(in) :: features
    real(real64), intent(in) :: lon_deg(:), lat_deg(:)
    logical, intent(in) :: closed
    integer, intent(in) :: kind
    integer, optional, intent(in) :: part_id
    integer, optional, intent(out) :: ierr
    character(len=*), parameter :: routine = 'um_features_add_part'
    character(len=:), allocatable :: problem
    integer(c_int64_t) :: offsets(2)
    integer(c_int32_t) :: closed_c(1), kind_c(1), id_c(1), status
    problem = size_problem('lat_deg', size(lat_deg, kind=int64), 'lon_deg', &
        size(lon_deg, kind=int64))
    if (len(problem) > 0) then
      call finish(UM_ERR_INVALID_ARGUMENT, features%ctx, routine, ierr, problem)
      return
    end if
    offsets = [0_c_int64_t, size(lon_deg, kind=c_int64_t)]
    closed_c = merge(1_c_int32_t, 0_c_int32_t, closed)
    kind_c = int(kind, c_int32_t)
    if (present(part_id)) then
      id_c = int(part_id, c_int32_t)
      status = c_um_features_add(features%ptr, offsets(2), lon_deg, lat_deg, 1_c_int64_t, &
          offsets, closed_c, kind_c, id_c)
    else
      status = c_um_features_add(features%ptr, offsets(2), lon_deg, lat_deg, 1_c_int64_t, &
          offsets, closed_c, kind_c)
    end if
    call finish(status, features%ctx, routine, ierr)
  end subroutine um_features_add_part

  !> Appends the lines of a GeoJSON file (all-or-nothing). kind_property:
  !> the property giving the kind (absent: "kind"); default_kind: the kind of
  !> features without a known one (absent or 0: such a feature is an error).
  subroutine um_features_read_geojson(features, path, kind_property, default_kind, ierr)
    type(um_features_t), intent(in) :: features
    character(len=*), intent(in) :: path
    character(len=*), optional, intent(in) :: kind_property
    integer, optional, intent(in) :: default_kind
    integer, optional, intent(out) :: ierr
    integer(c_int32_t) :: default_c, status
    default_c = 0
    if (present(default_kind)) default_c = int(default_kind, c_int32_t)
    if (present(kind_property)) then
      status = c_um_features_read_geojson(features%ptr, to_c(path), to_c(kind_property), &
          default_c)
    else
      status = c_um_features_read_geojson(features%ptr, to_c(path), &
          default_kind=default_c)
    end if
    call finish(status, features%ctx, 'um_features_read_geojson', ierr)
  end subroutine um_features_read_geojson

  !> Stored parts, points and segments (after cleaning).
  subroutine um_features_counts(features, n_parts, n_points, n_segments, ierr)
    type(um_features_t), intent(in) :: features
    integer(int64), optional, intent(out) :: n_parts, n_points, n_segments
    integer, optional, intent(out) :: ierr
    integer(c_int64_t) :: parts, points, segments
    parts = 0
    points = 0
    segments = 0
    call finish(c_um_features_counts(features%ptr, parts, points, segments), features%ctx, &
        'um_features_counts', ierr)
    if (present(n_parts)) n_parts = int(parts, int64)
    if (present(n_points)) n_points = int(points, int64)
    if (present(n_segments)) n_segments = int(segments, int64)
  end subroutine um_features_counts

  !> All points of the network (degrees, as given; consecutive duplicates
  !> dropped).
  subroutine um_features_get_points(features, lon_deg, lat_deg, ierr)
    type(um_features_t), intent(in) :: features
    real(real64), allocatable, intent(out) :: lon_deg(:), lat_deg(:)
    integer, optional, intent(out) :: ierr
    integer(c_int64_t) :: parts, points, segments
    integer(c_int32_t) :: status
    status = c_um_features_counts(features%ptr, parts, points, segments)
    if (status == UM_OK) then
      allocate (lon_deg(points), lat_deg(points))
      status = c_um_features_copy_points(features%ptr, lon_deg, lat_deg, points)
    end if
    call finish(status, features%ctx, 'um_features_get_points', ierr)
  end subroutine um_features_get_points

  !> The parts: part p holds points first(p) .. first(p+1)-1 (1-based; first
  !> has n_parts + 1 entries), closed (0/1), kind (UM_FEATURE_*) and id.
  subroutine um_features_get_parts(features, first, closed, kind, part_id, ierr)
    type(um_features_t), intent(in) :: features
    integer(int64), allocatable, intent(out) :: first(:)
    integer, allocatable, intent(out) :: closed(:), kind(:), part_id(:)
    integer, optional, intent(out) :: ierr
    integer(c_int64_t) :: parts, points, segments
    integer(c_int64_t), allocatable :: offsets(:)
    integer(c_int32_t), allocatable :: c_closed(:), c_kind(:), c_id(:)
    integer(c_int32_t) :: status
    status = c_um_features_counts(features%ptr, parts, points, segments)
    if (status == UM_OK) then
      allocate (offsets(parts + 1), c_closed(parts), c_kind(parts), c_id(parts))
      status = c_um_features_copy_parts(features%ptr, offsets, c_closed, c_kind, c_id, parts + 1)
      if (status == UM_OK) then
        first = int(offsets + 1, int64)
        closed = int(c_closed)
        kind = int(c_kind)
        part_id = int(c_id)
      end if
    end if
    call finish(status, features%ctx, 'um_features_get_parts', ierr)
  end subroutine um_features_get_parts

  ! =================================================================== spacing

  !> h = km everywhere.
  subroutine um_spacing_create_constant(ctx, km, spacing, ierr)
    type(um_context_t), intent(in) :: ctx
    real(real64), intent(in) :: km
    type(um_spacing_t), intent(out) :: spacing
    integer, optional, intent(out) :: ierr
    integer(c_int32_t) :: status
    status = c_um_spacing_create_constant(ctx%ptr, real(km, c_double), spacing%ptr)
    if (status == UM_OK) spacing%ctx = ctx%ptr
    call finish(status, ctx%ptr, 'um_spacing_create_constant', ierr)
  end subroutine um_spacing_create_constant

  !> Bilinear interpolation in a lon/lat grid: cell_width_km(i, j) is the
  !> width at (lon_deg(i), lat_deg(j)), i.e. MPAS cellWidth(lat, lon) as
  !> Fortran reads it from netCDF.
  subroutine um_spacing_create_grid(ctx, lon_deg, lat_deg, cell_width_km, spacing, ierr)
    type(um_context_t), intent(in) :: ctx
    real(real64), intent(in) :: lon_deg(:), lat_deg(:), cell_width_km(:, :)
    type(um_spacing_t), intent(out) :: spacing
    integer, optional, intent(out) :: ierr
    character(len=*), parameter :: routine = 'um_spacing_create_grid'
    integer(c_int32_t) :: status
    if (size(cell_width_km, 1) /= size(lon_deg) .or. size(cell_width_km, 2) /= size(lat_deg)) &
        then
      call finish(UM_ERR_INVALID_ARGUMENT, ctx%ptr, routine, ierr, &
          'cell_width_km must have shape (size(lon_deg), size(lat_deg)) = (' // &
          int_text(size(lon_deg, kind=int64)) // ', ' // int_text(size(lat_deg, kind=int64)) &
          // ')')
      return
    end if
    status = c_um_spacing_create_grid(ctx%ptr, size(lon_deg, kind=c_int64_t), lon_deg, &
        size(lat_deg, kind=c_int64_t), lat_deg, cell_width_km, spacing%ptr)
    if (status == UM_OK) spacing%ctx = ctx%ptr
    call finish(status, ctx%ptr, routine, ierr)
  end subroutine um_spacing_create_grid

  !> A named E3SM spacing: "QU240", "EC60to30", "RRS18to6", ...
  subroutine um_spacing_create_preset(ctx, name, spacing, ierr)
    type(um_context_t), intent(in) :: ctx
    character(len=*), intent(in) :: name
    type(um_spacing_t), intent(out) :: spacing
    integer, optional, intent(out) :: ierr
    integer(c_int32_t) :: status
    status = c_um_spacing_create_preset(ctx%ptr, to_c(name), spacing%ptr)
    if (status == UM_OK) spacing%ctx = ctx%ptr
    call finish(status, ctx%ptr, 'um_spacing_create_preset', ierr)
  end subroutine um_spacing_create_preset

  !> The grid of an MPAS-tools spacing file (netCDF lon, lat, cellWidth).
  subroutine um_spacing_create_from_file(ctx, path, spacing, ierr)
    type(um_context_t), intent(in) :: ctx
    character(len=*), intent(in) :: path
    type(um_spacing_t), intent(out) :: spacing
    integer, optional, intent(out) :: ierr
    integer(c_int32_t) :: status
    status = c_um_spacing_create_from_file(ctx%ptr, to_c(path), spacing%ptr)
    if (status == UM_OK) spacing%ctx = ctx%ptr
    call finish(status, ctx%ptr, 'um_spacing_create_from_file', ierr)
  end subroutine um_spacing_create_from_file

  !> h = fn(user_data, lon_deg, lat_deg) in km, fn a bind(c) function of
  !> interface um_spacing_fn. It is called from worker threads, concurrently:
  !> it must be thread-safe (no SAVEd state it writes). user_data (absent:
  !> c_null_ptr) is passed back, e.g. c_loc of a TARGET with parameters; it
  !> and fn must stay valid while the spacing or a mesh made from it lives.
  subroutine um_spacing_create_callback(ctx, fn, spacing, user_data, ierr)
    type(um_context_t), intent(in) :: ctx
    procedure(um_spacing_fn) :: fn
    type(um_spacing_t), intent(out) :: spacing
    type(c_ptr), optional, intent(in) :: user_data
    integer, optional, intent(out) :: ierr
    type(c_ptr) :: data
    integer(c_int32_t) :: status
    data = c_null_ptr
    if (present(user_data)) data = user_data
    status = c_um_spacing_create_callback(ctx%ptr, c_funloc(fn), data, spacing%ptr)
    if (status == UM_OK) spacing%ctx = ctx%ptr
    call finish(status, ctx%ptr, 'um_spacing_create_callback', ierr)
  end subroutine um_spacing_create_callback

  !> Destroys the spacing and nulls the handle; a null handle is fine.
  subroutine um_spacing_destroy(spacing, ierr)
    type(um_spacing_t), intent(inout) :: spacing
    integer, optional, intent(out) :: ierr
    call c_um_spacing_destroy(spacing%ptr)
    spacing%ptr = c_null_ptr
    spacing%ctx = c_null_ptr
    if (present(ierr)) ierr = UM_OK
  end subroutine um_spacing_destroy

  !> Limits |grad h| to g km per km (grid spacings only).
  subroutine um_spacing_limit_gradient(spacing, g, ierr)
    type(um_spacing_t), intent(in) :: spacing
    real(real64), intent(in) :: g
    integer, optional, intent(out) :: ierr
    call finish(c_um_spacing_limit_gradient(spacing%ptr, real(g, c_double)), spacing%ctx, &
        'um_spacing_limit_gradient', ierr)
  end subroutine um_spacing_limit_gradient

  !> h = min(max(h, km_min), km_max).
  subroutine um_spacing_clamp(spacing, km_min, km_max, ierr)
    type(um_spacing_t), intent(in) :: spacing
    real(real64), intent(in) :: km_min, km_max
    integer, optional, intent(out) :: ierr
    call finish(c_um_spacing_clamp(spacing%ptr, real(km_min, c_double), &
        real(km_max, c_double)), spacing%ctx, 'um_spacing_clamp', ierr)
  end subroutine um_spacing_clamp

  !> km(i) = h at (lon_deg(i), lat_deg(i)); the three have the same size.
  subroutine um_spacing_evaluate(spacing, lon_deg, lat_deg, km, ierr)
    type(um_spacing_t), intent(in) :: spacing
    real(real64), intent(in) :: lon_deg(:), lat_deg(:)
    real(real64), intent(out) :: km(:)
    integer, optional, intent(out) :: ierr
    character(len=*), parameter :: routine = 'um_spacing_evaluate'
    character(len=:), allocatable :: problem
    problem = size_problem('lat_deg', size(lat_deg, kind=int64), 'lon_deg', &
        size(lon_deg, kind=int64))
    if (len(problem) == 0) problem = size_problem('km', size(km, kind=int64), 'lon_deg', &
        size(lon_deg, kind=int64))
    if (len(problem) > 0) then
      call finish(UM_ERR_INVALID_ARGUMENT, spacing%ctx, routine, ierr, problem)
      return
    end if
    call finish(c_um_spacing_evaluate(spacing%ptr, size(lon_deg, kind=c_int64_t), lon_deg, &
        lat_deg, km), spacing%ctx, routine, ierr)
  end subroutine um_spacing_evaluate

  !> What a mesh of this spacing is expected to need: cells, the peak bytes
  !> of refining and optimising it, and what writing its MPAS mesh file adds.
  subroutine um_spacing_estimate(spacing, cells, refine_bytes, mpas_bytes, ierr)
    type(um_spacing_t), intent(in) :: spacing
    integer(int64), optional, intent(out) :: cells, refine_bytes, mpas_bytes
    integer, optional, intent(out) :: ierr
    integer(c_int64_t) :: c, r, m
    call finish(c_um_spacing_estimate(spacing%ptr, c, r, m), spacing%ctx, 'um_spacing_estimate', ierr)
    if (present(cells)) cells = c
    if (present(refine_bytes)) refine_bytes = r
    if (present(mpas_bytes)) mpas_bytes = m
  end subroutine um_spacing_estimate

  ! ====================================================================== mesh
  ! Getters allocate their results to the exact size (left unallocated on
  ! failure); vertex, triangle and part indices are 1-based.

  !> The restricted triangulation for spacing, with vertices on features
  !> when given; options absent = the defaults.
  subroutine um_mesh_refine(ctx, spacing, mesh, features, options, ierr)
    type(um_context_t), intent(in) :: ctx
    type(um_spacing_t), intent(in) :: spacing
    type(um_mesh_t), intent(out) :: mesh
    type(um_features_t), optional, intent(in) :: features
    type(um_options_t), optional, intent(in) :: options
    integer, optional, intent(out) :: ierr
    type(c_ptr) :: features_ptr, options_ptr
    integer(c_int32_t) :: status
    features_ptr = c_null_ptr
    options_ptr = c_null_ptr
    if (present(features)) features_ptr = features%ptr
    if (present(options)) options_ptr = options%ptr
    status = c_um_mesh_refine(ctx%ptr, spacing%ptr, features_ptr, options_ptr, mesh%ptr)
    if (status == UM_OK) mesh%ctx = ctx%ptr
    call finish(status, ctx%ptr, 'um_mesh_refine', ierr)
  end subroutine um_mesh_refine

  !> The weighted primal-dual optimisation of the mesh, in place (paper
  !> section 6; see um_mesh_optimise in unimesh.h); options absent = the
  !> defaults. On an error the mesh is left as it was.
  subroutine um_mesh_optimise(mesh, options, ierr)
    type(um_mesh_t), intent(inout) :: mesh
    type(um_options_t), optional, intent(in) :: options
    integer, optional, intent(out) :: ierr
    type(c_ptr) :: options_ptr
    integer(c_int32_t) :: status
    options_ptr = c_null_ptr
    if (present(options)) options_ptr = options%ptr
    status = c_um_mesh_optimise(mesh%ptr, options_ptr)
    call finish(status, mesh%ctx, 'um_mesh_optimise', ierr)
  end subroutine um_mesh_optimise

  !> Destroys the mesh and nulls the handle; a null handle is fine.
  subroutine um_mesh_destroy(mesh, ierr)
    type(um_mesh_t), intent(inout) :: mesh
    integer, optional, intent(out) :: ierr
    call c_um_mesh_destroy(mesh%ptr)
    mesh%ptr = c_null_ptr
    mesh%ctx = c_null_ptr
    if (present(ierr)) ierr = UM_OK
  end subroutine um_mesh_destroy

  !> Vertices, triangles, restricted edges and filtered (unrefined) ones.
  subroutine um_mesh_counts(mesh, n_vertices, n_triangles, n_restricted_edges, n_filtered, ierr)
    type(um_mesh_t), intent(in) :: mesh
    integer(int64), optional, intent(out) :: n_vertices, n_triangles, n_restricted_edges, &
        n_filtered
    integer, optional, intent(out) :: ierr
    integer(c_int64_t) :: v, t, r, f
    v = 0
    t = 0
    r = 0
    f = 0
    call finish(c_um_mesh_counts(mesh%ptr, v, t, r, f), mesh%ctx, 'um_mesh_counts', ierr)
    if (present(n_vertices)) n_vertices = int(v, int64)
    if (present(n_triangles)) n_triangles = int(t, int64)
    if (present(n_restricted_edges)) n_restricted_edges = int(r, int64)
    if (present(n_filtered)) n_filtered = int(f, int64)
  end subroutine um_mesh_counts

  !> Vertex positions in degrees (lon in (-180, 180]).
  subroutine um_mesh_get_vertices(mesh, lon_deg, lat_deg, ierr)
    type(um_mesh_t), intent(in) :: mesh
    real(real64), allocatable, intent(out) :: lon_deg(:), lat_deg(:)
    integer, optional, intent(out) :: ierr
    character(len=*), parameter :: routine = 'um_mesh_get_vertices'
    integer(c_int64_t) :: v, t, r, f
    integer(c_int32_t) :: status
    integer :: alloc_status
    status = c_um_mesh_counts(mesh%ptr, v, t, r, f)
    if (status == UM_OK) then
      allocate (lon_deg(v), lat_deg(v), stat=alloc_status)
      if (alloc_status /= 0) then
        call finish(UM_ERR_OUT_OF_MEMORY, mesh%ctx, routine, ierr, no_memory(2 * v))
        return
      end if
      status = c_um_mesh_copy_vertices(mesh%ptr, lon_deg, lat_deg, v)
      if (status /= UM_OK) deallocate (lon_deg, lat_deg)
    end if
    call finish(status, mesh%ctx, routine, ierr)
  end subroutine um_mesh_get_vertices

  !> triangles(:, j): the three vertices of triangle j (1-based),
  !> counter-clockwise seen from outside the sphere.
  subroutine um_mesh_get_triangles(mesh, triangles, ierr)
    type(um_mesh_t), intent(in) :: mesh
    integer, allocatable, intent(out) :: triangles(:, :)
    integer, optional, intent(out) :: ierr
    character(len=*), parameter :: routine = 'um_mesh_get_triangles'
    integer(c_int64_t) :: v, t, r, f
    integer(c_int32_t) :: status
    integer :: alloc_status
    status = c_um_mesh_counts(mesh%ptr, v, t, r, f)
    if (status == UM_OK) then
      allocate (triangles(3, t), stat=alloc_status)
      if (alloc_status /= 0) then
        call finish(UM_ERR_OUT_OF_MEMORY, mesh%ctx, routine, ierr, no_memory(3 * t))
        return
      end if
      status = copy_indices(c_um_mesh_copy_triangles, mesh%ptr, triangles, 3 * t)
      if (status /= UM_OK) deallocate (triangles)
    end if
    call finish(status, mesh%ctx, routine, ierr)
  end subroutine um_mesh_get_triangles

  !> parts(i): the features part (1-based, in the order added) vertex i was
  !> placed on, or -1 when it is not on a feature.
  subroutine um_mesh_get_vertex_parts(mesh, parts, ierr)
    type(um_mesh_t), intent(in) :: mesh
    integer, allocatable, intent(out) :: parts(:)
    integer, optional, intent(out) :: ierr
    character(len=*), parameter :: routine = 'um_mesh_get_vertex_parts'
    integer(c_int64_t) :: v, t, r, f
    integer(c_int32_t) :: status
    integer :: alloc_status
    status = c_um_mesh_counts(mesh%ptr, v, t, r, f)
    if (status == UM_OK) then
      allocate (parts(v), stat=alloc_status)
      if (alloc_status /= 0) then
        call finish(UM_ERR_OUT_OF_MEMORY, mesh%ctx, routine, ierr, no_memory(v))
        return
      end if
      status = copy_indices(c_um_mesh_copy_vertex_parts, mesh%ptr, parts, v)
      if (status /= UM_OK) deallocate (parts)
    end if
    call finish(status, mesh%ctx, routine, ierr)
  end subroutine um_mesh_get_vertex_parts

  !> vertices(:, e): the two vertices (1-based) of restricted edge e;
  !> parts(e): the part (1-based) whose segment its dual edge crosses.
  subroutine um_mesh_get_restricted_edges(mesh, vertices, parts, ierr)
    type(um_mesh_t), intent(in) :: mesh
    integer, allocatable, intent(out) :: vertices(:, :), parts(:)
    integer, optional, intent(out) :: ierr
    character(len=*), parameter :: routine = 'um_mesh_get_restricted_edges'
    integer(c_int64_t) :: v, t, r, f
    integer(c_int32_t) :: status
    integer(c_int32_t), allocatable :: vertices_c(:, :), parts_c(:)
    integer :: alloc_status
    status = c_um_mesh_counts(mesh%ptr, v, t, r, f)
    if (status == UM_OK) then
      allocate (vertices_c(2, r), parts_c(r), stat=alloc_status)
      if (alloc_status /= 0) then
        call finish(UM_ERR_OUT_OF_MEMORY, mesh%ctx, routine, ierr, no_memory(3 * r))
        return
      end if
      status = c_um_mesh_copy_restricted_edges(mesh%ptr, 1_c_int32_t, vertices_c, parts_c, r)
      if (status == UM_OK) then
        vertices = int(vertices_c)
        parts = int(parts_c)
      end if
    end if
    call finish(status, mesh%ctx, routine, ierr)
  end subroutine um_mesh_get_restricted_edges

  !> sides(i): UM_SIDE_OCEAN, UM_SIDE_LAND or UM_SIDE_COASTAL of vertex i.
  subroutine um_mesh_get_vertex_sides(mesh, sides, ierr)
    type(um_mesh_t), intent(in) :: mesh
    integer, allocatable, intent(out) :: sides(:)
    integer, optional, intent(out) :: ierr
    call get_sides(mesh, .true., sides, 'um_mesh_get_vertex_sides', ierr)
  end subroutine um_mesh_get_vertex_sides

  !> sides(j): UM_SIDE_OCEAN or UM_SIDE_LAND of triangle j's orthocentre.
  subroutine um_mesh_get_triangle_sides(mesh, sides, ierr)
    type(um_mesh_t), intent(in) :: mesh
    integer, allocatable, intent(out) :: sides(:)
    integer, optional, intent(out) :: ierr
    call get_sides(mesh, .false., sides, 'um_mesh_get_triangle_sides', ierr)
  end subroutine um_mesh_get_triangle_sides

  subroutine get_sides(mesh, per_vertex, sides, routine, ierr)
    type(um_mesh_t), intent(in) :: mesh
    logical, intent(in) :: per_vertex
    integer, allocatable, intent(out) :: sides(:)
    character(len=*), intent(in) :: routine
    integer, optional, intent(out) :: ierr
    integer(c_int64_t) :: v, t, r, f, n
    integer(c_int32_t) :: status
    integer(c_int32_t), allocatable :: sides_c(:)
    integer :: alloc_status
    status = c_um_mesh_counts(mesh%ptr, v, t, r, f)
    if (status == UM_OK) then
      n = merge(v, t, per_vertex)
      allocate (sides_c(n), stat=alloc_status)
      if (alloc_status /= 0) then
        call finish(UM_ERR_OUT_OF_MEMORY, mesh%ctx, routine, ierr, no_memory(n))
        return
      end if
      if (per_vertex) then
        status = c_um_mesh_copy_vertex_sides(mesh%ptr, sides_c, n)
      else
        status = c_um_mesh_copy_triangle_sides(mesh%ptr, sides_c, n)
      end if
      if (status == UM_OK) sides = int(sides_c)
    end if
    call finish(status, mesh%ctx, routine, ierr)
  end subroutine get_sides

  !> Three 1-based indices per triangle from copy (copy_triangles or
  !> copy_neighbours) into values(3, n_triangles).
  subroutine get_per_corner(tri, copy, values, routine, ierr)
    type(um_triangulation_t), intent(in) :: tri
    procedure(c_um_triangulation_copy_triangles) :: copy
    integer, allocatable, intent(out) :: values(:, :)
    character(len=*), intent(in) :: routine
    integer, optional, intent(out) :: ierr
    integer(c_int64_t) :: n_vertices, n_triangles, n_hidden
    integer(c_int32_t) :: status
    integer :: alloc_status
    status = c_um_triangulation_counts(tri%ptr, n_vertices, n_triangles, n_hidden)
    if (status == UM_OK) then
      allocate (values(3, n_triangles), stat=alloc_status)
      if (alloc_status /= 0) then
        call finish(UM_ERR_OUT_OF_MEMORY, tri%ctx, routine, ierr, no_memory(3 * n_triangles))
        return
      end if
      status = copy_indices(copy, tri%ptr, values, 3 * n_triangles)
      if (status /= UM_OK) deallocate (values)
    end if
    call finish(status, tri%ctx, routine, ierr)
  end subroutine get_per_corner

  !> Runs copy (a um_triangulation_copy_* of int32 indices) with base 1 into
  !> the n default integers of values. C writes straight into values when the
  !> default integer is int32 (the usual case: no second copy of a large
  !> mesh), else into an int32 buffer that is then converted.
  function copy_indices(copy, t, values, n) result(status)
    procedure(c_um_triangulation_copy_triangles) :: copy
    type(c_ptr), intent(in) :: t
    integer(c_int64_t), intent(in) :: n
    integer, target, intent(out) :: values(n)
    integer(c_int32_t) :: status
    integer(c_int32_t), pointer, contiguous :: view(:)
    integer(c_int32_t), allocatable, target :: buffer(:)
    if (kind(values) == c_int32_t .and. n > 0) then
      call c_f_pointer(c_loc(values), view, [n])
    else
      allocate (buffer(n))
      view => buffer
    end if
    status = copy(t, 1_c_int32_t, view, n)
    if (kind(values) /= c_int32_t .and. status == UM_OK) values = int(view)
  end function copy_indices

  !> "" when size_a equals size_b, else why not.
  function size_problem(name_a, size_a, name_b, size_b) result(problem)
    character(len=*), intent(in) :: name_a, name_b
    integer(int64), intent(in) :: size_a, size_b
    character(len=:), allocatable :: problem
    problem = ''
    if (size_a /= size_b) problem = name_a // ' has ' // int_text(size_a) // ' elements and ' &
        // name_b // ' has ' // int_text(size_b) // ': they must have one per point'
  end function size_problem

  !> min / 1st percentile / mean / max of a quality metric of the mesh:
  !> 'area_length_ratio', 'primal_dual', 'angle_min_deg', 'angle_max_deg',
  !> 'edge_spacing_ratio', or an operator diagnostic: 'centroid_offset',
  !> 'dual_edge_offset', 'primal_edge_offset' or 'cell_spacing_ratio'
  !> (see um_mesh_quality_summary in unimesh.h; rms and std are in the JSON).
  subroutine um_mesh_quality_summary(mesh, metric, min, p1, mean, max, ierr)
    type(um_mesh_t), intent(in) :: mesh
    character(len=*), intent(in) :: metric
    real(real64), optional, intent(out) :: min, p1, mean, max
    integer, optional, intent(out) :: ierr
    real(c_double) :: v(4)
    v = 0
    call finish(c_um_mesh_quality_summary(mesh%ptr, to_c(metric), v(1), v(2), v(3), v(4)), mesh%ctx, &
        'um_mesh_quality_summary', ierr)
    if (present(min)) min = v(1)
    if (present(p1)) p1 = v(2)
    if (present(mean)) mean = v(3)
    if (present(max)) max = v(4)
  end subroutine um_mesh_quality_summary

  !> Triangles with an angle over 90 degrees, and those not holding their
  !> orthocentre.
  subroutine um_mesh_quality_counts(mesh, obtuse, not_well_centred, ierr)
    type(um_mesh_t), intent(in) :: mesh
    integer, optional, intent(out) :: obtuse, not_well_centred
    integer, optional, intent(out) :: ierr
    integer(c_int64_t) :: o, w
    o = 0
    w = 0
    call finish(c_um_mesh_quality_counts(mesh%ptr, o, w), mesh%ctx, 'um_mesh_quality_counts', ierr)
    if (present(obtuse)) obtuse = int(o)
    if (present(not_well_centred)) not_well_centred = int(w)
  end subroutine um_mesh_quality_counts

  !> The quality report as JSON text (what quality.json holds).
  subroutine um_mesh_quality_json(mesh, text, ierr)
    type(um_mesh_t), intent(in) :: mesh
    character(len=:), allocatable, intent(out) :: text
    integer, optional, intent(out) :: ierr
    call mesh_json(mesh, c_um_mesh_quality_json, 'um_mesh_quality_json', text, ierr)
  end subroutine um_mesh_quality_json

  ! A JSON report sized, then copied: the sizing call (capacity 0) reports
  ! the length needed; the error it records is ours, not the caller's, and
  ! goes again.
  subroutine mesh_json(mesh, fn, name, text, ierr)
    type(um_mesh_t), intent(in) :: mesh
    procedure(mesh_json_fn) :: fn
    character(len=*), intent(in) :: name
    character(len=:), allocatable, intent(out) :: text
    integer, optional, intent(out) :: ierr
    character(kind=c_char), allocatable :: buf(:)
    integer(c_int64_t) :: needed
    integer(c_int32_t) :: status, before
    text = ''
    needed = 0
    before = UM_OK
    if (c_associated(mesh%ctx)) before = c_um_context_last_status(mesh%ctx)
    status = fn(mesh%ptr, capacity=0_c_int64_t, needed=needed)
    if (status == UM_ERR_BUFFER_TOO_SMALL) then
      if (before == UM_OK .and. c_associated(mesh%ctx)) status = c_um_context_clear_error(mesh%ctx)
      allocate (buf(needed))
      status = fn(mesh%ptr, buf, needed, needed)
      if (status == UM_OK) text = from_c_chars(buf, int(needed) - 1)
    end if
    call finish(status, mesh%ctx, name, ierr)
  end subroutine mesh_json

  !> Writes the MPAS mesh file (netCDF) of the mesh.
  subroutine um_mesh_write_mpas(mesh, path, ierr)
    type(um_mesh_t), intent(in) :: mesh
    character(len=*), intent(in) :: path
    integer, optional, intent(out) :: ierr
    call finish(c_um_mesh_write_mpas(mesh%ptr, to_c(path)), mesh%ctx, 'um_mesh_write_mpas', ierr)
  end subroutine um_mesh_write_mpas

  !> Writes the MPAS mesh file in the container asked for: UM_MPAS_FILE_AUTO
  !> (as um_mesh_write_mpas) or UM_MPAS_FILE_NETCDF4.
  subroutine um_mesh_write_mpas_as(mesh, path, format, ierr)
    type(um_mesh_t), intent(in) :: mesh
    character(len=*), intent(in) :: path
    integer(c_int32_t), intent(in) :: format
    integer, optional, intent(out) :: ierr
    call finish(c_um_mesh_write_mpas_as(mesh%ptr, to_c(path), format), mesh%ctx, 'um_mesh_write_mpas_as', ierr)
  end subroutine um_mesh_write_mpas_as

  !> Writes the component meshes and coupler grids into an existing
  !> directory: mesh.nc (with the maps), ocean.nc, land.nc, their graph.info
  !> files, SCRIP and ESMF grids of all three, rivers.json.
  subroutine um_mesh_write_components(mesh, directory, ierr)
    type(um_mesh_t), intent(in) :: mesh
    character(len=*), intent(in) :: directory
    integer, optional, intent(out) :: ierr
    call finish(c_um_mesh_write_components(mesh%ptr, to_c(directory)), mesh%ctx, 'um_mesh_write_components', ierr)
  end subroutine um_mesh_write_components

  !> The same from an MPAS mesh file with the ocean and land cell masks.
  subroutine um_mpas_file_write_components(ctx, mesh_path, directory, ierr)
    type(um_context_t), intent(in) :: ctx
    character(len=*), intent(in) :: mesh_path, directory
    integer, optional, intent(out) :: ierr
    call finish(c_um_mpas_file_write_components(ctx%ptr, to_c(mesh_path), to_c(directory)), ctx%ptr, &
                'um_mpas_file_write_components', ierr)
  end subroutine um_mpas_file_write_components

  !> The river routing report as JSON text (what rivers.json holds).
  subroutine um_mesh_river_report_json(mesh, text, ierr)
    type(um_mesh_t), intent(in) :: mesh
    character(len=:), allocatable, intent(out) :: text
    integer, optional, intent(out) :: ierr
    call mesh_json(mesh, c_um_mesh_river_report_json, 'um_mesh_river_report_json', text, ierr)
  end subroutine um_mesh_river_report_json

  !> Writes the triangulation in JIGSAW's .msh format.
  subroutine um_mesh_write_jigsaw(mesh, path, ierr)
    type(um_mesh_t), intent(in) :: mesh
    character(len=*), intent(in) :: path
    integer, optional, intent(out) :: ierr
    call finish(c_um_mesh_write_jigsaw(mesh%ptr, to_c(path)), mesh%ctx, 'um_mesh_write_jigsaw', ierr)
  end subroutine um_mesh_write_jigsaw

  !> Dimensions of the MPAS staggered mesh (its numbering is made on first
  !> use and kept with the mesh until um_mesh_release_mpas; each variable is
  !> made when it is copied).
  subroutine um_mesh_mpas_dimensions(mesh, n_cells, n_edges, n_vertices, max_edges, ierr)
    type(um_mesh_t), intent(in) :: mesh
    integer, optional, intent(out) :: n_cells, n_edges, n_vertices, max_edges
    integer, optional, intent(out) :: ierr
    integer(c_int64_t) :: c, e, v, m
    c = 0
    e = 0
    v = 0
    m = 0
    call finish(c_um_mesh_mpas_dimensions(mesh%ptr, c, e, v, m), mesh%ctx, &
        'um_mesh_mpas_dimensions', ierr)
    if (present(n_cells)) n_cells = int(c)
    if (present(n_edges)) n_edges = int(e)
    if (present(n_vertices)) n_vertices = int(v)
    if (present(max_edges)) max_edges = int(m)
  end subroutine um_mesh_mpas_dimensions

  !> Frees the numbering of the staggered mesh kept for um_mesh_get_mpas.
  subroutine um_mesh_release_mpas(mesh, ierr)
    type(um_mesh_t), intent(in) :: mesh
    integer, optional, intent(out) :: ierr
    call finish(c_um_mesh_release_mpas(mesh%ptr), mesh%ctx, 'um_mesh_release_mpas', ierr)
  end subroutine um_mesh_release_mpas

  !> The shape of an MPAS variable, checked against the type and rank asked
  !> for; status /= UM_OK with message set when they disagree.
  subroutine mpas_shape(mesh, name, want_type, rank, n_rows, n_columns, status, message)
    type(um_mesh_t), intent(in) :: mesh
    character(len=*), intent(in) :: name
    integer(c_int32_t), intent(in) :: want_type
    integer, intent(in) :: rank
    integer(c_int64_t), intent(out) :: n_rows, n_columns
    integer(c_int32_t), intent(out) :: status
    character(len=:), allocatable, intent(out) :: message
    integer(c_int32_t) :: type
    message = ''
    n_rows = 0
    n_columns = 0
    status = c_um_mesh_mpas_variable(mesh%ptr, to_c(name), type, n_rows, n_columns)
    if (status /= UM_OK) return
    if (type /= want_type) then
      status = UM_ERR_INVALID_ARGUMENT
      if (type == UM_MPAS_REAL) then
        message = 'MPAS variable ' // trim(name) // ' holds reals: pass a real(real64) array'
      else
        message = 'MPAS variable ' // trim(name) // ' holds integers: pass an integer array'
      end if
    else if (rank == 1 .and. n_columns /= 1) then
      status = UM_ERR_INVALID_ARGUMENT
      message = 'MPAS variable ' // trim(name) // ' has two dimensions: pass a rank-2 array'
    end if
  end subroutine mpas_shape

  !> finish() with the shape check's own message when it made one.
  subroutine finish_mpas(status, mesh, routine, ierr, message)
    integer(c_int32_t), intent(in) :: status
    type(um_mesh_t), intent(in) :: mesh
    character(len=*), intent(in) :: routine, message
    integer, optional, intent(out) :: ierr
    if (len(message) > 0) then
      call finish(status, mesh%ctx, routine, ierr, message)
    else
      call finish(status, mesh%ctx, routine, ierr)
    end if
  end subroutine finish_mpas

  subroutine mesh_get_mpas_real_1d(mesh, name, values, ierr)
    type(um_mesh_t), intent(in) :: mesh
    character(len=*), intent(in) :: name
    real(real64), allocatable, intent(out) :: values(:)
    integer, optional, intent(out) :: ierr
    character(len=*), parameter :: routine = 'um_mesh_get_mpas'
    integer(c_int64_t) :: rows, columns
    integer(c_int32_t) :: status
    character(len=:), allocatable :: message
    integer :: alloc_status
    call mpas_shape(mesh, name, UM_MPAS_REAL, 1, rows, columns, status, message)
    if (status == UM_OK) then
      allocate (values(rows), stat=alloc_status)
      if (alloc_status /= 0) then
        call finish(UM_ERR_OUT_OF_MEMORY, mesh%ctx, routine, ierr, no_memory(rows))
        return
      end if
      status = c_um_mesh_copy_mpas_real(mesh%ptr, to_c(name), values, rows)
      if (status /= UM_OK) deallocate (values)
    end if
    call finish_mpas(status, mesh, routine, ierr, message)
  end subroutine mesh_get_mpas_real_1d

  subroutine mesh_get_mpas_real_2d(mesh, name, values, ierr)
    type(um_mesh_t), intent(in) :: mesh
    character(len=*), intent(in) :: name
    real(real64), allocatable, intent(out) :: values(:, :)
    integer, optional, intent(out) :: ierr
    character(len=*), parameter :: routine = 'um_mesh_get_mpas'
    integer(c_int64_t) :: rows, columns
    integer(c_int32_t) :: status
    character(len=:), allocatable :: message
    integer :: alloc_status
    call mpas_shape(mesh, name, UM_MPAS_REAL, 2, rows, columns, status, message)
    if (status == UM_OK) then
      allocate (values(columns, rows), stat=alloc_status)
      if (alloc_status /= 0) then
        call finish(UM_ERR_OUT_OF_MEMORY, mesh%ctx, routine, ierr, no_memory(rows * columns))
        return
      end if
      status = c_um_mesh_copy_mpas_real(mesh%ptr, to_c(name), values, rows * columns)
      if (status /= UM_OK) deallocate (values)
    end if
    call finish_mpas(status, mesh, routine, ierr, message)
  end subroutine mesh_get_mpas_real_2d

  subroutine mesh_get_mpas_int_1d(mesh, name, values, ierr)
    type(um_mesh_t), intent(in) :: mesh
    character(len=*), intent(in) :: name
    integer, allocatable, intent(out) :: values(:)
    integer, optional, intent(out) :: ierr
    character(len=*), parameter :: routine = 'um_mesh_get_mpas'
    integer(c_int64_t) :: rows, columns
    integer(c_int32_t) :: status
    character(len=:), allocatable :: message
    integer(c_int32_t), allocatable :: buffer(:)
    integer :: alloc_status
    call mpas_shape(mesh, name, UM_MPAS_INT, 1, rows, columns, status, message)
    if (status == UM_OK) then
      allocate (buffer(rows), stat=alloc_status)
      if (alloc_status /= 0) then
        call finish(UM_ERR_OUT_OF_MEMORY, mesh%ctx, routine, ierr, no_memory(rows))
        return
      end if
      status = c_um_mesh_copy_mpas_int(mesh%ptr, to_c(name), 1_c_int32_t, buffer, rows)
      if (status == UM_OK) values = int(buffer)
    end if
    call finish_mpas(status, mesh, routine, ierr, message)
  end subroutine mesh_get_mpas_int_1d

  subroutine mesh_get_mpas_int_2d(mesh, name, values, ierr)
    type(um_mesh_t), intent(in) :: mesh
    character(len=*), intent(in) :: name
    integer, allocatable, intent(out) :: values(:, :)
    integer, optional, intent(out) :: ierr
    character(len=*), parameter :: routine = 'um_mesh_get_mpas'
    integer(c_int64_t) :: rows, columns
    integer(c_int32_t) :: status
    character(len=:), allocatable :: message
    integer(c_int32_t), allocatable :: buffer(:, :)
    integer :: alloc_status
    call mpas_shape(mesh, name, UM_MPAS_INT, 2, rows, columns, status, message)
    if (status == UM_OK) then
      allocate (buffer(columns, rows), stat=alloc_status)
      if (alloc_status /= 0) then
        call finish(UM_ERR_OUT_OF_MEMORY, mesh%ctx, routine, ierr, no_memory(rows * columns))
        return
      end if
      status = c_um_mesh_copy_mpas_int(mesh%ptr, to_c(name), 1_c_int32_t, buffer, rows * columns)
      if (status == UM_OK) values = int(buffer)
    end if
    call finish_mpas(status, mesh, routine, ierr, message)
  end subroutine mesh_get_mpas_int_2d

  function no_memory(n_elements) result(message)
    integer(int64), intent(in) :: n_elements
    character(len=:), allocatable :: message
    message = 'cannot allocate the ' // int_text(n_elements) // '-element result'
  end function no_memory

  pure function int_text(value) result(text)
    integer(int64), intent(in) :: value
    character(len=:), allocatable :: text
    character(len=24) :: digits
    write (digits, '(i0)') value
    text = trim(digits)
  end function int_text

  ! ============================================================ option table
  ! These need no context: the C library has nowhere to keep a message, so a
  ! failure reports the status text.

  !> Type (UM_OPTION_TYPE_*), inclusive bounds and default of an option key.
  subroutine um_option_info(key, type, min_value, max_value, default_value, ierr)
    integer, intent(in) :: key
    integer, optional, intent(out) :: type
    real(real64), optional, intent(out) :: min_value, max_value, default_value
    integer, optional, intent(out) :: ierr
    integer(c_int32_t) :: t
    real(c_double) :: lo, hi, default
    t = 0
    lo = 0
    hi = 0
    default = 0
    call finish(c_um_option_info(int(key, c_int32_t), t, lo, hi, default), c_null_ptr, &
        'um_option_info', ierr)
    if (present(type)) type = int(t)
    if (present(min_value)) min_value = real(lo, real64)
    if (present(max_value)) max_value = real(hi, real64)
    if (present(default_value)) default_value = real(default, real64)
  end subroutine um_option_info

  !> The key's name as um_options_set_string spells it ("" on failure).
  function um_option_name(key, ierr) result(name)
    integer, intent(in) :: key
    integer, optional, intent(out) :: ierr
    character(len=:), allocatable :: name
    character(kind=c_char), allocatable :: buf(:)
    integer(c_int64_t) :: capacity, needed
    integer(c_int32_t) :: status
    name = ''
    needed = 0
    ! Sizing call first, as for um_context_last_error.
    status = c_um_option_name(int(key, c_int32_t), capacity=0_c_int64_t, needed=needed)
    if (status == UM_ERR_BUFFER_TOO_SMALL) then
      capacity = needed
      allocate (buf(capacity))
      status = c_um_option_name(int(key, c_int32_t), buf, capacity, needed)
      if (status == UM_OK) name = from_c_chars(buf, int(needed) - 1)
    end if
    call finish(status, c_null_ptr, 'um_option_name', ierr)
  end function um_option_name

  !> The key of an option name; UM_ERR_UNKNOWN_OPTION if there is none.
  subroutine um_option_key(name, key, ierr)
    character(len=*), intent(in) :: name
    integer, intent(out) :: key
    integer, optional, intent(out) :: ierr
    integer(c_int32_t) :: k
    k = 0
    call finish(c_um_option_key(to_c(name), k), c_null_ptr, 'um_option_key', ierr)
    key = int(k)
  end subroutine um_option_key

end module unimesh
