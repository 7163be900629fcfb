#!/usr/bin/env python3
"""Upload time of a 200,000-sample record: POST /v1/records of the same
motion (1,000 s at dt = 0.005 s) as a PEER AT2 file, as a two-column CSV
with a header, and as JSON, against a release `topple serve` on SQLite —
each upload a new record (one sample changed per run), and a re-upload of
one already stored (200: read, hashed, found). Prints the median and range of
the wall time per upload as the client sees it, and the file sizes.

Usage: python3 bench/record_upload.py [--binary target/release/topple] [--runs 9]
"""

import argparse
import json
import math
import statistics
import subprocess
import tempfile
import time
import urllib.request

from scale_out import start

N = 200_000
DT = 0.005


def motion(bump):
    out = []
    for k in range(N):
        t = k * DT
        out.append(0.3 * math.sin(2 * math.pi * 1.3 * t) * math.exp(-t / 300.0))
    out[1000] += bump * 1e-7
    return out


def at2(acc):
    lines = ["PEER NGA STRONG MOTION DATABASE RECORD",
             "Bench Event 2026, Bench Station, 090",
             "ACCELERATION TIME SERIES IN UNITS OF G",
             f"NPTS= {N}, DT=   .0050 SEC"]
    for i in range(0, N, 5):
        lines.append("".join(f"{a:15.7E}" for a in acc[i:i + 5]))
    return "\n".join(lines) + "\n"


def csv(acc):
    rows = ["# Bench Event 2026, Bench Station, 090", "time_s,acc_g"]
    rows += [f"{k * DT:.3f},{a:.7E}" for k, a in enumerate(acc)]
    return "\n".join(rows) + "\n"


def as_json(acc):
    return json.dumps({"name": "Bench Event 2026", "dt": DT, "unit": "g",
                       "acc": [float(f"{a:.7E}") for a in acc]})


def upload(base, body):
    req = urllib.request.Request(f"{base}/v1/records", data=body.encode(), method="POST",
                                 headers={"content-type": "text/plain"})
    t0 = time.perf_counter()
    with urllib.request.urlopen(req, timeout=120) as r:
        r.read()
        status = r.status
    return time.perf_counter() - t0, status


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--binary", default="target/release/topple")
    ap.add_argument("--runs", type=int, default=9)
    args = ap.parse_args()
    with tempfile.TemporaryDirectory() as d:
        proc, base = start(args.binary, f"sqlite://{d}/topple.db", "records", workers=2)
        try:
            print(f"{N} samples; median (min–max) of {args.runs} uploads, s")
            for name, write in [("at2", at2), ("csv", csv), ("json", as_json)]:
                times, size = [], 0
                for run in range(args.runs):
                    body = write(motion(hash((name, run)) % 1000 + 1))
                    size = len(body)
                    took, status = upload(base, body)
                    assert status == 201, status
                    times.append(took)
                again, status = upload(base, body)
                assert status == 200, status
                print(f"{name:5} {size / 1e6:5.1f} MB  new: {statistics.median(times):.3f} "
                      f"({min(times):.3f}–{max(times):.3f})  again: {again:.3f}")
        finally:
            proc.terminate()
            proc.wait()


if __name__ == "__main__":
    main()
