#!/usr/bin/python3
"""What the Python module costs beside the CLI, and what threads gain (docs/python.md).

1. Whole processes, fig2 at n = 64 and n = 256 (the same scene and settings; no VTU or CSV:
   output.vtu = output.csv = false; the CLI still writes its report.json, the module writes nothing):
     CLI:    hemicontact solve problems/sofonea2017-fig2.json --set mesh.n=N ... --quiet
     Python: python3 -c "import hemicontact ...; hemicontact.solve(scene)"
   run alternately, --repeat times each; the medians and their ratio.
2. Eight random scenes (seeds 1..8 of the default-settings study, include/hemicontact/studies/random_scenes.hpp,
   n from --n-min to --n-max) solved one after the other, then in a ThreadPoolExecutor(2), in one
   process, --repeat times alternately; the medians and their ratio (target <= 0.6). Twice: in the
   seeds' order, and largest first (by unknowns, which each scene's mesh fixes before any solve):
   the sizes of random scenes spread over 15x, and the largest is about half of the eight's work, so
   in the seeds' order, where it comes last, the pool idles one worker while it runs; largest first
   is the usual remedy (longest processing time first) and what a study script should do.

Usage: PYTHONPATH=build/python /usr/bin/python3 bench/python_overhead.py [--cli build/hemicontact]
       [--repeat 5] [--n-min 24] [--n-max 48] [--json out.json]
"""
import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
FIG2 = ROOT / "problems" / "sofonea2017-fig2.json"
SETTINGS = ["output.vtu=false", "output.csv=false"]


def wall(argv, env=None):
    t0 = time.perf_counter()
    subprocess.run(argv, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, env=env)
    return time.perf_counter() - t0


def processes(cli, n, repeat, out):
    sets = [f"mesh.n={n}"] + SETTINGS
    cli_argv = [cli, "solve", str(FIG2), "--out", out, "--force", "--quiet"]
    for s in sets:
        cli_argv += ["--set", s]
    code = ("import hemicontact as hc; r = hc.solve(hc.Scene.load(%r, *%r)); assert r.ok" % (str(FIG2), sets))
    py_argv = [sys.executable, "-c", code]
    env = dict(os.environ)
    wall(cli_argv), wall(py_argv, env)  # warm the page cache
    t_cli, t_py = [], []
    for _ in range(repeat):
        t_cli.append(wall(cli_argv))
        t_py.append(wall(py_argv, env))
    # Also the median of the paired ratios (each Python run over the CLI run just before it): this
    # machine's speed flips between two modes ~30 % apart, and a pair mostly falls in one of them.
    paired = statistics.median(p / c for c, p in zip(t_cli, t_py))
    return {"n": n, "cli_s": statistics.median(t_cli), "python_s": statistics.median(t_py),
            "ratio": statistics.median(t_py) / statistics.median(t_cli), "paired_ratio": paired,
            "cli_all": t_cli, "python_all": t_py}


def threads(n_min, n_max, repeat, largest_first):
    import hemicontact as hc

    base = hc.Scene.load(FIG2)
    scenes = [hc.random_scene(base, seed, n_min, n_max) for seed in range(1, 9)]
    warm = [hc.solve(s) for s in scenes]  # warm-up, the reference answers, each scene's size
    if largest_first:
        order = sorted(range(len(scenes)), key=lambda i: -warm[i].report["dofs"])
        scenes = [scenes[i] for i in order]
        warm = [warm[i] for i in order]
    serial_e = [r.energy for r in warm]
    t_serial, t_pool = [], []
    for _ in range(repeat):
        t0 = time.perf_counter()
        for s in scenes:
            hc.solve(s)
        t_serial.append(time.perf_counter() - t0)
        t0 = time.perf_counter()
        with ThreadPoolExecutor(2) as pool:
            pooled_e = [r.energy for r in pool.map(hc.solve, scenes)]
        t_pool.append(time.perf_counter() - t0)
        # Round-off apart: concurrent solves run the BLAS on one thread each, which sums in
        # another order than a single solve's BLAS threads.
        assert all(abs(a - b) <= 1e-10 * abs(a) for a, b in zip(serial_e, pooled_e)), "threads changed an answer"
    return {"scenes": 8, "n_min": n_min, "n_max": n_max, "order": "largest first" if largest_first else "seeds",
            "dofs": [r.report["dofs"] for r in warm], "serial_s": statistics.median(t_serial),
            "pool2_s": statistics.median(t_pool), "ratio": statistics.median(t_pool) / statistics.median(t_serial),
            "serial_all": t_serial, "pool2_all": t_pool}


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--cli", default=str(ROOT / "build" / "hemicontact"))
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--n-min", type=int, default=24)
    ap.add_argument("--n-max", type=int, default=48)
    ap.add_argument("--sizes", default="64,256")
    ap.add_argument("--json")
    a = ap.parse_args()
    res = {"date": time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime()), "cpus": os.cpu_count(),
           "loadavg_before": os.getloadavg(), "processes": [], "threads": None}
    with tempfile.TemporaryDirectory() as tmp:
        for n in map(int, a.sizes.split(",")):
            p = processes(a.cli, n, a.repeat, os.path.join(tmp, f"fig2-{n}"))
            res["processes"].append(p)
            print(f"fig2 n={n}: CLI {p['cli_s']:.3f} s, Python {p['python_s']:.3f} s, ratio {p['ratio']:.3f} "
                  f"(paired {p['paired_ratio']:.3f})")
    res["threads"] = []
    for largest_first in (False, True):
        t = threads(a.n_min, a.n_max, a.repeat, largest_first)
        res["threads"].append(t)
        print(f"8 random scenes (n {a.n_min}..{a.n_max}, {t['order']}): serial {t['serial_s']:.3f} s, "
              f"ThreadPoolExecutor(2) {t['pool2_s']:.3f} s, ratio {t['ratio']:.3f}")
    res["loadavg_after"] = os.getloadavg()
    print(f"load average before {res['loadavg_before']}, after {res['loadavg_after']}")
    if a.json:
        Path(a.json).write_text(json.dumps(res, indent=2) + "\n")


if __name__ == "__main__":
    main()
