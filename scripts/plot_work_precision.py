#!/usr/bin/python3
"""Plot a work-precision study written by `hemicontact converge --adaptive` (or bench/adapt_study).

Usage:
    /usr/bin/python3 scripts/plot_work_precision.py DIR/work_precision.csv [--out PNG] [--title NAME]

Two log-log panels side by side: the relative energy-norm error against the number of unknowns N,
and against the whole-process time in seconds (the error_corrected column when present: the
measured error combined with the reference's own estimate, studies/adapt_study.hpp), one line per family (uniform, graded, adaptive;
hollow markers: a solve that was not certified), with an N^(-1/2) guide (the optimal P1 rate in
2D) through the finest adaptive point and the 1 % level dashed.
--out defaults to work_precision.png next to the CSV.

Only the Python standard library and matplotlib (Debian: python3-matplotlib) are used.
Exit codes: 0 written, 1 bad input, 2 matplotlib missing.
"""

import argparse
import csv
import os
import sys

from plotutil import save_atomically  # noqa: E402  (scripts/plotutil.py)

STYLE = {"uniform": ("tab:blue", "s", "uniform"), "graded": ("tab:green", "^", "graded (a priori)"),
         "adaptive": ("tab:red", "o", "adaptive")}


def read(path):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    need = {"family", "dofs", "seconds", "error", "ok"}
    if not rows or not need.issubset(rows[0].keys()):
        raise ValueError(f"{path}: not a work_precision.csv (columns {', '.join(sorted(need))})")
    fam = {}
    for r in rows:
        fam.setdefault(r["family"], []).append(
            (int(r["dofs"]), float(r["seconds"]), float(r.get("error_corrected") or r["error"]), r["ok"].strip() == "1"))
    return fam


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("csv")
    ap.add_argument("--out")
    ap.add_argument("--title", default="")
    args = ap.parse_args()
    try:
        fam = read(args.csv)
    except (OSError, ValueError) as e:
        print(f"plot_work_precision: {e}", file=sys.stderr)
        return 1
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print(f"plot_work_precision: matplotlib is not available for {sys.executable} "
              "(Debian: apt-get install python3-matplotlib)", file=sys.stderr)
        return 2
    out = args.out or os.path.join(os.path.dirname(os.path.abspath(args.csv)), "work_precision.png")
    fig, axes = plt.subplots(1, 2, figsize=(9.5, 4.0))
    for ax, col, xlabel in ((axes[0], 0, "unknowns N"), (axes[1], 1, "whole-process time [s]")):
        for name, pts in fam.items():
            colour, marker, label = STYLE.get(name, ("k", "x", name))
            pts = [p for p in pts if p[2] > 0]
            xs = [p[col] for p in pts]
            ys = [p[2] for p in pts]
            ax.plot(xs, ys, "-", color=colour, lw=1.2, label=label)
            for p in pts:
                ax.plot(p[col], p[2], marker, color=colour, ms=5, mfc=colour if p[3] else "none")
        ax.axhline(0.01, color="gray", ls="--", lw=0.8)
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel(xlabel)
        ax.grid(True, which="both", alpha=0.25)
    adaptive = [p for p in fam.get("adaptive", []) if p[2] > 0]
    if adaptive:
        n1, _, e1, _ = adaptive[-1]
        n0 = adaptive[0][0]
        axes[0].plot([n0, n1], [e1 * (n0 / n1) ** -0.5, e1], ":", color="k", lw=1, label=r"$N^{-1/2}$")
    axes[0].set_ylabel("relative energy-norm error (reference-corrected)")
    axes[0].legend(fontsize=8)
    if args.title:
        fig.suptitle(f"{args.title}: work precision (dashed: 1 %)", fontsize=10)
    fig.tight_layout()
    try:
        save_atomically(fig, out, dpi=90)
    except OSError as e:
        print(f"plot_work_precision: {out}: {e}", file=sys.stderr)
        return 1
    print(out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
