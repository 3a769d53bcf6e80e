"""The paper's Fig. 2 from Python: deformed mesh with the Gamma3 statuses, and the contact forces."""
import sys
from pathlib import Path

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
import hemicontact as hc

scene = hc.Scene.load(Path(__file__).resolve().parents[2] / "problems" / "sofonea2017-fig2.json")
scene["mesh.n"] = int(sys.argv[1]) if len(sys.argv) > 1 else 64
r = hc.solve(scene)
m = 0.1 / abs(r.u).max()  # largest displacement drawn as 10 % of the body
x, g = r.points + m * r.u, r.gamma3
fig, (a, b) = plt.subplots(1, 2, figsize=(11, 4.5))
a.triplot(x[:, 0], x[:, 1], r.cells, lw=0.2, color="0.6")
for status, marker in [("separated", "o"), ("compliance", "s"), ("contact", "^")]:
    on = [s.startswith(status) for s in r.statuses]
    a.plot(x[g["node"][on], 0], x[g["node"][on], 1], marker, ms=3, ls="", label=status)
a.set(aspect="equal", title=f"deformed x{m:.3g}, certificate {r.certificate.max_residual:.1e}")
a.legend(fontsize=7)
for key in ["xi", "sigma_nu", "sigma_tau", "lambda"]:
    b.plot(g["x"][:, 0], g[key], label=key)
b.set(xlabel="x on Gamma3", title="contact forces")
b.legend(fontsize=7)
fig.savefig(sys.argv[2] if len(sys.argv) > 2 else "fig2-python.png", dpi=120)
print(f"energy {r.energy:.10g}, statuses {r.status_counts}")
