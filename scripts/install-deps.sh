#!/usr/bin/env bash
# Install the Debian packages hemicontact needs, and only those that are missing.
# Idempotent: a second run installs nothing and does not call apt-get update.
# Usage: scripts/install-deps.sh [--without-gmsh] [--without-petsc] [--with-sanitizers]
#   --without-gmsh:    leave out the Gmsh API (libgmsh-dev, ~1 GB with its dependencies); .msh import is
#                      then not compiled in and the Gmsh-only tests skip with that reason.
#   --without-petsc:   leave out PETSc 3.18 and OpenMPI (the distributed engine, solver.engine = petsc,
#                      hemicontact-mpi); the build then refuses that engine naming the package.
#   --with-sanitizers: also Debian's clang 14 with its sanitizer and libFuzzer runtimes and the
#                      symbolizer, for scripts/run-sanitizers.sh (the CI's ASan/UBSan + fuzzing step).
set -euo pipefail

pkgs=(
  build-essential cmake pkg-config
  libeigen3-dev          # Eigen 3.4: dense/sparse linear algebra
  libsuitesparse-dev     # CHOLMOD (supernodal sparse Cholesky), METIS ordering
  libopenblas0-pthread   # CHOLMOD's supernodes are BLAS-bound; reference BLAS is 2-5x slower
  liblapack-dev          # LAPACK, linked by name: CHOLMOD's, and dlauum for S = L_CC L_CCᵀ
  coinor-libipopt-dev    # Ipopt 3.11.9 with MUMPS: the design's NLP backend
  libnlopt-cxx-dev       # NLopt 2.7: alternative local/global NLP backends
  nlohmann-json3-dev     # scene files and report.json
  zlib1g-dev             # compressed binary VTU output
  libgtest-dev           # unit tests
  libbenchmark-dev       # micro-benchmarks in bench/
  python3-matplotlib     # pictures (work-precision, convergence, Fig. 2); Debian's /usr/bin/python3
  python3-dev pybind11-dev  # the Python module (python/): Python's headers and pybind11
  python3-numpy          # the module's arrays
  python3-pytest         # the module's tests (tests/python)
  python3-meshio         # Result.export / to_meshio (optional at run time: the module imports it on use)
  python3-h5py           # meshio's XDMF writer (docs/python.md's r.export("u.xdmf"))
  python3-pip python3-venv python3-setuptools python3-wheel  # `pip install .` of the module (setup.py)
)
# Gmsh is part of the default install: users mesh their own geometry (mesh.type = "gmsh").
gmsh=1
# PETSc (with hypre's BoomerAMG, GAMG, TAO) and OpenMPI's mpirun: the petsc engine, default install.
petsc=1
for arg in "$@"; do
  case "$arg" in
    --without-gmsh) gmsh=0 ;;
    --without-petsc) petsc=0 ;;
    --with-sanitizers) pkgs+=(clang-14 libclang-rt-14-dev llvm-14) ;;
    *) echo "install-deps: unknown option '$arg' (usage: scripts/install-deps.sh [--without-gmsh] [--without-petsc] [--with-sanitizers])" >&2
       exit 1 ;;
  esac
done
if ((gmsh)); then pkgs+=(libgmsh-dev); fi
if ((petsc)); then pkgs+=(libpetsc-real-dev openmpi-bin); fi

missing=()
for p in "${pkgs[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if ((${#missing[@]} == 0)); then
  echo "install-deps: all ${#pkgs[@]} packages present" >&2
  exit 0
fi

sudo=""
if [[ $(id -u) -ne 0 ]]; then sudo="sudo"; fi
echo "install-deps: installing ${missing[*]}" >&2
export DEBIAN_FRONTEND=noninteractive
$sudo apt-get update -qq
$sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
echo "install-deps: done" >&2
