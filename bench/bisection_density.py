#!/usr/bin/env python3
"""How often a record's outcome signature changes at the scan tolerance.

A record spectrum bisects every pair of neighbouring levels whose signature
(overturned, mode, impact count) differs, down to the tolerance. Under an
ordered record a few changes lie in each scan step and the bisection costs
about 20 simulations a scan point; under a chaotic one the signature changes
at every scale and it costs about 117 a bisected scan step (the valley record). This script measures the difference
directly: at M random (size, scale) points above the rocking threshold it
runs `topple run` on a time history at scale s and at s + tolerance
(tolerance 1e-4 s_α, s_α = α/PGA, the record spectrum's default) and counts
the pairs whose signature differs.

Run:
    python3 bench/bisection_density.py            # target/release/topple, M = 40
    python3 bench/bisection_density.py --pairs 80 --binary PATH

Standard library only; about 4 M runs of the binary.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import random
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from estimates import ROOT, at2_record, ridge_record  # noqa: E402


def signature(binary: str, path: str, rec: dict, s: float, alpha: float, r_m: float, eta) -> tuple:
    """(overturned, mode, impacts) of the block of size R (m) under `rec` times `s`."""
    p = math.sqrt(3 * 9.81 / (4 * r_m))
    block = {"alpha": alpha, "p": p}
    if eta is not None:
        block["eta"] = eta
    spec = {"kind": "time_history", "block": block,
            "ground_motion": {"dt": rec["dt"], "unit": "g", "acc": [a * s for a in rec["acc"]]}}
    with open(path, "w") as f:
        json.dump(spec, f)
    out = subprocess.run([binary, "run", path], capture_output=True, text=True, check=True)
    d = json.loads(out.stdout)
    over = d["overturned"]
    return (over, d.get("mode"), d["impact_count"] if over else d.get("rocking_impacts"))


def density(binary, name, rec, alpha, eta, sizes, lo, hi, pairs, seed=1) -> float:
    rnd = random.Random(seed)
    pga = max(abs(a) for a in rec["acc"])
    s_alpha = alpha / pga
    tol = 1e-4 * s_alpha
    lo = max(lo, s_alpha)
    differ = 0
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "spec.json")
        for _ in range(pairs):
            r_m, s = rnd.choice(sizes), rnd.uniform(lo, hi)
            a = signature(binary, path, rec, s, alpha, r_m, eta)
            b = signature(binary, path, rec, s + tol, alpha, r_m, eta)
            differ += a != b
    print(f"{name}: {differ} of {pairs} pairs a tolerance apart differ (f = {differ / pairs:.3f})")
    return differ / pairs


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--binary", default=os.path.join(ROOT, "target", "release", "topple"))
    ap.add_argument("--pairs", type=int, default=40)
    args = ap.parse_args()
    # The two record spectra of bench/estimates.py: chaotic and ordered.
    density(args.binary, "valley (specs/records/valley_record_spectrum.json)",
            at2_record("valley_station_000.at2"), 0.245, None, [0.3, 1.0, 2.0, 3.0], 0.0, 2.0, args.pairs)
    density(args.binary, "ridge (3 sizes to 4x)", ridge_record(), 0.15, 0.9, [0.5, 1.0, 2.0], 0.2, 4.0,
            args.pairs)
    return 0


if __name__ == "__main__":
    sys.exit(main())
