#!/usr/bin/python3
"""Draw the load history of `hemicontact path`: the loop and its jumps.

Usage:
    /usr/bin/python3 scripts/plot_path.py DIR/path.json [--out PNG] [--title NAME]

Reads path.json (its "states": load, reaction, mean_u_nu, kind, segment, type; and its "jumps":
state_before, state_after, load_after, direction) and draws two panels:

  left:  the total normal reaction of Gamma3 against the load factor;
  right: the reaction against the mean u_nu over Gamma3.

The states are joined in the order of the history, one colour per segment (loading / unloading).
A jump is drawn as a dashed grey segment from the state before to the state after, with a red
marker at both ends and its load factor written beside it. States that failed the second-order
check (a saddle) or the certificate get a black x.
--out defaults to path.png next to the JSON; --title (e.g. the scene name) heads the plot.

Only the Python standard library and matplotlib (Debian: python3-matplotlib) are used.
Exit codes: 0 written, 1 bad input, 2 matplotlib missing.
"""

import argparse
import json
import math
import sys

from plotutil import save_figure  # noqa: E402  (scripts/plotutil.py)


def number(v):
    return math.nan if v is None else float(v)


def read(path):
    try:
        with open(path) as f:
            data = json.load(f)
    except (OSError, ValueError) as e:
        raise ValueError(f"cannot read {path}: {e}")
    if not isinstance(data.get("states"), list) or not isinstance(data.get("jumps"), list):
        raise ValueError(f"{path}: not a path.json of hemicontact path (no \"states\" / \"jumps\")")
    return data


def draw(ax, data, xkey, xlabel):
    states, jumps = data["states"], data["jumps"]
    loads = data.get("loads", [])
    colors = ["C0", "C1", "C2", "C3", "C4", "C5"]
    skip = set()
    for J in jumps:  # the jump itself is drawn dashed, not as part of a segment's line
        skip.add((J["state_before"], J["state_after"]))
    for seg in sorted({s["segment"] for s in states}):
        idx = [k for k, s in enumerate(states) if s["segment"] == seg]
        label = None
        if seg + 1 < len(loads):
            word = "loading" if loads[seg + 1] > loads[seg] else "unloading"
            label = f"{word} {loads[seg]:g} -> {loads[seg + 1]:g}"
        run = [idx[0]]
        for a, b in zip(idx, idx[1:]):
            if (a, b) in skip:
                ax.plot([number(states[k][xkey]) for k in run], [number(states[k]["reaction"]) for k in run], ".-",
                        color=colors[seg % len(colors)], ms=3, label=label)
                label, run = None, [b]
            else:
                run.append(b)
        ax.plot([number(states[k][xkey]) for k in run], [number(states[k]["reaction"]) for k in run], ".-",
                color=colors[seg % len(colors)], ms=3, label=label)
    for n, J in enumerate(jumps):
        a, b = states[J["state_before"]], states[J["state_after"]]
        xs, ys = [number(a[xkey]), number(b[xkey])], [number(a["reaction"]), number(b["reaction"])]
        ax.plot(xs, ys, "--", color="0.4", lw=1)
        ax.plot(xs, ys, "o", color="red", ms=5, mfc="none", label="jump" if n == 0 else None)
        ax.annotate(f"t = {J['load_after']:.6g}", (xs[1], ys[1]), fontsize=7, xytext=(4, -10),
                    textcoords="offset points")
    bad = [s for s in states if not s.get("certified") or s.get("type") == "saddle"]
    if bad:
        ax.plot([number(s[xkey]) for s in bad], [number(s["reaction"]) for s in bad], "kx", ms=7,
                label="saddle or not certified")
    ax.set_xlabel(xlabel)
    ax.set_ylabel("total normal reaction of $\\Gamma_3$")
    ax.grid(alpha=0.3)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[1])
    ap.add_argument("json", help="path.json written by hemicontact path")
    ap.add_argument("--out", help="PNG to write (default: path.png next to the JSON)")
    ap.add_argument("--title", default="", help="name shown in the title (e.g. the scene name)")
    args = ap.parse_args()
    try:
        data = read(args.json)
    except ValueError as e:
        print(f"plot_path.py: {e}", file=sys.stderr)
        return 1
    if not data["states"]:
        print(f"plot_path.py: {args.json}: no state to draw", file=sys.stderr)
        return 1
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("plot_path.py: matplotlib is missing (Debian: apt-get install python3-matplotlib)", file=sys.stderr)
        return 2
    fig, (ax_t, ax_u) = plt.subplots(1, 2, figsize=(12, 5))
    draw(ax_t, data, "load", "load factor t")
    draw(ax_u, data, "mean_u_nu", "mean $u_\\nu$ over $\\Gamma_3$")
    ax_t.legend(fontsize=7, loc="best")
    n_jumps = len(data["jumps"])
    certified = data.get("certified_states", "?")
    head = (args.title + ": " if args.title else "") + f"load path, {len(data['states'])} states ({certified} certified), "
    head += f"{n_jumps} jump(s)" + ("" if data.get("complete") else " — stopped early: " + data.get("failure", ""))
    fig.suptitle(head, fontsize=10)
    fig.tight_layout()
    return save_figure(fig, args.out, args.json, "path.png", "plot_path.py", dpi=120)


if __name__ == "__main__":
    sys.exit(main())
