"""A sweep in the friction coefficient mu: slip and stick along Gamma3, and the energy."""
import sys
from pathlib import Path

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
import hemicontact as hc

scene = hc.Scene.load(Path(__file__).resolve().parents[2] / "problems" / "sofonea2017-fig2.json")
scene["mesh.n"] = 32
mus, energy, stick = np.linspace(0, 1, 11), [], []
for mu in mus:
    scene["contact.friction.mu"] = float(mu)
    r = hc.solve(scene)
    assert r.ok, r.message
    energy.append(r.energy)
    stick.append(r.status_counts.get("stick", 0))
fig, (a, b) = plt.subplots(1, 2, figsize=(10, 4))
a.plot(mus, energy, "o-")
a.set(xlabel="mu", ylabel="energy")
b.plot(mus, stick, "s-")
b.set(xlabel="mu", ylabel="stick nodes on Gamma3")
fig.savefig(sys.argv[1] if len(sys.argv) > 1 else "mu-sweep.png", dpi=120)
print("mu, energy, stick:", *zip(mus.round(2), energy, stick), sep="\n")
