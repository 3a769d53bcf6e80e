"""Helpers shared by the plotting scripts (imported from the scripts' own folder)."""
import csv
import glob
import os
import re
import sys


def save_atomically(fig, out, **kwargs):
    """Draw into a temporary beside `out` (the name hemicontact uses, ".NAME.partial") and rename
    it into place, so an interrupted run never leaves half a picture under the final name."""
    tmp = os.path.join(os.path.dirname(out) or ".", "." + os.path.basename(out) + ".partial")
    # Created exclusively and never through a link, as hemicontact's own temporaries are: a name
    # planted there fails the picture instead of being written through, and is left alone.
    fd = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL | os.O_NOFOLLOW | os.O_CLOEXEC, 0o666)
    try:
        with os.fdopen(fd, "wb") as f:
            fig.savefig(f, format="png", **kwargs)
        os.replace(tmp, out)
    except BaseException:
        if os.path.lexists(tmp):
            os.remove(tmp)
        raise


def save_figure(fig, out, beside, name, program, **kwargs):
    """The scripts' one ending: `fig` saved atomically to `out`, or to `name` in the folder of the
    input file `beside` when no --out was given; "wrote OUT" on stdout. @return the exit code: 0,
    or 1 with the reason on stderr when the file cannot be written."""
    out = out or os.path.join(os.path.dirname(os.path.abspath(beside)), name)
    try:
        save_atomically(fig, out, **kwargs)
    except OSError as e:
        print(f"{program}: cannot write {out}: {e}", file=sys.stderr)
        return 1
    print(f"wrote {out}")
    return 0


def gamma3_csv_paths(dir_):
    """The Gamma3 CSVs of a solve: DIR/gamma3.csv, else the petsc engine's per-rank pieces
    gamma3_rank<r>.csv (each holds its rank's owned nodes), in rank order; [] when there is none."""
    one = os.path.join(dir_, "gamma3.csv")
    if os.path.exists(one):
        return [one]
    pieces = glob.glob(os.path.join(dir_, "gamma3_rank*.csv"))
    rank = lambda p: int(re.search(r"gamma3_rank(\d+)\.csv$", p).group(1))
    return sorted((p for p in pieces if re.search(r"gamma3_rank\d+\.csv$", p)), key=rank)


def read_gamma3_csv(dir_):
    """The rows (dicts of strings) of a solve's Gamma3 CSVs (gamma3_csv_paths) in the order of the
    whole list (their "index" column); [] when there is none."""
    rows = []
    for path in gamma3_csv_paths(dir_):
        with open(path, newline="") as f:
            rows.extend(csv.DictReader(f))
    return sorted(rows, key=lambda r: int(r["index"]))


def pvtu_pieces(path):
    """The piece files (paths) a .pvtu lists."""
    import xml.etree.ElementTree as ET
    root = ET.parse(path).getroot()
    return [os.path.join(os.path.dirname(path), p.get("Source")) for p in root.iter("Piece")]
