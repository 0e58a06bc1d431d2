! The Fortran binding end to end through `use unimesh`: version, status codes,
! the context, options and their errors (with ierr and through the abort
! hook), and the constants of unimesh_cint checked against what the C library
! says at run time. The static check of every constant and interface against
! the header is check_fortran_binding.py.
!
! Prints one line per failed check and closes with "N passed, M failed";
! exits non-zero when anything failed.

! A recording abort hook: lets the test see what a caller without ierr would
! get, instead of stopping. (In a module, not the program, so that no
! pointer to an internal procedure -- an executable-stack trampoline in
! gfortran -- is needed.)
module test_hooks
  implicit none
  private
  public :: recording_hook, hook_calls, hook_status, hook_message

  integer, save :: hook_calls = 0
  integer, save :: hook_status = 0
  character(len=:), allocatable, save :: hook_message

contains

  subroutine recording_hook(status, message)
    integer, intent(in) :: status
    character(len=*), intent(in) :: message
    hook_calls = hook_calls + 1
    hook_status = status
    hook_message = message
  end subroutine recording_hook

end module test_hooks

program test_fortran_api
  use, intrinsic :: iso_fortran_env, only: error_unit, int64, real64
  use, intrinsic :: iso_c_binding, only: c_associated
  use unimesh
  use test_checks
  use unimesh_cint, only: c_um_version_number
  use test_hooks
  implicit none


  call test_version()
  call test_status_constants()
  call test_context()
  call test_context_errors()
  call test_options()
  call test_option_errors()
  call test_option_table()
  call test_abort_hook()
  call test_handles()

  call finish_checks()

contains

  ! ================================================================ helpers

  pure function lower(text) result(out)
    character(len=*), intent(in) :: text
    character(len=len(text)) :: out
    integer :: i
    out = text
    do i = 1, len(out)
      if (out(i:i) >= 'A' .and. out(i:i) <= 'Z') out(i:i) = achar(iachar(out(i:i)) + 32)
    end do
  end function lower

  ! ================================================================== tests

  ! The constants this binding was compiled with agree with the loaded library.
  subroutine test_version()
    integer :: major, minor, patch, number, ierr
    character(len=:), allocatable :: string
    call um_version(major, minor, patch, number, string, ierr)
    call check_status(ierr, UM_OK, 'um_version')
    call check(major == UM_VERSION_MAJOR, 'UM_VERSION_MAJOR matches the library')
    call check(minor == UM_VERSION_MINOR, 'UM_VERSION_MINOR matches the library')
    call check(patch == UM_VERSION_PATCH, 'UM_VERSION_PATCH matches the library')
    call check(number == UM_VERSION_NUMBER, 'UM_VERSION_NUMBER matches the library')
    call check(string == UM_VERSION_STRING, 'UM_VERSION_STRING matches the library: ' // string)
    call check(c_um_version_number() == UM_VERSION_NUMBER, 'raw c_um_version_number')
    call check(UM_VERSION_NUMBER == 10000 * UM_VERSION_MAJOR + 100 * UM_VERSION_MINOR &
        + UM_VERSION_PATCH, 'UM_VERSION_NUMBER formula')
  end subroutine test_version

  ! Every status constant is one the library knows, in the band its value says.
  subroutine test_status_constants()
    integer, parameter :: statuses(*) = [UM_ERR_USAGE, UM_ERR_NULL_ARGUMENT, &
        UM_ERR_INVALID_HANDLE, UM_ERR_INVALID_ARGUMENT, UM_ERR_UNKNOWN_OPTION, &
        UM_ERR_OPTION_TYPE, UM_ERR_BUFFER_TOO_SMALL, UM_ERR_WRONG_ORDER, UM_ERR_INPUT, &
        UM_ERR_NONFINITE_INPUT, UM_ERR_COORDINATE_RANGE, UM_ERR_DUPLICATE_POINTS, &
        UM_ERR_TOO_FEW_POINTS, UM_ERR_DEGENERATE_INPUT, UM_ERR_NUMERICAL, &
        UM_ERR_OUT_OF_MEMORY, UM_ERR_MEMORY_CAP, UM_ERR_LIMIT, UM_ERR_IO, &
        UM_ERR_FILE_FORMAT, UM_CANCELLED, UM_ERR_INTERNAL]
    integer :: i
    character(len=16) :: label
    call check(UM_OK == 0, 'UM_OK is 0')
    call check(um_status_string(UM_OK) == 'success', 'um_status_string(UM_OK)')
    call check(um_status_string(12345) == 'unknown status', 'um_status_string(12345)')
    do i = 1, size(statuses)
      write (label, '(a, i0)') 'status ', statuses(i)
      call check(um_status_string(statuses(i)) /= 'unknown status', &
          trim(label) // ' is known to the library')
      call check(um_status_class(statuses(i)) == statuses(i) / 100 * 100, &
          trim(label) // ' is in its band')
    end do
    call check(um_status_class(-3) == 900, 'um_status_class(-3)')
  end subroutine test_status_constants

  subroutine test_context()
    type(um_context_t) :: ctx
    integer :: ierr, n, cap
    integer(int64) :: cap64
    call um_context_create(ctx, ierr)
    call check_status(ierr, UM_OK, 'um_context_create')
    call check(c_associated(ctx%ptr), 'um_context_create gives a handle')

    call um_context_set_threads(ctx, 3, ierr)
    call check_status(ierr, UM_OK, 'um_context_set_threads(3)')
    call um_context_get_threads(ctx, n, ierr)
    call check(ierr == UM_OK .and. n == 3, 'um_context_get_threads after 3')
    call um_context_set_threads(ctx, 0)
    call um_context_get_threads(ctx, n)
    call check(n >= 1, 'threads = 0 resolves to all cores')

    ! Above what a default integer holds: the int64 overloads.
    call um_context_set_memory_cap(ctx, 8_int64 * 1024_int64**3, ierr)
    call check_status(ierr, UM_OK, 'um_context_set_memory_cap(8 GiB)')
    call um_context_get_memory_cap(ctx, cap64, ierr)
    call check(ierr == UM_OK .and. cap64 == 8_int64 * 1024_int64**3, 'memory cap read back (int64)')
    call um_context_get_memory_cap(ctx, cap, ierr)
    call check_status(ierr, UM_ERR_LIMIT, '8 GiB into a default integer')
    call um_context_set_memory_cap(ctx, 1000000)
    call um_context_get_memory_cap(ctx, cap)
    call check(cap == 1000000, 'memory cap read back (default integer)')

    call check(um_context_last_error(ctx) == '', 'no error after successful calls')
    call check(um_context_last_status(ctx) == UM_OK, 'last status UM_OK')
    call um_context_destroy(ctx, ierr)
    call check(ierr == UM_OK .and. .not. c_associated(ctx%ptr), 'um_context_destroy nulls')
  end subroutine test_context

  ! Errors with ierr: status returned, message kept (the first one) until
  ! cleared, the failed call changes nothing.
  subroutine test_context_errors()
    type(um_context_t) :: ctx
    integer :: ierr, n
    character(len=:), allocatable :: message
    call um_context_create(ctx)
    call um_context_set_threads(ctx, 2)

    call um_context_set_threads(ctx, -2, ierr)
    call check_status(ierr, UM_ERR_INVALID_ARGUMENT, 'um_context_set_threads(-2)')
    message = um_context_last_error(ctx, ierr)
    call check_status(ierr, UM_OK, 'um_context_last_error')
    call check_contains(message, 'n_threads = -2', 'threads message')
    call check(um_context_last_status(ctx) == UM_ERR_INVALID_ARGUMENT, 'last status kept')
    call um_context_get_threads(ctx, n)
    call check(n == 2, 'failed set_threads changed nothing')

    ! The first error is kept; reading does not clear it.
    call um_context_set_memory_cap(ctx, -1, ierr)
    call check_status(ierr, UM_ERR_INVALID_ARGUMENT, 'um_context_set_memory_cap(-1)')
    call check_contains(um_context_last_error(ctx), 'n_threads = -2', 'first message kept')

    call um_context_clear_error(ctx, ierr)
    call check_status(ierr, UM_OK, 'um_context_clear_error')
    call check(um_context_last_error(ctx) == '', 'message cleared')
    call check(um_context_last_status(ctx) == UM_OK, 'status cleared')
    call um_context_destroy(ctx)
  end subroutine test_context_errors

  subroutine test_options()
    type(um_context_t) :: ctx
    type(um_options_t) :: opts
    integer :: ierr, i
    integer(int64) :: i64
    real(real64) :: x
    call um_context_create(ctx)
    call um_options_create(ctx, opts, ierr)
    call check(ierr == UM_OK .and. c_associated(opts%ptr), 'um_options_create')

    call um_options_get_double(opts, UM_OPT_SPHERE_RADIUS, x, ierr)
    call check(ierr == UM_OK .and. x == 6371220.0_real64, 'default sphere radius')
    call um_options_set_double(opts, UM_OPT_REFINE_ALPHA, 1.25_real64, ierr)
    call check_status(ierr, UM_OK, 'set refine_alpha')
    call um_options_get_double(opts, UM_OPT_REFINE_ALPHA, x)
    call check(x == 1.25_real64, 'refine_alpha read back')

    call um_options_set_int(opts, UM_OPT_OPTIM_OUTER_ITERATIONS, 8, ierr)
    call check_status(ierr, UM_OK, 'set optim_outer_iterations')
    call um_options_get_int(opts, UM_OPT_OPTIM_OUTER_ITERATIONS, i)
    call check(i == 8, 'optim_outer_iterations read back')
    call um_options_set_int(opts, UM_OPT_OPTIM_INNER_ITERATIONS, 5_int64)
    call um_options_get_int(opts, UM_OPT_OPTIM_INNER_ITERATIONS, i64)
    call check(i64 == 5_int64, 'int64 overloads of set_int/get_int')

    call um_options_set_string(opts, 'refine_alpha = 1.5; optim_outer_iterations=4;', ierr)
    call check_status(ierr, UM_OK, 'um_options_set_string')
    call um_options_get_double(opts, UM_OPT_REFINE_ALPHA, x)
    call um_options_get_int(opts, UM_OPT_OPTIM_OUTER_ITERATIONS, i)
    call check(x == 1.5_real64 .and. i == 4, 'values from um_options_set_string')

    call check(um_context_last_error(ctx) == '', 'no error after good option calls')
    call um_options_destroy(opts, ierr)
    call check(ierr == UM_OK .and. .not. c_associated(opts%ptr), 'um_options_destroy nulls')
    call um_context_destroy(ctx)
  end subroutine test_options

  ! Bad values and keys: a status, a message naming the option, nothing changed.
  subroutine test_option_errors()
    type(um_context_t) :: ctx
    type(um_options_t) :: opts
    integer :: ierr, i
    real(real64) :: x
    call um_context_create(ctx)
    call um_options_create(ctx, opts)
    call um_options_set_double(opts, UM_OPT_REFINE_ALPHA, 1.25_real64)

    call um_options_set_double(opts, UM_OPT_REFINE_ALPHA, 7.0_real64, ierr)
    call check_status(ierr, UM_ERR_INVALID_ARGUMENT, 'refine_alpha = 7')
    call check_contains(um_context_last_error(ctx), 'refine_alpha', 'out-of-range message')
    call um_options_get_double(opts, UM_OPT_REFINE_ALPHA, x)
    call check(x == 1.25_real64, 'failed set_double changed nothing')
    call um_context_clear_error(ctx)

    call um_options_set_int(opts, UM_OPT_REFINE_ALPHA, 1, ierr)
    call check_status(ierr, UM_ERR_OPTION_TYPE, 'integer set on a real option')
    call check_contains(um_context_last_error(ctx), 'refine_alpha', 'option type message')
    call um_context_clear_error(ctx)

    call um_options_set_double(opts, 9999, 1.0_real64, ierr)
    call check_status(ierr, UM_ERR_UNKNOWN_OPTION, 'unknown option key')
    call check_contains(um_context_last_error(ctx), '9999', 'unknown key message')
    call um_context_clear_error(ctx)

    ! All-or-nothing: the good item before the bad one is not applied either.
    call um_options_set_string(opts, 'optim_outer_iterations=3; refine_rho=0.5', ierr)
    call check_status(ierr, UM_ERR_INVALID_ARGUMENT, 'refine_rho=0.5 in a string')
    call check_contains(um_context_last_error(ctx), 'refine_rho', 'string message')
    call um_options_get_int(opts, UM_OPT_OPTIM_OUTER_ITERATIONS, i)
    call check(i == 20, 'failed set_string changed nothing')
    call um_context_clear_error(ctx)

    call um_options_set_string(opts, 'no_such_option=1', ierr)
    call check_status(ierr, UM_ERR_UNKNOWN_OPTION, 'unknown name in a string')
    call check_contains(um_context_last_error(ctx), 'no_such_option', 'unknown name message')

    call um_options_destroy(opts)
    call um_context_destroy(ctx)
  end subroutine test_option_errors

  ! Each UM_OPT_* value names, in the C library, the option of the same name:
  ! the strongest run-time check that the keys were transcribed right.
  subroutine test_option_table()
    integer, parameter :: keys(*) = [UM_OPT_SPHERE_RADIUS, UM_OPT_SURFACE_FLATTENING, UM_OPT_REFINE_ALPHA, &
        UM_OPT_REFINE_BETA, UM_OPT_REFINE_RHO, UM_OPT_REFINE_TOPOLOGY_CHECK, UM_OPT_REFINE_RELAX, &
        UM_OPT_REFINE_LATTICE, UM_OPT_OPTIM_OUTER_ITERATIONS, UM_OPT_OPTIM_INNER_ITERATIONS, &
        UM_OPT_OPTIM_TOLERANCE, UM_OPT_OPTIM_WEIGHTS, UM_OPT_OPTIM_FIX_BOUNDARY, &
        UM_OPT_OPTIM_COLLAPSE_RATIO, UM_OPT_OPTIM_SPLIT_RATIO, UM_OPT_OPTIM_CORNER_VERTICES, &
        UM_OPT_OPTIM_CENTROIDAL_SWEEPS, UM_OPT_OPTIM_RESEED_ROUNDS, UM_OPT_OCEAN_FLOOR]
    character(len=*), parameter :: names(*) = [character(len=32) :: 'UM_OPT_SPHERE_RADIUS', &
        'UM_OPT_SURFACE_FLATTENING', 'UM_OPT_REFINE_ALPHA', 'UM_OPT_REFINE_BETA', 'UM_OPT_REFINE_RHO', &
        'UM_OPT_REFINE_TOPOLOGY_CHECK', 'UM_OPT_REFINE_RELAX', 'UM_OPT_REFINE_LATTICE', &
        'UM_OPT_OPTIM_OUTER_ITERATIONS', &
        'UM_OPT_OPTIM_INNER_ITERATIONS', 'UM_OPT_OPTIM_TOLERANCE', 'UM_OPT_OPTIM_WEIGHTS', &
        'UM_OPT_OPTIM_FIX_BOUNDARY', 'UM_OPT_OPTIM_COLLAPSE_RATIO', 'UM_OPT_OPTIM_SPLIT_RATIO', &
        'UM_OPT_OPTIM_CORNER_VERTICES', 'UM_OPT_OPTIM_CENTROIDAL_SWEEPS', &
        'UM_OPT_OPTIM_RESEED_ROUNDS', 'UM_OPT_OCEAN_FLOOR']
    integer :: i, key, type, ierr
    real(real64) :: lo, hi, default
    character(len=:), allocatable :: name, expected
    do i = 1, size(keys)
      expected = lower(trim(names(i)(len('UM_OPT_') + 1:)))
      name = um_option_name(keys(i), ierr)
      call check(ierr == UM_OK .and. name == expected, &
          trim(names(i)) // ' is "' // expected // '" in C, not "' // name // '"')
      call um_option_key(expected, key, ierr)
      call check(ierr == UM_OK .and. key == keys(i), 'um_option_key("' // expected // '")')
      call um_option_info(keys(i), type, lo, hi, default, ierr)
      call check(ierr == UM_OK .and. (type == UM_OPTION_TYPE_INT .or. &
          type == UM_OPTION_TYPE_REAL) .and. lo <= default .and. default <= hi, &
          'um_option_info(' // trim(names(i)) // ')')
    end do
    call um_option_info(UM_OPT_OPTIM_WEIGHTS, type)
    call check(type == UM_OPTION_TYPE_INT, 'optim_weights is an integer option')
    call um_option_info(UM_OPT_REFINE_RHO, type)
    call check(type == UM_OPTION_TYPE_REAL, 'refine_rho is a real option')

    call um_option_key('no_such_option', key, ierr)
    call check_status(ierr, UM_ERR_UNKNOWN_OPTION, 'um_option_key(unknown)')
    name = um_option_name(4242, ierr)
    call check(ierr == UM_ERR_UNKNOWN_OPTION .and. name == '', 'um_option_name(unknown)')
  end subroutine test_option_table

  ! Without ierr a failure reaches the abort hook with routine and message.
  subroutine test_abort_hook()
    type(um_context_t) :: ctx
    type(um_options_t) :: opts
    call um_context_create(ctx)
    call um_options_create(ctx, opts)
    call um_set_abort_hook(recording_hook)

    call um_options_set_double(opts, UM_OPT_REFINE_BETA, -1.0_real64)
    call check(hook_calls == 1, 'abort hook called once')
    call check(hook_status == UM_ERR_INVALID_ARGUMENT, 'abort hook status')
    call check_contains(hook_message, 'um_options_set_double', 'abort hook names the routine')
    call check_contains(hook_message, 'refine_beta', 'abort hook names the option')

    ! An older uncleared error of another status is not passed off as this one.
    call um_options_set_int(opts, UM_OPT_REFINE_BETA, 1)
    call check(hook_calls == 2 .and. hook_status == UM_ERR_OPTION_TYPE, 'second hook call')
    call check_contains(hook_message, 'um_options_set_int', 'second hook message')
    call check(index(hook_message, 'refine_beta = -1') == 0, 'stale message not reused')

    ! Failures found by the binding itself reach the hook too.
    call um_context_set_memory_cap(ctx, 8_int64 * 1024_int64**3)
    block
      integer :: cap
      call um_context_get_memory_cap(ctx, cap)
    end block
    call check(hook_calls == 3 .and. hook_status == UM_ERR_LIMIT, 'binding-level failure')

    ! Restoring the default: no further calls to the recording hook.
    call um_set_abort_hook()
    call um_context_clear_error(ctx)
    call um_options_set_double(opts, UM_OPT_REFINE_BETA, 0.5_real64)
    call check(hook_calls == 3, 'no hook call on success')
    call um_options_destroy(opts)
    call um_context_destroy(ctx)
  end subroutine test_abort_hook

  ! Handle lifetimes: null and destroyed handles give statuses, not crashes;
  ! options outlive their context as the header allows.
  subroutine test_handles()
    type(um_context_t) :: ctx, never_created
    type(um_options_t) :: opts
    integer :: ierr
    real(real64) :: x
    character(len=:), allocatable :: message

    call um_context_set_threads(never_created, 1, ierr)
    call check_status(ierr, UM_ERR_NULL_ARGUMENT, 'null context handle')
    message = um_context_last_error(never_created, ierr)
    call check(ierr == UM_ERR_NULL_ARGUMENT .and. message == '', 'last_error of a null context')

    call um_context_create(ctx)
    call um_options_create(ctx, opts)
    call um_context_destroy(ctx)
    call um_context_destroy(ctx, ierr)
    call check_status(ierr, UM_OK, 'destroying a null context is a no-op')
    call um_options_set_double(opts, UM_OPT_REFINE_RHO, 1.5_real64, ierr)
    call um_options_get_double(opts, UM_OPT_REFINE_RHO, x)
    call check(ierr == UM_OK .and. x == 1.5_real64, 'options outlive their context')
    call um_options_set_double(opts, UM_OPT_REFINE_RHO, 0.0_real64, ierr)
    call check_status(ierr, UM_ERR_INVALID_ARGUMENT, 'errors still reported without a context')
    call um_options_destroy(opts)
    call um_options_destroy(opts, ierr)
    call check_status(ierr, UM_OK, 'destroying null options is a no-op')

    call um_options_create(never_created, opts, ierr)
    call check(ierr == UM_ERR_NULL_ARGUMENT .and. .not. c_associated(opts%ptr), &
        'options from a null context')
  end subroutine test_handles

end program test_fortran_api
