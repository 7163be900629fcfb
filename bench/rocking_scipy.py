"""The rocking block of Makris & Zhang (2001) written with SciPy, shared by the
independent cross-checks of topple's pulses (bench/ricker_scipy.py,
bench/mp_scipy.py): each defines its ground acceleration and compares the
minimum overturning amplitude found here with `topple run` on a spectrum.

The model, written from the paper alone:

* at rest until |ug| first exceeds g tan(alpha) (a scan and brentq), then
  rocking on side s = -sign(ug):
    theta'' = -p^2 [sin(alpha s - theta) + (ug/g) cos(alpha s - theta)];
* an impact when theta returns to 0 (a terminal, directional solve_ivp
  event): theta' is multiplied by eta; below 1e-9 rad/s the block is at rest
  and waits for the next exceedance;
* overturning when |theta| reaches pi/2 during the pulse; after the pulse it
  is decided from the energy E = theta'^2/(2p^2) + cos(alpha - |theta|):
  the block overturns while moving outward with E > 1; otherwise it returns
  to theta = 0 with the same energy, and after the impact the same test
  applies with the reduced energy;
* the minimum: scan a_p/(alpha g) upward from tan(alpha)/alpha in steps of
  `step` to the first overturning amplitude, then bisect that bracket to 1e-7.
"""

from __future__ import annotations

import json
import math
import subprocess

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

ALPHA, P, ETA, G = 0.25, 2.14, 0.9, 9.81
RTOL, ATOL = 1e-11, 1e-13


def first_exceedance(ug, t_from, T, thr, n):
    """The first time in [t_from, T] at which |ug| exceeds thr (n scan intervals), or None."""
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


def outcome(ug, T, scan_intervals):
    """(overturned, mode) of the block under ground acceleration ug on [0, T];
    scan_intervals(t_from) is the number of scan intervals for an exceedance
    after t_from."""
    thr = G * math.tan(ALPHA)
    t = first_exceedance(ug, 0.0, T, thr, scan_intervals(0.0))
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
                nxt = first_exceedance(ug, t + 1e-12, T, thr, scan_intervals(t + 1e-12))
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


def minimum(outcome_at, step, a_max=20.0):
    """The least a_p/(alpha g) at which outcome_at(level) overturns, and its mode."""
    level = math.tan(ALPHA) / ALPHA
    prev = level
    while level <= a_max:
        if outcome_at(level)[0]:
            lo, hi = prev, level
            while hi - lo > 1e-7:
                mid = 0.5 * (lo + hi)
                if outcome_at(mid)[0]:
                    hi = mid
                else:
                    lo = mid
            return hi, outcome_at(hi)[1]
        prev = level
        level = round(level + step, 12)
    return None, None


def topple_minima(binary, pulse, ratios):
    """topple's minimum overturning amplitude and mode at each w_p/p of ratios."""
    spec = {
        "kind": "spectrum",
        "block": {"alpha": ALPHA, "p": P, "eta": ETA},
        "pulse": pulse,
        "formulation": "nonlinear",
        "omega_ratio": ratios,
        "a_max_alpha_g": 20,
        "tolerance": 1e-7,
        "solver": {"method": "dop853", "rtol": RTOL, "atol": ATOL},
    }
    out = subprocess.run([binary, "run", "-"], input=json.dumps(spec), capture_output=True,
                         text=True, check=True).stdout
    lines = json.loads(out)["spectrum"]
    return [(l["min_overturn_alpha_g"], l["min_overturn_mode"]) for l in lines]


def relative_difference(s_min, t_min):
    """0 when neither overturns below a_max, inf when they disagree on whether."""
    if s_min is None or t_min is None:
        return 0.0 if s_min is None and t_min is None else math.inf
    return abs(s_min - t_min) / s_min
