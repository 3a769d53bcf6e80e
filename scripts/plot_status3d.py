#!/usr/bin/python3
"""Draw the contact status map of a 3-D solve: a view of the Gamma3 face with the slip directions.

Usage:
    /usr/bin/python3 scripts/plot_status3d.py DIR [--title NAME] [--out PNG] [--magnification M]

DIR is the output directory of `hemicontact solve` on a 3-D mesh; the script reads DIR/gamma3.csv
(the petsc engine's per-rank slabs: every DIR/gamma3_rank<r>.csv) (columns x, y, z, u_nu, u_tau, sigma_nu, sigma_tau, lambda, status and the 3-D columns
slip_dir_x, slip_dir_y, slip_dir_z, slip_angle_deg). It writes DIR/status3d.png (or --out):

  left:  the Gamma3 nodes seen along the face's normal axis (for a bottom face z = 0: the top
         view, x to the right, y up), coloured by normal status (separated / normal compliance /
         contact u_nu = g), round when sticking; on slipping nodes an arrow of fixed length shows
         the unit slip direction u_tau/|u_tau| projected on the view plane.
  right: the same nodes coloured by u_nu (the layer's compression), with the gap g as the top of
         the colour scale.

The view axis is the coordinate in which the Gamma3 nodes have the smallest extent (the normal of a
flat face). --magnification is accepted for the same command line as plot_fig2.py and not used:
the view is of the undeformed face. Only the Python standard library and matplotlib (Debian:
python3-matplotlib) are used. Exit codes: 0 written, 1 bad input, 2 matplotlib missing.
"""

import argparse
import csv
import math
import os
import sys

from plotutil import gamma3_csv_paths, save_atomically  # noqa: E402  (scripts/plotutil.py)

NORMAL_STYLE = {"separated": ("tab:gray", "separated"),
                "compliance": ("tab:orange", r"normal compliance ($u_\nu < g$)"),
                "contact": ("tab:red", r"contact ($u_\nu = g$)")}


def read_rows(paths):
    rows = []
    for path in paths:
        with open(path, newline="") as f:
            reader = csv.DictReader(f)
            need = {"x", "y", "z", "u_nu", "g", "status", "slip_dir_x", "slip_dir_y", "slip_dir_z"}
            missing = need - set(reader.fieldnames or [])
            if missing:
                raise ValueError(f"{path}: columns {sorted(missing)} missing (not a 3-D solve?)")
            for r in reader:
                normal, _, tangential = r["status"].partition("/")
                rows.append({"p": (float(r["x"]), float(r["y"]), float(r["z"])), "u_nu": float(r["u_nu"]),
                             "g": float(r["g"]), "normal": normal, "tangential": tangential,
                             "dir": (float(r["slip_dir_x"]), float(r["slip_dir_y"]), float(r["slip_dir_z"]))})
    if not rows:
        raise ValueError(f"{', '.join(paths)}: no Gamma3 node")
    return rows


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[1])
    ap.add_argument("dir", help="output directory of hemicontact solve (3-D mesh)")
    ap.add_argument("--title", default="", help="name shown in the title (e.g. the scene name)")
    ap.add_argument("--out", help="PNG to write (default: DIR/status3d.png)")
    ap.add_argument("--magnification", type=float, help="accepted, not used (see above)")
    args = ap.parse_args()
    paths = gamma3_csv_paths(args.dir)
    if not paths:
        print(f"plot_status3d: {os.path.join(args.dir, 'gamma3.csv')} not found (was the solve run with "
              "output.csv = false?)", file=sys.stderr)
        return 1
    try:
        rows = read_rows(paths)
    except (OSError, ValueError, KeyError) as e:
        print(f"plot_status3d: {e}", file=sys.stderr)
        return 1
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        from matplotlib.lines import Line2D
    except ImportError:
        print(f"plot_status3d: matplotlib is not available for {sys.executable} "
              "(Debian: apt-get install python3-matplotlib)", file=sys.stderr)
        return 2

    extent = [max(r["p"][a] for r in rows) - min(r["p"][a] for r in rows) for a in range(3)]
    normal_axis = min(range(3), key=lambda a: extent[a])
    a0, a1 = [a for a in range(3) if a != normal_axis]
    names = "xyz"
    X = [r["p"][a0] for r in rows]
    Y = [r["p"][a1] for r in rows]
    size = max(extent[a0], extent[a1]) or 1.0
    n_side = max(2.0, math.sqrt(len(rows)))
    spacing = size / (n_side - 1)
    marker_pt = min(9.0, max(2.0, 300.0 / n_side))

    fig, (ax, bx) = plt.subplots(1, 2, figsize=(14.0, 6.8))
    for r, x, y in zip(rows, X, Y):
        color = NORMAL_STYLE.get(r["normal"], ("tab:blue", r["normal"]))[0]
        marker = "o" if r["tangential"] == "stick" else "s"
        ax.plot(x, y, marker, color=color, markersize=marker_pt, markeredgecolor="k", markeredgewidth=0.3,
                alpha=0.85, zorder=2)
    slip = [(x, y, r["dir"][a0], r["dir"][a1]) for r, x, y in zip(rows, X, Y) if r["tangential"] == "slip"]
    if slip:
        ax.quiver([s[0] for s in slip], [s[1] for s in slip], [s[2] for s in slip], [s[3] for s in slip],
                  angles="xy", scale_units="xy", scale=1.0 / (0.8 * spacing), width=0.0025, color="k", zorder=3)
    counts = {}
    for r in rows:
        key = r["normal"] + "/" + r["tangential"]
        counts[key] = counts.get(key, 0) + 1
    handles = [Line2D([], [], linestyle="", marker="s", markersize=8, color=NORMAL_STYLE[k][0], label=NORMAL_STYLE[k][1])
               for k in NORMAL_STYLE if any(r["normal"] == k for r in rows)]
    handles.append(Line2D([], [], linestyle="", marker="o", markersize=8, color="0.5", label="stick (round)"))
    handles.append(Line2D([], [], linestyle="", marker=r"$\rightarrow$", markersize=10, color="k",
                          label=r"slip direction $u_\tau/|u_\tau|$"))
    ax.legend(handles=handles, loc="upper center", bbox_to_anchor=(0.5, -0.08), ncol=2, fontsize=9, frameon=False)
    ax.set_aspect("equal")
    ax.set_xlabel(names[a0])
    ax.set_ylabel(names[a1])
    ax.set_title("statuses: " + ", ".join(f"{k} {v}" for k, v in sorted(counts.items())), fontsize=9)

    gmax = max((r["g"] for r in rows if math.isfinite(r["g"])), default=max(r["u_nu"] for r in rows))
    sc = bx.scatter(X, Y, c=[r["u_nu"] for r in rows], cmap="viridis", vmin=min(0.0, min(r["u_nu"] for r in rows)),
                    vmax=gmax, s=marker_pt ** 2, marker="s")
    fig.colorbar(sc, ax=bx, label=r"$u_\nu$ (top of the scale: $g$)")
    bx.set_aspect("equal")
    bx.set_xlabel(names[a0])
    bx.set_ylabel(names[a1])
    bx.set_title(r"normal displacement $u_\nu$ on $\Gamma_3$", fontsize=10)
    fig.suptitle(f"{args.title + ': ' if args.title else ''}Gamma3 seen along {names[normal_axis]} "
                 f"({len(rows)} nodes)", fontsize=11)
    out = args.out or os.path.join(args.dir, "status3d.png")
    save_atomically(fig, out, dpi=110, bbox_inches="tight")
    print(f"plot_status3d: wrote {out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
