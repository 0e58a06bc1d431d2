! Spacing, features and mesh through `use unimesh`: constant, preset and
! callback spacings (a bind(c) Fortran function with c_ptr user data),
! evaluate, a features ring, um_mesh_refine and its allocatable getters
! (1-based indices), and errors with ierr.
!
! Meshes are coarse (2000 km) so the test runs in a fraction of a second;
! results are checked against properties every such mesh has.
!
! Prints one line per failed check and closes with "N passed, M failed";
! exits non-zero when anything failed.

! The Fortran spacing callback: h = user%base_km + user%km_per_degree * |lat|.
! Called from worker threads: it only reads its arguments.
module mesh_test_spacing
  use, intrinsic :: iso_c_binding, only: c_ptr, c_double, c_f_pointer, c_associated
  implicit none
  private
  public :: spacing_parameters, latitude_spacing, cancel_optimise, count_log

  type, bind(c) :: spacing_parameters
    real(c_double) :: base_km
    real(c_double) :: km_per_degree
  end type spacing_parameters

contains

  recursive real(c_double) function latitude_spacing(user_data, lon_deg, lat_deg) bind(c)
    type(c_ptr), value :: user_data
    real(c_double), value :: lon_deg
    real(c_double), value :: lat_deg
    type(spacing_parameters), pointer :: p
    call c_f_pointer(user_data, p)
    latitude_spacing = p%base_km + p%km_per_degree * abs(lat_deg) + 0 * lon_deg
  end function latitude_spacing

  !> Progress: cancels as soon as the optimisation reports a fraction > 0;
  !> counts its calls in user_data (an integer TARGET).
  integer(c_int32_t) function cancel_optimise(user_data, stage, fraction) bind(c)
    use, intrinsic :: iso_c_binding, only: c_int32_t
    type(c_ptr), value :: user_data, stage
    real(c_double), value :: fraction
    integer(c_int32_t), pointer :: calls
    call c_f_pointer(user_data, calls)
    calls = calls + 1
    cancel_optimise = 0
    if (fraction > 0 .and. c_associated(stage)) cancel_optimise = 1
  end function cancel_optimise

  !> Log: counts the messages.
  subroutine count_log(user_data, level, message) bind(c)
    use, intrinsic :: iso_c_binding, only: c_int32_t
    type(c_ptr), value :: user_data, message
    integer(c_int32_t), value :: level
    integer(c_int32_t), pointer :: count
    call c_f_pointer(user_data, count)
    if (level >= 0 .and. c_associated(message)) count = count + 1
  end subroutine count_log

end module mesh_test_spacing

program test_fortran_mesh
  use, intrinsic :: iso_fortran_env, only: error_unit, int64, real64
  use, intrinsic :: iso_c_binding, only: c_loc, c_associated, c_int32_t
  use unimesh
  use test_checks
  use mesh_test_spacing
  implicit none

  real(real64), parameter :: pi = 3.14159265358979323846_real64
  real(real64), parameter :: deg = pi / 180
  real(real64), parameter :: coarse_km = 2000
  real(real64), parameter :: ring_lat = 30
  ! A 5-degree arc of the ring rises up to 0.024 degrees above ring_lat.
  real(real64), parameter :: arc_bulge = 0.03_real64

  type(um_context_t) :: ctx

  call um_context_create(ctx)
  call um_context_set_threads(ctx, 2)

  call test_spacings()
  call test_mesh_without_features()
  call test_mesh_with_ring()
  call test_errors()

  call um_context_destroy(ctx)
  call finish_checks()

contains

  subroutine test_spacings()
    type(um_spacing_t) :: h
    type(spacing_parameters), target :: parameters
    real(real64) :: km(3)
    integer :: ierr

    call um_spacing_create_constant(ctx, 240.0_real64, h)
    call um_spacing_evaluate(h, [0.0_real64, 10.0_real64, 20.0_real64], &
        [0.0_real64, -45.0_real64, 90.0_real64], km)
    call check(all(km == 240), 'constant spacing evaluates to its value')
    call um_spacing_clamp(h, 300.0_real64, 400.0_real64)
    call um_spacing_evaluate(h, [0.0_real64], [0.0_real64], km(1:1))
    call check(km(1) == 300, 'clamp raises the constant to km_min')
    call um_spacing_destroy(h)
    call check(.not. c_associated(h%ptr), 'destroy nulls the handle')

    call um_spacing_create_preset(ctx, 'QU480', h)
    call um_spacing_evaluate(h, [0.0_real64, 100.0_real64, -50.0_real64], &
        [0.0_real64, 60.0_real64, -80.0_real64], km)
    call check(all(km == 480), 'QU480 is 480 km everywhere')
    call um_spacing_destroy(h)

    parameters = spacing_parameters(100.0_real64, 2.0_real64)
    call um_spacing_create_callback(ctx, latitude_spacing, h, c_loc(parameters), ierr)
    call check(ierr == UM_OK, 'callback spacing created')
    call um_spacing_evaluate(h, [0.0_real64, 0.0_real64, 0.0_real64], &
        [0.0_real64, 30.0_real64, -60.0_real64], km)
    call check(all(abs(km - [100.0_real64, 160.0_real64, 220.0_real64]) < 1e-12_real64), &
        'callback spacing sees its user data')
    call um_spacing_destroy(h)
  end subroutine test_spacings

  !> Checks what every mesh of the sphere has; returns the vertices.
  subroutine check_surface(mesh, lon, lat, label)
    type(um_mesh_t), intent(in) :: mesh
    real(real64), allocatable, intent(out) :: lon(:), lat(:)
    character(len=*), intent(in) :: label
    integer(int64) :: n_vertices, n_triangles
    integer, allocatable :: triangles(:, :)
    real(real64) :: a(3), b(3), c(3), normal(3)
    logical :: ccw
    integer :: j

    call um_mesh_counts(mesh, n_vertices=n_vertices, n_triangles=n_triangles)
    call um_mesh_get_vertices(mesh, lon, lat)
    call um_mesh_get_triangles(mesh, triangles)
    call check(size(lon, kind=int64) == n_vertices .and. size(lat, kind=int64) == n_vertices, &
        label // ': one position per vertex')
    call check(all(shape(triangles, kind=int64) == [3_int64, n_triangles]), &
        label // ': triangles(3, n_triangles)')
    call check(n_triangles == 2 * n_vertices - 4, label // ': Euler characteristic 2')
    call check(minval(triangles) == 1 .and. maxval(triangles) == n_vertices, &
        label // ': 1-based vertex indices, all used')
    call check(all(lon > -180 .and. lon <= 180 .and. abs(lat) <= 90), &
        label // ': positions in range')
    ccw = .true.
    do j = 1, size(triangles, 2)
      a = unit_vector(lon(triangles(1, j)), lat(triangles(1, j)))
      b = unit_vector(lon(triangles(2, j)), lat(triangles(2, j)))
      c = unit_vector(lon(triangles(3, j)), lat(triangles(3, j)))
      normal = cross(b - a, c - a)
      ccw = ccw .and. dot_product(normal, a) > 0
    end do
    call check(ccw, label // ': triangles counter-clockwise seen from outside')
  end subroutine check_surface

  pure function unit_vector(lon_deg, lat_deg) result(x)
    real(real64), intent(in) :: lon_deg, lat_deg
    real(real64) :: x(3)
    x = [cos(lat_deg * deg) * cos(lon_deg * deg), cos(lat_deg * deg) * sin(lon_deg * deg), &
        sin(lat_deg * deg)]
  end function unit_vector

  pure function cross(a, b) result(c)
    real(real64), intent(in) :: a(3), b(3)
    real(real64) :: c(3)
    c = [a(2) * b(3) - a(3) * b(2), a(3) * b(1) - a(1) * b(3), a(1) * b(2) - a(2) * b(1)]
  end function cross

  subroutine test_mesh_without_features()
    type(um_spacing_t) :: h
    type(um_mesh_t) :: mesh
    real(real64), allocatable :: lon(:), lat(:)
    integer, allocatable :: parts(:), sides(:), edges(:, :), edge_parts(:)
    integer(int64) :: n_restricted
    integer :: ierr

    call um_spacing_create_constant(ctx, coarse_km, h)
    call um_mesh_refine(ctx, h, mesh, ierr=ierr)
    call check(ierr == UM_OK, 'refine without features')
    call um_spacing_destroy(h)  ! the mesh does not need it any more
    call check_surface(mesh, lon, lat, 'constant mesh')
    call check(size(lon) > 12, 'refined beyond the icosahedron')
    call um_mesh_counts(mesh, n_restricted_edges=n_restricted)
    call check(n_restricted == 0, 'no restricted edges without features')
    call um_mesh_get_vertex_parts(mesh, parts)
    call check(size(parts) == size(lon) .and. all(parts == -1), 'no vertex on a feature')
    call um_mesh_get_vertex_sides(mesh, sides)
    call check(size(sides) == size(lon) .and. all(sides == UM_SIDE_OCEAN), 'all ocean')
    call um_mesh_get_restricted_edges(mesh, edges, edge_parts)
    call check(size(edges, 1) == 2 .and. size(edges, 2) == 0 .and. size(edge_parts) == 0, &
        'empty restricted edges')
    call um_mesh_destroy(mesh)
  end subroutine test_mesh_without_features

  subroutine test_mesh_with_ring()
    type(um_spacing_t) :: h
    type(um_features_t) :: gamma
    type(um_options_t) :: opts
    type(um_mesh_t) :: mesh
    type(spacing_parameters), target :: parameters
    real(real64) :: ring_lon(72)
    real(real64), allocatable :: lon(:), lat(:)
    integer, allocatable :: parts(:), sides(:), triangle_sides(:), edges(:, :), edge_parts(:)
    integer(int64) :: n_parts, n_triangles, n_restricted, n_after
    integer :: i, ierr
    integer(c_int32_t), target :: progress_calls, log_lines
    real(real64), allocatable :: plon(:), plat(:)
    integer(int64), allocatable :: first(:)
    integer, allocatable :: closed(:), kinds(:), ids(:)
    character(len=:), allocatable :: rivers
    logical :: written

    ! The callback spacing: its function and parameters must outlive the mesh.
    parameters = spacing_parameters(coarse_km, 0.0_real64)
    call um_spacing_create_callback(ctx, latitude_spacing, h, c_loc(parameters))
    ring_lon = [(-180 + 5 * i, i = 0, 71)]
    call um_features_create(ctx, gamma)
    call um_features_add_part(gamma, ring_lon, spread(ring_lat, 1, 72), .true., &
        UM_FEATURE_COASTLINE)
    call um_features_counts(gamma, n_parts=n_parts)
    call check(n_parts == 1, 'one part stored')
    call um_features_get_points(gamma, plon, plat)
    call um_features_get_parts(gamma, first, closed, kinds, ids)
    call check(size(plon) == 72 .and. all(abs(plat - ring_lat) < 1e-12_real64), 'the ring read back')
    call check(all(first == [1_int64, 73_int64]) .and. all(closed == [1]) .and. &
        all(kinds == [UM_FEATURE_COASTLINE]), 'its part read back')
    call um_options_create(ctx, opts)
    call um_options_set_double(opts, UM_OPT_REFINE_ALPHA, 1.2_real64)
    call um_mesh_refine(ctx, h, mesh, features=gamma, options=opts)
    call um_features_destroy(gamma)
    call um_options_destroy(opts)
    call check_surface(mesh, lon, lat, 'ring mesh')

    call um_mesh_counts(mesh, n_triangles=n_triangles, n_restricted_edges=n_restricted)
    call check(n_restricted > 0, 'restricted edges along the ring')
    call um_mesh_get_vertex_parts(mesh, parts)
    call check(any(parts == 1), 'vertices on part 1')
    call check(all(parts == 1 .or. parts == -1), 'parts are 1 or -1')
    call check(all(lat(pack([(i, i = 1, size(parts))], parts == 1)) > ring_lat - 1e-9_real64 &
        .and. lat(pack([(i, i = 1, size(parts))], parts == 1)) < ring_lat + arc_bulge), &
        'ring vertices on the ring')
    call um_mesh_get_restricted_edges(mesh, edges, edge_parts)
    call check(size(edges, 2, kind=int64) == n_restricted .and. all(edge_parts == 1), &
        'restricted edges cross part 1')
    call check(minval(edges) >= 1 .and. maxval(edges) <= size(lon), 'edge vertices 1-based')

    call um_mesh_get_vertex_sides(mesh, sides)
    call check(all(pack(sides, parts == 1) == UM_SIDE_COASTAL), 'ring vertices coastal')
    call check(all(pack(sides, lat > ring_lat + arc_bulge) /= UM_SIDE_OCEAN), &
        'north of the ring: land (the smaller side)')
    call check(all(pack(sides, lat < ring_lat) /= UM_SIDE_LAND), 'south of the ring: ocean')
    call um_mesh_get_triangle_sides(mesh, triangle_sides)
    call check(size(triangle_sides, kind=int64) == n_triangles, 'one side per triangle')
    call check(any(triangle_sides == UM_SIDE_LAND) .and. any(triangle_sides == UM_SIDE_OCEAN) &
        .and. all(triangle_sides == UM_SIDE_LAND .or. triangle_sides == UM_SIDE_OCEAN), &
        'triangles on both sides')

    ! Progress and log callbacks written in Fortran: cancelling from the
    ! progress callback stops the optimisation and leaves the mesh as it was.
    progress_calls = 0
    log_lines = 0
    call um_context_set_progress(ctx, cancel_optimise, c_loc(progress_calls))
    call um_context_set_log(ctx, count_log, UM_LOG_INFO, c_loc(log_lines))
    call um_mesh_optimise(mesh, ierr=ierr)
    call check(ierr == UM_CANCELLED, 'cancelled from a Fortran progress callback')
    call check(progress_calls >= 2, 'the progress callback was called')
    call check(log_lines >= 1, 'the log callback was called')
    call um_context_clear_error(ctx)
    call um_context_set_progress(ctx)
    call um_context_set_log(ctx)
    call um_mesh_counts(mesh, n_triangles=n_after)
    call check(n_after == n_triangles, 'a cancelled optimisation changes nothing')

    ! The optimisation keeps the ring's vertices on the ring and the sphere closed.
    call um_mesh_optimise(mesh)  ! no ierr: an error would reach the abort hook
    call check_surface(mesh, lon, lat, 'optimised ring mesh')
    call um_mesh_get_vertex_parts(mesh, parts)
    call check(any(parts == 1), 'optimised: vertices on part 1')
    call check(all(lat(pack([(i, i = 1, size(parts))], parts == 1)) > ring_lat - 1e-9_real64 &
        .and. lat(pack([(i, i = 1, size(parts))], parts == 1)) < ring_lat + arc_bulge), &
        'optimised: ring vertices still on the ring')

    ! The ocean (south of the ring) and land (north) component meshes, from
    ! the mesh and again from its mesh.nc.
    call execute_command_line('mkdir -p fortran_components fortran_components_again')
    call um_mesh_write_components(mesh, 'fortran_components', ierr)
    call check(ierr == UM_OK, 'components written')
    inquire (file='fortran_components/ocean.scrip.nc', exist=written)
    call check(written, 'the ocean SCRIP grid written')
    call um_mesh_river_report_json(mesh, rivers, ierr)
    call check(ierr == UM_OK .and. index(rivers, '"networks": 0') > 0, 'no rivers: an empty river report')
    call um_mpas_file_write_components(ctx, 'fortran_components/mesh.nc', 'fortran_components_again', ierr)
    call check(ierr == UM_OK, 'components from mesh.nc')
    call um_mpas_file_write_components(ctx, 'fortran_components/rivers.json', 'fortran_components_again', ierr)
    call check(ierr == UM_ERR_FILE_FORMAT, 'a file that is no mesh is refused')
    call um_context_clear_error(ctx)

    ! mesh.nc as netCDF-4 on request; another format is refused.
    call um_mesh_write_mpas_as(mesh, 'fortran_mesh4.nc', UM_MPAS_FILE_NETCDF4, ierr)
    call check(ierr == UM_OK, 'netCDF-4 mesh file written')
    call um_mpas_file_write_components(ctx, 'fortran_mesh4.nc', 'fortran_components_again', ierr)
    call check(ierr == UM_OK, 'components from the netCDF-4 mesh file')
    call um_mesh_write_mpas_as(mesh, 'fortran_mesh4.nc', 2_c_int32_t, ierr)
    call check(ierr == UM_ERR_INVALID_ARGUMENT, 'an unknown file format is refused')
    call um_context_clear_error(ctx)
    call um_mesh_destroy(mesh)
    call um_spacing_destroy(h)
  end subroutine test_mesh_with_ring

  subroutine test_errors()
    type(um_spacing_t) :: h
    type(um_features_t) :: gamma
    real(real64) :: km(2)
    integer :: ierr

    call um_spacing_create_constant(ctx, -1.0_real64, h, ierr)
    call check(ierr == UM_ERR_INVALID_ARGUMENT, 'negative constant spacing refused')
    call check(index(um_context_last_error(ctx), '-1') > 0, 'message names the value')
    call um_context_clear_error(ctx)

    call um_spacing_create_preset(ctx, 'XY12', h, ierr)
    call check(ierr == UM_ERR_INVALID_ARGUMENT, 'unknown preset refused')
    call um_context_clear_error(ctx)

    call um_spacing_create_constant(ctx, 100.0_real64, h)
    call um_spacing_evaluate(h, [0.0_real64, 1.0_real64], [0.0_real64], km, ierr)
    call check(ierr == UM_ERR_INVALID_ARGUMENT, 'evaluate with sizes that disagree')
    call um_spacing_limit_gradient(h, 0.1_real64, ierr)
    call check(ierr == UM_ERR_INVALID_ARGUMENT, 'limit_gradient needs a grid spacing')
    call um_context_clear_error(ctx)
    call um_spacing_destroy(h)

    call um_features_create(ctx, gamma)
    call um_features_add_part(gamma, [0.0_real64, 1.0_real64], [0.0_real64, 95.0_real64], &
        .false., UM_FEATURE_RIVER, ierr=ierr)
    call check(ierr == UM_ERR_COORDINATE_RANGE, 'latitude 95 refused')
    call um_context_clear_error(ctx)
    call um_features_destroy(gamma)
  end subroutine test_errors

end program test_fortran_mesh
