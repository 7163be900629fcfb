#!/usr/bin/env python3
"""Independent cross-check of topple's Ricker pulses: the minimum overturning
amplitude a_p0/(alpha g) of a rigid block (Makris & Zhang 2001, nonlinear
eq. 12) under the symmetric Ricker wavelet and its antisymmetric derivative,
computed here with SciPy's solve_ivp (DOP853, events) from the equations alone,
and compared with `topple run` on a spectrum spec.

The model, written from the paper and the wavelet definitions:

* f_p = w_p / 2 pi, c = (pi f_p)^2, t0 = 1.5 / f_p, tau = t - t0, 0 <= t <= 2 t0:
    symmetric:      ug = a_p (1 - 2 c tau^2) exp(-c tau^2)
    antisymmetric:  ug = a_p D(tau) / max|D|, D = (-6 c tau + 4 c^2 tau^3) exp(-c tau^2)
* the block (bench/rocking_scipy.py): rocking from the first exceedance of
  g tan(alpha) (a scan of 20,000 points and brentq), impacts, overturning
  during the pulse or, after it, from the energy;
* the minimum: scan a_p/(alpha g) upward from tan(alpha)/alpha in steps of
  0.02 to the first overturning amplitude, then bisect that bracket to 1e-7.

Usage: python bench/ricker_scipy.py [--topple target/release/topple]
(needs numpy and scipy: bench/requirements.txt). Exits 1 when a minimum
differs by more than 1e-4 relative.
"""

from __future__ import annotations

import argparse
import math
import sys

import rocking_scipy as rocking
from rocking_scipy import ALPHA, G, P

RATIOS = [1.0, 2.0, 4.0, 6.0]
SCAN_STEP = 0.02


def wavelet(symmetric: bool, a_p: float, w_p: float):
    f = w_p / (2 * math.pi)
    c = (math.pi * f) ** 2
    t0 = 1.5 / f
    if symmetric:
        unit = lambda tau: (1 - 2 * c * tau**2) * math.exp(-c * tau**2)
        norm = 1.0
    else:
        unit = lambda tau: (-6 * c * tau + 4 * c**2 * tau**3) * math.exp(-c * tau**2)
        ts = math.sqrt((3 - math.sqrt(6)) / (2 * c))
        norm = abs(unit(ts))
    T = 2 * t0
    return (lambda t: a_p * unit(t - t0) / norm if 0 <= t <= T else 0.0), T


def outcome(symmetric: bool, level: float, ratio: float):
    """(overturned, mode) of the block under the wavelet a_p = level alpha g."""
    ug, T = wavelet(symmetric, level * ALPHA * G, ratio * P)
    return rocking.outcome(ug, T, lambda t_from: 20000)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--topple", default="target/release/topple")
    args = ap.parse_args()
    worst = 0.0
    print(f"{'wavelet':<14} {'w_p/p':>6} {'scipy a_p0/(ag)':>16} {'topple':>16} {'rel diff':>10} modes")
    for symmetric in (True, False):
        theirs = rocking.topple_minima(args.topple, {"type": "ricker", "symmetric": symmetric}, RATIOS)
        for ratio, (t_min, t_mode) in zip(RATIOS, theirs):
            s_min, s_mode = rocking.minimum(lambda level: outcome(symmetric, level, ratio), SCAN_STEP)
            name = "symmetric" if symmetric else "antisymmetric"
            rel = rocking.relative_difference(s_min, t_min)
            if s_min is None or t_min is None:
                print(f"{name:<14} {ratio:>6} {'none <= 20':>16} {str(t_min):>16} {rel:>10.2e}")
            else:
                print(f"{name:<14} {ratio:>6} {s_min:>16.8f} {t_min:>16.8f} {rel:>10.2e} {s_mode}/{t_mode}")
            worst = max(worst, rel)
    print(f"largest relative difference: {worst:.2e}")
    return 0 if worst < 1e-4 else 1


if __name__ == "__main__":
    sys.exit(main())
