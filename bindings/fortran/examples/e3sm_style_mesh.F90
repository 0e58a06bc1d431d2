! An E3SM-style use of unimesh from Fortran: a model builds its global
! ocean/land/river mesh in memory at start-up - spacing from a Fortran
! function (finer near the equator, an ocean-model habit), GSHHG coastlines
! and rivers, refinement and the weighted optimisation - and fills the
! MPAS arrays its dynamical core needs without writing a file.
!
!   e3sm_style_mesh COAST.geojson RIVERS.geojson [base_km]
!
! Prints the array shapes and the checks it makes; exits 1 if one fails.
! Built twice under ctest: plain, and with floating-point traps
! (-ffpe-trap=invalid,zero,overflow) as in E3SM debug builds.
module e3sm_style_spacing
  use, intrinsic :: iso_c_binding, only: c_ptr, c_double, c_f_pointer
  implicit none
  private
  public :: resolution, equator_refined_km

  !> What the callback reads through its user-data pointer.
  type, bind(c) :: resolution
    real(c_double) :: coarse_km   ! at the poles
    real(c_double) :: fine_km     ! at the equator
  end type resolution

contains

  !> The spacing in km at (lon, lat) degrees: fine_km at the equator
  !> growing smoothly to coarse_km at the poles. Called from several worker
  !> threads at once, so it is recursive (gfortran's -fcheck=recursion
  !> would stop a concurrent call to a non-recursive procedure) and only
  !> reads its arguments.
  recursive real(c_double) function equator_refined_km(user_data, lon_deg, lat_deg) bind(c)
    type(c_ptr), value :: user_data
    real(c_double), value :: lon_deg, lat_deg
    type(resolution), pointer :: r
    real(c_double), parameter :: deg = 3.14159265358979323846_c_double / 180
    call c_f_pointer(user_data, r)
    equator_refined_km = r%fine_km + (r%coarse_km - r%fine_km) * sin(lat_deg * deg)**2 &
        + 0 * lon_deg
  end function equator_refined_km

end module e3sm_style_spacing

program e3sm_style_mesh
  use, intrinsic :: iso_fortran_env, only: output_unit, error_unit, real64
  use, intrinsic :: iso_c_binding, only: c_loc
  use unimesh
  use e3sm_style_spacing
  implicit none

  real(real64), parameter :: pi = 3.14159265358979323846_real64
  type(um_context_t) :: ctx
  type(um_spacing_t) :: h
  type(um_features_t) :: gamma
  type(um_mesh_t) :: mesh
  type(resolution), target :: res
  character(len=4096) :: coast, rivers, arg
  integer :: n_cells, n_edges, n_vertices, max_edges, failures, e, i, j, c
  integer, allocatable :: cells_on_edge(:, :), edges_on_cell(:, :), n_edges_on_cell(:)
  integer, allocatable :: ocean(:), land(:), feature(:), n_edges_on_edge(:), edges_on_edge(:, :)
  real(real64), allocatable :: dc_edge(:), dv_edge(:), area_cell(:), weights_on_edge(:, :)
  real(real64) :: radius, base_km, qt_min, qt_mean
  character(len=:), allocatable :: report

  failures = 0
  if (command_argument_count() < 2) then
    write (error_unit, '(a)') 'usage: e3sm_style_mesh COAST.geojson RIVERS.geojson [base_km]'
    stop 2
  end if
  call get_command_argument(1, coast)
  call get_command_argument(2, rivers)
  base_km = 480
  if (command_argument_count() >= 3) then
    call get_command_argument(3, arg)
    read (arg, *) base_km
  end if

  ! No ierr anywhere: an error goes to the abort hook, which stops the model
  ! with the library's message (what a model wants at start-up).
  call um_context_create(ctx)
  call um_context_set_threads(ctx, 0)
  res = resolution(coarse_km=base_km, fine_km=base_km / 2)
  call um_spacing_create_callback(ctx, equator_refined_km, h, c_loc(res))
  call um_features_create(ctx, gamma)
  call um_features_read_geojson(gamma, trim(coast))
  call um_features_read_geojson(gamma, trim(rivers))
  call um_mesh_refine(ctx, h, mesh, features=gamma)
  call um_mesh_optimise(mesh)
  call um_mesh_quality_counts(mesh, not_well_centred=j)
  call um_mesh_quality_summary(mesh, 'area_length_ratio', min=qt_min, mean=qt_mean)
  call um_mesh_quality_json(mesh, report)
  write (output_unit, '(a, f6.3, a, f6.3, a, i0)') 'quality: Q^T min ', qt_min, ' mean ', qt_mean, &
      '; not well-centred ', j

  call um_mesh_mpas_dimensions(mesh, n_cells, n_edges, n_vertices, max_edges)
  call um_mesh_get_mpas(mesh, 'cellsOnEdge', cells_on_edge)
  call um_mesh_get_mpas(mesh, 'edgesOnCell', edges_on_cell)
  call um_mesh_get_mpas(mesh, 'nEdgesOnCell', n_edges_on_cell)
  call um_mesh_get_mpas(mesh, 'dcEdge', dc_edge)
  call um_mesh_get_mpas(mesh, 'dvEdge', dv_edge)
  call um_mesh_get_mpas(mesh, 'areaCell', area_cell)
  call um_mesh_get_mpas(mesh, 'weightsOnEdge', weights_on_edge)
  call um_mesh_get_mpas(mesh, 'nEdgesOnEdge', n_edges_on_edge)
  call um_mesh_get_mpas(mesh, 'edgesOnEdge', edges_on_edge)
  call um_mesh_get_mpas(mesh, 'cellOceanMask', ocean)
  call um_mesh_get_mpas(mesh, 'cellLandMask', land)
  call um_mesh_get_mpas(mesh, 'edgeFeatureKind', feature)
  call um_mesh_release_mpas(mesh)  ! the model has its arrays now

  write (output_unit, '(a, 4(1x, i0))') 'nCells nEdges nVertices maxEdges:', n_cells, n_edges, &
      n_vertices, max_edges
  write (output_unit, '(a, 2(1x, i0))') 'cellsOnEdge shape:', shape(cells_on_edge)
  write (output_unit, '(a, 2(1x, i0))') 'edgesOnCell shape:', shape(edges_on_cell)
  write (output_unit, '(a, 2(1x, i0))') 'weightsOnEdge shape:', shape(weights_on_edge)
  write (output_unit, '(a, 2(1x, i0))') 'ocean / land+river cells:', sum(ocean), sum(land)
  write (output_unit, '(a, 1x, i0)') 'coastline edges:', count(feature == UM_FEATURE_COASTLINE)
  write (output_unit, '(a, 1x, i0)') 'river edges:', count(feature == UM_FEATURE_RIVER)

  ! What a dynamical core relies on.
  call expect(n_vertices == 2 * n_cells - 4 .and. n_edges == 3 * n_cells - 6, 'Euler on the sphere')
  call expect(all(shape(cells_on_edge) == [2, n_edges]), 'cellsOnEdge(2, nEdges)')
  call expect(all(shape(edges_on_cell) == [max_edges, n_cells]), 'edgesOnCell(maxEdges, nCells)')
  call expect(all(shape(weights_on_edge) == [2 * max_edges, n_edges]), &
      'weightsOnEdge(maxEdges2, nEdges)')
  call expect(minval(cells_on_edge) >= 1 .and. maxval(cells_on_edge) <= n_cells, &
      'cellsOnEdge 1-based')
  call expect(all(dc_edge > 0) .and. all(dv_edge > 0) .and. all(area_cell > 0), &
      'positive lengths and areas')
  radius = 6371220.0_real64
  call expect(abs(sum(area_cell) / (4 * pi * radius**2) - 1) < 1e-10_real64, &
      'areaCell sums to the sphere')
  call expect(all(ocean + land == 1) .and. sum(ocean) > 0 .and. sum(land) > 0, &
      'ocean and land+river meshes are complements')
  call expect(count(feature == UM_FEATURE_COASTLINE) > 0 .and. count(feature == UM_FEATURE_RIVER) > 0, &
      'coastline and river edges tagged')
  ! Every edge of a cell lists the cell in its cellsOnEdge.
  do c = 1, n_cells
    do i = 1, n_edges_on_cell(c)
      e = edges_on_cell(i, c)
      if (cells_on_edge(1, e) /= c .and. cells_on_edge(2, e) /= c) then
        call expect(.false., 'edgesOnCell and cellsOnEdge agree')
        exit
      end if
    end do
  end do
  call expect(index(report, '"before_optimisation"') > 0 .and. qt_min > 0.3_real64 .and. qt_mean > 0.9_real64, &
      'quality report before and after optimising')
  call expect(trsk_antisymmetry() < 1e-9_real64, &
      'TRSK: W(e,f) dc(e) dv(e) = -W(f,e) dc(f) dv(f) (energy-neutral Coriolis)')

  ! A model keeps these; the example gives them back (LeakSanitizer counts
  ! a main program's arrays that are still allocated at the end).
  deallocate (cells_on_edge, edges_on_cell, n_edges_on_cell, dc_edge, dv_edge, area_cell, &
      weights_on_edge, ocean, land, feature, n_edges_on_edge, edges_on_edge, report)
  call um_mesh_destroy(mesh)
  call um_features_destroy(gamma)
  call um_spacing_destroy(h)
  call um_context_destroy(ctx)
  if (failures > 0) then
    write (error_unit, '(i0, a)') failures, ' check(s) failed'
    stop 1
  end if
  write (output_unit, '(a)') 'all checks passed'

contains

  !> The largest violation of the TRSK antisymmetry, relative to the
  !> largest |W dc dv|.
  real(real64) function trsk_antisymmetry() result(worst)
    integer :: e, f, j, k
    real(real64) :: scale, here, there
    worst = 0
    scale = maxval(abs(weights_on_edge)) * maxval(dc_edge) * maxval(dv_edge)
    do e = 1, n_edges
      do j = 1, n_edges_on_edge(e)
        f = edges_on_edge(j, e)
        here = weights_on_edge(j, e) * dc_edge(e) * dv_edge(e)
        there = huge(1.0_real64)
        do k = 1, n_edges_on_edge(f)
          if (edges_on_edge(k, f) == e) there = weights_on_edge(k, f) * dc_edge(f) * dv_edge(f)
        end do
        worst = max(worst, abs(here + there) / scale)
      end do
    end do
  end function trsk_antisymmetry

  subroutine expect(ok, what)
    logical, intent(in) :: ok
    character(len=*), intent(in) :: what
    if (ok) then
      write (output_unit, '(2a)') 'ok: ', what
    else
      write (error_unit, '(2a)') 'FAILED: ', what
      failures = failures + 1
    end if
  end subroutine expect

end program e3sm_style_mesh
