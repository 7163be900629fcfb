#!/usr/bin/env python3
"""The estimate table: what a submission estimates against what the job reports.

Starts `topple serve` on a free loopback port with a new SQLite database in a
temporary directory, then submits each job of a table covering every kind
(pulse shapes, formulations, methods, record lengths) one at a time with
`?wait=`, and compares the answer's `estimate` (simulations, seconds) with the
result's numerics (`simulations`, `wall_time_s`). Prints a Markdown table and
the largest ratio either way; exits 1 if a ratio is beyond --factor (2 by
default).

For a job computed in several tasks the time compared is its elapsed time
(finished_at − started_at), as its wall_time_s is its tasks' total compute
time. A job is run twice: first on a fresh instance (estimate from the cost model
alone), then, as a new submission of the same table in another order with its
seed or grid nudged, after the instance has measured its rates.

Run:
    python3 bench/estimates.py                      # target/release/topple
    python3 bench/estimates.py --binary PATH --json out.json

Standard library only.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import shutil
import socket
import subprocess
import sys
import tempfile
import time
import urllib.request

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def ridge_record() -> dict:
    """The example record of the repository (3,000 samples at 0.01 s), in g."""
    acc = []
    with open(os.path.join(ROOT, "specs", "records", "ridge_station_090.csv")) as f:
        for line in f:
            if line.startswith("#") or line.startswith("time"):
                continue
            acc.append(float(line.split(",")[1]))
    return {"dt": 0.01, "unit": "g", "acc": acc}


def at2_record(name: str) -> dict:
    """A record of specs/records in the PEER AT2 format (NPTS, DT on line 4), in g."""
    with open(os.path.join(ROOT, "specs", "records", name)) as f:
        lines = f.read().splitlines()
    head = lines[3].replace(",", " ").split()
    npts = int(head[head.index("NPTS=") + 1])
    dt = float(head[head.index("DT=") + 1])
    acc = [float(v) for line in lines[4:] for v in line.split()][:npts]
    return {"dt": dt, "unit": "g", "acc": acc}


def enveloped_record(seed: int, n: int, dt: float, peak_g: float) -> dict:
    """A record of `n` samples: 24 sines of log-uniform frequency in 0.3–8 Hz
    under a rise–plateau–decay envelope (as a real record has), peak `peak_g`."""
    state = seed

    def uniform() -> float:
        nonlocal state
        state = (state * 6364136223846793005 + 1442695040888963407) % (1 << 64)
        return (state >> 11) / float(1 << 53)

    comps = []
    for _ in range(24):
        f = 0.3 * (8.0 / 0.3) ** uniform()
        comps.append((2 * math.pi * f, 2 * math.pi * uniform(), 0.5 + uniform()))
    duration = n * dt
    raw = []
    for k in range(n):
        t = k * dt
        if t < 0.1 * duration:
            env = (t / (0.1 * duration)) ** 2
        elif t < 0.35 * duration:
            env = 1.0
        else:
            env = math.exp(-4.0 * (t - 0.35 * duration) / duration)
        raw.append(env * sum(w * math.sin(om * t + ph) for om, ph, w in comps))
    m = max(abs(a) for a in raw)
    return {"dt": dt, "unit": "g", "acc": [round(peak_g * a / m, 6) for a in raw]}


def table() -> list[tuple[str, dict]]:
    ridge = ridge_record()
    valley = at2_record("valley_station_000.at2")
    long40 = enveloped_record(7, 4000, 0.01, 0.45)
    short10 = enveloped_record(3, 1000, 0.01, 0.35)
    loco = {"alpha": 0.25, "p": 2.14, "eta": 0.9}
    return [
        ("time_history one_sine nonlinear", {
            "kind": "time_history", "block": loco,
            "pulse": {"type": "one_sine", "omega_ratio": 5, "a_p_alpha_g": 4}}),
        ("time_history one_sine linear exact", {
            "kind": "time_history", "block": loco, "formulation": "linear",
            "solver": {"method": "exact"},
            "pulse": {"type": "one_sine", "omega_ratio": 5, "a_p_alpha_g": 3.02}}),
        ("time_history ricker nonlinear", {
            "kind": "time_history", "block": loco,
            "pulse": {"type": "ricker", "omega_ratio": 3, "a_p_alpha_g": 3}}),
        ("time_history record 3,000 samples", {
            "kind": "time_history", "block": {"b": 0.3, "h": 2.0, "eta": 0.9},
            "ground_motion": ridge}),
        ("time_history record 4,000 samples", {
            "kind": "time_history", "block": {"alpha": 0.15, "p": 2.0, "eta": 0.9},
            "ground_motion": long40}),
        ("spectrum one_sine nonlinear 40 freq", {
            "kind": "spectrum", "block": loco, "pulse": {"type": "one_sine"},
            "formulation": "nonlinear", "omega_ratio": {"from": 0.25, "to": 10, "steps": 40},
            "a_max_alpha_g": 20}),
        ("spectrum one_sine linear exact 40 freq", {
            "kind": "spectrum", "block": loco, "pulse": {"type": "one_sine"},
            "formulation": "linear", "solver": {"method": "exact"},
            "omega_ratio": {"from": 0.25, "to": 10, "steps": 40}, "a_max_alpha_g": 20}),
        ("spectrum one_cosine nonlinear 20 freq", {
            "kind": "spectrum", "block": loco, "pulse": {"type": "one_cosine"},
            "omega_ratio": {"from": 1, "to": 8, "steps": 20}, "a_max_alpha_g": 10}),
        ("spectrum ricker nonlinear 20 freq", {
            "kind": "spectrum", "block": loco, "pulse": {"type": "ricker"},
            "omega_ratio": {"from": 1, "to": 8, "steps": 20}, "a_max_alpha_g": 10}),
        ("spectrum one_sine coulomb mu 0.3 20 freq", {
            "kind": "spectrum", "block": loco, "pulse": {"type": "one_sine"},
            "omega_ratio": {"from": 1, "to": 10.5, "steps": 20}, "a_max_alpha_g": 20,
            "contact": {"model": "coulomb", "mu": 0.3}, "no_sliding_beside": True}),
        ("friction_spectrum one_sine 90 amplitudes", {
            "kind": "friction_spectrum", "block": loco, "pulse": {"type": "one_sine"},
            "omega_ratio": 7.336, "a_alpha_g": {"from": 1.1, "to": 10, "steps": 90}}),
        ("forensic pulse 2 blocks 12 freq", {
            "kind": "forensic", "pulse": {"type": "one_sine"},
            "observations": [
                {"name": "locomotive", "block": loco, "overturned": True},
                {"name": "transformer", "b": 0.6, "h": 1.2, "overturned": False}],
            "frequency_hz": {"from": 0.25, "to": 3.0, "steps": 12},
            "a_p_g": {"from": 0.05, "to": 3.0}}),
        ("forensic record 3,000 samples 2 blocks", {
            "kind": "forensic", "ground_motion": ridge,
            "observations": [
                {"name": "tombstone", "b": 0.2, "h": 1.0, "overturned": True},
                {"name": "rock", "b": 0.6, "h": 1.2, "overturned": False}],
            "scale": {"from": 0.1, "to": 4}}),
        ("forensic valley record 2 observations", {
            "kind": "forensic", "ground_motion": valley,
            "observations": [{"name": "slender cabinet", "b": 0.25, "h": 1.0, "overturned": True},
                             {"name": "squat pedestal", "b": 0.4, "h": 0.8, "overturned": False}],
            "pga_g": {"from": 0.05, "to": 2.0}}),
        ("record_spectrum ridge 3 sizes to 4x", {
            "kind": "record_spectrum", "block": {"alpha": 0.15, "eta": 0.9},
            "R_m": [0.5, 1.0, 2.0], "scale": {"from": 0.2, "to": 4.0}, "ground_motion": ridge}),
        ("record_spectrum valley 4,000 samples 4 sizes to 2x", {
            "kind": "record_spectrum", "block": {"alpha": 0.245},
            "R_m": [0.3, 1.0, 2.0, 3.0], "scale": {"from": 0.0, "to": 2.0},
            "ground_motion": valley}),
        ("record_spectrum 10 s record 5 sizes to 3x", {
            "kind": "record_spectrum", "block": {"alpha": 0.2},
            "R_m": {"from": 0.3, "to": 3, "steps": 5}, "scale": {"to": 3.0},
            "ground_motion": short10}),
        ("record_spectrum 40 s record 10 sizes to 5x", {
            "kind": "record_spectrum", "block": {"alpha": 0.15, "eta": 0.9},
            "R_m": {"from": 0.5, "to": 5, "steps": 10}, "scale": {"to": 5.0},
            "ground_motion": long40}),
        ("fragility pulse b,h uncertain 15 stripes x 200", {
            "kind": "fragility",
            "block": {"b": {"dist": "normal", "mean": 0.6, "sd": 0.06, "min": 0.4, "max": 0.8},
                      "h": {"dist": "normal", "mean": 1.5, "sd": 0.1, "min": 1.2, "max": 1.8}},
            "pulse": {"type": "one_sine", "frequency_hz": {"dist": "lognormal", "median": 1.0, "beta": 0.4}},
            "im": "pga_g", "stripes": {"from": 0.1, "to": 1.5, "steps": 15}, "samples": 200, "seed": 42}),
        ("fragility record suite 2 records 8 stripes x 20", {
            "kind": "fragility", "block": {"alpha": 0.2, "p": 2.0, "eta": 0.9},
            "ground_motions": [ridge, short10], "im": "pga_g",
            "stripes": {"from": 0.1, "to": 0.8, "steps": 8}, "samples": 20, "seed": 1}),
        ("survival power law 3 ages", json.load(open(os.path.join(ROOT, "specs", "survival_power_law.json")))),
    ]


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def request(url: str, method: str = "GET", body: dict | None = None, timeout: float = 900):
    data = None if body is None else json.dumps(body).encode()
    req = urllib.request.Request(url, data=data, method=method,
                                 headers={"content-type": "application/json"})
    try:
        with urllib.request.urlopen(req, timeout=timeout) as r:
            return r.status, json.loads(r.read() or b"null")
    except urllib.error.HTTPError as e:
        return e.code, json.loads(e.read() or b"null")


def iso(t: str) -> float:
    """Seconds of an RFC 3339 time."""
    from datetime import datetime
    return datetime.fromisoformat(t.replace("Z", "+00:00")).timestamp()


def simulations_of(result: dict) -> float:
    n = result.get("numerics") or {}
    for key in ("simulations",):
        if key in n:
            return float(n[key])
    return 1.0


def nudge(spec: dict) -> dict:
    """The same job, not byte-identical (a new key, so it computes again)."""
    s = json.loads(json.dumps(spec))
    if "seed" in s:
        s["seed"] += 1
    elif "block" in s and isinstance(s["block"], dict) and "eta" in s["block"] and isinstance(s["block"]["eta"], float):
        s["block"]["eta"] = round(s["block"]["eta"] - 0.001, 6)
    elif s["kind"] == "survival":
        s["age_years"] = [a + 1 for a in s["age_years"]]
    elif "block" in s and isinstance(s["block"], dict):
        s["block"]["eta"] = 0.85
    else:
        s["formulation"] = s.get("formulation", "nonlinear")
        s["tolerance_g"] = 2e-4
    return s


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--binary", default=os.path.join(ROOT, "target", "release", "topple"))
    ap.add_argument("--factor", type=float, default=2.0)
    ap.add_argument("--json", help="write every row as JSON here")
    ap.add_argument("--only", help="run only rows whose name contains this")
    args = ap.parse_args()
    tmp = tempfile.mkdtemp(prefix="topple-estimates-")
    binary = os.path.join(tmp, "topple")
    shutil.copy(args.binary, binary)
    port = free_port()
    log = open(os.path.join(tmp, "server.log"), "w")
    proc = subprocess.Popen([binary, "serve", "--addr", f"127.0.0.1:{port}",
                             "--database", f"sqlite://{tmp}/db.sqlite"],
                            stdout=log, stderr=subprocess.STDOUT)
    base = f"http://127.0.0.1:{port}"
    rows = []
    try:
        for _ in range(200):
            try:
                if request(base + "/healthz", timeout=1)[0] == 200:
                    break
            except OSError:
                time.sleep(0.05)
        jobs = [(n, s) for n, s in table() if not args.only or args.only in n]
        for round_name, specs in (("fresh", jobs), ("measured", [(n, nudge(s)) for n, s in reversed(jobs)])):
            for name, spec in specs:
                status, doc = request(base + "/v1/jobs?wait=60", "POST", spec)
                estimate = doc.get("estimate") if isinstance(doc, dict) else None
                while status in (200, 202) and doc.get("status") in ("queued", "running"):
                    status, doc = request(base + f"/v1/jobs/{doc['id']}?wait=60")
                if status == 200 and doc.get("status") == "succeeded" and "result" not in doc:
                    _, result = request(base + f"/v1/jobs/{doc['id']}/result")
                    doc["result"] = result
                if estimate:
                    doc["estimate"] = estimate
                if status != 200 or doc.get("status") != "succeeded":
                    print(f"{name}: {status} {json.dumps(doc)[:400]}", file=sys.stderr)
                    continue
                est = doc["estimate"]
                result = doc["result"]
                sims = simulations_of(result)
                # What the job took from its start to its end: a job split
                # into tasks reports their total compute time as its
                # wall_time_s, which counts tasks computed at once twice.
                elapsed = (iso(doc["finished_at"]) - iso(doc["started_at"]))
                wall = min(float(result["numerics"]["wall_time_s"]), elapsed) if result["numerics"].get("tasks") else float(result["numerics"]["wall_time_s"])
                row = {
                    "round": round_name, "job": name,
                    "est_simulations": est["simulations"], "simulations": sims,
                    "est_seconds": est["seconds"], "wall_time_s": wall,
                }
                row["ratio_simulations"] = est["simulations"] / max(sims, 1.0)
                # Below 10 ms, a wall time is overhead and noise, not work
                # (and Retry-After counts whole seconds): both are floored there.
                row["ratio_seconds"] = max(est["seconds"], 1e-2) / max(wall, 1e-2)
                rows.append(row)
                print(f"{round_name:8} {name:48} sims {est['simulations']:>10.0f} / {sims:>8.0f} "
                      f"({row['ratio_simulations']:.2f})  s {est['seconds']:>8.3f} / {wall:>8.3f} "
                      f"({row['ratio_seconds']:.2f})", flush=True)
    finally:
        proc.terminate()
        proc.wait(timeout=30)
    print()
    print("| round | job | estimated simulations | simulations | ratio | estimated s | took s | ratio |")
    print("|---|---|---:|---:|---:|---:|---:|---:|")
    for r in rows:
        print(f"| {r['round']} | {r['job']} | {r['est_simulations']:.0f} | {r['simulations']:.0f} | "
              f"{r['ratio_simulations']:.2f} | {r['est_seconds']:.3f} | {r['wall_time_s']:.3f} | {r['ratio_seconds']:.2f} |")
    worst = max((max(r["ratio_simulations"], 1 / r["ratio_simulations"],
                     r["ratio_seconds"], 1 / r["ratio_seconds"]), r["job"], r["round"]) for r in rows)
    print(f"\nworst ratio either way: {worst[0]:.2f} ({worst[2]}: {worst[1]})")
    if args.json:
        with open(args.json, "w") as f:
            json.dump(rows, f, indent=1)
    shutil.rmtree(tmp, ignore_errors=True)
    return 0 if worst[0] <= args.factor else 1


if __name__ == "__main__":
    sys.exit(main())
