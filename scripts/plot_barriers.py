#!/usr/bin/python3
"""Draw the energy profiles of the barriers found by `hemicontact minima --barriers`.

Usage:
    /usr/bin/python3 scripts/plot_barriers.py DIR/minima.json [--out PNG] [--title NAME]

Reads minima.json's "barriers" (each pair a, b with "from_a" and "from_b": the energy "profile"
along the converged string, image by image, "energy_saddle", "verified", "neighbours") and draws
each pair's profile against the image's position along the string (0 at minimum a, 1 at b); a
path's highest verified saddle is marked with a red star, an unverified highest point with a black
x. Pairs that are not neighbours (the path runs through intermediate minima) are drawn dotted.
--out defaults to barriers.png next to the JSON.

Only the Python standard library and matplotlib (Debian: python3-matplotlib) are used.
Exit codes: 0 written, 1 bad input, 2 matplotlib missing.
"""

import argparse
import json
import sys

from plotutil import save_figure  # noqa: E402  (scripts/plotutil.py)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[1])
    ap.add_argument("json", help="minima.json written by hemicontact minima --barriers")
    ap.add_argument("--out", help="PNG to write (default: barriers.png next to the JSON)")
    ap.add_argument("--title", default="", help="name shown in the title")
    args = ap.parse_args()
    try:
        with open(args.json) as f:
            bars = json.load(f).get("barriers")
    except (OSError, ValueError) as e:
        print(f"plot_barriers.py: cannot read {args.json}: {e}", file=sys.stderr)
        return 1
    if not isinstance(bars, list) or not bars:
        print(f"plot_barriers.py: {args.json}: no barriers (run minima --barriers)", file=sys.stderr)
        return 1
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("plot_barriers.py: matplotlib is missing (Debian: apt-get install python3-matplotlib)", file=sys.stderr)
        return 2
    fig, ax = plt.subplots(figsize=(9, 5.5))
    for n, b in enumerate(bars):
        for side, ls in (("from_a", "-"), ("from_b", "--")):
            s = b[side]
            prof = [float("nan") if v is None else v for v in s["profile"]]
            if not prof:
                continue
            xs = [i / (len(prof) - 1) for i in range(len(prof))]
            if side == "from_b":
                xs = [1 - x for x in xs]  # b's string runs from b to a
                if s["lambda"] == b["from_a"]["lambda"]:
                    continue  # the same energy: one string serves both sides
            style = ls if s["neighbours"] else ":"
            label = f"{b['a']}-{b['b']}" + ("" if side == "from_a" else f" (lambda of {b['b']})")
            ax.plot(xs, prof, style, color=f"C{n % 10}", label=label)
            top = max(range(len(prof)), key=lambda i: prof[i])
            mark = "r*" if s["verified"] else "kx"
            ax.plot(xs[top], s["energy_saddle"] if s["verified"] else prof[top], mark, ms=10)
    ax.set_xlabel("position along the string (0: minimum a, 1: minimum b)")
    ax.set_ylabel("energy $\\Pi$")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    ax.set_title((args.title + ": " if args.title else "") + "minimum-energy paths (red star: verified saddle)",
                 fontsize=10)
    fig.tight_layout()
    return save_figure(fig, args.out, args.json, "barriers.png", "plot_barriers.py", dpi=120)


if __name__ == "__main__":
    sys.exit(main())
