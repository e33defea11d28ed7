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
  if(PETSC_FOUND AND MPI_CXX_FOUND)
    set(TENSORMASS_PETSC_FOUND ON)
    message(STATUS "PETSc ${PETSC_VERSION}: solver.linear.type: petsc is available")
  elseif(TENSORMASS_WITH_PETSC STREQUAL "ON")
    message(FATAL_ERROR "TENSORMASS_WITH_PETSC=ON but PETSc (pkg-config PETSc) or MPI was not found: "
                        "apt-get install libpetsc-real-dev libopenmpi-dev")
  else()
    message(STATUS "PETSc not found: building without solver.linear.type: petsc")
  endif()
endif()
