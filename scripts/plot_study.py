#!/usr/bin/python3
"""Plot the work-precision study written by hemicontact_study (bench/study.cpp).

Usage:
    /usr/bin/python3 scripts/plot_study.py DIR/study.csv [--out DIR]

Writes, into --out (default: the CSV's directory):
    work_precision_<scene>.png  relative energy-norm error vs solve seconds (log-log), one line per
                                backend:formulation (colour) and eps (line style, when several were
                                run), one marker shape per mesh level; hollow markers = not
                                certified ("uncertified" or "not_converged" rows)
    time_vs_dofs.png            solve seconds and the linear elastic factor+solve seconds vs dofs
                                (log-log), one panel per scene

Only the Python standard library and matplotlib (Debian: python3-matplotlib) are used.
Exit codes: 0 written, 1 bad input, 2 matplotlib missing.
"""

import argparse
import csv
import math
import os
import sys
from collections import defaultdict

SOLVED = {"ok", "ok(backend_failed)", "uncertified", "not_converged"}
LINESTYLES = ["-", "--", ":", "-."]
MARKERS = ["o", "s", "^", "D", "v", "P", "X", "*", "<", ">", "h", "p"]


def number(s):
    try:
        v = float(s)
    except (TypeError, ValueError):
        return math.nan
    return v


def read_rows(path):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    need = {"scene", "level", "dofs", "backend", "formulation_requested", "eps", "status", "solve_s",
            "linear_s", "rel_error"}
    if rows and not need.issubset(rows[0].keys()):
        missing = ", ".join(sorted(need - set(rows[0].keys())))
        raise ValueError(f"{path}: not a hemicontact_study CSV (missing columns: {missing})")
    return rows


def series_label(row, several_eps):
    label = f"{row['backend']}:{row['formulation_requested']}"
    return f"{label} eps={row['eps']}" if several_eps else label


def plot_work_precision(plt, rows, scene, out_dir):
    ref = [r for r in rows if r["scene"] == scene and r["role"] in ("reference", "study+reference")]
    rows = [r for r in rows if r["scene"] == scene and r["status"] in SOLVED and r["role"] != "reference"]
    pts = [r for r in rows if number(r["rel_error"]) > 0 and number(r["solve_s"]) > 0]
    if not pts:
        print(f"plot_study: {scene}: no run with an error and a solve time; work-precision plot skipped")
        return None
    several_eps = len({r["eps"] for r in pts}) > 1
    levels = sorted({int(r["level"]) for r in pts})
    marker = {L: MARKERS[i % len(MARKERS)] for i, L in enumerate(levels)}
    series = defaultdict(list)
    for r in pts:
        series[series_label(r, several_eps)].append(r)
    # One colour per backend:formulation, one line style per eps.
    colors = {k: f"C{i % 10}" for i, k in enumerate(sorted({series_label(r, False) for r in pts}))}
    eps_values = sorted({r["eps"] for r in pts}, key=number)
    fig, ax = plt.subplots(figsize=(7.5, 5.5))
    for label, rs in sorted(series.items()):
        rs.sort(key=lambda r: int(r["level"]))
        color = colors[series_label(rs[0], False)]
        style = LINESTYLES[eps_values.index(rs[0]["eps"]) % len(LINESTYLES)]
        ax.plot([number(r["solve_s"]) for r in rs], [number(r["rel_error"]) for r in rs], linestyle=style,
                color=color, label=label)
        for r in rs:
            certified = r["status"] in ("ok", "ok(backend_failed)")
            ax.plot(number(r["solve_s"]), number(r["rel_error"]), marker[int(r["level"])], color=color,
                    markerfacecolor=color if certified else "none", markersize=7)
    # Legend entries for the levels (marker shapes, grey).
    for L in levels:
        ax.plot([], [], marker[L], color="0.4", linestyle="none", label=f"level {L}")
    ax.plot([], [], "o", color="0.4", markerfacecolor="none", linestyle="none", label="not certified")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("solve time [s] (build excluded)")
    ax.set_ylabel(r"$\Vert u_{ref} - P u_h \Vert_E \,/\, \Vert u_{ref} \Vert_E$")
    title = f"work-precision: {scene}"
    if ref:
        r = ref[0]
        title += f"\n(reference: level {r['level']}, {r['backend']}:{r['formulation_requested']}, eps={r['eps']})"
    ax.set_title(title, fontsize=10)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8, loc="best")
    fig.tight_layout()
    path = os.path.join(out_dir, f"work_precision_{scene}.png")
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path


def plot_time_vs_dofs(plt, rows, out_dir):
    scenes = sorted({r["scene"] for r in rows})
    solved = [r for r in rows if r["status"] in SOLVED and number(r["dofs"]) > 0]
    if not solved:
        print("plot_study: no solved run; time_vs_dofs plot skipped")
        return None
    fig, axes = plt.subplots(1, len(scenes), figsize=(6.5 * len(scenes), 5.0), squeeze=False)
    for ax, scene in zip(axes[0], scenes):
        rs = [r for r in solved if r["scene"] == scene]
        several_eps = len({r["eps"] for r in rs}) > 1
        series = defaultdict(list)
        for r in rs:
            series[series_label(r, several_eps)].append(r)
        colors = {k: f"C{i % 10}" for i, k in enumerate(sorted({series_label(r, False) for r in rs}))}
        eps_values = sorted({r["eps"] for r in rs}, key=number)
        for label, s in sorted(series.items()):
            s.sort(key=lambda r: number(r["dofs"]))
            ax.plot([number(r["dofs"]) for r in s], [number(r["solve_s"]) for r in s], marker="o",
                    linestyle=LINESTYLES[eps_values.index(s[0]["eps"]) % len(LINESTYLES)],
                    color=colors[series_label(s[0], False)], label=f"solve: {label}")
        # The linear elastic factor+solve depends on the mesh only: median over the runs of a level.
        lin = defaultdict(list)
        for r in rs:
            if number(r["linear_s"]) > 0:
                lin[number(r["dofs"])].append(number(r["linear_s"]))
        if lin:
            xs = sorted(lin)
            ys = [sorted(lin[x])[len(lin[x]) // 2] for x in xs]
            ax.plot(xs, ys, "k--", marker="x", label="linear elastic factor+solve")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("free dofs")
        ax.set_ylabel("seconds")
        ax.set_title(f"time vs dofs: {scene}")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8, loc="best")
    fig.tight_layout()
    path = os.path.join(out_dir, "time_vs_dofs.png")
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("csv", help="study.csv written by hemicontact_study")
    ap.add_argument("--out", help="output directory (default: the CSV's directory)")
    args = ap.parse_args()
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("plot_study: matplotlib is missing; install it with 'apt-get install python3-matplotlib' "
              "(Debian) and run /usr/bin/python3 scripts/plot_study.py DIR/study.csv again", file=sys.stderr)
        return 2
    try:
        rows = read_rows(args.csv)
    except (OSError, ValueError) as e:
        print(f"plot_study: {e}", file=sys.stderr)
        return 1
    out_dir = args.out or os.path.dirname(os.path.abspath(args.csv))
    os.makedirs(out_dir, exist_ok=True)
    written = [plot_work_precision(plt, rows, s, out_dir) for s in sorted({r["scene"] for r in rows})]
    written.append(plot_time_vs_dofs(plt, rows, out_dir))
    for p in written:
        if p:
            print(f"plot_study: wrote {p}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
