"""A rigid block on a Coulomb floor (stick, slide, rock, slide-rock, lift-off)
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
* lift-off where N or gz falls to 0: the history ends there;
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

Pulses as in bench/sliding_scipy.py (one-sine, one-cosine, rectangular,
Type-C3; vertical = ratio * ug or a pulse of its own `delay` s later).

topple's answers come from `examples/contact_cases.rs` (the engine's
dynamics::coulomb). Both sides' histories are merged into mode stretches
(rock merges across impacts; slide and slide-rock merge with the same
direction only; zero-length sticks omitted). Compared, tolerances:
* the mode sequence (names and directions) must be identical;
* outcome (overturned / lift-off / rest / undecided), overturn side, number
  of impacts and whether each one sticks must be identical;
* times (stretch bounds, impacts, overturn, lift-off, rest): 1e-7 s;
* slips (stretch ends, peak, residual): 1e-7 m;
* a rest reached by chattering (its time depends on the rest threshold and
  the tail summation) is compared to 1e-4 s.
A case prints FAIL with the first difference. Exit status 1 if any fails.

    python3 bench/contact_scipy.py [--engine target/release/examples/contact_cases] [--timeout 60]

Each case runs in its own engine process (time limit --timeout s), so a
case that hangs fails alone.
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


def motion(case):
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
        j = -k
        rx, ry = self.corner(j, 0.0)
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
        if mode in ("rock", "slide_rock"):
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
        grid = np.arange(t0, end + 1e-3, 1e-3)
        for a, b in zip(grid[:-1], grid[1:]):
            b = min(b, end)
            if b <= a:
                continue
            if over(b) > 0:
                return brentq(over, a, b, xtol=1e-15, rtol=8.9e-16)
        return None

    def integrate(mode, k, sig, t0, y0):
        """Integrate one mode from t0 to its first event: (kind, t, y)."""
        def rhs(t, y):
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
            nxt = [q for q in kinks if q > t + 1e-15]
            t1 = nxt[0] if nxt else cap
            sol = solve_ivp(rhs, (t, t1), y, method="DOP853", rtol=RTOL, atol=ATOL, events=events)
            hits = [(te[0], i) for i, te in enumerate(sol.t_events) if te.size]
            if hits:
                te, i = min(hits)
                return kinds[i], te, list(sol.y_events[i][0])
            t, y = t1, list(sol.y[:, -1])
            if t >= cap:
                return "cap", t, y

    raw, impacts = [], []
    out = {"overturned": False, "overturn_time": None, "overturn_side": None, "lift_off": None,
           "rest_time": None, "undecided": False, "chatter": False}
    t, y = 0.0, [0.0, blk.h, 0.0, 0.0, 0.0, 0.0]
    state = from_rest(0.0, y, False)
    moved = False
    guard = 0
    while True:
        mode, k, sig = state
        if mode == "flight":
            out["lift_off"] = t
            s1 = raw[-1][5] if raw else y[0]
            raw.append(["flight", t, t, None, s1, s1])
            break
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
                "peak_slide": max([abs(s) for s in slips], default=0.0),
                "residual_slide": slips[-1] if slips else 0.0, "end": end})
    return out


def merge(raw):
    modes = []
    for mode, a, b, d, s0, s1 in raw:
        if mode == "stick" and b <= a:
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
]


# --------------------------------------------------------------- compare ---
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
    if (mine["lift_off"] is None) != (ref["lift_off"] is None):
        return False, "lift_off", dt, dx
    if mine["impact_count"] != ref["impact_count"]:
        return False, "impact count", dt, dx
    # Each lists the impacts it followed one by one; a chattering tail is
    # summed (counted above, not listed) from a velocity of its own choosing,
    # so the lists are compared over their common length.
    n = min(len(mine["impacts"]), len(ref["impacts"]))
    if [i["sticking"] for i in mine["impacts"][:n]] != [i["sticking"] for i in ref["impacts"][:n]]:
        return False, "impact kind", dt, dx
    if (mine["rest_time"] is None) != (ref["rest_time"] is None):
        return False, "rest", dt, dx
    last = len(ref["modes"]) - 1
    for n, (a, b) in enumerate(zip(mine["modes"], ref["modes"])):
        dt = max(dt, abs(a["from"] - b["from"]))
        if not (ref["chatter"] and n == last):
            dt = max(dt, abs(a["to"] - b["to"]))
        dx = max(dx, abs(a["slip_from"] - b["slip_from"]), abs(a["slip_to"] - b["slip_to"]))
    for a, b in zip(mine["impacts"], ref["impacts"]):
        dt = max(dt, abs(a["t"] - b["t"]))
    for key in ("overturn_time", "lift_off"):
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
    if r["lift_off"] is not None:
        return f"lift-off {r['lift_off']:.4f}"
    if r["rest_time"] is not None:
        return f"rest {r['rest_time']:.4f}"
    return "never moves"


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--engine", help="a built contact_cases example (default: cargo run)")
    ap.add_argument("--timeout", type=float, default=60.0, help="seconds allowed per engine case")
    ap.add_argument("--verbose", action="store_true")
    ap.add_argument("--reversal", choices=["cascade", "flat"], default="cascade",
                    help="a sliding impact that turns the block back: the other corner lands at once "
                         "(cascade) or the block lands flat (flat)")
    args = ap.parse_args()
    global REVERSAL
    REVERSAL = args.reversal
    self_test()
    engine = args.engine
    if not engine:
        subprocess.run(["cargo", "build", "--quiet", "--release", "--example", "contact_cases"], check=True)
        engine = "target/release/examples/contact_cases"
    failed, worst_t, worst_x = 0, 0.0, 0.0
    for n, case in enumerate(CASES):
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
        v = (" r=%+.1f" % case["ratio"]) if "ratio" in case else (" own-v" if "vertical" in case else "")
        print(f"{'ok  ' if ok else 'FAIL'} {n:2d} a={case['alpha']:.2f} p={case['p']:.2f} mu={case['mu']:.2f}"
              f"/{case.get('mu_k', case['mu']):.2f} {case['shape']:11s} ag={case['a_g']:.3f} w/p={case['omega'] / case['p']:.1f}{v}"
              f" | {outcome(ref)} imp={ref['impact_count']} res={ref['residual_slide']:+.5f} [{seq(ref)}]"
              f" |dt| {dt:.1e} |dx| {dx:.1e}" + ("" if ok else f"  <- {why}"))
        if mine is not None and (not ok or args.verbose):
            print(f"       engine: {outcome(mine)} imp={mine['impact_count']} res={mine['residual_slide']:+.5f} [{seq(mine)}]")
            if not ok:
                for a, b in zip(mine["modes"], ref["modes"]):
                    print(f"         eng {a['mode']:10s} {a['from']:.9f}-{a['to']:.9f} {a['slip_to']:+.9f}"
                          f" | ref {b['mode']:10s} {b['from']:.9f}-{b['to']:.9f} {b['slip_to']:+.9f}")
    print(f"{len(CASES) - failed}/{len(CASES)} agree; largest time difference {worst_t:.1e} s, "
          f"slip {worst_x:.1e} m (tolerances {T_TOL:g} s, {X_TOL:g} m)")
    sys.exit(1 if failed else 0)


if __name__ == "__main__":
    main()
