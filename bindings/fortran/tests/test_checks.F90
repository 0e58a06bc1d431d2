! The checking helpers every Fortran test program shares: each check counts
! as passed or failed (a failure prints one line), and finish_checks closes
! with "N passed, M failed" and stops non-zero when anything failed.
module test_checks
  use, intrinsic :: iso_fortran_env, only: error_unit
  implicit none
  private
  public :: check, check_status, check_contains, finish_checks

  integer, save :: passed = 0, failed = 0

contains

  subroutine check(ok, what)
    logical, intent(in) :: ok
    character(len=*), intent(in) :: what
    if (ok) then
      passed = passed + 1
    else
      failed = failed + 1
      write (error_unit, '(2a)') 'FAILED: ', what
    end if
  end subroutine check

  subroutine check_status(ierr, expected, what)
    integer, intent(in) :: ierr, expected
    character(len=*), intent(in) :: what
    character(len=80) :: detail
    write (detail, '(a, i0, a, i0, a)') ' (ierr = ', ierr, ', expected ', expected, ')'
    call check(ierr == expected, what // trim(detail))
  end subroutine check_status

  subroutine check_contains(text, part, what)
    character(len=*), intent(in) :: text, part, what
    call check(index(text, part) > 0, what // ': "' // part // '" not in "' // text // '"')
  end subroutine check_contains

  subroutine finish_checks()
    write (*, '(i0, a, i0, a)') passed, ' passed, ', failed, ' failed'
    if (failed > 0) error stop 1
  end subroutine finish_checks

end module test_checks
