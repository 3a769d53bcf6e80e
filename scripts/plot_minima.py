#!/usr/bin/python3
"""Compare the distinct solutions found by `hemicontact minima` along Gamma3.

Usage:
    /usr/bin/python3 scripts/plot_minima.py DIR/minima.json [--out PNG] [--title NAME]

Reads minima.json (its "solutions", each with "nodes": x, y, u_nu, sigma_nu, g, status, and its
"energy" and "type") and draws two panels against the position along Gamma3 (the coordinate in
which the Gamma3 nodes spread most, x on a bottom edge):

  top:    u_nu, one line per distinct solution (solid: local minimum, dashed: saddle, dotted:
          unchecked), with the layer thickness g (the rigid foundation) as a grey line;
  bottom: sigma_nu, the normal stress, same lines.

Markers show each node's normal status (o separated, s normal compliance, ^ contact u_nu = g).
--out defaults to minima.png next to the JSON; --title (e.g. the scene name) heads the plot.

Only the Python standard library and matplotlib (Debian: python3-matplotlib) are used.
Exit codes: 0 written, 1 bad input, 2 matplotlib missing.
"""

import argparse
import json
import math
import sys

from plotutil import save_figure  # noqa: E402  (scripts/plotutil.py)

MARKER = {"separated": "o", "compliance": "s", "contact": "^"}
LINE = {"local minimum": "-", "saddle": "--"}


def number(v):
    return math.nan if v is None else float(v)


def read(path):
    try:
        with open(path) as f:
            data = json.load(f)
    except (OSError, ValueError) as e:
        raise ValueError(f"cannot read {path}: {e}")
    sols = data.get("solutions")
    if not isinstance(sols, list):
        raise ValueError(f"{path}: not a minima.json of hemicontact minima (no \"solutions\")")
    return data, sols


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[1])
    ap.add_argument("json", help="minima.json written by hemicontact minima")
    ap.add_argument("--out", help="PNG to write (default: minima.png next to the JSON)")
    ap.add_argument("--title", default="", help="name shown in the title (e.g. the scene name)")
    args = ap.parse_args()
    try:
        data, sols = read(args.json)
    except ValueError as e:
        print(f"plot_minima.py: {e}", file=sys.stderr)
        return 1
    if not sols:
        print(f"plot_minima.py: {args.json}: no solution to draw", file=sys.stderr)
        return 1
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("plot_minima.py: matplotlib is missing (Debian: apt-get install python3-matplotlib)", file=sys.stderr)
        return 2

    nodes0 = sols[0]["nodes"]
    if not nodes0:
        print(f"plot_minima.py: {args.json}: the scene has no Gamma3 nodes, so there is no profile to draw",
              file=sys.stderr)
        return 1
    axes = [a for a in ("x", "y", "z") if a in nodes0[0]]
    spread = {a: max(n[a] for n in nodes0) - min(n[a] for n in nodes0) for a in axes}
    axis = max(axes, key=lambda a: spread[a])

    fig, (ax_u, ax_s) = plt.subplots(2, 1, figsize=(11, 7.5), sharex=True)
    colors = plt.rcParams["axes.prop_cycle"].by_key().get("color", ["C0"])
    for k, s in enumerate(sols):
        nodes = sorted(s["nodes"], key=lambda n: n[axis])
        xs = [n[axis] for n in nodes]
        c = colors[k % len(colors)]
        ls = LINE.get(s.get("type", ""), ":")
        label = f"{k}: E = {s['energy']:.6g}, {s.get('type', '?')} ({s.get('n_starts', '?')} starts)"
        ax_u.plot(xs, [number(n["u_nu"]) for n in nodes], ls, color=c, label=label)
        ax_s.plot(xs, [number(n["sigma_nu"]) for n in nodes], ls, color=c)
        for n in nodes:
            m = MARKER.get(n["status"].split("/")[0], "x")
            ax_u.plot(n[axis], number(n["u_nu"]), m, color=c, ms=4, mfc="none")
            ax_s.plot(n[axis], number(n["sigma_nu"]), m, color=c, ms=4, mfc="none")
    gs = [number(n.get("g")) for n in sorted(nodes0, key=lambda n: n[axis])]
    if any(math.isfinite(g) for g in gs):
        ax_u.plot(sorted(n[axis] for n in nodes0), gs, color="0.5", lw=3, alpha=0.5, zorder=0, label="g (rigid foundation)")
    ax_u.axhline(0, color="0.8", lw=0.8)
    ax_s.axhline(0, color="0.8", lw=0.8)
    ax_u.set_ylabel(r"$u_\nu$")
    ax_s.set_ylabel(r"$\sigma_\nu$")
    ax_s.set_xlabel(f"{axis} along $\\Gamma_3$")
    ax_u.legend(fontsize=7 if len(sols) <= 12 else 6, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0)
    sm = data.get("smallness", {})
    note = ""
    if sm.get("computed"):
        note = " — (21) holds: unique" if sm.get("uniqueness_guaranteed") else " — (21) fails"
    title = (args.title + ": " if args.title else "") + f"{len(sols)} distinct solution(s){note}"
    ax_u.set_title(title + "\nmarkers: o separated, s compliance, ^ contact; solid: minimum, dashed: saddle",
                   fontsize=9)
    fig.tight_layout()
    return save_figure(fig, args.out, args.json, "minima.png", "plot_minima.py", dpi=120)


if __name__ == "__main__":
    sys.exit(main())
