#!/usr/bin/env python3
"""Singular exponent of a clamped-free elastic corner (Williams 1952), the rate that limits
the P1 energy-norm convergence of the paper's scenes (docs/convergence.md).

Near a corner of opening angle omega with one side clamped (u = 0) and the other traction-free,
the displacement behaves like r^lam; the energy-norm error of P1 on uniform meshes is then
O(h^min(lam, 1)). With Kolosov-Muskhelishvili potentials phi = A z^lam, psi = B z^lam
(2G(u_x + i u_y) = kappa phi - z conj(phi') - conj(psi)):
  clamped side  theta = 0:     kappa A - lam conj(A) - conj(B) = 0
  free side     theta = omega: A e^{i lam w} + lam conj(A) e^{i(2-lam)w} + conj(B) e^{-i lam w} = 0
Eliminating B leaves a real 2x2 system in (Re A, Im A); lam is the smallest root of its
determinant in (0, 1]. kappa = 3 - 4 nu (plane strain) or (3 - nu)/(1 + nu) (plane stress).

usage: corner_exponent.py [--nu 0.4] [--plane stress|strain] [--angle-deg 90]
"""
import argparse
import math

import numpy as np


def determinant(lam, kappa, omega):
    def free_side(a):
        return (a * np.exp(1j * lam * omega) + lam * np.conj(a) * np.exp(1j * (2 - lam) * omega)
                + (kappa * a - lam * np.conj(a)) * np.exp(-1j * lam * omega))
    c1, c2 = free_side(1.0), free_side(1j)
    return c1.real * c2.imag - c2.real * c1.imag


def smallest_root(kappa, omega, lo=1e-3, hi=1.0, samples=4000):
    grid = np.linspace(lo, hi, samples)
    values = [determinant(x, kappa, omega) for x in grid]
    for a, b, fa, fb in zip(grid[:-1], grid[1:], values[:-1], values[1:]):
        if fa == 0:
            return a
        if fa * fb < 0:
            for _ in range(200):  # bisection to round-off
                m = 0.5 * (a + b)
                fm = determinant(m, kappa, omega)
                if fa * fm <= 0:
                    b = m
                else:
                    a, fa = m, fm
            return 0.5 * (a + b)
    return None


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--nu", type=float, default=0.4)
    p.add_argument("--plane", choices=["stress", "strain"], default="stress")
    p.add_argument("--angle-deg", type=float, default=90.0)
    a = p.parse_args()
    kappa = (3 - a.nu) / (1 + a.nu) if a.plane == "stress" else 3 - 4 * a.nu
    lam = smallest_root(kappa, math.radians(a.angle_deg))
    if lam is None:
        # Complex exponents (e.g. the 180-degree clamped-free transition, Re lam = 1/2) are not
        # searched: say so rather than claim regularity.
        print("no real exponent in (0, 1] (complex exponents are not searched)")
    else:
        print(f"clamped-free corner, angle {a.angle_deg:g} deg, nu = {a.nu:g} (plane {a.plane}), "
              f"kappa = {kappa:.4f}: u ~ r^{lam:.4f}, P1 energy-norm rate h^{min(lam, 1.0):.4f}")


if __name__ == "__main__":
    main()
