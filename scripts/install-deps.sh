#!/usr/bin/env bash
# Installs what tensormass needs on Debian 12 (run as root, or with sudo).
set -euo pipefail
SUDO=""
if [ "$(id -u)" != 0 ]; then SUDO=sudo; fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
# libopenblas0-openmp: CHOLMOD's dense kernels on an optimised BLAS (5x
# faster factorisations than the reference BLAS, docs/results/runtime.md).
$SUDO apt-get install -y -qq --no-install-recommends \
  g++ cmake ninja-build git clang-format \
  python3 python3-sympy python3-jinja2 python3-pytest python3-numpy python3-dev pybind11-dev \
  libeigen3-dev libsuitesparse-dev libyaml-cpp-dev nlohmann-json3-dev libxxhash-dev \
  libgtest-dev libgmock-dev libbenchmark-dev \
  libopenblas0-openmp \
  python3-meshio python3-matplotlib python3-gmsh gmsh libgmsh-dev calculix-ccx python3-dolfinx
# PETSc with OpenMPI (solver.linear.type: petsc, cmake/petsc.cmake; the build
# goes on without it when missing), found through pkg-config.
$SUDO apt-get install -y -qq --no-install-recommends pkg-config libpetsc-real-dev libopenmpi-dev openmpi-bin libscotch-dev
# The fuzzers (scripts/run-fuzzers.sh): clang with libFuzzer and the
# sanitizer runtimes, LLVM's OpenMP for the runtime library built by clang,
# llvm-symbolizer for readable stacks in clang's sanitizer reports.
$SUDO apt-get install -y -qq --no-install-recommends clang libclang-rt-dev libomp-dev llvm
