#!/usr/bin/env bash
# Installs every dependency from Debian 12 packages and builds Release into build/.
# Run as root on a fresh machine; safe to run again (idempotent).
set -euo pipefail
cd "$(dirname "$0")/.."

packages=(
  build-essential cmake pkg-config git
  ninja-build                             # the build's generator: compiles while the layers link (make waits)
  petsc-dev libopenmpi-dev openmpi-bin    # PETSc 3.18 with MPI and MUMPS
  slepc-dev                               # SLEPc on that PETSc: the eigenproblems of `thermocontact stability`
  libsuitesparse-dev                      # CHOLMOD, called through its own API (any PETSc version)
  libopenblas0-pthread                    # optimised BLAS: CHOLMOD factorises 5x faster than with reference BLAS
  libeigen3-dev libtomlplusplus-dev libcli11-dev libfmt-dev libmetis-dev
  libgmsh-dev gmsh
  zlib1g-dev                              # zlib-compressed binary .vtu ([output] compression)
  libhdf5-openmpi-dev                     # parallel HDF5: [output] format = "vtkhdf", one file per step from all ranks
  googletest libgtest-dev libbenchmark-dev
  python3 python3-matplotlib python3-numpy  # plots of history.csv and of fields
)
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${packages[@]}" >/dev/null

# Ninja for a new build directory; one configured before keeps its generator (CMake refuses to
# switch). docs/choices.md, "Ninja, tests at -O1 and benchmarks outside the default build".
[ -f build/CMakeCache.txt ] || export CMAKE_GENERATOR=Ninja
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release
cmake --build build -j"$(nproc)"
echo "built: build/bin/thermocontact"
