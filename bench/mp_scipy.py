#!/usr/bin/env python3
"""Independent cross-check of topple's Mavroeidis-Papageorgiou pulses: the
minimum overturning amplitude a_p0/(alpha g) of a rigid block (Makris & Zhang
2001, nonlinear eq. 12) under the Mavroeidis & Papageorgiou (2003) near-fault
pulse, computed here with SciPy's solve_ivp (DOP853, events) from the
equations alone, and compared with `topple run` on a spectrum spec.

The model, written from the paper and the pulse's definition:

* f_p = w_p / 2 pi, support 0 <= t <= gamma / f_p, tau = t - gamma / (2 f_p):
    ground velocity  v(tau) = (V/2) [1 + cos(2 pi f_p tau / gamma)] cos(2 pi f_p tau + nu)
    ground accel.    ug = dv/dt by the product rule, zero outside the support;
  V so that max |ug| = a_p: the extrema of ug are the zeros of its
  derivative (again by the product rule), bracketed on a grid of 400
  points per carrier cycle and located by brentq; the largest |ug| there
  sets V;
* the block (bench/rocking_scipy.py): rocking from the first exceedance of
  g tan(alpha) (a scan of 200 points per carrier cycle and brentq), impacts,
  overturning during the pulse or, after it, from the energy;
* the minimum: scan a_p/(alpha g) upward from tan(alpha)/alpha in steps of
  0.005 to the first overturning amplitude, then bisect that bracket to 1e-7.
  The step is finer than bench/ricker_scipy.py's 0.02: at gamma = 3,
  nu = pi/2, w_p/p = 1 the lowest overturning band is [1.17136, 1.18074],
  0.0094 wide, which a 0.02 scan steps over (topple scans at 0.02 too, but
  bisects wherever the impact count changes, and finds it).

Usage: python bench/mp_scipy.py [--topple target/release/topple]
(needs numpy and scipy: bench/requirements.txt). Exits 1 when a minimum
differs by more than 1e-6 relative.
"""

from __future__ import annotations

import argparse
import math
import sys

import numpy as np
from scipy.optimize import brentq

import rocking_scipy as rocking
from rocking_scipy import ALPHA, G, P

RATIOS = [1.0, 2.0, 4.0]
SCAN_STEP = 0.005
CASES = [(2.0, 0.0), (3.0, math.pi / 2)]


def pulse(gamma: float, nu: float, a_p: float, w_p: float):
    """(ug(t), T): the ground acceleration and the support's end."""
    f = w_p / (2 * math.pi)
    T = gamma / f
    a, b = 2 * math.pi * f / gamma, 2 * math.pi * f  # bell and carrier, rad/s

    def shape(t):
        """dv/dt and d2v/dt2 of the velocity with V = 1."""
        tau = t - T / 2
        e, de, dde = 0.5 * (1 + math.cos(a * tau)), -0.5 * a * math.sin(a * tau), -0.5 * a * a * math.cos(a * tau)
        c, dc, ddc = math.cos(b * tau + nu), -b * math.sin(b * tau + nu), -b * b * math.cos(b * tau + nu)
        return de * c + e * dc, dde * c + 2 * de * dc + e * ddc

    n = int(400 * gamma) + 1
    ts = np.linspace(0.0, T, n + 1)
    jerk = [shape(t)[1] for t in ts]
    peak = 0.0
    for k in range(n):
        if jerk[k] == 0.0:
            peak = max(peak, abs(shape(ts[k])[0]))
        elif jerk[k] * jerk[k + 1] < 0:
            tk = brentq(lambda t: shape(t)[1], ts[k], ts[k + 1], xtol=1e-15, rtol=1e-15)
            peak = max(peak, abs(shape(tk)[0]))
    scale = a_p / peak
    return (lambda t: scale * shape(t)[0] if 0.0 <= t <= T else 0.0), T, f


def outcome(gamma: float, nu: float, level: float, ratio: float):
    """(overturned, mode) of the block under the pulse a_p = level alpha g."""
    ug, T, f = pulse(gamma, nu, level * ALPHA * G, ratio * P)
    return rocking.outcome(ug, T, lambda t_from: max(int(200 * (T - t_from) * f), 1000))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--topple", default="target/release/topple")
    args = ap.parse_args()
    worst = 0.0
    print(f"{'gamma':>5} {'nu':>7} {'w_p/p':>6} {'scipy a_p0/(ag)':>16} {'topple':>16} {'rel diff':>10} modes",
          flush=True)
    for gamma, nu in CASES:
        theirs = rocking.topple_minima(
            args.topple, {"type": "mavroeidis_papageorgiou", "gamma": gamma, "nu": nu}, RATIOS)
        for ratio, (t_min, t_mode) in zip(RATIOS, theirs):
            s_min, s_mode = rocking.minimum(lambda level: outcome(gamma, nu, level, ratio), SCAN_STEP)
            rel = rocking.relative_difference(s_min, t_min)
            if s_min is None or t_min is None:
                print(f"{gamma:>5} {nu:>7.4f} {ratio:>6} {'none <= 20':>16} {str(t_min):>16} {rel:>10.2e}")
            else:
                print(f"{gamma:>5} {nu:>7.4f} {ratio:>6} {s_min:>16.8f} {t_min:>16.8f} {rel:>10.2e} {s_mode}/{t_mode}",
                      flush=True)
            worst = max(worst, rel)
    print(f"largest relative difference: {worst:.2e}")
    return 0 if worst < 1e-6 else 1


if __name__ == "__main__":
    sys.exit(main())
