#!/usr/bin/env python3
"""The engines of the commands that hold the whole model (`converge`, the Python module's solve, the
adaptive solve): each study as a whole process with solver.engine = auto (which hands a level above
solver.method_choice.petsc_above to the petsc engine, streamed back: studies/petsc_process.hpp) and
with solver.engine = cholmod, side by side in one session; an adaptive solve with auto (its graded
levels stay in the process) and with every level after the first forced to the petsc engine.

Each row: wall time, the peak resident memory of the process tree (the study's process and the
engine it runs, summed while both live; sampled every 10 ms from /proc), which engine solved the
largest mesh, and the largest difference between the two engines' results (relative energy norm
and absolute error (adaptive: estimate) of every level; relative max |u| difference for solve). A run past
--timeout is killed and shown as "> T". Writes DIR/study_engines.md and .json.

  /usr/bin/python3 bench/study_engines.py --build build --out /tmp/study-engines   (Debian's, with NumPy)
"""
import argparse
import json
import os
import signal
import subprocess
import sys
import tempfile
import threading
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BOX = os.path.join(ROOT, "problems", "sofonea2017-3d.json")
ENGINES = ("auto", "cholmod")

# (name, what, arguments): converge studies, Python solves, and adaptive solves (target error).
STUDIES = [
    ("converge 3D n=4,8 ref 16", "converge", ["--levels", "4,8", "--reference", "16"]),
    ("converge 3D n=6,12 ref 24", "converge", ["--levels", "6,12", "--reference", "24"]),
    ("converge 3D n=8,16 ref 32", "converge", ["--levels", "8,16", "--reference", "32"]),
    ("Python solve 3D n=24", "python", [24]),
    ("Python solve 3D n=32", "python", [32]),
    ("adaptive 3D to 12 %", "adapt", [0.12]),
    ("adaptive 3D to 7 %", "adapt", [0.07]),
]
# An adaptive run's second engine: every level after the first on the petsc engine, by a
# memory_fraction so small that no factorization is predicted to fit (choose_level_engine).
PETSC_LEVELS = ["--set", "solver.method_choice.memory_fraction=1e-6"]

PY_SOLVE = """
import sys, numpy as np, hemicontact as hc
scene = hc.Scene.load(sys.argv[1]); scene["mesh.n"] = int(sys.argv[2]); scene["solver.engine"] = sys.argv[3]
r = hc.solve(scene)
np.save(sys.argv[4], r.u)
print(r.report["engine_choice"]["engine"], r.solved_by, r.ok, r.energy, sep="|")
"""


def tree_rss_kb(pid):
    """The resident memory of @p pid and its descendants now (kB; 0 for what has ended)."""
    total, todo = 0, [pid]
    while todo:
        p = todo.pop()
        try:
            with open(f"/proc/{p}/status") as f:
                for line in f:
                    if line.startswith("VmRSS:"):
                        total += int(line.split()[1])
            for task in os.listdir(f"/proc/{p}/task"):
                with open(f"/proc/{p}/task/{task}/children") as f:
                    todo += [int(c) for c in f.read().split()]
        except (FileNotFoundError, ProcessLookupError, PermissionError):
            pass
    return total


def run_tree(cmd, timeout, env=None):
    """(seconds, peak MB of the tree, stdout, exit code), or (None, None, '', note) past the timeout."""
    peak = [0]
    t0 = time.perf_counter()
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True, env=env,
                            start_new_session=True)
    done = threading.Event()

    def sample():
        while not done.is_set():
            peak[0] = max(peak[0], tree_rss_kb(proc.pid))
            time.sleep(0.01)

    th = threading.Thread(target=sample)
    th.start()
    try:
        out, _ = proc.communicate(timeout=timeout)
    except subprocess.TimeoutExpired:
        os.killpg(proc.pid, signal.SIGKILL)
        proc.communicate()
        done.set()
        th.join()
        return None, None, "", f"> {timeout:g} s"
    secs = time.perf_counter() - t0
    done.set()
    th.join()
    return secs, peak[0] / 1024, out, proc.returncode


def converge_run(build, args, engine, timeout, work):
    out = os.path.join(work, f"conv-{engine}")
    cmd = [os.path.join(build, "hemicontact"), "converge", BOX, "--out", out, "--force", "--quiet",
           "--set", "output.vtu=false", "--set", "output.plot=false", "--set", f'solver.engine="{engine}"'] + args
    secs, mb, _, code = run_tree(cmd, timeout)
    r = {"seconds": secs, "peak_mb": mb, "exit": code}
    path = os.path.join(out, "convergence.json")
    if secs is not None and os.path.exists(path):
        with open(path) as f:
            st = json.load(f)
        r["levels"] = st["levels"] + [st["reference"]]
        r["engine"] = st["engine_choice"]["engine"]
        r["solved_by"] = st["reference"]["solved_by"]
        r["ok"] = st["ok"]
    return r


def adapt_run(build, target, engine, timeout, work):
    """`hemicontact solve` of the 3D scene to @p target: auto, or ("cholmod") with the levels forced
    to the petsc engine (PETSC_LEVELS): the second column of an adaptive row."""
    out = os.path.join(work, f"adapt-{engine}-{target}")
    cmd = [os.path.join(build, "hemicontact"), "solve", BOX, "--out", out, "--force", "--quiet",
           "--set", "output.vtu=false", "--set", "output.plot=false", "--set", f"adapt.target_error={target}"]
    secs, mb, _, code = run_tree(cmd + (PETSC_LEVELS if engine == "cholmod" else []), timeout)
    r = {"seconds": secs, "peak_mb": mb, "exit": code}
    path = os.path.join(out, "report.json")
    if secs is not None and os.path.exists(path):
        with open(path) as f:
            rep = json.load(f)
        hist = rep["adapt"]["history"]
        r.update(levels=[{"energy_norm": h["energy_norm"], "error": h["estimate"]} for h in hist],
                 engine="petsc levels" if engine == "cholmod" else "auto", ok=rep["ok"],
                 solved_by=", ".join(h["method"] for h in hist))
    return r


def python_run(build, n, engine, timeout, work):
    u_file = os.path.join(work, f"u-{engine}-{n}.npy")
    env = dict(os.environ, PYTHONPATH=os.path.join(build, "python"))
    secs, mb, out, code = run_tree(["/usr/bin/python3", "-c", PY_SOLVE, BOX, str(n), engine, u_file], timeout, env)
    r = {"seconds": secs, "peak_mb": mb, "exit": code}
    if secs is not None and code == 0:
        e, by, ok, energy = out.strip().split("|")
        r.update(engine=e, solved_by=by, ok=ok == "True", energy=float(energy), u_file=u_file)
    return r


def difference(what, a, b):
    """The largest difference between the two engines' results (see the file comment)."""
    if "engine" not in a or "engine" not in b:
        return None
    if what in ("converge", "adapt"):
        d = 0.0
        for la, lb in zip(a["levels"], b["levels"]):
            d = max(d, abs(la["energy_norm"] - lb["energy_norm"]) / lb["energy_norm"], abs(la["error"] - lb["error"]))
        return d
    import numpy as np
    ua, ub = np.load(a["u_file"]), np.load(b["u_file"])
    return float(np.abs(ua - ub).max() / np.abs(ub).max())


def cell(r):
    if r.get("seconds") is None:
        return str(r.get("exit"))
    mark = "" if r.get("ok") else " (not ok)"
    return f"{r['seconds']:.2f} s, {r['peak_mb']:.0f} MB{mark}"


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--build", default=os.path.join(ROOT, "build"))
    ap.add_argument("--out", required=True)
    ap.add_argument("--timeout", type=float, default=120)
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)
    rows = []
    with tempfile.TemporaryDirectory() as work:
        for name, what, extra in STUDIES:
            runs = {}
            for engine in ENGINES:
                run = {"converge": converge_run, "python": python_run, "adapt": adapt_run}[what]
                runs[engine] = run(args.build, extra if what == "converge" else extra[0], engine, args.timeout, work)
                print(f"{name:28s} {engine:8s} {cell(runs[engine])}", file=sys.stderr, flush=True)
            rows.append({"study": name, "runs": runs, "difference": difference(what, runs["auto"], runs["cholmod"])})
    lines = ["| study | auto | cholmod (adaptive: the levels on the petsc engine) | auto / other, wall | "
             "auto's largest mesh solved by (adaptive: each level's method) | largest difference |",
             "|---|---|---|---|---|---|"]
    for row in rows:
        a, c = row["runs"]["auto"], row["runs"]["cholmod"]
        speed = f"{a['seconds'] / c['seconds']:.2f}" if a.get("seconds") and c.get("seconds") else "-"
        diff = f"{row['difference']:.1e}" if row["difference"] is not None else "-"
        lines.append(f"| {row['study']} | {cell(a)} | {cell(c)} | {speed} | {a.get('solved_by', '-')} | {diff} |")
    with open(os.path.join(args.out, "study_engines.md"), "w") as f:
        f.write("\n".join(lines) + "\n")
    for row in rows:
        for r in row["runs"].values():
            r.pop("levels", None)
            r.pop("u_file", None)
    with open(os.path.join(args.out, "study_engines.json"), "w") as f:
        json.dump(rows, f, indent=2)
    print("\n".join(lines))
    failed = [row["study"] for row in rows if any(r.get("seconds") is None or not r.get("ok") for r in row["runs"].values())]
    if failed:
        print("not every run ended ok: " + ", ".join(failed), file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
