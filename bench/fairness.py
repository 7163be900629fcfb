#!/usr/bin/env python3
"""Fair turns: a small job is not held behind big ones.

With two record spectra of a 40-s record (4,000 samples at 0.01 s, ten
sizes, scale to 5 × PGA) running, time histories are submitted one after
another — by the tenant that submitted the spectra and by another — and the
time from each submission to its finished status is measured (submitted
with ?wait=, so the answer comes as soon as the job is done).

Setups: one instance on SQLite, and two instances on one PostgreSQL
(127.0.0.1:5432, user postgres, trust auth; a new database, dropped at the
end), the time histories sent to both alternately. Each instance runs with
the default workers (the number of cores). Prints, per setup and tenant, the
time histories' latencies (median, largest) and the spectra's progress
meanwhile; exits 1 if any time history took longer than --limit (2 s).
With --big forensic the two big jobs are forensic queries of three blocks
on such a record instead.

    python3 bench/fairness.py [--binary target/release/topple] [--setups sqlite,postgres]

Standard library only.
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import socket
import statistics
import subprocess
import sys
import tempfile
import time
import urllib.error
import urllib.request

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from estimates import enveloped_record  # noqa: E402

ADMIN = os.environ.get("TOPPLE_TEST_POSTGRES", "postgres://postgres@127.0.0.1:5432/postgres")


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def request(url, method="GET", body=None, token=None, timeout=120):
    data = None if body is None else json.dumps(body).encode()
    headers = {"content-type": "application/json"}
    if token:
        headers["authorization"] = f"Bearer {token}"
    req = urllib.request.Request(url, data=data, method=method, headers=headers)
    try:
        with urllib.request.urlopen(req, timeout=timeout) as r:
            return r.status, json.loads(r.read() or b"null")
    except urllib.error.HTTPError as e:
        return e.code, json.loads(e.read() or b"null")


def tokens(binary: str, tmp: str) -> tuple[dict, str]:
    """Tokens of tenants `lab` and `field`, and the tokens file."""
    out, lines = {}, []
    for name in ("lab", "field"):
        made = json.loads(subprocess.run([binary, "token", name], capture_output=True, text=True,
                                         check=True).stdout)
        out[name] = made["token"]
        lines.append(made["line"])
    path = os.path.join(tmp, "tokens")
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")
    return out, path


def start(binary, database, tokens_file, name, log_dir):
    port = free_port()
    log = open(os.path.join(log_dir, f"{name}.log"), "w")
    p = subprocess.Popen([binary, "serve", "--addr", f"127.0.0.1:{port}", "--database", database,
                          "--tokens-file", tokens_file, "--instance", name],
                         stdout=log, stderr=subprocess.STDOUT)
    base = f"http://127.0.0.1:{port}"
    for _ in range(400):
        try:
            if request(base + "/readyz", timeout=1)[0] == 200:
                return p, base
        except OSError:
            pass
        time.sleep(0.05)
    p.kill()
    sys.exit(f"{name} never became ready")


def spectrum(seed: int) -> dict:
    return {"kind": "record_spectrum", "block": {"alpha": 0.15, "eta": 0.9},
            "R_m": {"from": 0.5, "to": 5, "steps": 10}, "scale": {"to": 5.0},
            "ground_motion": enveloped_record(seed, 4000, 0.01, 0.45)}


def forensic(seed: int) -> dict:
    # Three blocks seen after the same 40-s record, scales to 5 x PGA.
    return {"kind": "forensic", "scale": {"to": 5.0},
            "observations": [
                {"name": "column", "overturned": True, "block": {"alpha": 0.15, "p": 2.2}},
                {"name": "cabinet", "overturned": False, "block": {"alpha": 0.2, "p": 2.7}},
                {"name": "statue", "overturned": True, "block": {"alpha": 0.12, "p": 3.0}}],
            "ground_motion": enveloped_record(seed, 4000, 0.01, 0.45)}


BIG = {"record_spectrum": spectrum, "forensic": forensic}


def history(k: int) -> dict:
    # Distinct specs: each is computed, none answered from the cache.
    return {"kind": "time_history", "block": {"alpha": 0.25, "p": 2.14, "eta": 0.9},
            "pulse": {"type": "one_sine", "omega_ratio": 3 + 0.01 * (k % 100),
                      "a_p_alpha_g": 2.5 + 1e-4 * (os.getpid() % 1000)}}


def measure(bases, tok, histories, limit, kind):
    big = []
    for i, seed in enumerate((11, 12)):
        status, doc = request(bases[0] + "/v1/jobs", "POST", BIG[kind](seed), tok["lab"])
        assert status == 202, (status, doc)
        big.append(doc["id"])
        print(f"  {kind} {doc['id']}: estimated {doc['estimate']['simulations']:.0f} "
              f"simulations, {doc['estimate']['seconds']:.0f} s", flush=True)
    # Both running.
    deadline = time.time() + 60
    while time.time() < deadline:
        states = [request(bases[0] + f"/v1/jobs/{j}", token=tok["lab"])[1]["status"] for j in big]
        if all(s == "running" for s in states):
            break
        time.sleep(0.2)
    time.sleep(2.0)
    rows = {"lab": [], "field": []}
    for k in range(histories):
        tenant = ("lab", "field")[k % 2]
        base = bases[k % len(bases)]
        t0 = time.monotonic()
        status, doc = request(base + "/v1/jobs?wait=30", "POST", history(k), tok[tenant])
        dt = time.monotonic() - t0
        ok = status == 200 and doc.get("status") == "succeeded"
        rows[tenant].append(dt if ok else float("inf"))
        progress = [request(bases[0] + f"/v1/jobs/{j}", token=tok["lab"])[1].get("progress", 0) for j in big]
        print(f"  time history {k:2} by {tenant:5} on instance {k % len(bases)}: {dt:6.3f} s "
              f"({doc.get('status')}); spectra at {progress[0]:.3f}, {progress[1]:.3f}", flush=True)
        time.sleep(0.7)
    for j in big:
        request(bases[0] + f"/v1/jobs/{j}/cancel", "POST", token=tok["lab"])
    worst = 0.0
    for tenant, ts in rows.items():
        print(f"  {tenant:5}: {len(ts)} time histories, median {statistics.median(ts):.3f} s, "
              f"largest {max(ts):.3f} s")
        worst = max(worst, max(ts))
    return worst


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--binary", default=os.path.join(ROOT, "target", "release", "topple"))
    ap.add_argument("--setups", default="sqlite,postgres")
    ap.add_argument("--histories", type=int, default=20)
    ap.add_argument("--limit", type=float, default=2.0)
    ap.add_argument("--big", choices=sorted(BIG), default="record_spectrum",
                    help="the kind of the two big jobs: record spectra, or forensic queries "
                         "of three blocks on the same 40-s record")
    args = ap.parse_args()
    tmp = tempfile.mkdtemp(prefix="topple-fairness-")
    binary = os.path.join(tmp, "topple")
    shutil.copy(args.binary, binary)
    tok, tokens_file = tokens(binary, tmp)
    worst = {}
    for setup in args.setups.split(","):
        procs = []
        db_name = f"topple_fair_{os.getpid()}"
        try:
            if setup == "sqlite":
                print("one instance, SQLite", flush=True)
                p, base = start(binary, f"sqlite://{tmp}/db.sqlite", tokens_file, "a", tmp)
                procs.append(p)
                bases = [base]
            else:
                print("two instances, PostgreSQL", flush=True)
                subprocess.run(["psql", ADMIN, "-q", "-c", f"CREATE DATABASE {db_name}"], check=True)
                url = ADMIN.rsplit("/", 1)[0] + "/" + db_name
                bases = []
                for name in ("a", "b"):
                    p, base = start(binary, url, tokens_file, name, tmp)
                    procs.append(p)
                    bases.append(base)
            worst[setup] = measure(bases, tok, args.histories, args.limit, args.big)
        finally:
            for p in procs:
                p.terminate()
            for p in procs:
                p.wait(timeout=60)
            if setup != "sqlite":
                subprocess.run(["psql", ADMIN, "-q", "-c", f"DROP DATABASE IF EXISTS {db_name} WITH (FORCE)"])
    print()
    for setup, w in worst.items():
        print(f"{setup}: slowest time history {w:.3f} s (limit {args.limit} s)")
    shutil.rmtree(tmp, ignore_errors=True)
    return 0 if all(w <= args.limit for w in worst.values()) else 1


if __name__ == "__main__":
    sys.exit(main())
