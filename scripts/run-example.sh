#!/usr/bin/env bash
# README command 1: set up, build, and run the main job — the paper's example (Sofonea, Han,
# Barboteu 2017, §5) in its Fig. 2 form (loads × 1e6, see problems/README.md), as printed, and as
# a 3D body, each with its picture (Fig. 2: deformed mesh, Γ3 statuses and forces; 3D: the bottom
# face's status map), then the paper's Fig. 3
# (mesh convergence of the Fig. 2 scene, levels 4..128 against h = 1/256).
# Prints the status summary and certificate of each solve and the convergence table; results go
# to out/. Extra arguments are passed to the solves (e.g. --set mesh.n=128).
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$here"
# The programs only (hemicontact, and hemicontact-mpi where PETSc is installed, which it depends
# on): the tests and benchmarks are built by the test command.
bash scripts/build.sh hemicontact_cli
build="${BUILD_DIR:-build}"
for scene in sofonea2017-fig2 sofonea2017-printed sofonea2017-3d; do
  echo
  echo "=== problems/$scene.json ==="
  "$build/hemicontact" solve "problems/$scene.json" --out "out/$scene" --force --plot "$@"
done
echo
echo "=== Fig. 3: convergence of problems/sofonea2017-fig2.json ==="
"$build/hemicontact" converge problems/sofonea2017-fig2.json --levels 4,8,...,128 --reference 256 \
  --out out/sofonea2017-fig2-convergence --force --plot --quiet
