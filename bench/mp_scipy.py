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
* at rest until |ug| first exceeds g tan(alpha) (a scan of 200 points per
  carrier cycle and brentq), then rocking on side s = -sign(ug):
    theta'' = -p^2 ( sin(alpha s - theta) + (ug/g) cos(alpha s - theta) )
* impact at theta = 0: theta_dot <- eta theta_dot; the block comes to rest
  when an impact leaves |theta_dot| < 1e-9 (it may start again later in the
  pulse); overturning when |theta| reaches pi/2;
* after the pulse: the free motion's energy E = theta_dot^2/(2 p^2) +
  cos(alpha - |theta|) decides: moving outward with E > 1 overturns; otherwise
  the block returns to theta = 0, and after the impact the same test applies
  with the reduced energy;
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
import json
import math
import subprocess
import sys

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

ALPHA, P, ETA, G = 0.25, 2.14, 0.9, 9.81
RTOL, ATOL = 1e-11, 1e-13
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


def first_exceedance(ug, t_from, T, thr, f):
    n = max(int(200 * (T - t_from) * f), 1000)
    ts = np.linspace(t_from, T, n + 1)
    vals = [abs(ug(t)) - thr for t in ts]
    if vals[0] > 0:
        return t_from
    for k in range(n):
        if vals[k + 1] > 0:
            return brentq(lambda t: abs(ug(t)) - thr, ts[k], ts[k + 1], xtol=1e-15, rtol=1e-15)
    return None


def energy(theta, theta_dot):
    return theta_dot**2 / (2 * P**2) + math.cos(ALPHA - abs(theta))


def outcome(gamma: float, nu: float, level: float, ratio: float):
    """(overturned, mode) of the block under the pulse a_p = level alpha g."""
    ug, T, f = pulse(gamma, nu, level * ALPHA * G, ratio * P)
    thr = G * math.tan(ALPHA)
    t = first_exceedance(ug, 0.0, T, thr, f)
    impacts = 0
    if t is None:
        return False, None
    side = -math.copysign(1.0, ug(t))
    y = [0.0, 0.0]
    while True:
        if t >= T:
            break
        s = side

        def rhs(tt, yy):
            a = ug(tt) / G
            return [yy[1], -P**2 * (math.sin(ALPHA * s - yy[0]) + a * math.cos(ALPHA * s - yy[0]))]

        def hit_zero(tt, yy):
            return yy[0]

        hit_zero.terminal = True
        hit_zero.direction = -s  # theta returns through zero from side s

        def topple(tt, yy):
            return abs(yy[0]) - math.pi / 2

        topple.terminal = True
        sol = solve_ivp(rhs, (t, T), y, method="DOP853", rtol=RTOL, atol=ATOL,
                        events=[hit_zero, topple])
        if sol.t_events[1].size:
            return True, (1 if impacts else 2)
        if sol.t_events[0].size:
            t = float(sol.t_events[0][0])
            v = float(sol.y_events[0][0][1]) * ETA
            impacts += 1
            if abs(v) < 1e-9:
                nxt = first_exceedance(ug, t + 1e-12, T, thr, f)
                if nxt is None:
                    return False, None
                t, y, side = nxt, [0.0, 0.0], -math.copysign(1.0, ug(nxt))
                continue
            y, side = [0.0, v], math.copysign(1.0, v)
            continue
        t, y = T, [float(sol.y[0][-1]), float(sol.y[1][-1])]
    # Free motion after the pulse, decided by the energy.
    theta, theta_dot = y
    while True:
        outward = theta * theta_dot > 0 or (theta == 0 and theta_dot != 0)
        if outward and energy(theta, theta_dot) > 1:
            return True, (1 if impacts else 2)
        # Returns to theta = 0 with the same energy: |theta_dot| there.
        e = energy(theta, theta_dot)
        v0 = math.sqrt(max(0.0, 2 * P**2 * (e - math.cos(ALPHA))))
        v = ETA * v0
        impacts += 1
        if energy(0.0, v) <= 1 or v < 1e-12:
            return False, None
        theta, theta_dot = 0.0, v


def minimum(gamma: float, nu: float, ratio: float, a_max: float = 20.0):
    level = math.tan(ALPHA) / ALPHA
    prev = level
    while level <= a_max:
        if outcome(gamma, nu, level, ratio)[0]:
            lo, hi = prev, level
            while hi - lo > 1e-7:
                mid = 0.5 * (lo + hi)
                if outcome(gamma, nu, mid, ratio)[0]:
                    hi = mid
                else:
                    lo = mid
            return hi, outcome(gamma, nu, hi, ratio)[1]
        prev = level
        level = round(level + SCAN_STEP, 12)
    return None, None


def topple_minima(binary: str, gamma: float, nu: float):
    spec = {
        "kind": "spectrum",
        "block": {"alpha": ALPHA, "p": P, "eta": ETA},
        "pulse": {"type": "mavroeidis_papageorgiou", "gamma": gamma, "nu": nu},
        "formulation": "nonlinear",
        "omega_ratio": RATIOS,
        "a_max_alpha_g": 20,
        "tolerance": 1e-7,
        "solver": {"method": "dop853", "rtol": 1e-11, "atol": 1e-13},
    }
    out = subprocess.run([binary, "run", "-"], input=json.dumps(spec), capture_output=True,
                         text=True, check=True).stdout
    lines = json.loads(out)["spectrum"]
    return [(l["min_overturn_alpha_g"], l["min_overturn_mode"]) for l in lines]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--topple", default="target/release/topple")
    args = ap.parse_args()
    worst = 0.0
    print(f"{'gamma':>5} {'nu':>7} {'w_p/p':>6} {'scipy a_p0/(ag)':>16} {'topple':>16} {'rel diff':>10} modes",
          flush=True)
    for gamma, nu in CASES:
        theirs = topple_minima(args.topple, gamma, nu)
        for ratio, (t_min, t_mode) in zip(RATIOS, theirs):
            s_min, s_mode = minimum(gamma, nu, ratio)
            if s_min is None or t_min is None:
                # Neither overturns below a_max, or they disagree on whether.
                rel = 0.0 if s_min is None and t_min is None else math.inf
                print(f"{gamma:>5} {nu:>7.4f} {ratio:>6} {'none <= 20':>16} {str(t_min):>16} {rel:>10.2e}")
            else:
                rel = abs(s_min - t_min) / s_min
                print(f"{gamma:>5} {nu:>7.4f} {ratio:>6} {s_min:>16.8f} {t_min:>16.8f} {rel:>10.2e} {s_mode}/{t_mode}",
                      flush=True)
            worst = max(worst, rel)
    print(f"largest relative difference: {worst:.2e}")
    return 0 if worst < 1e-6 else 1


if __name__ == "__main__":
    sys.exit(main())
