#!/usr/bin/python3
"""Plot a mesh-convergence study written by `hemicontact converge` (the paper's Fig. 3).

Usage:
    /usr/bin/python3 scripts/plot_convergence.py DIR/convergence.csv [--out PNG] [--title NAME]

Draws the relative energy-norm error ||u_ref - u_h||_E / ||u_ref||_E against h on log-log axes,
one marker per level (hollow: the solve did not converge or was not certified), the observed order
between consecutive levels next to each segment, and an O(h) guide line through the finest level.
The reference level and the reference-corrected rate fit (error = C sqrt(h^2a - h_ref^2a), drawn
dotted with its rate a) are read from convergence.json next to the CSV when it is there.
--out defaults to convergence.png next to the CSV; --title (e.g. the scene name) heads the plot.

Only the Python standard library and matplotlib (Debian: python3-matplotlib) are used.
Exit codes: 0 written, 1 bad input, 2 matplotlib missing.
"""

import argparse
import csv
import json
import math
import os
import sys

from plotutil import save_figure  # noqa: E402  (scripts/plotutil.py)


def number(s):
    try:
        return float(s)
    except (TypeError, ValueError):
        return math.nan


def read_levels(path):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    need = {"n", "h", "error", "order", "ok"}
    if not rows:
        raise ValueError(f"{path}: no level")
    if not need.issubset(rows[0].keys()):
        missing = ", ".join(sorted(need - set(rows[0].keys())))
        raise ValueError(f"{path}: not a convergence.csv of hemicontact converge (missing columns: {missing})")
    levels = [{"n": int(r["n"]), "h": number(r["h"]), "error": number(r["error"]), "order": number(r["order"]),
               "ok": r["ok"].strip() == "1"} for r in rows]
    return sorted(levels, key=lambda l: -l["h"])


def study_json(csv_path):
    path = os.path.join(os.path.dirname(os.path.abspath(csv_path)), "convergence.json")
    try:
        with open(path) as f:
            return json.load(f)
    except (OSError, ValueError):
        return {}


def reference_level(study):
    try:
        return study["reference"]["n"]
    except (KeyError, TypeError):
        return None


def rate_fit(study):
    fit = study.get("rate_fit") if isinstance(study, dict) else None
    if not isinstance(fit, dict) or not all(k in fit for k in ("alpha", "C")):
        return None
    return fit


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[1])
    ap.add_argument("csv", help="convergence.csv written by hemicontact converge")
    ap.add_argument("--out", help="PNG to write (default: convergence.png next to the CSV)")
    ap.add_argument("--title", default="", help="name shown in the title (e.g. the scene name)")
    args = ap.parse_args()

    try:
        levels = read_levels(args.csv)
    except (OSError, ValueError, KeyError) as e:
        print(f"plot_convergence: {e}", file=sys.stderr)
        return 1
    pts = [l for l in levels if l["error"] > 0 and l["h"] > 0]
    if not pts:
        print(f"plot_convergence: {args.csv}: no level with a positive error (only the reference?)", file=sys.stderr)
        return 1

    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        import matplotlib.ticker
    except ImportError:
        print(f"plot_convergence: matplotlib is not available for {sys.executable} "
              "(Debian: apt-get install python3-matplotlib)", file=sys.stderr)
        return 2

    fig, ax = plt.subplots(figsize=(6.5, 5.0))
    hs = [l["h"] for l in pts]
    es = [l["error"] for l in pts]
    ax.plot(hs, es, "-", color="C0", linewidth=1.5, zorder=2)
    for l in pts:
        ax.plot(l["h"], l["error"], "o", markersize=7, color="C0", markerfacecolor="C0" if l["ok"] else "white",
                zorder=3)
    ax.plot([], [], "o-", color="C0", label=r"$\Vert u_{ref} - u_h\Vert_E \,/\, \Vert u_{ref}\Vert_E$")
    if not all(l["ok"] for l in pts):
        ax.plot([], [], "o", color="C0", markerfacecolor="white", label="not converged / not certified")

    # O(h) guide through the finest level, over the whole range of h.
    h_last, e_last = pts[-1]["h"], pts[-1]["error"]
    h_guide = [max(hs), min(hs)]
    ax.plot(h_guide, [e_last * h / h_last for h in h_guide], "--", color="0.35", linewidth=1.2, label=r"$O(h)$")

    study = study_json(args.csv)
    ref = reference_level(study)
    fit = rate_fit(study)
    if fit and ref:
        a, c, h_ref = fit["alpha"], fit["C"], 1.0 / ref
        grid = [max(hs) * (min(hs) / max(hs)) ** (k / 60) for k in range(61)]
        ax.plot(grid, [c * math.sqrt(max(h ** (2 * a) - h_ref ** (2 * a), 0.0)) for h in grid], ":", color="C3",
                linewidth=1.4, label=rf"fit $C\sqrt{{h^{{2a}} - h_{{ref}}^{{2a}}}}$, $a$ = {a:.2f}")

    # Observed order next to each segment.
    for a, b in zip(pts, pts[1:]):
        if math.isfinite(b["order"]):
            ax.annotate(f"{b['order']:.2f}", (math.sqrt(a["h"] * b["h"]), math.sqrt(a["error"] * b["error"])),
                        textcoords="offset points", xytext=(6, -12), fontsize=9, color="C0")

    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xticks(hs)
    ax.set_xticklabels([f"1/{l['n']}" if abs(l["h"] * l["n"] - 1) < 1e-12 else f"{l['h']:.3g}" for l in pts])
    ax.xaxis.set_minor_locator(matplotlib.ticker.NullLocator())
    ax.set_xlabel(r"mesh size $h$")
    ax.set_ylabel(r"relative error $\Vert u_{ref} - u_h\Vert_E \,/\, \Vert u_{ref}\Vert_E$")
    head = f"{args.title}: " if args.title else ""
    sub = f"reference h = 1/{ref}" if ref else "reference solution"
    ax.set_title(f"{head}relative error in the energy norm\n({sub}; numbers: observed orders)", fontsize=11)
    ax.grid(True, which="major", linestyle=":", linewidth=0.6)
    ax.legend(loc="lower right")
    fig.tight_layout()
    return save_figure(fig, args.out, args.csv, "convergence.png", "plot_convergence", dpi=130)


if __name__ == "__main__":
    sys.exit(main())
