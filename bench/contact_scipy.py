"""A rigid block on a Coulomb floor (stick, slide, rock, slide-rock, flight)
cross-checked against an independent SciPy model, written from the
constrained rigid-body equations alone.

Model (ground frame, mass 1, g = 9.81). Half-width b = R sin(alpha),
half-height h = R cos(alpha), R = 3 g / (4 p^2), I_c = R^2 / 3. The block
feels the horizontal pseudo-force -ug and gravity gz = g + uv downwards.
theta is clockwise-positive (x right, y up); theta > 0 rocks on the right
corner (k = +1), theta < 0 on the left (k = -1); corner k relative to the
centre r_k = (k b cos th - h sin th, -k b sin th - h cos th). State
(x_c, y_c, th, vx, vy, w) relative to the ground.

In every mode the right-hand side solves (numpy.linalg.solve) five linear
equations for (a_cx, a_cy, th'', F, N):
    a_cx - F = -ug,    a_cy - N = -gz,    I_c th'' + r_x N - r_y F = 0,
and two constraints:
* rock on k: the corner's acceleration is zero (both components,
  a_c + th'' (r_y, -r_x) - w^2 r = 0);
* slide-rock on k with slip direction s: the corner's vertical
  acceleration is zero and F = -s mu_k N;
* slide (flat): th'' = 0 replaces the moment equation, a_cy = 0 and
  F = -s mu_k N.
Transitions are solve_ivp events (DOP853, rtol 1e-12, atol 1e-13), legs
between the kinks of the ground motion:
* stick -> motion where |ug| first exceeds min(mu_s, tan alpha) gz (a 1e-3 s
  grid scan and brentq): slide (s = -sgn ug) if mu_s < tan alpha; otherwise
  rock on k = -sgn ug if the rock system at th = w = 0 needs |F| <= mu_s N,
  else slide-rock on k (s = k) if mu_k > tan alpha, else slide;
* rock -> slide-rock where |F| reaches mu_s N (s = -sgn F); slide-rock ->
  rock where the corner's horizontal velocity returns to 0 and the rock
  system needs |F| <= mu_s N (else slide-rock the other way); slide -> stick
  where x' = 0 (the same start rule decides whether it moves on at once);
  a flat slide with mu_k > tan alpha tips at once into slide-rock on k = s;
* flight where N or gz falls to 0: a_c = (-ug, -gz), th'' = 0, until a
  corner's height y_c + r_y reaches 0 (landing) or |th| = pi/2 (overturning
  in the air). The landing corner j strikes like an impact below (general
  th: the same 5x5 impulse-momentum systems with r_j at that th); then rock
  (sticking) or slide-rock on j, or flat as below where th = 0 and the
  rotation does not lift the block onto j. A block that took off flat
  (th = w = 0) lands on both corners: first the single-corner impact on its
  leading corner j = sgn(vx) is tried, taken if it tips the block up onto j
  (j w+ > 0); else vy -> 0 and vx -> 0 if |vx| <= mu_s |vy|, else
  vx - sgn(vx) mu_k |vy| (a flat slide). Slip in the air: the lower corner's
  (k = sgn th) horizontal position minus k b; its extremes are solve_ivp
  events (that corner's horizontal velocity 0) and count in the peak slide;
* impact at th = 0: the other corner lands without rebound. A sticking
  impulse (its whole velocity zero after, 5x5 impulse-momentum system) if
  |P_t| <= mu_s P_n, else a sliding one (P_t = sgn(P_t stick) mu_k P_n, its
  vertical velocity zero after). Then rock (sticking) or slide-rock on the
  new corner (s = sign of its horizontal velocity); |w+| < 1e-12 p alpha
  lands flat (stick, or slide if the corner slips). A sliding impulse that
  turns the block back towards its old corner (that corner would go into
  the floor): by default that corner lands at once by the same rules
  (sequential impacts); --reversal flat lands the block flat there (slip
  velocity: the landing corner's). Self-test: the sticking
  impact of a block rocking on a held corner gives Housner's
  eta = 1 - 1.5 sin^2 alpha.
* overturning at |th| = pi/2; after the ground motion the run continues to
  rest or overturning (cap: end + 30 s, 2000 impacts -> "undecided").
  Rocking with sticking impacts whose rebound falls below 1e-6 p alpha after
  the ground motion is at rest: the remaining chatter is summed in closed
  form, 2 w+ / (p^2 sin alpha) / (1 - eta) (small-amplitude flights).
* slip: the base centre's displacement along the floor (for rock and
  slide-rock the pivot's horizontal position minus k b).

Ground motion: a pulse as in bench/sliding_scipy.py (one-sine, one-cosine,
rectangular, Type-C3; vertical = ratio * ug or a pulse of its own `delay` s
later), or a record: `"record": {"dt": s, "acc": [m/s^2 samples]}`, with
optionally `ratio` (uv = ratio * ug) or `"vertical_record": {"dt": (the
same), "acc": [...]}` of its own (the shorter padded with zeros). A record's
acceleration is linear between samples t_k = k dt and zero after the last
one; the kinks of the forcing, where the legs break, are then every sample
time. Its onset of motion (|ug| first above min(mu_s, tan alpha) gz, or gz
below 0) is solved exactly on the sample interval where it happens (both
sides are linear there) instead of by the grid scan. The ground's velocity
and displacement, exact integrals from rest (per interval v += dt (a0 +
a1) / 2, u += v dt + dt^2 (a0 / 3 + a1 / 6); quadratic / cubic inside,
`record_kinematics`), are not needed by the model (it works relative to the
ground): they make the synthetic records end at rest (baseline correction)
and give the PGV / PGD printed with each record case. The records of CASES
are synthetic and deterministic (`accelerogram`: damped sinusoids of 1-5 Hz
under a build-up / decay envelope, dt 0.01 or 0.005 s, a few zero samples at
the end, no files, no random generator).

topple's answers come from `examples/contact_cases.rs` (the engine's
dynamics::coulomb). Both sides' histories are merged into mode stretches
(rock merges across impacts; slide and slide-rock merge with the same
direction only; stretches of no length omitted, but flights). Compared, tolerances:
* the mode sequence (names and directions) must be identical;
* outcome (overturned / rest / undecided), overturn side, number of
  flights, number of impacts (landings included) and whether each one
  sticks must be identical;
* times (stretch bounds, impacts, overturn, first flight, rest): 1e-7 s;
* slips (stretch ends, peak, residual): 1e-7 m;
* a rest reached by chattering (its time depends on the rest threshold and
  the tail summation) is compared to 1e-4 s: the final rest where this
  model sums the tail itself (after the ground motion). A chattering that
  comes to rest while the ground still moves is followed impact by impact
  here and summed in closed form by the engine; its end is a stretch bound,
  compared to 1e-7 s like any time.
Each side lists the impacts it followed one by one, not those it summed: the
lists are compared stick by stick (impacts grouped by the sticks begun
before them), each group over the common length.
A case prints FAIL with the first difference. Exit status 1 if any fails.

    python3 bench/contact_scipy.py [--engine target/release/examples/contact_cases] [--timeout 60]
                                   [--only 0-5,40] [--verbose]

Each case runs in its own engine process (time limit --timeout s), so a
case that hangs fails alone. --only runs some cases (numbers and ranges).
"""

from __future__ import annotations

import argparse
import bisect
import json
import math
import subprocess
import sys

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

# topple's rest velocity, relative to p alpha (README: chattering ends below it).
REST = 1e-12
G = 9.81
RTOL, ATOL = 1e-12, 1e-13
T_TOL, X_TOL, CHATTER_T_TOL = 1e-7, 1e-7, 1e-4
MAX_IMPACTS, AFTER = 2000, 30.0
# A sliding impact can turn the block back towards the corner it rocked on
# (that corner would then go into the floor). "cascade": that corner lands at
# once, by the same impact rules (sequential impacts); "flat": the block lands
# flat there. Option --reversal.
REVERSAL = "cascade"


# ---------------------------------------------------------------- pulses ---
def cn_phase(n):
    span = (2 * n + 1) * math.pi
    return brentq(lambda p: math.tan(p) * (span - 2 * p) - 2.0, 1e-9, math.pi / 2 - 1e-9, xtol=1e-15)


def pulse(spec):
    a, w = spec["a_g"] * G, spec["omega"]
    shape = spec["shape"]
    if shape == "one_sine":
        phi, span = -math.pi / 2, 2 * math.pi
    elif shape == "one_cosine":
        phi, span = 0.0, 2 * math.pi
    elif shape == "rectangular":
        phi, span = None, math.pi
    elif shape == "c3":
        phi = cn_phase(3)
        span = 7 * math.pi - 2 * phi
    else:
        raise ValueError(shape)
    dur = span / w

    def acc(t):
        if t < 0 or t > dur:
            return 0.0
        return a if phi is None else a * math.cos(w * t + phi)

    return acc, dur


# --------------------------------------------------------------- records ---
def record_kinematics(dt, acc):
    """Ground velocity and displacement at every sample (from rest at t = 0)
    of an acceleration linear between samples: the exact per-interval
    integrals, summed."""
    a = np.asarray(acc, dtype=float)
    a0, a1 = a[:-1], a[1:]
    dv = 0.5 * dt * (a0 + a1)
    v = np.concatenate(([0.0], np.cumsum(dv)))
    du = v[:-1] * dt + dt * dt * (a0 / 3.0 + a1 / 6.0)
    u = np.concatenate(([0.0], np.cumsum(du)))
    return v, u


def ground_kinematics(dt, acc, t):
    """(v_g, u_g) at t: quadratic / cubic inside the interval holding t,
    constant velocity after the last sample."""
    v, u = record_kinematics(dt, acc)
    n = len(acc)
    end = (n - 1) * dt
    if t <= 0:
        return 0.0, 0.0
    if t >= end:
        return v[-1], u[-1] + v[-1] * (t - end)
    k = min(int(t / dt), n - 2)
    tau = t - k * dt
    a0, slope = acc[k], (acc[k + 1] - acc[k]) / dt
    return (v[k] + a0 * tau + 0.5 * slope * tau * tau,
            u[k] + v[k] * tau + 0.5 * a0 * tau * tau + slope * tau ** 3 / 6.0)


class Linear:
    """Samples every dt, linear between them, zero outside [0, (n - 1) dt]
    (the engine's interpolation, term for term)."""

    def __init__(self, dt, acc):
        self.dt, self.a = dt, [float(x) for x in acc]
        self.n = len(self.a)
        self.end = (self.n - 1) * dt

    def __call__(self, t):
        if not 0.0 <= t <= self.end:
            return 0.0
        x = t / self.dt
        k = min(int(math.floor(x)), self.n - 2)
        a0 = self.a[k]
        return a0 + (self.a[k + 1] - a0) * (x - k)


def record_motion(case):
    rec = case["record"]
    dt, h = rec["dt"], list(rec["acc"])
    v = None
    if "vertical_record" in case:
        vr = case["vertical_record"]
        if vr["dt"] != dt:
            raise ValueError("the vertical record's dt differs")
        v = list(vr["acc"])
    elif "ratio" in case:
        v = [case["ratio"] * a for a in h]
    n = max(len(h), len(v) if v is not None else 0)
    h += [0.0] * (n - len(h))
    ug = Linear(dt, h)
    if v is None:
        uv = lambda t: 0.0
    else:
        v += [0.0] * (n - len(v))
        uv = Linear(dt, v)
    kinks = [k * dt for k in range(n)]
    return ug, uv, kinks


def accelerogram(dur, dt, pga_g, parts, rise=0.15, zeros=5):
    """A synthetic accelerogram (m/s^2 samples): damped sinusoids
    A e^(-zeta 2 pi f (t - t0)) sin(2 pi f (t - t0) + phi) from t0 on
    (parts: (f Hz, A, zeta, t0 s, phi)), under a smooth build-up over
    `rise` of the record and a smooth fall to 0 at `dur`; then a baseline
    correction (a sin^2 window) so that the ground velocity returns to 0 at
    the end, scaled to PGA `pga_g` g, followed by `zeros` zero samples."""
    n = int(round(dur / dt)) + 1
    t = np.arange(n) * dt
    a = np.zeros(n)
    for f, amp, zeta, t0, phi in parts:
        tau = np.clip(t - t0, 0.0, None)
        on = t >= t0
        a += on * amp * np.exp(-zeta * 2 * math.pi * f * tau) * np.sin(2 * math.pi * f * tau + phi)
    x = np.clip(t / (rise * dur), 0.0, 1.0)
    a *= x * x * (3 - 2 * x)                      # smooth build-up from 0
    y = np.clip((dur - t) / (0.1 * dur), 0.0, 1.0)
    a *= y * y * (3 - 2 * y)                      # smooth fall to 0 at dur
    a[0] = a[-1] = 0.0
    win = np.sin(math.pi * t / dur) ** 2
    v_end = record_kinematics(dt, a)[0][-1]
    a -= v_end / record_kinematics(dt, win)[0][-1] * win
    a *= pga_g * G / np.abs(a).max()
    return [float(q) for q in a] + [0.0] * zeros


def motion(case):
    if "record" in case:
        return record_motion(case)
    ug, dur = pulse(case)
    kinks = [0.0, dur]
    if "ratio" in case:
        r = case["ratio"]
        uv = lambda t: r * ug(t)
    elif "vertical" in case:
        v, vdur = pulse(case["vertical"])
        d = case["vertical"].get("delay", 0.0)
        uv = lambda t: v(t - d)
        kinks += [d, d + vdur]
    else:
        uv = lambda t: 0.0
    return ug, uv, sorted(set(kinks))


def sgn(x):
    return 1.0 if x > 0 else (-1.0 if x < 0 else 0.0)


# ----------------------------------------------------------------- block ---
class Block:
    def __init__(self, alpha, p, mu_s, mu_k):
        self.alpha, self.p = alpha, p
        self.R = 3 * G / (4 * p * p)
        self.b, self.h = self.R * math.sin(alpha), self.R * math.cos(alpha)
        self.I = self.R ** 2 / 3
        self.mu_s, self.mu_k = mu_s, mu_k
        self.tan = math.tan(alpha)

    def corner(self, k, th):
        c, s = math.cos(th), math.sin(th)
        return k * self.b * c - self.h * s, -k * self.b * s - self.h * c

    def solve(self, mode, k, sig, ug, gz, y):
        """(a_cx, a_cy, th'', F, N) of a mode, from its 5x5 linear system."""
        th, w = y[2], y[5]
        A = np.zeros((5, 5))
        rhs = np.zeros(5)
        # unknowns 0 a_cx, 1 a_cy, 2 th'', 3 F, 4 N
        A[0, 0], A[0, 3], rhs[0] = 1.0, -1.0, -ug
        A[1, 1], A[1, 4], rhs[1] = 1.0, -1.0, -gz
        if mode == "slide":
            A[2, 2] = 1.0                      # th'' = 0 (both corners down)
            A[3, 1] = 1.0                      # a_cy = 0
            A[4, 3], A[4, 4] = 1.0, sig * self.mu_k
            return np.linalg.solve(A, rhs)
        rx, ry = self.corner(k, th)
        A[2, 2], A[2, 4], A[2, 3] = self.I, rx, -ry   # I th'' = -(rx N - ry F)
        if mode == "rock":
            A[3, 0], A[3, 2], rhs[3] = 1.0, ry, w * w * rx
        elif mode == "slide_rock":
            A[3, 3], A[3, 4] = 1.0, sig * self.mu_k
        else:
            raise ValueError(mode)
        A[4, 1], A[4, 2], rhs[4] = 1.0, -rx, w * w * ry
        return np.linalg.solve(A, rhs)

    def impact(self, k, y, sticking, kappa=0.0):
        """Landing of corner j = -k at th = 0: (new y, P_t, P_n)."""
        return self.land(-k, y, sticking, kappa)

    def land(self, j, y, sticking, kappa=0.0):
        """Landing of corner j at the block's th: (new y, P_t, P_n)."""
        rx, ry = self.corner(j, y[2])
        vx, vy, w = y[3], y[4], y[5]
        A = np.zeros((5, 5))
        rhs = np.zeros(5)
        # unknowns 0 dvx, 1 dvy, 2 dw, 3 P_t, 4 P_n
        A[0, 0], A[0, 3] = 1.0, -1.0
        A[1, 1], A[1, 4] = 1.0, -1.0
        A[2, 2], A[2, 4], A[2, 3] = self.I, rx, -ry
        if sticking:
            A[3, 0], A[3, 2], rhs[3] = 1.0, ry, -(vx + ry * w)
        else:
            A[3, 3], A[3, 4] = 1.0, -kappa
        A[4, 1], A[4, 2], rhs[4] = 1.0, -rx, -(vy - rx * w)
        z = np.linalg.solve(A, rhs)
        y2 = list(y)
        y2[3], y2[4], y2[5] = vx + z[0], vy + z[1], w + z[2]
        return y2, z[3], z[4]

    def corner_velocity(self, k, y):
        rx, ry = self.corner(k, y[2])
        return y[3] + y[5] * ry, y[4] - y[5] * rx


# ------------------------------------------------------------- simulate ---
def simulate(case):
    ug, uv, kinks = motion(case)
    end = kinks[-1]
    cap = end + AFTER
    blk = Block(case["alpha"], case["p"], case["mu"], case.get("mu_k", case["mu"]))
    p, alpha = blk.p, blk.alpha
    eta = 1 - 1.5 * math.sin(alpha) ** 2
    gz = lambda t: G + uv(t)

    def slip(mode, k, y):
        if mode == "flight":
            k = 1 if y[2] >= 0 else -1
        if mode in ("rock", "slide_rock", "flight"):
            return y[0] + blk.corner(k, y[2])[0] - k * blk.b
        return y[0]

    def rock_needs(t, k, y):
        z = blk.solve("rock", k, 0.0, ug(t), gz(t), y)
        return z[3], z[4]

    def settle(t, y, mode, k, sig):
        """The mode actually taken at t from a proposed one."""
        if gz(t) <= 0:
            return ("flight", 0, 0.0)
        if mode == "slide" and blk.mu_k > blk.tan:
            mode, k = "slide_rock", sig
        if mode == "rock":
            F, N = rock_needs(t, k, y)
            if N <= 0:
                return ("flight", 0, 0.0)
            if abs(F) > blk.mu_s * N:
                mode, sig = "slide_rock", -sgn(F)
        if mode in ("slide_rock", "slide"):
            z = blk.solve(mode, k, sig, ug(t), gz(t), y)
            if z[4] <= 0:
                return ("flight", 0, 0.0)
        return (mode, k, sig)

    def from_rest(t, y, forced):
        """At rest relative to the ground at t: stick, or how it starts."""
        g_ = gz(t)
        if g_ <= 0:
            return ("flight", 0, 0.0)
        a = ug(t)
        if not forced and abs(a) <= min(blk.mu_s, blk.tan) * g_:
            return ("stick", 0, 0.0)
        s = -sgn(a)
        if blk.mu_s < blk.tan:
            return settle(t, y, "slide", 0, s)
        F, N = rock_needs(t, s, y)
        if N > 0 and abs(F) <= blk.mu_s * N:
            return settle(t, y, "rock", s, 0.0)
        if blk.mu_k > blk.tan:
            return settle(t, y, "slide_rock", s, s)
        return settle(t, y, "slide", 0, s)

    def next_onset(t0):
        """First time >= t0 where the block at rest starts to move or lifts
        off, before the end of the ground motion; None if it does not."""
        def over(t):
            return max(abs(ug(t)) - min(blk.mu_s, blk.tan) * gz(t), -gz(t))
        if over(t0) > 0:
            return t0
        if "record" in case:
            return record_onset(t0)
        grid = np.arange(t0, end + 1e-3, 1e-3)
        for a, b in zip(grid[:-1], grid[1:]):
            b = min(b, end)
            if b <= a:
                continue
            if over(b) > 0:
                return brentq(over, a, b, xtol=1e-15, rtol=8.9e-16)
        return None

    def record_onset(t0):
        """next_onset for a record: on each sample interval ug and uv are
        linear, and so are the three conditions s ug - c gz > 0 (s = +-1)
        and -gz > 0: the first crossing is solved exactly there."""
        c = min(blk.mu_s, blk.tan)
        dt, n = ug.dt, ug.n
        funcs = [lambda a, b: a - c * (G + b), lambda a, b: -a - c * (G + b), lambda a, b: -(G + b)]
        k = min(int(math.floor(t0 / dt)), n - 2)
        ta = t0
        ha, va = ug(ta), uv(ta)
        while k <= n - 2:
            tb = (k + 1) * dt
            hb, vb = ug.a[k + 1], uv(tb)
            best = None
            for f in funcs:
                fa, fb = f(ha, va), f(hb, vb)
                if fb > 0:
                    s_ = min(max(-fa / (fb - fa), 0.0), 1.0) if fb != fa else 0.0
                    tc = max(ta + s_ * (tb - ta), t0)
                    best = tc if best is None else min(best, tc)
            if best is not None:
                return best
            k, ta, ha, va = k + 1, tb, hb, vb
        return None

    def integrate(mode, k, sig, t0, y0, extremes=None):
        """Integrate one mode from t0 to its first event: (kind, t, y). In
        flight, the slips at the lower corner's turning points are appended
        to `extremes`."""
        def rhs(t, y):
            if mode == "flight":
                return [y[3], y[4], y[5], -ug(t), -gz(t), 0.0]
            z = blk.solve(mode, k, sig, ug(t), gz(t), y)
            return [y[3], y[4], y[5], z[0], z[1], z[2]]

        events, kinds = [], []

        def ev(f, kind, direction):
            # At the mode's start every event function is on its armed side
            # (the start checks made sure of that) but may be exactly 0 there
            # (th = 0 after an impact, a corner's velocity 0 when it starts
            # to slip); a first step that overshoots a short excursion would
            # then put the root at t0. So t0 itself reads as the armed side.
            def g(t, y):
                return -float(direction) if t == t0 else f(t, y)
            g.terminal, g.direction = True, direction
            events.append(g)
            kinds.append(kind)

        if mode == "flight":
            for j in (1, -1):
                ev(lambda t, y, j=j: y[1] + blk.corner(j, y[2])[1], "land%+d" % j, -1)
            ev(lambda t, y: y[2] - math.pi / 2, "overturn", 1)
            ev(lambda t, y: -y[2] - math.pi / 2, "overturn", 1)

            def turn(t, y):
                return blk.corner_velocity(1 if y[2] >= 0 else -1, y)[0]
            turn.terminal, turn.direction = False, 0
        else:
            ev(lambda t, y: blk.solve(mode, k, sig, ug(t), gz(t), y)[4], "lift", -1)
            ev(lambda t, y: gz(t), "lift", -1)
        if mode == "rock":
            def slip_ev(t, y):
                z = blk.solve(mode, k, sig, ug(t), gz(t), y)
                return abs(z[3]) - blk.mu_s * z[4]
            ev(slip_ev, "slip", 1)
        if mode in ("rock", "slide_rock"):
            ev(lambda t, y: k * y[2], "impact", -1)
            ev(lambda t, y: k * y[2] - math.pi / 2, "overturn", 1)
        if mode == "slide_rock":
            ev(lambda t, y: sig * blk.corner_velocity(k, y)[0], "stop", -1)
        if mode == "slide":
            ev(lambda t, y: sig * y[3], "stop", -1)
        t, y = t0, list(y0)
        while True:
            i = bisect.bisect_right(kinks, t + 1e-15)
            t1 = kinks[i] if i < len(kinks) else cap
            sol = solve_ivp(rhs, (t, t1), y, method="DOP853", rtol=RTOL, atol=ATOL,
                            events=events + ([turn] if mode == "flight" else []))
            hits = [(te[0], i) for i, te in enumerate(sol.t_events[:len(events)]) if te.size]
            if hits:
                te, i = min(hits)
            if mode == "flight" and extremes is not None:
                for tx, yx in zip(sol.t_events[-1], sol.y_events[-1]):
                    if not hits or tx <= te:
                        extremes.append(slip("flight", 0, yx))
            if hits:
                return kinds[i], te, list(sol.y_events[i][0])
            t, y = t1, list(sol.y[:, -1])
            if t >= cap:
                return "cap", t, y

    raw, impacts = [], []

    def struck(j, y):
        """Corner j's impact at the block's th: (y after, sticking)."""
        y1, Pt, Pn = blk.land(j, y, True)
        sticking = abs(Pt) <= blk.mu_s * Pn and Pn > 0
        if not sticking:
            y1, Pt, Pn = blk.land(j, y, False, sgn(Pt) * blk.mu_k)
        return y1, sticking

    def landing(t, y, j):
        """The landing at t of a block in the air (corner j's event first):
        (mode, k, sig, y after)."""
        th, w, vx, vy = y[2], y[5], y[3], y[4]
        if th == 0.0 and w == 0.0:
            if vx != 0.0:
                jj = int(sgn(vx))
                y1, sticking = struck(jj, y)
                if y1[5] * jj > 0:
                    impacts.append({"t": t, "theta_dot_before": w, "theta_dot_after": y1[5],
                                    "sticking": bool(sticking)})
                    u = blk.corner_velocity(jj, y1)[0]
                    st = settle(t, y1, "rock", jj, 0.0) if sticking else settle(t, y1, "slide_rock", jj, sgn(u))
                    return st + (y1,)
            pn = max(-vy, 0.0)
            u = 0.0 if abs(vx) <= blk.mu_s * pn else vx - sgn(vx) * blk.mu_k * pn
            impacts.append({"t": t, "theta_dot_before": 0.0, "theta_dot_after": 0.0, "sticking": u == 0.0})
            y1 = [y[0], blk.h, 0.0, u, 0.0, 0.0]
            st = from_rest(t, y1, False) if u == 0.0 else settle(t, y1, "slide", 0, sgn(u))
            return st + (y1,)
        if th != 0.0:
            j = int(sgn(th))
        y1, sticking = struck(j, y)
        impacts.append({"t": t, "theta_dot_before": w, "theta_dot_after": y1[5], "sticking": bool(sticking)})
        u = blk.corner_velocity(j, y1)[0]
        if th == 0.0 and (j * y1[5] <= 0 or abs(y1[5]) <= REST * p * alpha):
            y2 = [y1[0], blk.h, 0.0, 0.0 if sticking else u, 0.0, 0.0]
            st = from_rest(t, y2, False) if sticking or u == 0.0 else settle(t, y2, "slide", 0, sgn(u))
            return st + (y2,)
        if sticking:
            return settle(t, y1, "rock", j, 0.0) + (y1,)
        return settle(t, y1, "slide_rock", j, sgn(u)) + (y1,)

    out = {"overturned": False, "overturn_time": None, "overturn_side": None, "first_flight": None,
           "flights": 0, "rest_time": None, "undecided": False, "chatter": False}
    extremes = []
    t, y = 0.0, [0.0, blk.h, 0.0, 0.0, 0.0, 0.0]
    state = from_rest(0.0, y, False)
    moved = False
    guard = 0
    while True:
        mode, k, sig = state
        if mode == "flight":
            moved = True
            out["flights"] += 1
            if out["first_flight"] is None:
                out["first_flight"] = t
            s0 = slip("flight", 0, y)
            kind, te, ye = integrate("flight", 0, 0.0, t, y, extremes)
            raw.append(["flight", t, te, None, s0, slip("flight", 0, ye)])
            t, y = te, ye
            if kind == "cap":
                out["undecided"] = True
                break
            if kind == "overturn":
                out["overturned"], out["overturn_time"] = True, t
                out["overturn_side"] = float(sgn(y[2]))
                break
            state = landing(t, y, int(kind[4:]))
            y = state[3]
            state = state[:3]
            if len(impacts) >= MAX_IMPACTS:
                out["undecided"] = True
                break
            continue
        s0 = slip(mode, k, y)
        if mode == "stick":
            y = [y[0], blk.h, 0.0, 0.0, 0.0, 0.0]
            if t >= end:
                out["rest_time"] = t if moved else None
                break
            ts = next_onset(t)
            if ts is None:
                raw.append(["stick", t, end, None, s0, s0])
                if moved:
                    out["rest_time"] = t
                break
            raw.append(["stick", t, ts, None, s0, s0])
            t = ts
            state = from_rest(t, y, True)
            continue
        moved = True
        kind, te, ye = integrate(mode, k, sig, t, y)
        guard = guard + 1 if te - t < 1e-12 else 0
        if guard > 5:
            raise RuntimeError(f"zero-length transitions at t={t} in {mode}")
        raw.append([mode, t, te, (sig if mode != "rock" else None), s0, slip(mode, k, ye)])
        t, y = te, ye
        if kind == "cap":
            out["undecided"] = True
            break
        if kind == "lift":
            state = ("flight", 0, 0.0)
        elif kind == "overturn":
            out["overturned"], out["overturn_time"], out["overturn_side"] = True, t, float(k)
            break
        elif kind == "slip":
            F, _ = rock_needs(t, k, y)
            state = settle(t, y, "slide_rock", k, -sgn(F))
        elif kind == "stop" and mode == "slide":
            y[3] = 0.0
            state = from_rest(t, y, False)
            if state[0] == "stick" and t >= end:
                out["rest_time"] = t
                break
        elif kind == "stop":
            F, N = rock_needs(t, k, y)
            if abs(F) <= blk.mu_s * N:
                state = settle(t, y, "rock", k, 0.0)
            else:
                if -sgn(F) != -sig:
                    print(f"  note: slide-rock stop at {t}: rock needs F={F}, sliding {sig}", file=sys.stderr)
                state = settle(t, y, "slide_rock", k, -sig)
        elif kind == "impact":
            y[2] = 0.0
            pivot = k
            while True:
                j = -pivot
                w_before = y[5]
                y1, Pt, Pn = blk.impact(pivot, y, True)
                sticking = abs(Pt) <= blk.mu_s * Pn
                if not sticking:
                    y1, Pt, Pn = blk.impact(pivot, y, False, sgn(Pt) * blk.mu_k)
                impacts.append({"t": t, "theta_dot_before": w_before, "theta_dot_after": y1[5],
                                "sticking": bool(sticking)})
                y = y1
                if len(impacts) >= MAX_IMPACTS or abs(y[5]) < REST * p * alpha or j * y[5] > 0:
                    break
                # The impulse turned the block back towards the corner it
                # came from (possible for a sliding impact): that corner would
                # go into the floor.
                if REVERSAL == "flat":
                    break
                pivot = j          # "cascade": it lands at once, same rules
            if len(impacts) >= MAX_IMPACTS:
                out["undecided"] = True
                break
            if abs(y[5]) < REST * p * alpha or j * y[5] < 0:
                u = y[3] + y[5] * blk.corner(j, 0.0)[1]
                y = [y[0], blk.h, 0.0, u if not sticking else 0.0, 0.0, 0.0]
                if sticking or u == 0.0:
                    state = from_rest(t, y, False)
                else:
                    state = settle(t, y, "slide", 0, sgn(u))
            elif sticking:
                if t >= end and abs(y[5]) < 1e-6 * p * alpha and mode == "rock" and pivot == k:
                    tail = 2 * abs(y[5]) / (p * p * math.sin(alpha)) / (1 - eta)
                    raw.append(["rock", t, t + tail, None, slip("rock", j, y), slip("rock", j, y)])
                    out["rest_time"], out["chatter"] = t + tail, True
                    # The impacts of the tail, each rebound eta times the last,
                    # until one falls below the rest velocity.
                    out["tail_impacts"] = math.ceil(
                        math.log(REST * p * alpha / abs(y[5])) / math.log(eta))
                    t += tail
                    break
                state = settle(t, y, "rock", j, 0.0)
            else:
                state = settle(t, y, "slide_rock", j, sgn(blk.corner_velocity(j, y)[0]))
    modes = merge(raw)
    slips = [m["slip_to"] for m in modes]
    out.update({"modes": modes, "impacts": impacts,
                "impact_count": len(impacts) + out.get("tail_impacts", 0),
                "peak_slide": max([abs(s) for s in slips + extremes], default=0.0),
                "residual_slide": slips[-1] if slips else 0.0, "end": end})
    return out


def merge(raw):
    modes = []
    for mode, a, b, d, s0, s1 in raw:
        if mode != "flight" and b - a <= 1e-12 * max(abs(a), 1.0):
            continue
        last = modes[-1] if modes else None
        if last and last["mode"] == mode and (mode in ("rock", "stick") or last["direction"] == d):
            last["to"], last["slip_to"] = b, s1
            continue
        modes.append({"mode": mode, "from": a, "to": b, "direction": d, "slip_from": s0, "slip_to": s1})
    return modes


# ------------------------------------------------------------ self-tests ---
def self_test():
    for alpha in (0.1, 0.25, 0.4):
        blk = Block(alpha, 2.0, 1.0, 1.0)
        for k in (1, -1):
            # rocking back onto th = 0 on corner k, the corner held: w- = -k
            w = -k * 1.0
            rx, ry = blk.corner(k, 0.0)
            y = [0.0, blk.h, 0.0, -w * ry, w * rx, w]
            y1, Pt, Pn = blk.impact(k, y, True)
            eta = 1 - 1.5 * math.sin(alpha) ** 2
            assert abs(y1[5] / w - eta) < 1e-13, (alpha, y1[5] / w, eta)
            assert Pn > 0
            # free rocking at th = 0 from rest: th'' = -k p^2 sin(alpha)
            z = blk.solve("rock", k, 0.0, 0.0, G, [0.0, blk.h, 0.0, 0.0, 0.0, 0.0])
            assert abs(z[2] + k * blk.p ** 2 * math.sin(alpha)) < 1e-12
            # the threshold tan(alpha) g: th'' = 0 and F/N = tan(alpha)
            z = blk.solve("rock", k, 0.0, -k * blk.tan * G, G, [0.0, blk.h, 0.0, 0.0, 0.0, 0.0])
            assert abs(z[2]) < 1e-12 and abs(abs(z[3] / z[4]) - blk.tan) < 1e-12
    # record kinematics: a ramp a = t (0.1 s samples) integrates to t^2/2, t^3/6
    dt = 0.1
    acc = [k * dt for k in range(11)]
    for t in (0.0, 0.05, 0.3, 0.77, 1.0):
        v, u = ground_kinematics(dt, acc, t)
        assert abs(v - t * t / 2) < 1e-14 and abs(u - t ** 3 / 6) < 1e-14, (t, v, u)
    v, u = ground_kinematics(dt, acc, 1.5)
    assert abs(v - 0.5) < 1e-14 and abs(u - (1 / 6 + 0.5 * 0.5)) < 1e-14


# ----------------------------------------------------------------- cases ---
def _c(alpha, p, mu, shape, amp, wp, mu_k=None, tan_units=True, **kw):
    c = {"alpha": alpha, "p": p, "mu": mu, "shape": shape,
         "a_g": amp * math.tan(alpha) if tan_units else amp, "omega": wp * p}
    if mu_k is not None:
        c["mu_k"] = mu_k
    c.update(kw)
    return c


CASES = [
    # the locomotive (alpha 0.25, p 2.14, one-sine at omega = 3p, a_g = 2 and 4 x 0.25 g)
    _c(0.25, 2.14, 0.2, "one_sine", 0.5, 3, tan_units=False),
    _c(0.25, 2.14, 0.2, "one_sine", 1.0, 3, tan_units=False),
    _c(0.25, 2.14, 0.3, "one_sine", 0.5, 3, tan_units=False),
    _c(0.25, 2.14, 0.3, "one_sine", 1.0, 3, tan_units=False),
    # never moves, pure sliding (mu < tan alpha)
    _c(0.3, 2.0, 0.6, "one_sine", 0.8, 4),
    _c(0.2, 1.5, 0.1, "one_cosine", 1.5, 2, mu_k=0.08),
    _c(0.4, 2.5, 0.2, "c3", 2.0, 5),
    _c(0.35, 3.0, 0.3, "rectangular", 1.2, 6, mu_k=0.25),
    # rocking with a firm floor: rest, overturning, slender and squat
    _c(0.25, 2.14, 1.0, "one_sine", 2.0, 3),
    _c(0.25, 2.14, 1.0, "one_sine", 4.0, 3),
    _c(0.15, 2.0, 0.8, "one_sine", 3.0, 4),
    _c(0.1, 1.5, 0.5, "one_cosine", 2.0, 2),
    _c(0.4, 2.5, 1.0, "one_cosine", 1.5, 3),
    _c(0.45, 3.0, 0.9, "c3", 3.0, 6),
    _c(0.2, 2.5, 0.6, "rectangular", 1.5, 5),
    _c(0.3, 1.5, 0.7, "one_sine", 5.0, 8),
    # rocking that slips: slide-rock, sliding impacts
    _c(0.25, 2.14, 0.3, "one_sine", 3.0, 3),
    _c(0.3, 2.0, 0.35, "one_sine", 4.0, 5, mu_k=0.32),
    _c(0.2, 2.5, 0.25, "one_cosine", 3.0, 4, mu_k=0.21),
    _c(0.4, 1.8, 0.45, "c3", 3.0, 4),
    _c(0.15, 3.0, 0.2, "one_sine", 6.0, 6, mu_k=0.16),
    _c(0.35, 2.2, 0.4, "one_cosine", 2.5, 2.5),
    _c(0.1, 2.0, 0.12, "c3", 4.0, 7),
    # slide onset although mu_s >= tan alpha (the rock would need more friction)
    _c(0.3, 2.0, 0.32, "rectangular", 3.0, 4, mu_k=0.25),
    _c(0.3, 2.0, 0.33, "rectangular", 3.0, 4, mu_k=0.32),
    # sliding impacts: an overturning, a sliding impact that turns the block
    # back (see REVERSAL), a slide-rock chattering down to a flat slide
    {"alpha": 0.4, "p": 3.0, "mu": 0.446, "shape": "one_cosine", "a_g": 2.473051387278336,
     "omega": 10.126110755972402},
    {"alpha": 0.45, "p": 2.5, "mu": 0.512, "mu_k": 0.461, "shape": "one_sine", "a_g": 0.9998366962465205,
     "omega": 5.4977906618285655},
    {"alpha": 0.35, "p": 3.0, "mu": 0.39, "mu_k": 0.351, "shape": "c3", "a_g": 0.882497717321181,
     "omega": 6.069761841796002},
    # a lift of micro-radians, shorter than a step, twice (just above the
    # threshold); a slip that turns back at once after an impact, at the
    # friction limit (the locomotive, omega = 10p, 1.76 alpha g)
    _c(0.25, 2.14, 0.3, "one_sine", 1.0001, 3),
    _c(0.25, 2.14, 0.3, "one_sine", 1.76 * 0.25, 10, tan_units=False),
    _c(0.25, 2.14, 0.3, "one_sine", 2.225 * 0.25, 10, tan_units=False),
    # vertical: proportional and pulses of their own
    _c(0.25, 2.14, 0.3, "one_sine", 3.0, 3, ratio=0.5),
    _c(0.25, 2.14, 0.3, "one_sine", 3.0, 3, ratio=-0.5),
    _c(0.4, 2.0, 0.8, "one_cosine", 2.0, 3, ratio=0.5),
    _c(0.2, 2.0, 0.15, "one_sine", 1.5, 4, ratio=-0.5),
    _c(0.3, 2.0, 0.6, "one_sine", 2.0, 3,
       vertical={"shape": "one_sine", "a_g": 0.4, "omega": 12.0, "delay": 0.1}),
    _c(0.25, 2.5, 0.35, "one_sine", 3.0, 4, mu_k=0.3,
       vertical={"shape": "one_cosine", "a_g": -0.5, "omega": 9.0, "delay": 0.0}),
    _c(0.3, 2.0, 0.6, "one_sine", 1.6, 3,
       vertical={"shape": "one_sine", "a_g": 1.5, "omega": 8.0, "delay": 0.1}),
    _c(0.15, 2.0, 0.2, "c3", 1.5, 5,
       vertical={"shape": "c3", "a_g": 0.3, "omega": 20.0, "delay": 0.2}),
    # flight: a vertical pulse above g lifts a rocking, slide-rocking or
    # sliding block off the floor; it lands on a corner (rock, slide-rock)
    # or flat (stick, slide), then rests or overturns
    _c(0.2, 2.0, 0.3, "one_sine", 1.5, 2,
       vertical={"shape": "one_sine", "a_g": 1.2, "omega": 8.0, "delay": 0.0}),
    _c(0.2, 2.0, 0.3, "one_sine", 1.5, 2,
       vertical={"shape": "one_sine", "a_g": 1.6, "omega": 8.0, "delay": 0.15}),
    _c(0.2, 2.0, 0.8, "one_sine", 1.5, 4,
       vertical={"shape": "one_sine", "a_g": 1.2, "omega": 16.0, "delay": 0.0}),
    _c(0.2, 2.0, 0.3, "one_sine", 3.0, 4,
       vertical={"shape": "one_sine", "a_g": 1.6, "omega": 16.0, "delay": 0.15}),
    _c(0.35, 2.0, 0.3, "one_sine", 1.5, 2,
       vertical={"shape": "one_sine", "a_g": 1.6, "omega": 8.0, "delay": 0.0}),
    _c(0.35, 2.0, 0.3, "one_sine", 3.0, 4, mu_k=0.25,
       vertical={"shape": "one_sine", "a_g": 1.2, "omega": 16.0, "delay": 0.15}),
    # flight without vertical motion: a squat block spun off its corner
    # (the normal force falls to 0) under a strong one-cosine pulse
    _c(0.4, 2.14, 0.6, "one_cosine", 3.2, 2, mu_k=0.5, tan_units=False),
    # the demand for friction jumps past mu at the pulse's end: the pivot
    # slips from there, the way the free motion takes it
    _c(0.2, 2.0, 0.7, "one_cosine", 2.0, 1.5),
    _c(0.2, 3.0, 0.7, "one_cosine", 2.0, 1.5),
]


# Synthetic accelerograms (see `accelerogram`): (duration s, damped
# sinusoids (f Hz, A, zeta, t0 s, phi)).
RECORDS = {
    # 6 s, 1.2-4.9 Hz
    "A": (6.0, [(1.2, 1.0, 0.05, 0.0, 0.3), (2.3, 0.7, 0.08, 0.6, 1.1),
                (3.7, 0.4, 0.1, 1.1, 2.0), (4.9, 0.25, 0.1, 1.8, 0.5)]),
    # 8 s, long-period rich, 1.0-4.1 Hz
    "B": (8.0, [(1.0, 1.0, 0.04, 0.5, 0.0), (1.7, 0.8, 0.06, 0.0, 2.4),
                (2.9, 0.5, 0.08, 1.5, 4.0), (4.1, 0.3, 0.1, 2.2, 1.3)]),
    # 5 s, 1.4-4.6 Hz
    "C": (5.0, [(2.1, 1.0, 0.06, 0.0, 0.9), (3.3, 0.8, 0.07, 0.4, 3.1),
                (4.6, 0.6, 0.08, 0.9, 5.0), (1.4, 0.5, 0.05, 0.2, 2.2)]),
    # a vertical component, 6 s, 3.1-5 Hz
    "V": (6.0, [(3.1, 1.0, 0.07, 0.2, 0.4), (4.4, 0.8, 0.08, 0.5, 2.7),
                (5.0, 0.5, 0.1, 1.0, 1.9)]),
}


def _r(alpha, p, mu, rec, pga, mu_k=None, dt=0.01, vertical=None, **kw):
    """A record case: record `rec` of RECORDS at PGA `pga` g sampled every
    `dt`, optionally a vertical record (name, PGA g) of its own."""
    dur, parts = RECORDS[rec]
    c = {"alpha": alpha, "p": p, "mu": mu, "record": {"dt": dt, "acc": accelerogram(dur, dt, pga, parts)}}
    if mu_k is not None:
        c["mu_k"] = mu_k
    if vertical is not None:
        vdur, vparts = RECORDS[vertical[0]]
        c["vertical_record"] = {"dt": dt, "acc": accelerogram(vdur, dt, vertical[1], vparts)}
    c.update(kw)
    return c


CASES += [
    # records: a squat block that slides (mu < tan alpha), kinetic below static
    _r(0.4, 2.5, 0.25, "A", 0.7),
    _r(0.4, 2.5, 0.2, "B", 0.5, mu_k=0.17),
    # rocks and rests after the record; rests in a quiet stretch of it
    # (chattering while the ground moves), rocks again and rests
    _r(0.25, 2.14, 0.8, "A", 0.35),
    _r(0.25, 2.14, 0.8, "B", 0.35),
    # slide-rock (dt 0.005); one that rests in the record first
    _r(0.3, 2.0, 0.35, "C", 0.7, mu_k=0.32, dt=0.005),
    _r(0.25, 2.14, 0.3, "A", 0.6),
    # overturns after impacts
    _r(0.2, 3.0, 0.8, "A", 0.7),
    # slender: rests after 1778 impacts; overturns; rests in the record,
    # rocks again and overturns
    _r(0.1, 3.0, 0.5, "C", 0.25, dt=0.005),
    _r(0.12, 4.0, 0.6, "A", 0.3),
    _r(0.12, 2.5, 0.5, "B", 0.35),
    # a vertical record of its own: rocking, sliding, slide-rock, lift-off
    _r(0.3, 2.0, 0.6, "A", 0.5, vertical=("V", 0.3)),
    _r(0.25, 2.14, 0.35, "B", 0.6, vertical=("V", 0.4)),
    _r(0.4, 2.5, 0.25, "A", 0.6, vertical=("V", 0.4)),
    _r(0.2, 3.0, 0.3, "A", 0.5, vertical=("V", 0.6)),
    _r(0.3, 2.0, 0.6, "B", 0.5, vertical=("V", 1.05)),
    _r(0.4, 2.5, 0.25, "A", 0.6, vertical=("V", 1.5)),
    _r(0.2, 3.0, 0.5, "A", 0.5, vertical=("V", 1.3)),
    # proportional vertical (ratio * ug)
    _r(0.25, 2.14, 0.3, "B", 0.5, ratio=0.5),
    _r(0.3, 2.0, 0.35, "C", 0.7, mu_k=0.32, dt=0.005, ratio=0.3),
]


# --------------------------------------------------------------- compare ---
def impact_groups(r):
    """The impacts of a history split at the sticks (a stick's start is at
    or after the impacts before it)."""
    starts = [m["from"] for m in r["modes"] if m["mode"] == "stick"]
    groups = [[] for _ in range(len(starts) + 1)]
    for i in r["impacts"]:
        groups[sum(1 for s in starts if s < i["t"])].append(i)
    return groups


def compare(mine, ref):
    """(ok, first difference, dt, dx)."""
    dt = dx = 0.0
    ours = [(m["mode"], m["direction"]) for m in mine["modes"]]
    theirs = [(m["mode"], m["direction"]) for m in ref["modes"]]
    if ours != theirs:
        return False, "modes differ", dt, dx
    for key in ("overturned", "overturn_side"):
        if mine[key] != ref[key]:
            return False, key, dt, dx
    if mine["flights"] != ref["flights"]:
        return False, "flights", dt, dx
    if mine["impact_count"] != ref["impact_count"]:
        return False, "impact count", dt, dx
    # Each lists the impacts it followed one by one; a chattering tail is
    # summed (counted above, not listed) from a velocity of its own choosing,
    # so the lists are compared over their common length. A chattering that
    # comes to rest while the ground still moves (the engine sums it, this
    # model follows it) ends in a stick: the lists are compared stick by
    # stick (impacts grouped by the number of sticks begun before them).
    pairs = []
    for g_m, g_r in zip(impact_groups(mine), impact_groups(ref)):
        pairs += list(zip(g_m, g_r))
    if any(a["sticking"] != b["sticking"] for a, b in pairs):
        return False, "impact kind", dt, dx
    if (mine["rest_time"] is None) != (ref["rest_time"] is None):
        return False, "rest", dt, dx
    last = len(ref["modes"]) - 1
    for n, (a, b) in enumerate(zip(mine["modes"], ref["modes"])):
        dt = max(dt, abs(a["from"] - b["from"]))
        if not (ref["chatter"] and n == last):
            dt = max(dt, abs(a["to"] - b["to"]))
        dx = max(dx, abs(a["slip_from"] - b["slip_from"]), abs(a["slip_to"] - b["slip_to"]))
    for a, b in pairs:
        dt = max(dt, abs(a["t"] - b["t"]))
    for key in ("overturn_time", "first_flight"):
        if ref[key] is not None:
            dt = max(dt, abs(mine[key] - ref[key]))
    dx = max(dx, abs(mine["peak_slide"] - ref["peak_slide"]),
             abs(mine["residual_slide"] - ref["residual_slide"]))
    why = []
    if ref["rest_time"] is not None:
        dr = abs(mine["rest_time"] - ref["rest_time"])
        if dr > (CHATTER_T_TOL if ref["chatter"] else T_TOL):
            why.append(f"rest time {dr:.1e} s")
    if dt > T_TOL:
        why.append(f"time {dt:.1e} s")
    if dx > X_TOL:
        why.append(f"slip {dx:.1e} m")
    return not why, ", ".join(why), dt, dx


def seq(r):
    abbrev = {"stick": "St", "slide": "S", "rock": "R", "slide_rock": "SR", "flight": "F"}
    return " ".join(abbrev[m["mode"]] + ("" if m["direction"] is None else ("+" if m["direction"] > 0 else "-"))
                    for m in r["modes"])


def outcome(r):
    if r.get("undecided"):
        return "undecided"
    if r["overturned"]:
        return f"overturn{'+' if r['overturn_side'] > 0 else '-'} {r['overturn_time']:.4f}"
    if r["rest_time"] is not None:
        return f"rest {r['rest_time']:.4f}"
    return "never moves"


def describe(case):
    """A case's ground motion, for its line."""
    if "record" in case:
        rec = case["record"]
        dt, acc = rec["dt"], rec["acc"]
        v, u = record_kinematics(dt, acc)
        d = (f"record {len(acc)}x{dt:g}s PGA {max(abs(a) for a in acc) / G:.2f}g"
             f" PGV {np.abs(v).max():.2f} PGD {np.abs(u).max():.3f}")
        if "vertical_record" in case:
            d += f" +v PGA {max(abs(a) for a in case['vertical_record']['acc']) / G:.2f}g"
        elif "ratio" in case:
            d += " r=%+.1f" % case["ratio"]
        return d
    v = (" r=%+.1f" % case["ratio"]) if "ratio" in case else (" own-v" if "vertical" in case else "")
    return f"{case['shape']:11s} ag={case['a_g']:.3f} w/p={case['omega'] / case['p']:.1f}{v}"


def selection(spec, n):
    if not spec:
        return list(range(n))
    out = []
    for part in spec.split(","):
        a, _, b = part.partition("-")
        out += list(range(int(a), int(b or a) + 1))
    return [i for i in out if 0 <= i < n]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--engine", help="a built contact_cases example (default: cargo run)")
    ap.add_argument("--timeout", type=float, default=60.0, help="seconds allowed per engine case")
    ap.add_argument("--verbose", action="store_true")
    ap.add_argument("--reversal", choices=["cascade", "flat"], default="cascade",
                    help="a sliding impact that turns the block back: the other corner lands at once "
                         "(cascade) or the block lands flat (flat)")
    ap.add_argument("--only", help="case numbers to run, e.g. 0-5,40 (default: all)")
    args = ap.parse_args()
    global REVERSAL
    REVERSAL = args.reversal
    self_test()
    engine = args.engine
    if not engine:
        subprocess.run(["cargo", "build", "--quiet", "--release", "--example", "contact_cases"], check=True)
        engine = "target/release/examples/contact_cases"
    failed, worst_t, worst_x = 0, 0.0, 0.0
    chosen = selection(args.only, len(CASES))
    for n in chosen:
        case = CASES[n]
        ref = simulate(case)
        # One process per case, with a time limit: a hanging case is a
        # failure of its own and does not hide the others.
        try:
            out = subprocess.run([engine], input=json.dumps([case]), capture_output=True, text=True,
                                 check=True, timeout=args.timeout).stdout
            mine = json.loads(out)[0]
            ok, why, dt, dx = compare(mine, ref)
        except subprocess.TimeoutExpired:
            mine, ok, why, dt, dx = None, False, f"engine did not answer within {args.timeout:g} s", 0.0, 0.0
        failed += not ok
        worst_t, worst_x = max(worst_t, dt), max(worst_x, dx)
        print(f"{'ok  ' if ok else 'FAIL'} {n:2d} a={case['alpha']:.2f} p={case['p']:.2f} mu={case['mu']:.2f}"
              f"/{case.get('mu_k', case['mu']):.2f} {describe(case)}"
              f" | {outcome(ref)} imp={ref['impact_count']} res={ref['residual_slide']:+.5f} [{seq(ref)}]"
              f" |dt| {dt:.1e} |dx| {dx:.1e}" + ("" if ok else f"  <- {why}"))
        if mine is not None and (not ok or args.verbose):
            print(f"       engine: {outcome(mine)} imp={mine['impact_count']} res={mine['residual_slide']:+.5f} [{seq(mine)}]")
            if not ok:
                for a, b in zip(mine["modes"], ref["modes"]):
                    print(f"         eng {a['mode']:10s} {a['from']:.9f}-{a['to']:.9f} {a['slip_to']:+.9f}"
                          f" | ref {b['mode']:10s} {b['from']:.9f}-{b['to']:.9f} {b['slip_to']:+.9f}")
    print(f"{len(chosen) - failed}/{len(chosen)} agree; largest time difference {worst_t:.1e} s, "
          f"slip {worst_x:.1e} m (tolerances {T_TOL:g} s, {X_TOL:g} m)")
    sys.exit(1 if failed else 0)


if __name__ == "__main__":
    main()
