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
! Adding a handle type (e.g. um_triangulation_t) follows um_options_t: a type
! holding the C pointer plus the borrowed context pointer its errors are
! recorded in, create/destroy routines, and `call finish(status, h%ctx, ...)`
! after every C call.
module unimesh
  use, intrinsic :: iso_c_binding, only: c_ptr, c_null_ptr, c_associated, c_f_pointer, &
      c_char, c_null_char, c_int32_t, c_int64_t, c_double, c_size_t
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
  public :: UM_OPT_SPHERE_RADIUS, UM_OPT_REFINE_ALPHA, UM_OPT_REFINE_BETA, UM_OPT_REFINE_RHO, &
      UM_OPT_REFINE_TOPOLOGY_CHECK, UM_OPT_OPTIM_OUTER_ITERATIONS, &
      UM_OPT_OPTIM_INNER_ITERATIONS, UM_OPT_OPTIM_TOLERANCE, UM_OPT_OPTIM_WEIGHTS, &
      UM_OPT_OPTIM_FIX_BOUNDARY, UM_OPT_OPTIM_COLLAPSE_RATIO, UM_OPT_OPTIM_SPLIT_RATIO
  public :: UM_OPTION_TYPE_INT, UM_OPTION_TYPE_REAL

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
      um_context_last_error, um_context_last_status, um_context_clear_error
  public :: um_options_create, um_options_destroy, um_options_set_double, um_options_set_int, &
      um_options_get_double, um_options_get_int, um_options_set_string
  public :: um_option_info, um_option_name, um_option_key

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
