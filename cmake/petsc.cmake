# PETSc (Debian: libpetsc-real-dev, with OpenMPI) behind `solver.linear.type:
# petsc`: Krylov solvers and preconditioners (algebraic multigrid: GAMG) for
# the linear systems of every integrator. TENSORMASS_WITH_PETSC: AUTO (the
# default: used when pkg-config finds it), ON (required) or OFF. Left out of
# sanitizer and fuzzer builds (OpenMPI's own allocations would be reported).
set(TENSORMASS_WITH_PETSC AUTO CACHE STRING "Link PETSc for solver.linear.type: petsc (AUTO, ON, OFF)")
set_property(CACHE TENSORMASS_WITH_PETSC PROPERTY STRINGS AUTO ON OFF)
set(TENSORMASS_PETSC_FOUND OFF)
if(NOT TENSORMASS_WITH_PETSC STREQUAL "OFF" AND NOT TENSORMASS_SANITIZE AND NOT TENSORMASS_BUILD_FUZZERS)
  find_package(PkgConfig)
  if(PkgConfig_FOUND)
    pkg_check_modules(PETSC IMPORTED_TARGET PETSc)
  endif()
  find_package(MPI COMPONENTS CXX QUIET)
  # Scotch (libscotch-dev, which Debian's PETSc depends on) cuts the mesh
  # among the ranks, sequentially and deterministically.
  find_library(TENSORMASS_SCOTCH_LIBRARY NAMES scotch)
  find_library(TENSORMASS_SCOTCH_ERROR_LIBRARY NAMES scotcherr)
  find_path(TENSORMASS_SCOTCH_INCLUDE_DIR scotch.h PATH_SUFFIXES scotch)
  set(TENSORMASS_SCOTCH_FOUND OFF)
  if(TENSORMASS_SCOTCH_LIBRARY AND TENSORMASS_SCOTCH_ERROR_LIBRARY AND TENSORMASS_SCOTCH_INCLUDE_DIR)
    set(TENSORMASS_SCOTCH_FOUND ON)
  endif()
  if(PETSC_FOUND AND MPI_CXX_FOUND AND TENSORMASS_SCOTCH_FOUND)
    set(TENSORMASS_PETSC_FOUND ON)
    message(STATUS "PETSc ${PETSC_VERSION}: solver.linear.type: petsc is available")
  elseif(TENSORMASS_WITH_PETSC STREQUAL "ON")
    message(FATAL_ERROR "TENSORMASS_WITH_PETSC=ON but PETSc (pkg-config PETSc), MPI or Scotch was not found: "
                        "apt-get install libpetsc-real-dev libopenmpi-dev libscotch-dev")
  else()
    message(STATUS "PETSc not found: building without solver.linear.type: petsc")
  endif()
endif()
