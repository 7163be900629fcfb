#!/usr/bin/env python3
"""Every kind of result document, as topple computes it, against the schema
topple describes (components/schemas/JobResult of `topple openapi`), and the
schema refusing wrong types in typed fields: the description cannot drift
from the documents.

    validate_results.py TOPPLE_BIN

Runs in the schemathesis venv (jsonschema_rs, PyYAML); tests/schemathesis.sh
calls it. Prints one line per document and `N passed, N failed`.
"""

import copy
import glob
import json
import os
import subprocess
import sys

import jsonschema_rs
import yaml

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

EXTRA = [
    ("lift-off friction spectrum", {
        "kind": "friction_spectrum", "block": {"alpha": 0.25, "p": 2.14, "eta": 0.9},
        "pulse": {"type": "one_cosine"}, "omega_ratio": 1.0, "a_alpha_g": [2.0, 6.0]}),
    ("lift-off time history with a series", {
        "kind": "time_history", "block": {"alpha": 0.25, "p": 2.14, "eta": 0.9},
        "pulse": {"type": "one_cosine", "omega_ratio": 1.0, "a_p_alpha_g": 6.0},
        "outputs": {"series": 50}}),
    ("record time history", {
        "kind": "time_history", "block": {"b": 0.6, "h": 1.2, "mu": 0.5},
        "ground_motion": {"dt": 0.01, "unit": "g", "acc": [0.0, 0.3, 0.5, 0.2, -0.4, -0.1, 0.0]},
        "outputs": {"series": 20}}),
    ("linear spectrum, Cn", {
        "kind": "spectrum", "block": {"alpha": 0.2, "p": 2.0, "eta": 0.85},
        "pulse": {"type": "cn", "n": 2}, "formulation": "linear",
        "omega_ratio": [1.0, 4.0], "a_max_alpha_g": 8}),
    ("coulomb spectrum with the no-sliding one beside it", {
        "kind": "spectrum", "block": {"alpha": 0.25, "p": 2.14},
        "pulse": {"type": "one_sine"}, "omega_ratio": [3.0, 6.0], "a_max_alpha_g": 6,
        "tolerance": 1e-3, "scan_step_alpha_g": 0.05,
        "contact": {"model": "coulomb", "mu": 0.3}, "no_sliding_beside": True}),
    ("forensic query on a Coulomb floor with a slide in centimetres (implausible_slide)", {
        "kind": "forensic", "pulse": {"type": "one_sine"}, "frequency_hz": [1.0],
        "a_p_g": {"from": 0.05, "to": 0.3}, "contact": {"model": "coulomb", "mu": 0.3},
        "observations": [
            {"name": "loco", "overturned": True, "block": {"alpha": 0.25, "p": 2.14}},
            {"name": "box", "overturned": False, "slid_m": [5, 30],
             "block": {"alpha": 0.25, "p": 2.14}}]}),
    ("time history on a record file", {
        "kind": "time_history", "block": {"alpha": 0.15, "p": 2.0, "eta": 0.9},
        "ground_motion": {"file": os.path.join(ROOT, "specs", "records", "ridge_station_090.at2")},
        "outputs": {"series": 20}}),
    ("fragility on a suite of record files", {
        "kind": "fragility", "block": {"alpha": 0.2, "p": 2.0},
        "ground_motions": [
            {"file": os.path.join(ROOT, "specs", "records", "ridge_station_090.csv")},
            {"file": os.path.join(ROOT, "specs", "records", "ridge_station_090.at2"),
             "name": "the same as AT2"}],
        "stripes": [0.2, 0.4], "samples": 16, "seed": 1}),
    ("time history without reactions", {
        "kind": "time_history", "block": {"alpha": 0.25, "p": 2.14},
        "pulse": {"type": "one_sine", "omega_ratio": 3.0, "a_p_alpha_g": 2.0},
        "formulation": "linear", "outputs": {"reactions": False, "impacts": False}}),
]


def run(binary, spec):
    out = subprocess.run([binary, "run", "-"], input=json.dumps(spec).encode(),
                         capture_output=True, check=True, timeout=300)
    return json.loads(out.stdout)


def validator(document, name):
    root = {"$ref": f"#/components/schemas/{name}", "components": document["components"]}
    return jsonschema_rs.validator_for(root)


def main():
    binary = sys.argv[1]
    description = yaml.safe_load(subprocess.run([binary, "openapi"], capture_output=True,
                                                 check=True).stdout)
    any_result = validator(description, "JobResult")
    # The kinds and their result schemas, as the description's union maps them.
    mapping = description["components"]["schemas"]["JobResult"]["discriminator"]["mapping"]
    by_kind = {k: validator(description, ref.rsplit("/", 1)[-1]) for k, ref in mapping.items()}
    cases = [(os.path.basename(p), json.load(open(p)))
             for p in sorted(glob.glob(os.path.join(ROOT, "specs", "*.json")))] + EXTRA
    passed = failed = 0
    kinds = set()

    def check(what, ok, detail=""):
        nonlocal passed, failed
        print(f"{'ok  ' if ok else 'FAIL'} {what}{(': ' + detail) if detail and not ok else ''}")
        if ok:
            passed += 1
        else:
            failed += 1

    documents = []
    for name, spec in cases:
        doc = run(binary, spec)
        documents.append(doc)
        kinds.add(doc["kind"])
        errors = [e.message for e in any_result.iter_errors(doc)][:3]
        check(f"{name} ({doc['kind']}) is a JobResult", not errors, "; ".join(errors))
        errors = [e.message for e in by_kind[doc["kind"]].iter_errors(doc)][:3]
        check(f"{name} is a {doc['kind']} result", not errors, "; ".join(errors))
    check("every kind was produced", kinds == set(by_kind), str(sorted(kinds)))

    # The schema refuses a wrong type in typed fields.
    mutations = [
        ("time_history", lambda d: d.__setitem__("overturned", "yes")),
        ("time_history", lambda d: d["numerics"].__setitem__("events", "four")),
        ("time_history", lambda d: d.__setitem__("kind", "time_histroy")),
        ("spectrum", lambda d: d["spectrum"][0].__setitem__("eq21_alpha_g", "1.5")),
        ("spectrum", lambda d: d["spectrum"][0].__setitem__("transitions", [{"a_alpha_g": "x"}])),
        ("friction_spectrum", lambda d: d["points"][0].__setitem__("lift_off", 1)),
        ("forensic", lambda d: d.__setitem__("frequencies", {"0": 1})),
        ("record_spectrum", lambda d: d["spectrum"][0].__setitem__("R_m", "0.5 m")),
        ("record_spectrum", lambda d: d["record"].__delitem__("pga_g")),
        ("forensic", lambda d: d.__setitem__("excitation", "record")),
        ("survival", lambda d: d["rocks"][0].__setitem__("annual_toppling_rate", "1e-4")),
        ("fragility", lambda d: d["stripes"][0].__setitem__("overturned", -1.5)),
        ("fragility", lambda d: d.__setitem__("monotone", "no")),
        ("survival", lambda d: d["ages"][0].__delitem__("survival_probability")),
        ("forensic", lambda d: d.__setitem__("consistent_scale", [["0.5", 1.0]])),
        ("forensic", lambda d: d.__setitem__("per_observation", [{"name": "x"}])),
        ("time_history", lambda d: d.__delitem__("engine")),
    ]
    for kind, mutate in mutations:
        doc = copy.deepcopy(next(d for d in documents if d["kind"] == kind))
        mutate(doc)
        check(f"a {kind} result with a wrong field is refused",
              not any_result.is_valid(doc) and not by_kind[kind].is_valid(doc))
    print(f"{passed} passed, {failed} failed")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
