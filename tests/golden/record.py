#!/usr/bin/env python3
"""A golden corpus of topple's outputs: every spec of specs/ and variants of
every kind (linear and nonlinear, every pulse type, records, lift-off, a
fragility split across tasks, a survival naming a fragility job) as the JSON
result, the CSV table and the SVG figure, from `topple run` and from a live
server. Timings, ids and the engine's version string are blanked, so two
corpora of the same engine are equal byte for byte.

    record.py TOPPLE_BIN OUT_DIR          write the corpus
    GOLDEN_ONLY=regex record.py ...       only the cases whose name matches
    diff -r OUT_DIR_BEFORE OUT_DIR_AFTER  compare two

Used to show that a change of structure changes no output.
"""

import json
import os
import re
import shutil
import socket
import subprocess
import sys
import tempfile
import time
import urllib.request

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
RECORDS = os.path.join(ROOT, "specs", "records")

BLOCK = {"alpha": 0.25, "p": 2.14, "eta": 0.9}
PULSES = [
    {"type": "one_sine"}, {"type": "one_cosine"}, {"type": "cn", "n": 2},
    {"type": "half_sine"}, {"type": "rectangular"}, {"type": "ricker"},
    {"type": "ricker", "symmetric": False},
    {"type": "mavroeidis_papageorgiou", "gamma": 2.5, "nu": 90},
]


def variants():
    """(name, spec) of every case beside specs/*.json."""
    out = []
    for pulse in PULSES:
        tag = pulse["type"] + ("_antisym" if pulse.get("symmetric") is False else "")
        for form in ["nonlinear", "linear"]:
            out.append((f"th_{tag}_{form}", {
                "kind": "time_history", "block": BLOCK, "formulation": form,
                "pulse": dict(pulse, omega_ratio=3.0, a_p_alpha_g=2.5),
                "outputs": {"series": 40}}))
        out.append((f"spectrum_{tag}", {
            "kind": "spectrum", "block": BLOCK, "pulse": pulse,
            "omega_ratio": [1.0, 3.0, 6.0], "a_max_alpha_g": 12}))
        out.append((f"friction_{tag}", {
            "kind": "friction_spectrum", "block": dict(BLOCK, mu=0.4), "pulse": pulse,
            "omega_ratio": 3.0, "a_alpha_g": [1.5, 3.0, 6.0]}))
    out += [
        ("th_liftoff", {
            "kind": "time_history", "block": BLOCK,
            "pulse": {"type": "one_cosine", "omega_ratio": 1.0, "a_p_alpha_g": 6.0},
            "outputs": {"series": 50}}),
        ("friction_liftoff", {
            "kind": "friction_spectrum", "block": BLOCK, "pulse": {"type": "one_cosine"},
            "omega_ratio": 1.0, "a_alpha_g": [2.0, 6.0]}),
        ("th_no_reactions", {
            "kind": "time_history", "block": {"alpha": 0.25, "p": 2.14},
            "pulse": {"type": "one_sine", "omega_ratio": 3.0, "a_p_alpha_g": 2.0},
            "formulation": "linear", "outputs": {"reactions": False, "impacts": False}}),
        ("th_record_inline", {
            "kind": "time_history", "block": {"b": 0.6, "h": 1.2, "mu": 0.5},
            "ground_motion": {"dt": 0.01, "unit": "g",
                              "acc": [0.0, 0.3, 0.5, 0.2, -0.4, -0.1, 0.0]},
            "outputs": {"series": 20}}),
        ("th_record_file", {
            "kind": "time_history", "block": {"alpha": 0.15, "p": 2.0, "eta": 0.9},
            "ground_motion": {"file": os.path.join(RECORDS, "ridge_station_090.at2")},
            "outputs": {"series": 30}}),
        ("fragility_records", {
            "kind": "fragility", "block": {"alpha": 0.2, "p": 2.0},
            "ground_motions": [
                {"file": os.path.join(RECORDS, "ridge_station_090.csv")},
                {"file": os.path.join(RECORDS, "ridge_station_090.at2"),
                 "name": "the same as AT2"}],
            "stripes": [0.2, 0.4], "samples": 16, "seed": 1}),
    ]
    return out


def blank(text):
    """The text with what differs from run to run blanked."""
    text = re.sub(r'"(wall_time_s|simulations_per_second|created_at|started_at|finished_at|id|key)":\s*("[^"]*"|[0-9.eE+-]+)',
                  r'"\1": "-"', text)
    text = re.sub(r"topple-engine/[0-9A-Za-z./-]+", "topple-engine/-", text)
    text = re.sub(r"(wall[ _]time[^0-9]{0,12})[0-9.eE+-]+", r"\1-", text)
    text = re.sub(r"[0-9a-f]{8}-[0-9a-f]{4}-[0-9a-f]{4}-[0-9a-f]{4}-[0-9a-f]{12}", "<uuid>", text)
    return text


ONLY = re.compile(os.environ.get("GOLDEN_ONLY", ""))


def write(out_dir, name, text):
    with open(os.path.join(out_dir, name), "w") as f:
        f.write(blank(text))


def cli(binary, out_dir, name, spec):
    if not ONLY.search(name):
        return
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "spec.json")
        svg = os.path.join(tmp, "figure.svg")
        with open(path, "w") as f:
            json.dump(spec, f)
        res = subprocess.run([binary, "run", path, "--plot", svg], capture_output=True,
                             timeout=600)
        write(out_dir, f"cli_{name}.json", res.stdout.decode() + f"\nexit {res.returncode}\n"
              + res.stderr.decode())
        if os.path.exists(svg):
            write(out_dir, f"cli_{name}.svg", open(svg).read())
        res = subprocess.run([binary, "run", path, "--format", "csv"], capture_output=True,
                             timeout=600)
        write(out_dir, f"cli_{name}.csv", res.stdout.decode() + f"\nexit {res.returncode}\n")


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def request(base, method, path, body=None, ctype="application/json"):
    data = None if body is None else (body if isinstance(body, bytes) else json.dumps(body).encode())
    req = urllib.request.Request(base + path, data=data, method=method)
    if data is not None:
        req.add_header("Content-Type", ctype)
    try:
        with urllib.request.urlopen(req, timeout=600) as r:
            return r.status, r.read().decode()
    except urllib.error.HTTPError as e:
        return e.code, e.read().decode()


def served(base, out_dir, name, spec):
    if not ONLY.search(name) and not name.startswith("fragility_pbr"):
        return None
    status, text = request(base, "POST", "/v1/jobs?wait=600", spec)
    doc = json.loads(text)
    job = doc.get("id")
    for _ in range(1200):
        status, text = request(base, "GET", f"/v1/jobs/{job}")
        if json.loads(text).get("status") in ("succeeded", "failed", "canceled"):
            break
        time.sleep(0.5)
    for suffix, query in [("json", ""), ("csv", "?format=csv"), ("svg", "?format=svg")]:
        status, text = request(base, "GET", f"/v1/jobs/{job}/result{query}")
        write(out_dir, f"srv_{name}.{suffix}", f"{status}\n{text}")
    return job


def main():
    binary, out_dir = sys.argv[1], sys.argv[2]
    if not os.environ.get("GOLDEN_ONLY"):
        shutil.rmtree(out_dir, ignore_errors=True)
    os.makedirs(out_dir, exist_ok=True)
    cases = [(os.path.splitext(os.path.basename(p))[0], json.load(open(os.path.join(ROOT, "specs", p))))
             for p in sorted(os.listdir(os.path.join(ROOT, "specs"))) if p.endswith(".json")]
    ridge = json.load(open(os.path.join(RECORDS, "record_spectrum_ridge.json")))
    ridge["ground_motion"]["file"] = os.path.join(RECORDS, ridge["ground_motion"]["file"])
    cases.append(("record_spectrum_ridge", ridge))
    cases += variants()
    for name, spec in cases:
        cli(binary, out_dir, name, spec)
    with tempfile.TemporaryDirectory() as tmp:
        port = free_port()
        base = f"http://127.0.0.1:{port}"
        server = subprocess.Popen([binary, "serve", "--addr", f"127.0.0.1:{port}",
                                   "--database", f"sqlite://{tmp}/golden.db"],
                                  stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        try:
            for _ in range(100):
                try:
                    request(base, "GET", "/healthz")
                    break
                except OSError:
                    time.sleep(0.1)
            # A record by id.
            status, text = request(base, "POST", "/v1/records",
                                   open(os.path.join(RECORDS, "ridge_station_090.at2"), "rb").read(),
                                   "text/plain")
            write(out_dir, "srv_record_upload.json", f"{status}\n{text}")
            record = json.loads(text)["id"]
            served(base, out_dir, "th_record_id", {
                "kind": "time_history", "block": {"alpha": 0.15, "p": 2.0, "eta": 0.9},
                "ground_motion": {"record": record}, "outputs": {"series": 30}})
            ridge = json.load(open(os.path.join(RECORDS, "record_spectrum_ridge.json")))
            ridge["ground_motion"] = {"record": record}
            served(base, out_dir, "record_spectrum_id", ridge)
            # A fragility split across tasks, then a survival naming it.
            fragility = json.load(open(os.path.join(ROOT, "specs", "pbr_fragility.json")))
            frag_job = served(base, out_dir, "fragility_pbr", fragility)
            # 9,000 simulations: more than one task.
            served(base, out_dir, "fragility_split", dict(fragility, samples=600))
            served(base, out_dir, "fragility_records_id", {
                "kind": "fragility", "block": {"alpha": 0.2, "p": 2.0},
                "ground_motions": [{"record": record}, {"record": record, "name": "again"}],
                "stripes": [0.2, 0.4], "samples": 64, "seed": 3})
            survival = json.load(open(os.path.join(ROOT, "specs", "survival_power_law.json")))
            survival["fragility"] = {"job": frag_job}
            served(base, out_dir, "survival_from_fragility_job", survival)
            for name, spec in cases:
                if all(isinstance(v, dict) and "file" in v for v in [spec.get("ground_motion")]) \
                        or "ground_motions" in spec:
                    continue  # files are the CLI's
                served(base, out_dir, name, spec)
        finally:
            server.terminate()
            server.wait(timeout=60)
    print(f"{len(os.listdir(out_dir))} files in {out_dir}")


if __name__ == "__main__":
    main()
