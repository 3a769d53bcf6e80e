#!/usr/bin/env python3
"""The method-choice benchmark (solver.formulation = auto, src/solver/method_choice.cpp): for each
scene shape, every method of the project as a whole `hemicontact solve` process, and which one auto
took.

Methods, each its own process (wall time and peak RSS from /usr/bin/time -v; the petsc engine is
exec'd by `hemicontact solve` into build/hemicontact-mpi, one process, and measured the same way):
  auto        the default: nothing set
  condensed   --set solver.formulation=condensed (linear materials only)
  full+newton --set solver.formulation=full --backend newton
  full+ipopt  --set solver.formulation=full --backend ipopt
  full+ssn    --set solver.formulation=full --backend ssn (the full space's exact solver, CHOLMOD)
  petsc       --set solver.engine=petsc (its own default backend, ssn)
Scenes: fig2 (problems/sofonea2017-fig2.json) at n = 64..1024, fig2's conditions on strips of
aspect 10..1000 (x = [0, A], 2A x 2 cells), the 3D box (problems/sofonea2017-3d.json) at
n = 8..32, a Gmsh plate (the 3D scene's laws on tests/data/make_strip_msh.py's plate, 2 x 2 x 0.5,
unstructured node numbering, read from an MSH file) at 16x16x4..48x48x12 cubes, the shipped 2D
Hencky scene (problems/sofonea2017-fig2-hencky.json) and the 3D scene with the same Hencky law, and
random scenes (hemicontact_random_study's seeds 1..--random, the largest --random-keep of them by
Gamma3 nodes: each row runs the exact command the study records).
Each row: wall time (CPU seconds, user + system, in parentheses: less sensitive to a loaded
machine) and peak memory of every method, the fastest, what auto chose, auto's time over the
fastest's, whether each run was certified, and the largest relative energy difference to auto's.
A row's methods take turns (one process of each per round, best of --repeats, --min-time), so a
drift of the machine's speed reaches all of them alike. A run past --timeout seconds is killed and
shown as "> T". Writes DIR/method_choice.md and .json.

  python3 bench/method_choice.py --build build --repeats 2 --out /tmp/method-choice
  python3 bench/method_choice.py --build build --only strip --out /tmp/mc   # one family

Timings on a shared 2-core machine are noisy: run the committed table on an idle machine.
"""
import argparse
import csv
import json
import os
import re
import shlex
import signal
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
FIG2 = os.path.join(ROOT, "problems", "sofonea2017-fig2.json")
BOX = os.path.join(ROOT, "problems", "sofonea2017-3d.json")
HENCKY = os.path.join(ROOT, "problems", "sofonea2017-fig2-hencky.json")

METHODS = {
    "auto": [],
    "condensed": ["--set", "solver.formulation=\"condensed\""],
    "full+newton": ["--set", "solver.formulation=\"full\"", "--backend", "newton"],
    "full+ipopt": ["--set", "solver.formulation=\"full\"", "--backend", "ipopt"],
    "full+ssn": ["--set", "solver.formulation=\"full\"", "--backend", "ssn"],
    "petsc": ["--set", "solver.engine=\"petsc\""],
}


def sets(*pairs):
    out = []
    for p in pairs:
        out += ["--set", p]
    return out


HENCKY_3D = ["--set", "material.model=\"hencky\"", "--set", "material.shear_ratio=0.5", "--set", "material.eps_ref=1"]


def gmsh_plate(workdir, cubes):
    """The 3D scene's laws on a Gmsh plate of cubes = (nx, ny, nz): the scene file's path."""
    msh = os.path.join(workdir, "plate-%dx%dx%d.msh" % cubes)
    with open(msh, "w") as f:
        subprocess.run([sys.executable, os.path.join(ROOT, "tests", "data", "make_strip_msh.py"), "3d"] +
                       [str(c) for c in cubes], stdout=f, check=True)
    with open(BOX) as f:
        scene = json.load(f)
    scene["mesh"] = {"type": "gmsh", "file": msh}
    # Clamped on top, pushed on the sides' upper halves, in contact below (fig2's conditions).
    scene["boundary"] = {
        "gamma1": [{"physical": "clamped"}],
        "gamma2": [{"side": "left", "from": 0.25, "to": 0.5, "traction": [8000.0, 0.0, 0.0]},
                   {"side": "right", "from": 0.25, "to": 0.5, "traction": [-8000.0, 0.0, 0.0]}],
        "gamma3": [{"physical": "contact"}]}
    path = msh[:-4] + ".json"
    with open(path, "w") as f:
        json.dump(scene, f, indent=1)
    return path


def random_scenes(build, workdir, seeds, keep):
    """The random study's recorded commands for seeds 1..@p seeds, the @p keep largest by Gamma3 nodes:
    (name, scene file, overrides)."""
    out = os.path.join(workdir, "random")
    exe = os.path.join(build, "bench", "hemicontact_random_study")
    subprocess.run([exe, "--seeds", str(seeds), "--out", out], capture_output=True, text=True, check=True)
    with open(os.path.join(out, "random-default.csv")) as f:
        rows = list(csv.DictReader(f))
    picked = []
    for r in rows:
        words = shlex.split(r["command"])
        if words[:2] != ["hemicontact", "solve"]:
            raise SystemExit("method_choice.py: unexpected random-study command: " + r["command"])
        scene, overrides = os.path.join(ROOT, words[2]), words[3:]
        nx = int(next(o.split("=")[1] for o in overrides if o.startswith("mesh.nx=")))
        picked.append((nx, int(r["seed"]), scene, overrides))
    picked.sort(reverse=True)
    return [(f"random seed {seed} (nx={nx})", scene, ov) for nx, seed, scene, ov in picked[:keep]]


def scenes(only, build, workdir, random_seeds, random_keep):
    """(family, name, scene file, overrides, linear material)."""
    rows = []
    for n in (64, 128, 256, 512, 1024):
        rows.append(("fig2", f"fig2 n={n}", FIG2, sets(f"mesh.n={n}"), True))
    for a in (10, 30, 100, 300, 1000):
        rows.append(("strip", f"strip {a}x1", FIG2,
                     sets("mesh.n=null", f"mesh.x=[0,{a}]", f"mesh.nx={2 * a}", "mesh.ny=2"), True))
    for n in (8, 16, 24, 32):
        rows.append(("box3d", f"3D box n={n}", BOX, sets(f"mesh.n={n}"), True))
    if not only or "gmsh" in only:
        for cubes in ((16, 16, 4), (32, 32, 8), (48, 48, 12)):
            rows.append(("gmsh", "Gmsh plate %dx%dx%d" % cubes, gmsh_plate(workdir, cubes), [], True))
    for n in (64, 128):
        rows.append(("hencky", f"hencky 2D n={n}", HENCKY, sets(f"mesh.n={n}"), False))
    for n in (8, 12, 16):
        rows.append(("hencky3d", f"hencky 3D n={n}", BOX, sets(f"mesh.n={n}") + HENCKY_3D, False))
    if random_keep and (not only or "random" in only):
        for name, scene, overrides in random_scenes(build, workdir, random_seeds, random_keep):
            rows.append(("random", name, scene, overrides, True))
    return [r for r in rows if not only or r[0] in only]


REPEAT_BELOW = 2.0  # seconds: only runs this short are repeated (their noise is a larger share)
MAX_REPEATS = 60    # a cap on --min-time's repeats (60 runs of a 10 ms process: 0.6 s)


def run_interleaved(build, scene, overrides, methods, timeout, repeats, min_time=0.0):
    """Each of @p methods' best by wall time, its whole processes taken in turns (one of each
    method per round, so that a drift of the machine's speed reaches every method alike instead of
    the one measured while it lasted): @p repeats of them, and more while a method's wall times add
    up to less than @p min_time seconds (at most MAX_REPEATS; as a benchmark library's minimum time:
    the best of a 20 ms process needs more samples than that of a 2 s one); one where the first took
    REPEAT_BELOW seconds or more. {method: (seconds, CPU seconds, peak MB, report, note)}."""
    best, spent, count = {}, {m: 0.0 for m in methods}, {m: 0 for m in methods}
    todo = list(methods)
    while todo:
        for method in list(todo):
            r = run_process(build, scene, overrides, method, timeout)
            count[method] += 1
            if r[0] is None:  # timed out or failed to time: that is its result
                best[method] = r
                todo.remove(method)
                continue
            spent[method] += r[0]
            if method not in best or r[0] < best[method][0]:
                best[method] = r
            if r[0] >= REPEAT_BELOW or count[method] >= MAX_REPEATS or (
                    count[method] >= max(1, repeats) and spent[method] >= min_time):
                todo.remove(method)
    return best


def run_process(build, scene, overrides, method, timeout):
    """One whole process: (seconds, CPU seconds, peak MB, report dict or None, note)."""
    with tempfile.TemporaryDirectory() as out:
        cmd = ["/usr/bin/time", "-v", os.path.join(build, "hemicontact"), "solve", scene, "--out", out, "--force",
               "--quiet"] + overrides + METHODS[method]
        t0 = time.perf_counter()
        # Its own process group, killed whole on a timeout: killing /usr/bin/time alone left the
        # solve running, and it took a core from every later row.
        proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                                start_new_session=True)
        try:
            stdout, stderr = proc.communicate(timeout=timeout)
        except subprocess.TimeoutExpired:
            os.killpg(proc.pid, signal.SIGKILL)
            proc.communicate()
            return None, None, None, None, f"> {timeout:g} s"
        p = subprocess.CompletedProcess(cmd, proc.returncode, stdout, stderr)
        # The wall time to the millisecond (/usr/bin/time prints hundredths: too coarse for the
        # 10-40 ms solves of the small scenes); it includes /usr/bin/time's own start, ~1 ms.
        elapsed = time.perf_counter() - t0
        wall = re.search(r"Elapsed \(wall clock\) time.*: (?:(\d+):)?(\d+):([\d.]+)", p.stderr)
        rss = re.search(r"Maximum resident set size \(kbytes\): (\d+)", p.stderr)
        user = re.search(r"User time \(seconds\): ([\d.]+)", p.stderr)
        sys_ = re.search(r"System time \(seconds\): ([\d.]+)", p.stderr)
        cpu = float(user.group(1)) + float(sys_.group(1)) if user and sys_ else None
        secs = elapsed if wall else None
        mb = int(rss.group(1)) / 1024 if rss else None
        report = None
        path = os.path.join(out, "report.json")
        if os.path.exists(path):
            with open(path) as f:
                report = json.load(f)
        note = "" if p.returncode == 0 else f"exit {p.returncode}"
        return secs, cpu, mb, report, note


def measure(build, scene_rows, timeout, repeats, min_time=0.0):
    results = []
    for family, name, scene, overrides, linear in scene_rows:
        row = {"family": family, "scene": name, "runs": {}}
        methods = [m for m in METHODS if linear or m != "condensed"]
        best = run_interleaved(build, scene, overrides, methods, timeout, repeats, min_time)
        for method in methods:
            secs, cpu, mb, rep, note = best[method]
            r = {"seconds": secs, "cpu_seconds": cpu, "peak_mb": mb, "note": note}
            if rep:
                r["certified"] = bool(rep.get("certificate", {}).get("passed"))
                r["energy"] = rep.get("energy", {}).get("total") if isinstance(rep.get("energy"), dict) else rep.get("energy")
                r["formulation"] = rep.get("formulation")
                r["solved_by"] = rep.get("solved_by")
                mc = rep.get("method_choice") or {}
                ec = rep.get("engine_choice") or {}
                # solver.engine = auto may have sent the solve to the petsc engine (engine_choice).
                r["chosen"] = "petsc engine" if ec.get("engine") == "petsc" else mc.get("chosen")
                r["reason"] = mc.get("reason")
            row["runs"][method] = r
            print(f"{name:16s} {method:12s} {secs if secs is not None else '-':>8} s "
                  f"{mb if mb is not None else '-':>8} MB {note} {r.get('formulation', '')}", file=sys.stderr, flush=True)
        results.append(row)
    return results


def cell(r):
    if r.get("seconds") is None:
        return r.get("note") or "-"
    mark = "" if r.get("certified") else " (not certified)"
    secs = f"{r['seconds'] * 1000:.0f} ms" if r["seconds"] < 1 else f"{r['seconds']:.2f} s"
    return f"{secs} ({r['cpu_seconds']:.2f}), {r['peak_mb']:.0f} MB{mark}"


def ratio(runs, key):
    """auto's value over the smallest certified one's, with that method's name."""
    vals = {m: r[key] for m, r in runs.items() if r.get(key) is not None and r.get("certified")}
    auto = runs.get("auto", {}).get(key)
    if not vals or auto is None or min(vals.values()) <= 0:  # /usr/bin/time's 0.01 s resolution
        return "-"
    best = min(vals, key=vals.get)
    return f"{auto / vals[best]:.2f} ({best})"


def table(results):
    head = "| scene | " + " | ".join(METHODS) + " | auto chose | auto / fastest, wall | auto / fastest, CPU |"
    lines = [head, "|" + "---|" * (len(METHODS) + 4)]
    for row in results:
        runs = row["runs"]
        auto = runs.get("auto", {})
        chose = (auto.get("chosen") or auto.get("formulation") or "-") + (
            f" + {auto.get('solved_by')}" if auto.get("solved_by") else "")
        cells = [cell(runs[m]) if m in runs else "n/a" for m in METHODS]
        lines.append(f"| {row['scene']} | " + " | ".join(cells) +
                     f" | {chose} | {ratio(runs, 'seconds')} | {ratio(runs, 'cpu_seconds')} |")
    return "\n".join(lines) + "\n"


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--build", default=os.path.join(ROOT, "build"))
    ap.add_argument("--out", required=True)
    ap.add_argument("--only", default="",
                    help="comma-separated families: fig2,strip,box3d,gmsh,hencky,hencky3d,random")
    ap.add_argument("--random", type=int, default=200, help="random study seeds 1..N to pick from")
    ap.add_argument("--random-keep", type=int, default=4, help="how many random scenes (the largest)")
    ap.add_argument("--timeout", type=float, default=120)
    ap.add_argument("--repeats", type=int, default=1,
                    help="best of this many processes by wall time (runs under %g s only; a row's methods "
                         "take turns)" % REPEAT_BELOW)
    ap.add_argument("--min-time", type=float, default=0.0,
                    help="repeat a run under %g s beyond --repeats until its runs add up to this many "
                         "seconds (at most %d runs)" % (REPEAT_BELOW, MAX_REPEATS))
    ap.add_argument("--methods", default="", help="comma-separated subset of: " + ",".join(METHODS))
    ap.add_argument("--max-n", type=int, default=0, help="leave out fig2 and 3D boxes above this mesh.n")
    ap.add_argument("--table", default="", help="only print the table of an earlier run's method_choice.json")
    a = ap.parse_args()
    if a.table:
        with open(a.table) as f:
            results = json.load(f)
        for m in list(METHODS):
            if not any(m in row["runs"] for row in results):
                del METHODS[m]
        print(table(results))
        return 0
    only = [s for s in a.only.split(",") if s]
    for m in [m for m in a.methods.split(",") if m]:
        if m not in METHODS:
            ap.error(f"unknown method {m}")
    keep = [m for m in a.methods.split(",") if m]
    for m in list(METHODS):
        if keep and m not in keep:
            del METHODS[m]
    with tempfile.TemporaryDirectory() as workdir:
        rows = [r for r in scenes(only, a.build, workdir, a.random, a.random_keep)
                if not a.max_n or " n=" not in r[1] or int(r[1].split(" n=")[1]) <= a.max_n]
        results = measure(a.build, rows, a.timeout, a.repeats, a.min_time)
    os.makedirs(a.out, exist_ok=True)
    with open(os.path.join(a.out, "method_choice.json"), "w") as f:
        json.dump(results, f, indent=1)
    md = table(results)
    with open(os.path.join(a.out, "method_choice.md"), "w") as f:
        f.write(md)
    print(md)
    return 0 if results else 3


if __name__ == "__main__":
    sys.exit(main())
