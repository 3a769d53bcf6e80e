#!/usr/bin/env python3
"""The 3D scene's reference energy and its work-precision study (docs/adaptivity.md §6).

1. Uniform levels: `hemicontact solve SCENE --set mesh.n=N` (the engine solve picks: petsc in one
   process above 10 000 unknowns, cholmod below), Π(u_h) and ‖u_h‖_E from each report.json.
2. The exact energy Π(u) by Richardson extrapolation with the observed rate: Π(u_h) = Π* + C h^p
   fitted (least squares in Π*, C, p) to the finest four levels; the uncertainty is the larger of
   the spread over the fits that drop one level and the distance to the three-level Richardson
   value on the finest n/4, n/2, n. Written to --data with every level and how it was made.
3. Errors without a reference solution on the mesh: Galerkin's error in the energy is of second
   order, Π(u_h) − Π(u) ≈ ½‖u − u_h‖²_E, so e_h = sqrt(2 (Π(u_h) − Π*)) / ‖u_h‖_E.
4. The ZZ estimate on the uniform levels (the adaptive loop's first level, cholmod, up to
   --estimate-max N) and the adaptive solves (`--set adapt.target_error=T --set
   adapt.reference_energy=Π*` from each --adaptive-from n) give the efficiency index η/e per mesh.
5. --out gets work_precision3d.csv, .json and .png (error against unknowns and against seconds).

Usage: bench/reference3d.py --cli build/hemicontact --runs DIR --out DIR [--data FILE]
       [--levels 8,12,...] [--estimate-max 32] [--adaptive-from 4,12] [--target 0.01]
Runs whose report.json is already in --runs are reused (delete them to measure again).
"""
import argparse
import csv
import json
import math
import os
import subprocess
import sys
import time


def solve(cli, scene, folder, sets):
    report = os.path.join(folder, "report.json")
    if not os.path.exists(report):
        cmd = [cli, "solve", scene, "--out", folder, "--force", "--quiet"]
        for s in sets:
            cmd += ["--set", s]
        t0 = time.monotonic()
        p = subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
        rc = p.returncode
        if not os.path.exists(report):
            sys.exit("%s: exit %d\n%s" % (" ".join(cmd), rc, p.stderr[-2000:]))
        with open(os.path.join(folder, "process_seconds.txt"), "w") as f:
            f.write("%.3f %d\n" % (time.monotonic() - t0, rc))
    with open(report) as f:
        r = json.load(f)
    with open(os.path.join(folder, "process_seconds.txt")) as f:
        r["process_seconds"] = float(f.read().split()[0])
    return r


def fit(h, energy):
    """Least squares of Π = Π* + C h^p: for each p the problem is linear in (Π*, C); p by golden search."""
    def linear(p):
        x = [hi ** p for hi in h]
        n = len(x)
        mx, my = sum(x) / n, sum(energy) / n
        c = sum((xi - mx) * (yi - my) for xi, yi in zip(x, energy)) / sum((xi - mx) ** 2 for xi in x)
        pstar = my - c * mx
        res = sum((pstar + c * xi - yi) ** 2 for xi, yi in zip(x, energy))
        return res, pstar, c
    lo, hi = 0.2, 4.0
    g = (math.sqrt(5) - 1) / 2
    for _ in range(200):
        a, b = hi - g * (hi - lo), lo + g * (hi - lo)
        if linear(a)[0] < linear(b)[0]:
            hi = b
        else:
            lo = a
    p = 0.5 * (lo + hi)
    res, pstar, c = linear(p)
    return {"energy": pstar, "C": c, "p": p, "residual_rms": math.sqrt(res / len(h))}


SCENE_NAME = "sofonea2017-3d"  # the plot's title: the scene's file name (main sets it)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--cli", default="build/hemicontact")
    ap.add_argument("--scene", default="problems/sofonea2017-3d.json")
    ap.add_argument("--runs", required=True)
    ap.add_argument("--out", required=True)
    ap.add_argument("--data", default=None)
    ap.add_argument("--levels", default="8,12,16,20,24,32,40,48,64,80")
    ap.add_argument("--estimate-max", type=int, default=32)
    ap.add_argument("--adaptive-from", default="4,12")
    ap.add_argument("--target", type=float, default=0.01)
    a = ap.parse_args()
    global SCENE_NAME
    SCENE_NAME = os.path.splitext(os.path.basename(a.scene))[0]
    os.makedirs(a.runs, exist_ok=True)
    os.makedirs(a.out, exist_ok=True)
    levels = [int(n) for n in a.levels.split(",")]
    uniform = []
    for n in levels:
        r = solve(a.cli, a.scene, os.path.join(a.runs, "n%d" % n), ["mesh.n=%d" % n, "check.smallness=false"])
        if not r["ok"]:
            sys.exit("n = %d not certified: %s" % (n, r["message"]))
        uniform.append({"n": n, "dofs": r["dofs"], "energy": r["energy"], "energy_norm": r["energy_norm"],
                        "certificate": r["certificate"]["max_residual"], "engine": r["engine_choice"]["engine"],
                        "seconds": r["process_seconds"]})
    finest = uniform[-4:]
    best = fit([1.0 / u["n"] for u in finest], [u["energy"] for u in finest])
    drops = []
    for k in range(len(finest)):
        sub = finest[:k] + finest[k + 1:]
        drops.append(fit([1.0 / u["n"] for u in sub], [u["energy"] for u in sub]))
    spread = max(abs(d["energy"] - best["energy"]) for d in drops)
    # The classic three-level extrapolation on the finest levels n/4, n/2, n (h halved twice), with
    # its own observed rate: its distance to the fit bounds the pre-asymptotic drift.
    by_n = {u["n"]: u["energy"] for u in uniform}
    three = None
    for n in sorted(by_n, reverse=True):
        if n % 4 == 0 and n // 2 in by_n and n // 4 in by_n:
            e1, e2, e4 = by_n[n // 4], by_n[n // 2], by_n[n]
            p3 = math.log2((e1 - e2) / (e2 - e4))
            three = {"levels": [n // 4, n // 2, n], "p": p3, "energy": e4 - (e2 - e4) / (2 ** p3 - 1)}
            break
    if three:
        spread = max(spread, abs(three["energy"] - best["energy"]))
    ref = {"scene": a.scene, "energy": best["energy"], "energy_uncertainty": spread, "rate_p": best["p"],
           "fit": best, "fits_dropping_one_level": drops, "three_level_richardson": three, "levels": uniform,
           "how": "Uniform symmetric boxes n^3 (6 n^3 tetrahedra), each solved by `hemicontact solve SCENE "
                  "--set mesh.n=n` (engine auto: petsc in one process above 10 000 unknowns), every level "
                  "certified; Pi(u_h) = Pi* + C h^p fitted by least squares to the finest four levels (p "
                  "observed, not assumed); energy_uncertainty = the largest change of Pi* when one of them "
                  "is left out, or the distance to the three-level Richardson value on the finest n/4, n/2, n "
                  "if larger. Made by bench/reference3d.py."}
    for u in uniform:
        u["error"] = math.sqrt(2 * max(0.0, u["energy"] - ref["energy"])) / u["energy_norm"]
    if a.data:
        with open(a.data, "w") as f:
            json.dump(ref, f, indent=2)
            f.write("\n")
    rows = []
    for u in uniform:
        row = {"family": "uniform", "level": u["n"], "dofs": u["dofs"], "seconds": u["seconds"], "error": u["error"],
               "estimate": float("nan"), "efficiency": float("nan"), "certificate": u["certificate"]}
        if u["n"] <= a.estimate_max:
            r = solve(a.cli, a.scene, os.path.join(a.runs, "zz%d" % u["n"]),
                      ["mesh.n=%d" % u["n"], "adapt.target_error=1e-5", "adapt.max_levels=1", "check.smallness=false"])
            row["estimate"] = r["adapt"]["history"][0]["estimate"]
            row["efficiency"] = row["estimate"] / u["error"]
        rows.append(row)
    for n0 in [int(n) for n in a.adaptive_from.split(",")]:
        r = solve(a.cli, a.scene, os.path.join(a.runs, "adaptive%d" % n0),
                  ["mesh.n=%d" % n0, "adapt.target_error=%g" % a.target, "adapt.reference_energy=%.10g" % ref["energy"],
                   "check.smallness=false"])
        for L in r["adapt"]["history"]:
            rows.append({"family": "adaptive from n = %d" % n0, "level": L["level"], "dofs": L["dofs"],
                         "seconds": L["cumulative_seconds"], "error": L["reference_error"], "estimate": L["estimate"],
                         "efficiency": L["estimate"] / L["reference_error"], "certificate": L["certificate"]})
    with open(os.path.join(a.out, "work_precision3d.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        w.writeheader()
        w.writerows(rows)
    with open(os.path.join(a.out, "work_precision3d.json"), "w") as f:
        json.dump({"reference": {k: ref[k] for k in ("energy", "energy_uncertainty", "rate_p")}, "rows": rows}, f, indent=2)
    for row in rows:
        print("%-22s %4s %8d %9.2f s  error %.4f  estimate %.4f  eff. %.3f  cert. %.1e" % (
            row["family"], row["level"], row["dofs"], row["seconds"], row["error"], row["estimate"], row["efficiency"],
            row["certificate"]))
    print("reference energy %.4f +- %.2g, p = %.3f (error ~ h^%.3f)" % (ref["energy"], spread, best["p"], best["p"] / 2))
    plot(rows, os.path.join(a.out, "work_precision3d.png"))


def slope(rows, last=4):
    x = [math.log(r["dofs"]) for r in rows][-last:]
    y = [math.log(r["error"]) for r in rows][-last:]
    mx, my = sum(x) / len(x), sum(y) / len(y)
    return sum((xi - mx) * (yi - my) for xi, yi in zip(x, y)) / sum((xi - mx) ** 2 for xi in x)


def plot(rows, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(1, 2, figsize=(11, 4.2))
    for fam in dict.fromkeys(r["family"] for r in rows):
        rs = [r for r in rows if r["family"] == fam]
        lab = "%s (N^%.2f, last 3 meshes)" % (fam, slope(rs, 3)) if len(rs) > 2 else fam
        ax[0].loglog([r["dofs"] for r in rs], [r["error"] for r in rs], "o-", label=lab)
        ax[1].loglog([r["seconds"] for r in rs], [r["error"] for r in rs], "o-", label=fam)
    ax[0].set_xlabel("unknowns N")
    ax[1].set_xlabel("seconds (uniform: whole process; adaptive: cumulative in the loop)")
    for x in ax:
        x.set_ylabel("relative energy error (reference energy)")
        x.grid(True, which="both", alpha=0.3)
        x.legend(fontsize=8)
    fig.suptitle("%s: uniform and adaptive P1, error from the extrapolated energy" % SCENE_NAME)
    fig.tight_layout()
    fig.savefig(path, dpi=110)


if __name__ == "__main__":
    main()
