! A Fortran model using the installed binding: `use unimesh`, a uniform
! 2000 km mesh refined in memory. Exits 1 on any failure.
program consumer_fortran
  use, intrinsic :: iso_fortran_env, only: int64
  use unimesh
  implicit none
  type(um_context_t) :: ctx
  type(um_spacing_t) :: spacing
  type(um_mesh_t) :: mesh
  integer :: ierr, number
  integer(int64) :: n_vertices
  call um_version(number=number)
  if (number /= UM_VERSION_NUMBER) error stop 1
  call um_context_create(ctx, ierr)
  if (ierr /= UM_OK) error stop 1
  call um_spacing_create_constant(ctx, 2000.0d0, spacing, ierr)
  if (ierr /= UM_OK) error stop 1
  call um_mesh_refine(ctx, spacing, mesh, ierr=ierr)
  if (ierr /= UM_OK) error stop 1
  call um_mesh_counts(mesh, n_vertices=n_vertices, ierr=ierr)
  if (ierr /= UM_OK .or. n_vertices < 12) error stop 1
  print '(a, i0, a)', 'Fortran consumer refined ', n_vertices, ' cells'
  call um_mesh_destroy(mesh)
  call um_spacing_destroy(spacing)
  call um_context_destroy(ctx)
end program consumer_fortran
