#!/usr/bin/env python3
"""Scaling of the petsc engine (the distributed one, for meshes beyond one process): the 3D paper
scene (problems/sofonea2017-3d.json) on n^3 boxes, run as `mpirun -np P hemicontact solve ... --set
solver.engine="petsc"` for each n and P, one run at a time. Reads each run's report.json and prints
one row per run: unknowns, ranks, wall time (the whole process, measured here), the solve's own
time, peak memory summed over the ranks and the largest rank's (getrusage, from report.json
"petsc"), bytes per unknown, which mesh layout ran (per-rank slabs or blocks, or DMPlex) and the most
nodes one rank held,
the method (ssn by default; --backend tao:bnls for TAO), Newton and Krylov counts, Krylov per Newton
step (mean and largest), how many times the AMG hierarchy was built, the certificate, the share of
K's entries that couple two ranks (report.json petsc.partition), and the speedup against P = 1 of
the same n.
The CSV goes to --out.

  python3 bench/petsc_scaling.py --build build --levels 8,16,24,32 --ranks 1,2 --out /tmp/petsc-scaling

Weak scaling (--weak-per-rank K): one run per rank count P, on the box whose 3 n^3 unknowns are
nearest K P (n = (K P / 3)^(1/3) rounded to an even number, which the 3D scene's symmetric pattern
needs); the rows then carry the weak efficiency (the 1-rank wall time over this one's) and the
growth of the largest rank's peak memory against the 1-rank run (the distributed mesh's target: at
most 1.3x from 1 to 16 ranks at K = 260 000).

  python3 bench/petsc_scaling.py --weak-per-rank 260000 --ranks 1,2,4,8,16 --out /tmp/petsc-weak

Runs of a million unknowns or more take the whole of a 2-core machine: run them alone.
"""
import argparse
import csv
import json
import os
import subprocess
import sys
import time
from pathlib import Path


def main() -> int:
    here = Path(__file__).resolve().parent.parent
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--build", default=str(here / "build"), help="build folder with hemicontact and hemicontact-mpi")
    ap.add_argument("--scene", default=str(here / "problems" / "sofonea2017-3d.json"))
    ap.add_argument("--levels", default="8,16,24,32", help="box cells per side, comma-separated")
    ap.add_argument("--ranks", default="1,2", help="MPI ranks, comma-separated")
    ap.add_argument("--set", action="append", default=[], help="extra --set path=value for every run")
    ap.add_argument("--mesh", default="auto", choices=["auto", "blocks"],
                    help="solver.petsc.mesh: auto (per-rank slabs where they cover the scene, a box's blocks beyond one "
                         "rank per layer, DMPlex elsewhere) or blocks")
    ap.add_argument("--backend", default="", help="ssn (the engine's default) or tao:bnls, tao:bntr, tao:bntl")
    ap.add_argument("--weak-per-rank", type=int, default=0,
                    help="weak scaling: about this many unknowns per rank (--levels is then ignored)")
    ap.add_argument("--out", required=True, help="folder for the runs and scaling.csv")
    a = ap.parse_args()
    ranks = [int(x) for x in a.ranks.split(",")]
    if a.weak_per_rank > 0:
        # n even: the 3D scene's symmetric pattern splits its cells in mirror pairs.
        runs = [(2 * round((a.weak_per_rank * p / 3) ** (1 / 3) / 2), p) for p in ranks]
    else:
        runs = [(int(n), p) for n in a.levels.split(",") for p in ranks]
    exe = Path(a.build) / "hemicontact"
    if not exe.exists():
        print(f"petsc_scaling: {exe} not found (build first)", file=sys.stderr)
        return 2
    out = Path(a.out)
    out.mkdir(parents=True, exist_ok=True)
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
               OMPI_MCA_rmaps_base_oversubscribe="1")
    rows = []
    base = {}
    for n, p in runs:
        run = out / f"n{n}-np{p}"
        cmd = ["mpirun", "-np", str(p), str(exe), "solve", a.scene, "--set", f"mesh.n={n}",
               "--set", 'solver.engine="petsc"', "--set", f'solver.petsc.mesh="{a.mesh}"',
               "--set", "output.vtu=false", "--set", "output.csv=false",
               "--quiet", "--force", "--out", str(run)]
        for s in a.set:
            cmd += ["--set", s]
        if a.backend:
            cmd += ["--backend", a.backend]
        t0 = time.monotonic()
        r = subprocess.run(cmd, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
        wall = time.monotonic() - t0
        if r.returncode != 0:
            print(f"petsc_scaling: n={n} np={p} exited {r.returncode}:\n{r.stderr}", file=sys.stderr)
            return 1
        rep = json.loads((run / "report.json").read_text())
        pe = rep["petsc"]
        row = {
            "n": n, "ranks": p, "unknowns": pe["unknowns"], "wall_s": round(wall, 2),
            "solve_s": round(rep["timings"]["solve_total"], 2),
            "peak_mb_sum": round(pe["peak_rss_mb_sum"], 1), "bytes_per_dof": round(pe["bytes_per_dof"]),
            # the largest rank's peak, and what each rank holds of the mesh (the per-rank slabs
            # hold about nodes/P plus two ghost layers, DMPlex's parts two cell layers around theirs)
            "peak_mb_max_rank": round(pe["peak_rss_mb_max"], 1),
            "mesh": pe["partition"]["type"],
            "local_nodes_max": pe["local_nodes"],
            "newton": pe["newton_iterations"], "krylov": pe["krylov_iterations"],
            "krylov_per_newton": round(pe["krylov_per_newton"], 1),
            "method": pe.get("method", ""),
            "krylov_max_step": max((m.get("krylov", 0) for m in pe["minimizations"]), default=0),
            "pc_builds": sum(1 for m in pe["minimizations"] if m.get("pc_built")),
            "polish_newton": pe["polish_newton_iterations"],
            "certificate": rep["certificate"]["max_residual"], "statuses": json.dumps(rep["status_counts"]),
            # the partition's coupled share of K's entries (0 on one rank)
            "off_rank": round(pe.get("partition", {}).get("off_rank_entries", 0.0), 5),
        }
        if a.weak_per_rank > 0:
            # Weak scaling: against the 1-rank run (the first of --ranks, which should be 1).
            if not base:
                base = {"wall": wall, "peak": row["peak_mb_max_rank"], "ranks": p}
            row["unknowns_per_rank"] = round(row["unknowns"] / p)
            row["weak_efficiency"] = round(base["wall"] / wall, 2)
            row["peak_growth"] = round(row["peak_mb_max_rank"] / base["peak"], 2)
        else:
            if p == 1:
                base[n] = wall
            row["speedup"] = round(base[n] / wall, 2) if n in base else ""
        rows.append(row)
        print(" ".join(f"{k}={v}" for k, v in row.items() if k != "statuses"), flush=True)
    with open(out / "scaling.csv", "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(rows[0].keys()))
        w.writeheader()
        w.writerows(rows)
    print(f"petsc_scaling: {out / 'scaling.csv'}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
