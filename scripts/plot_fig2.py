#!/usr/bin/python3
"""Draw a solve's results in the manner of the paper's Fig. 2 (Sofonea, Han, Barboteu 2017).

Usage:
    /usr/bin/python3 scripts/plot_fig2.py DIR [--magnification M] [--title NAME] [--out PNG]

DIR is the output directory of `hemicontact solve`; the script reads DIR/solution.vtu (the petsc
engine's slabs: the pieces of DIR/solution.pvtu) (ASCII VTK
XML: points, triangles, point data "displacement", "gamma3", "status_normal",
"status_tangential", "xi", "sigma_nu", "sigma_tau", "lambda") and, when present, DIR/gamma3.csv
or the per-rank DIR/gamma3_rank<r>.csv (the Gamma3 nodes in order along Gamma3, with their status). It writes DIR/fig2.png (or --out):

  left:  the deformed mesh x + M u. M defaults to the 1-2-5 number nearest to the one that makes
         the largest displacement 10% of the body's size; it is printed in the title. Gamma3 nodes
         are coloured by normal status (separated / normal compliance / contact u_nu = g) and
         shaped by tangential status (stick / slip+ / slip-). On a bottom edge Gamma3 the layer's
         surface and the rigid foundation u_nu = g (magnified alike) are drawn.
  right: the interface forces along Gamma3 against x: xi_nu (the layer's reaction), sigma_nu,
         sigma_tau and the friction bound lambda = F_b(u_nu).

2-D only. Only the Python standard library and matplotlib (Debian: python3-matplotlib) are used.
Exit codes: 0 written, 1 bad input, 2 matplotlib missing.
"""

import argparse
import math
import os
import struct
import sys
import zlib
import xml.etree.ElementTree as ET

from plotutil import pvtu_pieces, read_gamma3_csv, save_atomically  # noqa: E402  (scripts/plotutil.py)

NORMAL = ["separated", "compliance", "contact"]  # status_normal codes 0, 1, 2
TANGENTIAL = ["stick", "slip+", "slip-", "slip"]  # status_tangential codes 0..3
NORMAL_STYLE = {"separated": ("tab:gray", "separated"),
                "compliance": ("tab:orange", r"normal compliance ($u_\nu < g$)"),
                "contact": ("tab:red", r"contact ($u_\nu = g$)")}
TANGENTIAL_STYLE = {"stick": ("o", "stick"), "slip+": (">", "slip+"), "slip-": ("<", "slip−"),
                    "slip": ("^", "slip")}


class InputError(Exception):
    pass


def read_vtu(path):
    """Points (N x 3), triangles, and the point data arrays (lists of tuples or numbers) of a .vtu
    written by hemicontact: ASCII, or binary with the arrays in a raw appended block (VTK's layout
    for header_type UInt64), zlib-compressed when the file names vtkZLibDataCompressor."""
    try:
        with open(path, "rb") as f:
            data = f.read()
    except OSError as e:
        raise InputError(f"cannot read {path}: {e}")
    # The appended block may hold any bytes: the XML is what comes before it.
    at = data.find(b'<AppendedData encoding="raw">')
    block = b""
    if at >= 0:
        block = data[data.index(b"_", at) + 1:]
        data = data[:at] + b"</VTKFile>\n"
    try:
        root = ET.fromstring(data)
    except ET.ParseError as e:
        raise InputError(f"cannot read {path}: {e}")
    compressed = root.get("compressor") == "vtkZLibDataCompressor"
    piece = root.find("./UnstructuredGrid/Piece")
    if piece is None:
        raise InputError(f"{path}: not a VTK UnstructuredGrid file")
    codes = {"Float64": "d", "Float32": "f", "Int64": "q", "Int32": "i", "UInt8": "B"}

    def appended(el):
        offset = int(el.get("offset"))
        if compressed:
            nblocks, _, _ = struct.unpack_from("<3Q", block, offset)
            sizes = struct.unpack_from(f"<{nblocks}Q", block, offset + 24)
            pos, raw = offset + 24 + 8 * nblocks, b""
            for size in sizes:
                raw += zlib.decompress(block[pos:pos + size])
                pos += size
        else:
            (nbytes,) = struct.unpack_from("<Q", block, offset)
            raw = block[offset + 8:offset + 8 + nbytes]
        code = codes[el.get("type")]
        return list(struct.unpack(f"<{len(raw) // struct.calcsize(code)}{code}", raw))

    def array(el):
        fmt = el.get("format", "ascii")
        if fmt == "appended":
            vals = appended(el)
        elif fmt == "ascii":
            kind = int if el.get("type", "").startswith(("Int", "UInt")) else float
            vals = [kind(t) for t in (el.text or "").split()]
        else:
            raise InputError(f"{path}: DataArray {el.get('Name')} has format {fmt}")
        nc = int(el.get("NumberOfComponents", "1"))
        return vals if nc == 1 else [tuple(vals[i:i + nc]) for i in range(0, len(vals), nc)]

    point_data = {el.get("Name"): array(el) for el in piece.findall("./PointData/DataArray")}
    pts_el = piece.find("./Points/DataArray")
    cells = {el.get("Name"): array(el) for el in piece.findall("./Cells/DataArray")}
    if pts_el is None or not {"connectivity", "offsets", "types"}.issubset(cells):
        raise InputError(f"{path}: points or cells missing")
    points = array(pts_el)
    if any(t != 5 for t in cells["types"]):
        raise InputError(f"{path}: only 2-D triangle meshes (VTK_TRIANGLE) are drawn")
    conn, tris = cells["connectivity"], []
    start = 0
    for end in cells["offsets"]:
        tris.append(conn[start:end])
        start = end
    for name in ("displacement", "gamma3", "status_normal", "status_tangential", "xi", "sigma_nu", "sigma_tau",
                 "lambda"):
        if name not in point_data:
            raise InputError(f"{path}: point data '{name}' missing")
    return points, tris, point_data


def read_pieces(pvtu):
    """read_vtu over the pieces of the petsc engine's .pvtu, joined into one mesh (a node on two
    slabs appears twice, with the same values: harmless in a picture)."""
    try:
        paths = pvtu_pieces(pvtu)
    except (OSError, ET.ParseError) as e:
        raise InputError(f"cannot read {pvtu}: {e}")
    if not paths:
        raise InputError(f"{pvtu}: no piece")
    points, tris, pd = [], [], {}
    for path in paths:
        p, t, d = read_vtu(path)
        tris += [[v + len(points) for v in tri] for tri in t]
        points += p
        for name, vals in d.items():
            pd.setdefault(name, []).extend(vals)
    return points, tris, pd


def gamma3_rows(dir_, points, pd, by_place=False):
    """Gamma3 nodes in order along Gamma3: from gamma3.csv (or its per-rank pieces) when present,
    else the VTU sorted by x. by_place: the points are joined pieces, whose indices are not the
    CSV's node numbers, so a row's point is found by its coordinates (the same doubles in both)."""
    rows = []
    csv_rows = read_gamma3_csv(dir_)
    at = {(p[0], p[1]): i for i, p in enumerate(points)} if by_place else None
    if csv_rows:
        for r in csv_rows:
            if at is not None:
                r["node"] = at[(float(r["x"]), float(r["y"]))]
            normal, _, tangential = r["status"].partition("/")
            rows.append({"node": int(r["node"]), "x": float(r["x"]), "y": float(r["y"]), "g": float(r["g"]),
                         "xi": float(r["xi"]), "sigma_nu": float(r["sigma_nu"]),
                         "sigma_tau": float(r["sigma_tau"]), "lambda": float(r["lambda"]), "normal": normal,
                         "tangential": tangential})
        return rows
    for i, on in enumerate(pd["gamma3"]):
        if on:
            rows.append({"node": i, "x": points[i][0], "y": points[i][1], "g": math.nan, "xi": pd["xi"][i],
                         "sigma_nu": pd["sigma_nu"][i], "sigma_tau": pd["sigma_tau"][i], "lambda": pd["lambda"][i],
                         "normal": NORMAL[pd["status_normal"][i]],
                         "tangential": TANGENTIAL[pd["status_tangential"][i]]})
    # Joined pieces hold a node on two slabs twice: once each.
    return sorted({(r["x"], r["y"]): r for r in rows}.values(), key=lambda r: (r["x"], r["y"]))


def nice(x):
    """The 1-2-5 number nearest to x in log scale."""
    if not (x > 0 and math.isfinite(x)):
        return 1.0
    e = math.floor(math.log10(x))
    return min((m * 10.0 ** k for k in (e - 1, e, e + 1) for m in (1, 2, 5)), key=lambda c: abs(math.log(c / x)))


def fmt_mag(m):
    return f"{m:g}" if 1e-3 <= m < 1e5 else f"{m:.0e}".replace("e+0", "e").replace("e+", "e")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[1])
    ap.add_argument("dir", help="output directory of hemicontact solve")
    ap.add_argument("--magnification", type=float, help="displacement magnification M (default: auto, see above)")
    ap.add_argument("--title", default="", help="name shown in the title (e.g. the scene name)")
    ap.add_argument("--out", help="PNG to write (default: DIR/fig2.png)")
    args = ap.parse_args()
    if args.magnification is not None and not (args.magnification > 0 and math.isfinite(args.magnification)):
        print(f"plot_fig2: --magnification must be a positive number, got {args.magnification}", file=sys.stderr)
        return 1

    vtu = os.path.join(args.dir, "solution.vtu")
    pvtu = os.path.join(args.dir, "solution.pvtu")
    if not os.path.exists(vtu) and not os.path.exists(pvtu):
        print(f"plot_fig2: {vtu} not found (was the solve run with output.vtu = false?)", file=sys.stderr)
        return 1
    try:
        pieces = not os.path.exists(vtu)
        points, tris, pd = read_pieces(pvtu) if pieces else read_vtu(vtu)
        g3 = gamma3_rows(args.dir, points, pd, by_place=pieces)
    except (InputError, OSError, ValueError, KeyError, IndexError) as e:
        print(f"plot_fig2: {e}", file=sys.stderr)
        return 1

    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        from matplotlib.lines import Line2D
        from matplotlib.tri import Triangulation
    except ImportError:
        print(f"plot_fig2: matplotlib is not available for {sys.executable} "
              "(Debian: apt-get install python3-matplotlib)", file=sys.stderr)
        return 2

    u = pd["displacement"]
    xs = [p[0] for p in points]
    ys = [p[1] for p in points]
    size = max(max(xs) - min(xs), max(ys) - min(ys))
    umax = max(math.hypot(d[0], d[1]) for d in u)
    m = args.magnification if args.magnification is not None else nice(0.1 * size / umax if umax > 0 else 1.0)
    X = [x + m * d[0] for x, d in zip(xs, u)]
    Y = [y + m * d[1] for y, d in zip(ys, u)]

    fig = plt.figure(figsize=(14.0, 7.2))
    grid = fig.add_gridspec(3, 2, width_ratios=[1.0, 1.05], hspace=0.12, wspace=0.18)
    ax = fig.add_subplot(grid[:, 0])
    fx = [fig.add_subplot(grid[0, 1])]
    fx += [fig.add_subplot(grid[i, 1], sharex=fx[0]) for i in (1, 2)]

    # ---- left: deformed mesh and Gamma3 statuses
    ax.triplot(Triangulation(X, Y, tris), color="0.45", linewidth=0.35)
    # The foundation is drawn when Gamma3 is a bottom edge and, magnified, it stays near the body
    # (with the printed loads M ~ 1e4 would put it thousands of body sizes below).
    bottom = bool(g3) and all(abs(r["y"] - min(ys)) <= 1e-12 * size for r in g3)
    foundation = bottom and all(math.isfinite(r["g"]) and m * r["g"] <= 0.5 * size for r in g3)
    if foundation:
        # On a bottom edge nu = (0, -1): the layer's surface is y0, the foundation y0 - g (magnified alike).
        gx = [r["x"] for r in g3]
        ax.plot(gx, [r["y"] for r in g3], ":", color="tab:green", linewidth=1.0)
        ax.plot(gx, [r["y"] - m * r["g"] for r in g3], "-", color="k", linewidth=1.6)
    size_pt = min(6.5, max(2.5, 260.0 / max(1, len(g3))))  # neighbours must not overlap
    for r in g3:
        color = NORMAL_STYLE.get(r["normal"], ("tab:blue", r["normal"]))[0]
        marker = TANGENTIAL_STYLE.get(r["tangential"], ("s", r["tangential"]))[0]
        ax.plot(X[r["node"]], Y[r["node"]], marker, color=color, markersize=size_pt, markeredgecolor="k",
                markeredgewidth=0.4, zorder=4)
    handles = []
    for key in NORMAL:
        if any(r["normal"] == key for r in g3):
            handles.append(Line2D([], [], linestyle="", marker="s", markersize=8, color=NORMAL_STYLE[key][0],
                                  label=NORMAL_STYLE[key][1]))
    for key in TANGENTIAL:
        if any(r["tangential"] == key for r in g3):
            handles.append(Line2D([], [], linestyle="", marker=TANGENTIAL_STYLE[key][0], markersize=7, color="0.3",
                                  label=TANGENTIAL_STYLE[key][1]))
    if foundation:
        handles.append(Line2D([], [], linestyle=":", color="tab:green", label="layer surface (reference)"))
        handles.append(Line2D([], [], linestyle="-", color="k", label=r"rigid foundation $u_\nu = g$"))
    fig.legend(handles=handles, loc="lower left", bbox_to_anchor=(0.06, 0.005), ncol=3, fontsize=9, frameon=False)
    ax.set_aspect("equal")
    ax.set_xlabel(r"$x_1 + M u_1$")
    ax.set_ylabel(r"$x_2 + M u_2$")
    ax.set_title(f"deformed mesh x + M u, magnification M = {fmt_mag(m)} (max |u| = {umax:.3g})", fontsize=11)

    # ---- right: interface forces along Gamma3, one panel each: sigma_nu (dominated by the obstacle's
    # reaction where u_nu = g) would flatten xi_nu (the layer's reaction, <= max c) in a shared one.
    gx = [r["x"] for r in g3]
    ms = 4 if len(g3) <= 80 else 0
    panels = [[("sigma_nu", r"$\sigma_\nu$", "tab:blue", "s", 1)],
              [("xi", r"$\xi_\nu \in \partial j_\nu(u_\nu)$ (layer)", "tab:orange", "o", 1)],
              [("sigma_tau", r"$\sigma_\tau$", "tab:purple", "^", 1),
               ("lambda", r"$\pm\lambda = \pm F_b(u_\nu)$", "tab:green", "", 1),
               ("lambda", None, "tab:green", "", -1)]]
    for bx, panel in zip(fx, panels):
        for key, label, color, marker, sign in panel:
            bx.plot(gx, [sign * r[key] for r in g3], "-" if marker else "--", marker=marker or None, markersize=ms,
                    color=color, linewidth=1.3, label=label)
        bx.axhline(0, color="0.6", linewidth=0.7)
        bx.grid(True, linestyle=":", linewidth=0.6)
        bx.legend(fontsize=9, loc="best")
    for bx, ylabel in zip(fx, [r"$\sigma_\nu$ (normal stress)", r"$\xi_\nu$ (layer reaction)",
                               r"$\sigma_\tau$, $\pm\lambda$ (friction)"]):
        bx.set_ylabel(ylabel, fontsize=9)
    for bx in fx[:2]:
        bx.tick_params(labelbottom=False)
    fx[0].set_title(r"interface forces on $\Gamma_3$ (force per unit length)", fontsize=11)
    fx[2].set_xlabel(r"$x_1$ along $\Gamma_3$")

    name = args.title or os.path.basename(os.path.normpath(args.dir))
    counts = {}
    for r in g3:
        key = f"{r['normal']}/{r['tangential']}"
        counts[key] = counts.get(key, 0) + 1
    # Only the scaled scene reproduces the paper's Fig. 2; the printed loads are too small for it
    # (docs/model.md section 5, problems/README.md), and other scenes are merely drawn in its manner.
    note = {"sofonea2017-fig2": " (the paper's Fig. 2: loads x 1e6)",
            "sofonea2017-printed": " (the paper's data as printed: not its Fig. 2, see problems/README.md)"}.get(name, "")
    fig.suptitle(f"{name}: deformed mesh and interface forces{note}\n{len(g3)} Γ3 nodes: "
                 + ", ".join(f"{v} {k}" for k, v in sorted(counts.items())), fontsize=12)
    fig.subplots_adjust(left=0.06, right=0.98, top=0.87, bottom=0.17)
    out = args.out or os.path.join(args.dir, "fig2.png")
    try:
        save_atomically(fig, out, dpi=120)
    except OSError as e:
        print(f"plot_fig2: cannot write {out}: {e}", file=sys.stderr)
        return 1
    print(f"wrote {out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
