! The triangulation through `use unimesh`: um_triangulation_t, its create
! routines (lon/lat and xyz, with and without weights), counts, the
! allocatable getters with 1-based indices, the check, and the errors (with
! ierr and through the abort hook).
!
! The results are checked against what holds for any triangulation of the
! sphere and, for the Delaunay case, against a brute-force test of the empty
! circumcircle property, not against stored answers.
!
! ctest builds this file twice: as is, and with gfortran's
! -ffpe-trap=invalid,zero,overflow (as E3SM debug builds do), under which any
! invalid operation, division by zero or overflow in the library, this
! binding or the test stops the program with SIGFPE. The NaN of the error
! test is made with ieee_value, which raises no exception.
!
! Prints one line per failed check and closes with "N passed, M failed";
! exits non-zero when anything failed.

! A recording abort hook, so that the test sees what a caller without ierr
! gets instead of stopping.
module triangulation_test_hooks
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

end module triangulation_test_hooks

program test_fortran_triangulation
  use, intrinsic :: iso_fortran_env, only: error_unit, int64, real64
  use, intrinsic :: iso_c_binding, only: c_associated
  use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_quiet_nan
  use unimesh
  use test_checks
  use triangulation_test_hooks
  implicit none

  real(real64), parameter :: pi = 3.14159265358979323846_real64
  real(real64), parameter :: deg = pi / 180
  integer, parameter :: n_fib = 300


  call test_octahedron()
  call test_fibonacci_sphere()
  call test_xyz_matches_lonlat()
  call test_weighted()
  call test_large_parallel()
  call test_input_errors()
  call test_abort_hook()
  call test_handles()

  call finish_checks()

contains

  ! ================================================================= points

  !> n points of a Fibonacci sphere, in degrees (lon in [-180, 180)).
  subroutine fibonacci(n, lon_deg, lat_deg)
    integer, intent(in) :: n
    real(real64), allocatable, intent(out) :: lon_deg(:), lat_deg(:)
    real(real64), parameter :: golden_angle = 360 * (1 - 2 / (1 + sqrt(5.0_real64)))
    integer :: i
    allocate (lon_deg(n), lat_deg(n))
    do i = 1, n
      lat_deg(i) = asin(1 - 2 * (i - 0.5_real64) / n) / deg
      lon_deg(i) = modulo((i - 1) * golden_angle, 360.0_real64) - 180
    end do
  end subroutine fibonacci

  pure function unit_vectors(lon_deg, lat_deg) result(xyz)
    real(real64), intent(in) :: lon_deg(:), lat_deg(:)
    real(real64) :: xyz(3, size(lon_deg))
    xyz(1, :) = cos(lat_deg * deg) * cos(lon_deg * deg)
    xyz(2, :) = cos(lat_deg * deg) * sin(lon_deg * deg)
    xyz(3, :) = sin(lat_deg * deg)
  end function unit_vectors

  pure function cross(a, b) result(c)
    real(real64), intent(in) :: a(3), b(3)
    real(real64) :: c(3)
    c = [a(2) * b(3) - a(3) * b(2), a(3) * b(1) - a(1) * b(3), a(1) * b(2) - a(2) * b(1)]
  end function cross

  ! ======================================================= shared invariants

  !> What holds for the output of any triangulation of the sphere whose
  !> vertices are the points p (3, n) not listed in hidden: indices 1-based
  !> and in range, each triangle of distinct vertices, counter-clockwise
  !> seen from outside, Euler's count, every neighbour across the edge
  !> opposite vertex k sharing the other two vertices and pointing back,
  !> orthocentres of unit length.
  subroutine check_invariants(tri, p, label)
    type(um_triangulation_t), intent(in) :: tri
    real(real64), intent(in) :: p(:, :)
    character(len=*), intent(in) :: label
    integer, allocatable :: triangles(:, :), neighbours(:, :), hidden(:)
    real(real64), allocatable :: centres(:, :)
    integer :: ierr, n_vertices, n_triangles, n_hidden, j, k, m, a, b, other
    logical :: ok_range, ok_distinct, ok_orientation, ok_shared, ok_back, ok_unit, ok_used
    logical, allocatable :: used(:)

    call um_triangulation_counts(tri, n_vertices, n_triangles, n_hidden, ierr)
    call check_status(ierr, UM_OK, label // ': um_triangulation_counts')
    call check(n_vertices + n_hidden == size(p, 2), label // ': vertices + hidden = points')
    call check(n_triangles == 2 * n_vertices - 4, label // ': Euler, 2V - 4 triangles')

    call um_triangulation_get_triangles(tri, triangles, ierr)
    call check(ierr == UM_OK .and. allocated(triangles), label // ': get_triangles')
    call um_triangulation_get_neighbours(tri, neighbours, ierr)
    call check(ierr == UM_OK .and. allocated(neighbours), label // ': get_neighbours')
    call um_triangulation_get_orthocentres(tri, centres, ierr)
    call check(ierr == UM_OK .and. allocated(centres), label // ': get_orthocentres')
    call um_triangulation_get_hidden(tri, hidden, ierr)
    call check(ierr == UM_OK .and. allocated(hidden), label // ': get_hidden')
    if (.not. (allocated(triangles) .and. allocated(neighbours) .and. allocated(centres) &
        .and. allocated(hidden))) return
    call check(all(shape(triangles) == [3, n_triangles]), label // ': triangles(3, n_triangles)')
    call check(all(shape(neighbours) == [3, n_triangles]), label // ': neighbours(3, n_triangles)')
    call check(all(shape(centres) == [3, n_triangles]), label // ': orthocentres(3, n_triangles)')
    call check(size(hidden) == n_hidden, label // ': hidden has n_hidden entries')

    ok_range = all(triangles >= 1 .and. triangles <= size(p, 2)) .and. &
        all(neighbours >= 1 .and. neighbours <= n_triangles)
    call check(ok_range, label // ': indices are 1-based and in range')
    if (.not. ok_range) return

    ! Every point but the hidden ones is a vertex, and no hidden one is.
    allocate (used(size(p, 2)))
    used = .false.
    do j = 1, n_triangles
      do k = 1, 3
        used(triangles(k, j)) = .true.
      end do
    end do
    ok_used = count(used) == n_vertices
    do j = 1, n_hidden
      ok_used = ok_used .and. .not. used(hidden(j))
    end do
    call check(ok_used, label // ': the vertices are exactly the points not hidden')

    ok_distinct = .true.
    ok_orientation = .true.
    ok_shared = .true.
    ok_back = .true.
    ok_unit = .true.
    do j = 1, n_triangles
      associate (t => triangles(:, j))
        ok_distinct = ok_distinct .and. t(1) /= t(2) .and. t(2) /= t(3) .and. t(1) /= t(3)
        ok_orientation = ok_orientation .and. &
            dot_product(cross(p(:, t(2)) - p(:, t(1)), p(:, t(3)) - p(:, t(1))), p(:, t(1))) > 0
        do k = 1, 3
          other = neighbours(k, j)
          a = t(modulo(k, 3) + 1)
          b = t(modulo(k + 1, 3) + 1)
          ! The neighbour holds the edge a-b (as b-a) and not the vertex t(k).
          ok_shared = ok_shared .and. any(triangles(:, other) == a) .and. &
              any(triangles(:, other) == b) .and. .not. any(triangles(:, other) == t(k))
          do m = 1, 3
            if (triangles(m, other) /= a .and. triangles(m, other) /= b) &
                ok_back = ok_back .and. neighbours(m, other) == j
          end do
        end do
      end associate
      ok_unit = ok_unit .and. abs(norm2(centres(:, j)) - 1) < 1e-12_real64
    end do
    call check(ok_distinct, label // ': three distinct vertices per triangle')
    call check(ok_orientation, label // ': triangles counter-clockwise seen from outside')
    call check(ok_shared, label // ': neighbour k shares the edge opposite vertex k')
    call check(ok_back, label // ': neighbours point back')
    call check(ok_unit, label // ': orthocentres are unit vectors')

    call um_triangulation_check(tri, ierr)
    call check_status(ierr, UM_OK, label // ': um_triangulation_check')
  end subroutine check_invariants

  !> The empty circumcircle test by brute force: for the Delaunay
  !> triangulation of points on the sphere, no point lies beyond the plane
  !> of any triangle; the orthocentre is then that plane's unit normal.
  subroutine check_delaunay(tri, p, label)
    type(um_triangulation_t), intent(in) :: tri
    real(real64), intent(in) :: p(:, :)
    character(len=*), intent(in) :: label
    integer, allocatable :: triangles(:, :)
    real(real64), allocatable :: centres(:, :)
    real(real64) :: normal(3), worst, centre_error
    integer :: j, i
    character(len=64) :: detail
    call um_triangulation_get_triangles(tri, triangles)
    call um_triangulation_get_orthocentres(tri, centres)
    worst = -huge(worst)
    centre_error = 0
    do j = 1, size(triangles, 2)
      associate (t => triangles(:, j))
        normal = cross(p(:, t(2)) - p(:, t(1)), p(:, t(3)) - p(:, t(1)))
        normal = normal / norm2(normal)
        do i = 1, size(p, 2)
          if (any(t == i)) cycle
          worst = max(worst, dot_product(normal, p(:, i) - p(:, t(1))))
        end do
        centre_error = max(centre_error, norm2(centres(:, j) - normal))
      end associate
    end do
    ! Tolerance for the rounding of this test's own arithmetic only.
    write (detail, '(a, es10.2, a)') ' (largest height above a triangle: ', worst, ')'
    call check(worst < 1e-13_real64, label // ': every circumcircle is empty (brute force)' &
        // trim(detail))
    call check(centre_error < 1e-9_real64, label // ': orthocentres are the circumcentres')
  end subroutine check_delaunay

  ! ================================================================== tests

  ! 6 points, 8 triangles: the faces of the octahedron, one per octant.
  subroutine test_octahedron()
    real(real64), parameter :: lon(6) = [0, 90, 180, -90, 0, 0]
    real(real64), parameter :: lat(6) = [0, 0, 0, 0, 90, -90]
    type(um_context_t) :: ctx
    type(um_triangulation_t) :: tri
    integer :: ierr, n_vertices, n_triangles, n_hidden, j
    integer(int64) :: v64, t64, h64
    integer, allocatable :: triangles(:, :)
    real(real64), allocatable :: centres(:, :)
    logical :: ok
    call um_context_create(ctx)
    call um_triangulation_create(ctx, lon, lat, tri, ierr=ierr)
    call check(ierr == UM_OK .and. c_associated(tri%ptr), 'octahedron: create')
    call check(c_associated(tri%ctx, ctx%ptr), 'octahedron: borrows its context')
    call um_triangulation_counts(tri, n_vertices, n_triangles, n_hidden)
    call check(n_vertices == 6 .and. n_triangles == 8 .and. n_hidden == 0, &
        'octahedron: 6 vertices, 8 triangles, none hidden')
    call um_triangulation_counts(tri, v64, t64, h64, ierr)
    call check(ierr == UM_OK .and. v64 == 6 .and. t64 == 8 .and. h64 == 0, &
        'octahedron: int64 counts')
    call check_invariants(tri, unit_vectors(lon, lat), 'octahedron')

    ! Each face holds one of +-x (points 1, 3), one of +-y (2, 4) and one of
    ! +-z (5, 6); its orthocentre is (+-1, +-1, +-1)/sqrt(3).
    call um_triangulation_get_triangles(tri, triangles)
    call um_triangulation_get_orthocentres(tri, centres)
    ok = .true.
    do j = 1, 8
      ok = ok .and. count(triangles(:, j) == 1 .or. triangles(:, j) == 3) == 1 &
          .and. count(triangles(:, j) == 2 .or. triangles(:, j) == 4) == 1 &
          .and. count(triangles(:, j) == 5 .or. triangles(:, j) == 6) == 1
    end do
    call check(ok, 'octahedron: one point per axis in each face')
    call check(all(abs(abs(centres) - 1 / sqrt(3.0_real64)) < 1e-12_real64), &
        'octahedron: orthocentres at the octant centres')
    call check(size(centres, 2) == 8, 'octahedron: 8 orthocentres')
    call um_triangulation_destroy(tri, ierr)
    call check(ierr == UM_OK .and. .not. c_associated(tri%ptr) .and. &
        .not. c_associated(tri%ctx), 'octahedron: destroy nulls the handle')
    call um_context_destroy(ctx)
  end subroutine test_octahedron

  subroutine test_fibonacci_sphere()
    type(um_context_t) :: ctx
    type(um_triangulation_t) :: tri
    real(real64), allocatable :: lon(:), lat(:)
    integer :: ierr, n_vertices, n_triangles, n_hidden
    call fibonacci(n_fib, lon, lat)
    call um_context_create(ctx)
    call um_context_set_threads(ctx, 2)
    call um_triangulation_create(ctx, lon, lat, tri, ierr=ierr)
    call check_status(ierr, UM_OK, 'fibonacci: create')
    call um_triangulation_counts(tri, n_vertices, n_triangles, n_hidden)
    call check(n_vertices == n_fib .and. n_triangles == 2 * n_fib - 4 .and. n_hidden == 0, &
        'fibonacci: 300 vertices, 596 triangles')
    call check_invariants(tri, unit_vectors(lon, lat), 'fibonacci')
    call check_delaunay(tri, unit_vectors(lon, lat), 'fibonacci')
    call um_triangulation_destroy(tri)
    call um_context_destroy(ctx)
  end subroutine test_fibonacci_sphere

  ! The same points as vectors (of any length, in a strided section) give
  ! the same triangles, up to their order and the rotation of each.
  subroutine test_xyz_matches_lonlat()
    type(um_context_t) :: ctx
    type(um_triangulation_t) :: from_lonlat, from_xyz
    real(real64), allocatable :: lon(:), lat(:), wide(:, :)
    integer, allocatable :: t1(:, :), t2(:, :)
    integer :: ierr, j
    logical :: same
    call fibonacci(n_fib, lon, lat)
    call um_context_create(ctx)
    call um_triangulation_create(ctx, lon, lat, from_lonlat)
    ! Columns 1, 3, 5, ... of a (3, 2n) array, scaled: not contiguous, not unit.
    allocate (wide(3, 2 * n_fib))
    wide = 0
    wide(:, 1::2) = 7.5_real64 * unit_vectors(lon, lat)
    call um_triangulation_create_xyz(ctx, wide(:, 1::2), from_xyz, ierr=ierr)
    call check_status(ierr, UM_OK, 'create_xyz from a strided section')
    call check_invariants(from_xyz, unit_vectors(lon, lat), 'xyz')
    call um_triangulation_get_triangles(from_lonlat, t1)
    call um_triangulation_get_triangles(from_xyz, t2)
    same = size(t1, 2) == size(t2, 2)
    if (same) then
      do j = 1, size(t1, 2)
        t1(:, j) = canonical(t1(:, j))
        t2(:, j) = canonical(t2(:, j))
      end do
      do j = 1, size(t1, 2)
        same = same .and. any(t2(1, :) == t1(1, j) .and. t2(2, :) == t1(2, j) .and. &
            t2(3, :) == t1(3, j))
      end do
    end if
    call check(same, 'xyz and lon/lat give the same triangles')
    call um_triangulation_destroy(from_lonlat)
    call um_triangulation_destroy(from_xyz)
    call um_context_destroy(ctx)
  end subroutine test_xyz_matches_lonlat

  !> The triangle rotated to start at its smallest index (orientation kept).
  pure function canonical(t) result(c)
    integer, intent(in) :: t(3)
    integer :: c(3)
    integer :: k
    k = minloc(t, 1)
    c = [t(k), t(modulo(k, 3) + 1), t(modulo(k + 1, 3) + 1)]
  end function canonical

  ! A point with weight -0.5 sinks to 0.8 of the radius, well inside the hull
  ! of its neighbours: hidden. Weights passed as a strided section.
  subroutine test_weighted()
    integer, parameter :: sunk = 8
    type(um_context_t) :: ctx
    type(um_triangulation_t) :: tri
    real(real64), allocatable :: lon(:), lat(:), weights(:)
    integer, allocatable :: hidden(:), triangles(:, :)
    integer :: ierr, n_vertices, n_triangles, n_hidden
    call fibonacci(n_fib, lon, lat)
    allocate (weights(2 * n_fib))
    weights = 1  ! the entries that are not passed: must not be read
    weights(1::2) = 0
    weights(2 * sunk - 1) = -0.5_real64
    call um_context_create(ctx)
    call um_triangulation_create(ctx, lon, lat, tri, weights(1::2), ierr)
    call check_status(ierr, UM_OK, 'weighted: create')
    call um_triangulation_counts(tri, n_vertices, n_triangles, n_hidden)
    call check(n_vertices == n_fib - 1 .and. n_triangles == 2 * (n_fib - 1) - 4 .and. &
        n_hidden == 1, 'weighted: one point hidden')
    call um_triangulation_get_hidden(tri, hidden, ierr)
    call check(ierr == UM_OK .and. size(hidden) == 1, 'weighted: get_hidden')
    if (size(hidden) == 1) call check(hidden(1) == sunk, 'weighted: the hidden point is point 8')
    call um_triangulation_get_triangles(tri, triangles)
    call check(.not. any(triangles == sunk), 'weighted: the hidden point is no vertex')
    call check_invariants(tri, unit_vectors(lon, lat), 'weighted')
    call um_triangulation_destroy(tri)

    ! All-zero weights are the Delaunay triangulation; none hidden.
    call um_triangulation_create(ctx, lon, lat, tri, spread(0.0_real64, 1, n_fib))
    call um_triangulation_get_hidden(tri, hidden)
    call check(size(hidden) == 0, 'zero weights: get_hidden gives an empty array')
    call check_delaunay(tri, unit_vectors(lon, lat), 'zero weights')
    call um_triangulation_destroy(tri)
    call um_context_destroy(ctx)
  end subroutine test_weighted

  ! Large enough for the library's parallel loops (run under the FP traps
  ! too): weighted, checked, and the same with 1 and 2 threads.
  subroutine test_large_parallel()
    integer, parameter :: n = 40000
    type(um_context_t) :: ctx
    type(um_triangulation_t) :: one, two
    real(real64), allocatable :: lon(:), lat(:), weights(:), c1(:, :), c2(:, :)
    integer, allocatable :: t1(:, :), t2(:, :), n1(:, :), n2(:, :)
    integer :: ierr, i
    call fibonacci(n, lon, lat)
    weights = [(2e-4_real64 * sin(real(i, real64)), i = 1, n)]
    call um_context_create(ctx)
    call um_context_set_threads(ctx, 1)
    call um_triangulation_create(ctx, lon, lat, one, weights, ierr)
    call check_status(ierr, UM_OK, 'large: create with 1 thread')
    call um_context_set_threads(ctx, 2)
    call um_triangulation_create(ctx, lon, lat, two, weights, ierr)
    call check_status(ierr, UM_OK, 'large: create with 2 threads')
    call check_invariants(two, unit_vectors(lon, lat), 'large')
    call um_triangulation_get_triangles(one, t1)
    call um_triangulation_get_triangles(two, t2)
    call um_triangulation_get_neighbours(one, n1)
    call um_triangulation_get_neighbours(two, n2)
    call um_triangulation_get_orthocentres(one, c1)
    call um_triangulation_get_orthocentres(two, c2)
    call check(all(shape(t1) == shape(t2)) .and. all(shape(c1) == shape(c2)), 'large: same sizes')
    if (all(shape(t1) == shape(t2))) then
      call check(all(t1 == t2) .and. all(n1 == n2) .and. all(c1 == c2), &
          'large: the same result for 1 and 2 threads')
    end if
    call um_triangulation_destroy(one)
    call um_triangulation_destroy(two)
    call um_context_destroy(ctx)
  end subroutine test_large_parallel

  ! Bad input: a status, a message naming the argument and C's 0-based
  ! index, no handle.
  subroutine test_input_errors()
    type(um_context_t) :: ctx
    type(um_triangulation_t) :: tri
    real(real64), allocatable :: lon(:), lat(:), weights(:)
    real(real64) :: xyz2(2, 6)
    integer :: ierr
    character(len=:), allocatable :: message
    call fibonacci(12, lon, lat)
    call um_context_create(ctx)

    ! A NaN latitude at Fortran index 5 is lat_deg[4] in C.
    lat(5) = ieee_value(lat(5), ieee_quiet_nan)
    call um_triangulation_create(ctx, lon, lat, tri, ierr=ierr)
    call check(ierr /= UM_OK, 'NaN latitude: ierr /= 0')
    call check_status(ierr, UM_ERR_NONFINITE_INPUT, 'NaN latitude')
    call check(.not. c_associated(tri%ptr), 'NaN latitude: no handle')
    message = um_context_last_error(ctx)
    call check_contains(message, 'lat_deg[4]', 'NaN latitude message')
    call check_contains(message, 'nan', 'NaN latitude message')
    call um_context_clear_error(ctx)
    call fibonacci(12, lon, lat)

    lat(3) = 90.5_real64
    call um_triangulation_create(ctx, lon, lat, tri, ierr=ierr)
    call check_status(ierr, UM_ERR_COORDINATE_RANGE, 'latitude 90.5')
    call check_contains(um_context_last_error(ctx), 'lat_deg[2] = 90.5', 'latitude range message')
    call um_context_clear_error(ctx)
    call fibonacci(12, lon, lat)

    allocate (weights(12))
    weights = 0
    weights(7) = 2
    call um_triangulation_create(ctx, lon, lat, tri, weights, ierr)
    call check_status(ierr, UM_ERR_INVALID_ARGUMENT, 'weight 2')
    call check_contains(um_context_last_error(ctx), 'weights[6]', 'weight message')
    call um_context_clear_error(ctx)

    lon(9) = lon(2)
    lat(9) = lat(2)
    call um_triangulation_create(ctx, lon, lat, tri, ierr=ierr)
    call check_status(ierr, UM_ERR_DUPLICATE_POINTS, 'duplicate points')
    call um_context_clear_error(ctx)
    call fibonacci(12, lon, lat)

    call um_triangulation_create(ctx, lon(1:3), lat(1:3), tri, ierr=ierr)
    call check_status(ierr, UM_ERR_TOO_FEW_POINTS, 'three points')
    call um_context_clear_error(ctx)

    ! All in the northern hemisphere: they do not surround the centre.
    call um_triangulation_create(ctx, [0.0_real64, 90.0_real64, 180.0_real64, -90.0_real64, &
        45.0_real64], [10.0_real64, 20.0_real64, 30.0_real64, 40.0_real64, 80.0_real64], tri, &
        ierr=ierr)
    call check_status(ierr, UM_ERR_DEGENERATE_INPUT, 'points in one hemisphere')
    call um_context_clear_error(ctx)

    ! Found by the binding: sizes that disagree.
    call um_triangulation_create(ctx, lon, lat(1:11), tri, ierr=ierr)
    call check_status(ierr, UM_ERR_INVALID_ARGUMENT, 'lat_deg shorter than lon_deg')
    call um_triangulation_create(ctx, lon, lat, tri, weights(1:5), ierr)
    call check_status(ierr, UM_ERR_INVALID_ARGUMENT, 'weights shorter than the points')
    xyz2 = 1
    call um_triangulation_create_xyz(ctx, xyz2, tri, ierr=ierr)
    call check_status(ierr, UM_ERR_INVALID_ARGUMENT, 'xyz with 2 rows')
    call um_triangulation_create_xyz(ctx, unit_vectors(lon, lat), tri, weights(1:11), ierr)
    call check_status(ierr, UM_ERR_INVALID_ARGUMENT, 'xyz: weights shorter than the points')
    call check(.not. c_associated(tri%ptr), 'no handle after binding-level failures')

    ! The xyz checks of the library: a zero vector, named by its 0-based index.
    block
      real(real64) :: xyz(3, 12)
      xyz = unit_vectors(lon, lat)
      xyz(:, 4) = 0
      call um_triangulation_create_xyz(ctx, xyz, tri, ierr=ierr)
      call check_status(ierr, UM_ERR_INVALID_ARGUMENT, 'zero vector in xyz')
      call check_contains(um_context_last_error(ctx), 'point 3', 'zero vector message')
      call um_context_clear_error(ctx)
    end block
    call um_context_destroy(ctx)
  end subroutine test_input_errors

  ! Without ierr a failure reaches the abort hook with routine and message.
  subroutine test_abort_hook()
    type(um_context_t) :: ctx
    type(um_triangulation_t) :: tri, null_tri
    real(real64), allocatable :: lon(:), lat(:)
    integer, allocatable :: triangles(:, :)
    call fibonacci(20, lon, lat)
    call um_context_create(ctx)
    call um_set_abort_hook(recording_hook)

    lat(11) = ieee_value(lat(11), ieee_quiet_nan)
    call um_triangulation_create(ctx, lon, lat, tri)
    call check(hook_calls == 1 .and. hook_status == UM_ERR_NONFINITE_INPUT, 'hook: NaN')
    call check_contains(hook_message, 'um_triangulation_create', 'hook names the routine')
    call check_contains(hook_message, 'lat_deg[10]', 'hook names argument and index')
    call um_context_clear_error(ctx)
    call fibonacci(20, lon, lat)

    call um_triangulation_create(ctx, lon(1:19), lat, tri)
    call check(hook_calls == 2 .and. hook_status == UM_ERR_INVALID_ARGUMENT, 'hook: sizes')
    call check_contains(hook_message, 'lat_deg has 20 elements and lon_deg has 19', &
        'hook: size message')

    call um_triangulation_get_triangles(null_tri, triangles)
    call check(hook_calls == 3 .and. hook_status == UM_ERR_NULL_ARGUMENT, 'hook: null handle')
    call check_contains(hook_message, 'um_triangulation_get_triangles', 'hook: getter name')
    call check(.not. allocated(triangles), 'hook: nothing allocated on failure')

    call um_set_abort_hook()
    call um_triangulation_create(ctx, lon, lat, tri)
    call um_triangulation_check(tri)
    call check(hook_calls == 3, 'no hook call on success')
    call um_triangulation_destroy(tri)
    call um_context_destroy(ctx)
  end subroutine test_abort_hook

  ! Null and destroyed handles give statuses; a triangulation outlives its
  ! context.
  subroutine test_handles()
    type(um_context_t) :: ctx, never_created
    type(um_triangulation_t) :: tri, null_tri
    real(real64), allocatable :: lon(:), lat(:), centres(:, :)
    integer, allocatable :: neighbours(:, :), hidden(:)
    integer :: ierr, n_vertices, n_triangles, n_hidden
    call fibonacci(50, lon, lat)

    call um_triangulation_create(never_created, lon, lat, tri, ierr=ierr)
    call check(ierr == UM_ERR_NULL_ARGUMENT .and. .not. c_associated(tri%ptr), &
        'triangulation from a null context')
    call um_triangulation_counts(null_tri, n_vertices, n_triangles, n_hidden, ierr)
    call check_status(ierr, UM_ERR_NULL_ARGUMENT, 'counts of a null triangulation')
    call um_triangulation_get_neighbours(null_tri, neighbours, ierr)
    call check(ierr == UM_ERR_NULL_ARGUMENT .and. .not. allocated(neighbours), &
        'neighbours of a null triangulation')
    call um_triangulation_get_orthocentres(null_tri, centres, ierr)
    call check(ierr == UM_ERR_NULL_ARGUMENT .and. .not. allocated(centres), &
        'orthocentres of a null triangulation')
    call um_triangulation_get_hidden(null_tri, hidden, ierr)
    call check(ierr == UM_ERR_NULL_ARGUMENT .and. .not. allocated(hidden), &
        'hidden of a null triangulation')
    call um_triangulation_check(null_tri, ierr)
    call check_status(ierr, UM_ERR_NULL_ARGUMENT, 'check of a null triangulation')

    call um_context_create(ctx)
    call um_triangulation_create(ctx, lon, lat, tri)
    call um_context_destroy(ctx)
    call um_triangulation_counts(tri, n_vertices, n_triangles, n_hidden, ierr)
    call check(ierr == UM_OK .and. n_triangles == 96, 'triangulation outlives its context')
    call check_invariants(tri, unit_vectors(lon, lat), 'after the context')
    call um_triangulation_destroy(tri)
    call um_triangulation_destroy(tri, ierr)
    call check_status(ierr, UM_OK, 'destroying a null triangulation is a no-op')
  end subroutine test_handles

end program test_fortran_triangulation
