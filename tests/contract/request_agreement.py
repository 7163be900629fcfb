#!/usr/bin/env python3
"""The request schema (components/schemas/JobSpec of the served
/openapi.yaml) and the server agree on the catalogue of bad inputs: every
spec below breaks one rule JSON Schema can express, and both the schema and
the server (POST /v1/jobs, a 422 or 400 naming the field) refuse it. Every
spec the repository ships, and a set of valid variants, passes the schema
(the schema is not stricter than the server on real specs), and the server
accepts the variants. Rules the schema cannot express (bounds that depend on
the block, `to` above `from`) are listed too: the server refuses them, the
schema lets them through, so a client learns of them from the server's 422.
Specs naming a stored record (`{"record": id}`, uploaded first from
specs/records/) are held to the same: the schema and the server accept the
id alone, and refuse a bad id, an id beside samples, and a file.

    request_agreement.py BASE_URL

Runs in the schemathesis venv (jsonschema_rs, PyYAML) against a live
server; tests/schemathesis.sh calls it. Prints one line per case and
`N passed, N failed`.
"""

import copy
import glob
import json
import os
import sys
import urllib.error
import urllib.request

import jsonschema_rs
import yaml

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

TH = {"kind": "time_history", "block": {"alpha": 0.2, "p": 2.0},
      "pulse": {"type": "one_sine", "omega_ratio": 3.0, "a_p_alpha_g": 2.0}}
GM = {"kind": "time_history", "block": {"b": 0.5, "h": 1.5},
      "ground_motion": {"dt": 0.01, "unit": "g", "acc": [0.0, 0.3, -0.2, 0.0]}}
SP = {"kind": "spectrum", "block": {"alpha": 0.2, "p": 2.0}, "pulse": {"type": "one_sine"},
      "omega_ratio": [2.0], "a_max_alpha_g": 3.0}
FR = {"kind": "friction_spectrum", "block": {"alpha": 0.25, "p": 2.14, "eta": 0.9},
      "pulse": {"type": "one_cosine"}, "omega_ratio": 4.0, "a_alpha_g": [2.0]}
FO = {"kind": "forensic", "pulse": {"type": "one_sine"},
      "observations": [{"name": "cabinet", "b": 0.5, "h": 1.5, "overturned": True}],
      "frequency_hz": [1.0], "a_p_g": {"from": 0.1, "to": 0.5}}
FOR = {"kind": "forensic", "ground_motion": {"dt": 0.01, "unit": "g", "acc": [0.0, 0.4, -0.3, 0.0]},
       "observations": [{"name": "cabinet", "b": 0.5, "h": 1.5, "overturned": True}],
       "pga_g": {"from": 0.1, "to": 1.0}}
SU = {"kind": "survival", "hazard": {"im": "pga_g", "points": [[0.1, 1e-2], [1.0, 1e-5]]},
      "fragility": {"median_g": 0.4, "beta": 0.3}, "age_years": [1000, 10000]}
FG = {"kind": "fragility", "block": {"alpha": {"dist": "uniform", "min": 0.15, "max": 0.25}, "p": 2.0},
      "pulse": {"type": "one_sine", "frequency_hz": 0.8}, "stripes": [0.2, 0.3], "samples": 20, "seed": 3}
RS = {"kind": "record_spectrum", "block": {"alpha": 0.2},
      "ground_motion": {"dt": 0.01, "unit": "g", "acc": [0.0, 0.4, -0.3, 0.0]},
      "R_m": [0.5, 1.0], "scale": {"to": 3.0}}

DELETE = object()


def edit(base, **changes):
    """`base` with fields set (a path "a.b.0" -> value) or deleted (DELETE)."""
    spec = copy.deepcopy(base)
    for path, value in changes.items():
        keys = [int(k) if k.isdigit() else k for k in path.split("__")]
        node = spec
        for k in keys[:-1]:
            node = node[k]
        if value is DELETE:
            del node[keys[-1]]
        else:
            node[keys[-1]] = value
    return spec


# (what, spec, the pointer the server names)
BAD = [
    ("misspelt kind", edit(TH, kind="time_histroy"), "/kind"),
    ("misspelt formulation", edit(TH, formulation="nonlinaer"), "/formulation"),
    ("misspelt pulse type", edit(TH, pulse__type="one_sin"), "/pulse/type"),
    ("vertical ratio beyond 100", edit(SP, vertical={"ratio": 1e3}), "/vertical/ratio"),
    ("misspelt contact model", edit(TH, contact={"model": "columb", "mu": 0.3}), "/contact/model"),
    ("a spectrum's contact model misspelt", edit(SP, contact={"model": "friction", "mu": 0.3}),
     "/contact/model"),
    ("a residual slide of no amplitudes",
     edit(SP, contact={"model": "coulomb", "mu": 0.3}, residual_slide={"steps": 0}), "/residual_slide/steps"),
    ("a negative friction coefficient", edit(TH, contact={"model": "coulomb", "mu": -0.3}), "/contact/mu"),
    ("a contact field unknown", edit(TH, contact={"model": "coulomb", "mu": 0.3, "mu_s": 0.3}), "/contact/mu_s"),
    ("a seen slide of one size", edit(FO, contact={"model": "coulomb", "mu": 0.3},
                                      observations=[{"name": "cabinet", "b": 0.5, "h": 1.5, "overturned": False, "slid_m": [0.1]}]), "/observations/0/slid_m"),
    ("unknown field in vertical", edit(SP, vertical={"ratio": 0.5, "phase": 1.0}), "/vertical/phase"),
    ("a fragility's vertical pulse of its own", edit(FG, vertical={"type": "one_sine"}), "/vertical/type"),
    ("unknown field", edit(TH, omega=3.0), "/omega"),
    ("unknown block field", edit(TH, block__beta=1.0), "/block/beta"),
    ("a string for a number", edit(TH, block__alpha="0.2"), "/block/alpha"),
    ("no block", edit(TH, block=DELETE), "/block"),
    ("alpha = 0", edit(TH, block__alpha=0.0), "/block/alpha"),
    ("alpha = 1.6 > pi/2", edit(TH, block__alpha=1.6), "/block/alpha"),
    ("p < 0", edit(TH, block__p=-1.0), "/block/p"),
    ("eta > 1", edit(TH, block__eta=1.5), "/block/eta"),
    ("eta < 0", edit(TH, block__eta=-0.1), "/block/eta"),
    ("mu = 0", edit(TH, block__mu=0.0), "/block/mu"),
    ("g = 0", edit(TH, block__g=0.0), "/block/g"),
    ("alpha without p", edit(TH, block__p=DELETE), "/block/p"),
    ("empty block", edit(TH, block={}), "/block"),
    ("parameters and geometry", edit(TH, block={"alpha": 0.2, "p": 2.0, "b": 0.5, "h": 1.5}),
     "/block"),
    ("b without h", edit(GM, block={"b": 0.5}), "/block/h"),
    ("b < 0", edit(GM, block={"b": -0.5, "h": 1.5}), "/block/b"),
    ("no pulse type", edit(TH, pulse__type=DELETE), "/pulse/type"),
    ("two frequencies", edit(TH, pulse__omega_p=6.0), "/pulse/omega_ratio"),
    ("no frequency", edit(TH, pulse__omega_ratio=DELETE), "/pulse"),
    ("no amplitude", edit(TH, pulse__a_p_alpha_g=DELETE), "/pulse"),
    ("two amplitudes", edit(TH, pulse__a_p_g=0.5), "/pulse/a_p_alpha_g"),
    ("omega_ratio = 0", edit(TH, pulse__omega_ratio=0.0), "/pulse/omega_ratio"),
    ("omega_ratio > 1e4", edit(TH, pulse__omega_ratio=2e4), "/pulse/omega_ratio"),
    ("omega_p < 0", edit(TH, pulse={"type": "one_sine", "omega_p": -3.0, "a_p_alpha_g": 2.0}),
     "/pulse/omega_p"),
    ("frequency_hz = 0",
     edit(TH, pulse={"type": "one_sine", "frequency_hz": 0.0, "a_p_alpha_g": 2.0}),
     "/pulse/frequency_hz"),
    ("|a_p_alpha_g| > 1e8", edit(TH, pulse__a_p_alpha_g=-2e8), "/pulse/a_p_alpha_g"),
    ("n for a one-sine pulse", edit(TH, pulse__n=2), "/pulse/n"),
    ("cn with n = 0", edit(TH, pulse__type="cn", pulse__n=0), "/pulse/n"),
    ("cn with n = 1001", edit(TH, pulse__type="cn", pulse__n=1001), "/pulse/n"),
    ("gamma for a one-sine pulse", edit(TH, pulse__gamma=2.0), "/pulse/gamma"),
    ("nu for a one-sine pulse", edit(TH, pulse__nu=0.5), "/pulse/nu"),
    ("mavroeidis_papageorgiou without gamma",
     edit(TH, pulse__type="mavroeidis_papageorgiou"), "/pulse/gamma"),
    ("mavroeidis_papageorgiou with gamma = 1",
     edit(TH, pulse__type="mavroeidis_papageorgiou", pulse__gamma=1.0), "/pulse/gamma"),
    ("mavroeidis_papageorgiou with gamma > 20",
     edit(TH, pulse__type="mavroeidis_papageorgiou", pulse__gamma=25.0), "/pulse/gamma"),
    ("a pulse and a record", edit(GM, pulse=TH["pulse"]), "/ground_motion"),
    ("neither pulse nor record", edit(TH, pulse=DELETE), "/pulse"),
    ("record without dt", edit(GM, ground_motion__dt=DELETE), "/ground_motion/dt"),
    ("record dt = 2 s", edit(GM, ground_motion__dt=2.0), "/ground_motion/dt"),
    ("record without unit", edit(GM, ground_motion__unit=DELETE), "/ground_motion/unit"),
    ("record in km/s2", edit(GM, ground_motion__unit="km/s2"), "/ground_motion/unit"),
    ("record of one sample", edit(GM, ground_motion__acc=[0.1]), "/ground_motion/acc"),
    ("record without samples", edit(GM, ground_motion__acc=DELETE), "/ground_motion/acc"),
    ("unknown method", edit(TH, solver={"method": "rk4"}), "/solver/method"),
    ("rtol = 1", edit(TH, solver={"method": "dop853", "rtol": 1.0}), "/solver/rtol"),
    ("atol = 0", edit(TH, solver={"method": "dop853", "atol": 0.0}), "/solver/atol"),
    ("series > 1e6", edit(TH, outputs={"series": 2_000_000}), "/outputs/series"),
    ("negative series", edit(TH, outputs={"series": -1}), "/outputs/series"),
    ("duration = 0", edit(TH, outputs={"duration": 0.0}), "/outputs/duration"),
    ("spectrum without pulse", edit(SP, pulse=DELETE), "/pulse"),
    ("spectrum pulse with a frequency", edit(SP, pulse__omega_ratio=2.0), "/pulse/omega_ratio"),
    ("spectrum pulse with an amplitude", edit(SP, pulse__a_p_g=0.2), "/pulse/a_p_g"),
    ("spectrum without frequencies", edit(SP, omega_ratio=DELETE), "/omega_ratio"),
    ("spectrum frequencies twice", edit(SP, omega_p=[4.0]), "/omega_p"),
    ("spectrum empty list", edit(SP, omega_ratio=[]), "/omega_ratio"),
    ("spectrum negative frequency", edit(SP, omega_ratio=[2.0, -1.0]), "/omega_ratio/1"),
    ("spectrum steps = 0", edit(SP, omega_ratio={"from": 1.0, "to": 2.0, "steps": 0}),
     "/omega_ratio/steps"),
    ("spectrum range from 0", edit(SP, omega_ratio={"from": 0.0, "to": 2.0, "steps": 3}),
     "/omega_ratio"),
    ("a_max_alpha_g < 1", edit(SP, a_max_alpha_g=0.5), "/a_max_alpha_g"),
    ("a_max_alpha_g > 1e4", edit(SP, a_max_alpha_g=2e4), "/a_max_alpha_g"),
    ("highest amplitude twice", edit(SP, a_max_g=1.0), "/a_max_g"),
    ("a_max = 0", edit(SP, a_max_alpha_g=DELETE, a_max=0.0), "/a_max"),
    ("tolerance > 0.1", edit(SP, tolerance=0.5), "/tolerance"),
    ("scan step > 1", edit(SP, scan_step_alpha_g=2.0), "/scan_step_alpha_g"),
    ("principal width > 1", edit(SP, principal_relative_width=1.5), "/principal_relative_width"),
    ("friction without frequency", edit(FR, omega_ratio=DELETE), "/omega_ratio"),
    ("friction frequency twice", edit(FR, frequency_hz=1.0), "/frequency_hz"),
    ("friction omega_ratio = 0", edit(FR, omega_ratio=0.0), "/omega_ratio"),
    ("friction omega_p < 0", edit(FR, omega_ratio=DELETE, omega_p=-1.0), "/omega_p"),
    ("friction without amplitudes", edit(FR, a_alpha_g=DELETE), "/a_alpha_g"),
    ("friction amplitudes twice", edit(FR, a_p_g=[0.5]), "/a_p_g"),
    ("friction pulse with an amplitude", edit(FR, pulse__a_p=1.0), "/pulse/a_p"),
    ("friction n for one-cosine", edit(FR, pulse__n=3), "/pulse/n"),
    ("spectrum gamma for one-sine", edit(SP, pulse__gamma=2.0), "/pulse/gamma"),
    ("forensic mavroeidis_papageorgiou without gamma",
     edit(FO, pulse__type="mavroeidis_papageorgiou"), "/pulse/gamma"),
    ("forensic without observations", edit(FO, observations=DELETE), "/observations"),
    ("forensic no observation", edit(FO, observations=[]), "/observations"),
    ("forensic 33 observations", edit(FO, observations=FO["observations"] * 33), "/observations"),
    ("observation without outcome", edit(FO, observations__0__overturned=DELETE),
     "/observations/0/overturned"),
    ("observation block and b", edit(FO, observations__0__block={"alpha": 0.2, "p": 2.0}),
     "/observations/0/block"),
    ("observation without block", edit(FO, observations=[{"name": "x", "overturned": False}]),
     "/observations/0/block"),
    ("observation b without h", edit(FO, observations__0__h=DELETE), "/observations/0/h"),
    ("observation h < 0", edit(FO, observations__0__h=-1.0), "/observations/0/h"),
    ("forensic without frequencies", edit(FO, frequency_hz=DELETE), "/frequency_hz"),
    ("forensic frequencies twice", edit(FO, omega_p=[6.0]), "/omega_p"),
    ("forensic amplitudes twice", edit(FO, a_p={"from": 1.0, "to": 4.0}), "/a_p"),
    ("forensic amplitude from < 0", edit(FO, a_p_g={"from": -0.1, "to": 0.5}), "/a_p_g/from"),
    ("forensic amplitude range without to", edit(FO, a_p_g={"from": 0.1}), "/a_p_g/to"),
    ("forensic tolerance > 0.1", edit(FO, tolerance_g=0.5), "/tolerance_g"),
    ("forensic scan step > 1", edit(FO, scan_step_g=2.0), "/scan_step_g"),
    ("forensic without pulse or record", edit(FO, pulse=DELETE), "/pulse"),
    ("forensic with a pulse and a record", edit(FOR, pulse=FO["pulse"]), "/ground_motion"),
    ("forensic record with a frequency axis", edit(FOR, frequency_hz=[1.0]), "/frequency_hz"),
    ("forensic record with an amplitude axis", edit(FOR, a_p_g={"from": 0.1, "to": 1.0}),
     "/a_p_g"),
    ("forensic pulse with a scale axis", edit(FO, scale={"to": 2.0}), "/scale"),
    ("forensic record scale twice", edit(FOR, scale={"to": 2.0}), "/pga_g"),
    ("forensic record tolerance twice", edit(FOR, tolerance=1e-3, tolerance_g=1e-4), "/tolerance"),
    ("forensic record PGA from < 0", edit(FOR, pga_g={"from": -0.1, "to": 1.0}), "/pga_g/from"),
    ("forensic record scale without to", edit(FOR, pga_g=DELETE, scale={"from": 0.5}),
     "/scale/to"),
    ("forensic record tolerance = 0", edit(FOR, tolerance=0.0), "/tolerance"),
    ("forensic record without unit", edit(FOR, ground_motion__unit=DELETE), "/ground_motion/unit"),
    ("fragility without block", edit(FG, block=DELETE), "/block"),
    ("fragility a pulse and records", edit(FG, ground_motions=[{"dt": 0.01, "acc": [0.0, 0.1], "unit": "g"}]),
     "/ground_motions"),
    ("fragility two frequencies", edit(FG, pulse__omega_p=5.0), "/pulse/frequency_hz"),
    ("fragility without stripes", edit(FG, stripes=DELETE), "/stripes"),
    ("fragility samples = 0", edit(FG, samples=0), "/samples"),
    ("fragility unknown distribution", edit(FG, block__p={"dist": "gamma"}), "/block/p/dist"),
    ("fragility unknown im", edit(FG, im="sa_g"), "/im"),
    ("survival without hazard", edit(SU, hazard=DELETE), "/hazard"),
    ("survival with a fragility and rocks", edit(SU, rocks=[{"fragility": {"median_g": 0.4, "beta": 0.3},
                                                             "age_years": 1000}]), "/fragility"),
    ("survival without age", edit(SU, age_years=DELETE), "/age_years"),
    ("survival median twice", edit(SU, fragility__median=0.4), "/fragility/median"),
    ("survival with an unknown intensity", edit(SU, hazard__im="sa_g"), "/hazard/im"),
    ("survival hazard of one point", edit(SU, hazard__points=[[0.1, 1e-2]]), "/hazard/points"),
    ("survival beta > 3", edit(SU, fragility__beta=4.0), "/fragility/beta"),
    ("survival fragility median 0", edit(SU, fragility__median_g=0.0), "/fragility/median_g"),
    ("survival unknown distribution", edit(SU, age_years={"dist": "gamma"}), "/age_years/dist"),
    ("record spectrum without record", edit(RS, ground_motion=DELETE), "/ground_motion"),
    ("record spectrum without block", edit(RS, block=DELETE), "/block"),
    ("record spectrum without sizes", edit(RS, R_m=DELETE), "/p"),
    ("record spectrum sizes twice", edit(RS, p=[2.0]), "/R_m"),
    ("record spectrum empty sizes", edit(RS, R_m=[]), "/R_m"),
    ("record spectrum without scale", edit(RS, scale=DELETE), "/scale"),
    ("record spectrum scale twice", edit(RS, pga_g={"to": 1.0}), "/pga_g"),
    ("record spectrum scale without to", edit(RS, scale={"from": 0.5}), "/scale/to"),
    ("record spectrum scale from < 0", edit(RS, scale={"from": -1.0, "to": 2.0}), "/scale/from"),
    ("record spectrum with a block size", edit(RS, block={"alpha": 0.2, "p": 2.0}), "/block/p"),
    ("record spectrum principal width > 1", edit(RS, principal_relative_width=2.0),
     "/principal_relative_width"),
]

# Rules JSON Schema cannot state (they depend on the block or on two values):
# the server refuses, the schema accepts.
SERVER_ONLY = [
    ("omega_p outside 1e-3..1e4 p for this block",
     edit(TH, pulse={"type": "one_sine", "omega_p": 1e6, "a_p_alpha_g": 2.0}), "/pulse/omega_p"),
    ("a_p = 0 m/s2", edit(TH, pulse={"type": "one_sine", "omega_ratio": 3.0, "a_p": 0.0}),
     "/pulse/a_p"),
    ("a_max_g above 1e4 alpha g", edit(SP, a_max_alpha_g=DELETE, a_max_g=1e5), "/a_max_g"),
    ("range with to < from", edit(SP, omega_ratio={"from": 4.0, "to": 2.0, "steps": 3}),
     "/omega_ratio"),
    ("scan step below the tolerance", edit(SP, tolerance=0.05, scan_step_alpha_g=0.01),
     "/scan_step_alpha_g"),
    ("forensic amplitude to <= from", edit(FO, a_p_g={"from": 0.5, "to": 0.5}), "/a_p_g"),
    ("fragility normal alpha without truncation",
     edit(FG, block__alpha={"dist": "normal", "mean": 0.2, "sd": 0.05}), "/block/alpha/min"),
    ("survival with an unknown fragility job",
     edit(SU, fragility={"job": "01a20c35-0ff0-7eab-bb8e-86d14f37f92a"}), "/fragility/job"),
    ("survival rates rising", edit(SU, hazard__points=[[0.1, 1e-3], [1.0, 1e-2]]),
     "/hazard/points/1"),
    ("forensic record of zeros", edit(FOR, ground_motion__acc=[0.0, 0.0]), "/ground_motion/acc"),
    ("record spectrum scaled below the rocking threshold", edit(RS, scale={"to": 0.1}), "/scale/to"),
    ("a spectrum's vertical pulse with an absolute amplitude", edit(SP, vertical={"type": "one_sine", "omega_p": 3.0,
                                                                            "a_p_g": 0.2}), "/vertical/a_p_g"),
    ("exact under a vertical ratio", edit(SP, formulation="linear", solver={"method": "exact"},
                                         vertical={"ratio": 0.3}), "/solver/method"),
    ("a friction spectrum's vertical pulse without its amplitude ratio",
     edit(FR, vertical={"type": "one_sine", "frequency_ratio": 2.0}), "/vertical/amplitude_ratio"),
    ("a fragility's vertical ratio beyond 100", edit(FG, vertical={"ratio": 1e3}), "/vertical/ratio"),
    ("coulomb without mu", edit(TH, contact={"model": "coulomb"}), "/contact/mu"),
    ("a seen slide in pure rocking", edit(FO, observations=[{"name": "cabinet", "b": 0.5, "h": 1.5, "overturned": False, "slid_m": [0.0, 0.1]}]), "/observations/0/slid_m"),
    ("a seen slide of sizes in the wrong order", edit(FO, contact={"model": "coulomb", "mu": 0.3},
                                                      observations=[{"name": "cabinet", "b": 0.5, "h": 1.5, "overturned": False, "slid_m": [0.3, 0.1]}]), "/observations/0/slid_m"),
    ("a residual slide without a coulomb floor", edit(SP, residual_slide={"steps": 5}), "/residual_slide"),
    ("the no-sliding spectrum beside pure rocking", edit(SP, no_sliding_beside=True), "/no_sliding_beside"),
    ("a fragility's kinetic coefficient above the static one",
     edit(FG, contact={"model": "coulomb", "mu": 0.3, "mu_kinetic": 0.5}), "/contact/mu_kinetic"),
    ("a forensic query's coulomb floor under the linear equations",
     edit(FO, contact={"model": "coulomb", "mu": 0.3}, formulation="linear"), "/formulation"),
    ("a spectrum's coulomb floor without mu", edit(SP, contact={"model": "coulomb"}), "/contact/mu"),
    ("a kinetic coefficient above the static one",
     edit(TH, contact={"model": "coulomb", "mu": 0.3, "mu_kinetic": 0.4}), "/contact/mu_kinetic"),
    ("coulomb with the linear equations",
     edit(TH, contact={"model": "coulomb", "mu": 0.3}, formulation="linear"), "/formulation"),
    ("a friction coefficient under pure rocking", edit(TH, contact={"model": "no_sliding", "mu": 0.3}),
     "/contact/mu"),
    ("a fragility's vertical ratio distribution beyond 100",
     edit(FG, vertical={"ratio": {"dist": "uniform", "min": -200.0, "max": 0.5}}), "/vertical/ratio/min"),
]

# Valid variants, beyond the shipped specs: every unit, both block forms,
# explicit nulls for optional fields.
GOOD = [
    ("time history", TH),
    ("on a coulomb floor", edit(TH, contact={"model": "coulomb", "mu": 0.3, "mu_kinetic": 0.25})),
    ("pure rocking by name", edit(TH, contact={"model": "no_sliding"})),
    ("record by geometry", GM),
    ("cn with n", edit(TH, pulse__type="cn", pulse__n=2)),
    ("mavroeidis_papageorgiou with gamma and nu",
     edit(TH, pulse__type="mavroeidis_papageorgiou", pulse__gamma=2.5, pulse__nu=-1.0)),
    ("mavroeidis_papageorgiou with nu by default",
     edit(TH, pulse__type="mavroeidis_papageorgiou", pulse__gamma=1.5)),
    ("omega_p and a_p_g", edit(TH, pulse={"type": "one_cosine", "omega_p": 6.0, "a_p_g": 0.5})),
    ("frequency_hz and a_p", edit(TH, pulse={"type": "one_sine", "frequency_hz": 1.0, "a_p": 4.0})),
    ("explicit nulls", edit(TH, formulation=None, solver=None, outputs=None, block__eta=None,
                            pulse__omega_p=None, pulse__n=None)),
    ("linear, exact", edit(TH, formulation="linear", solver={"method": "exact"})),
    ("linear record, exact", edit(GM, formulation="linear", solver={"method": "exact"})),
    ("spectrum", SP),
    ("spectrum on a coulomb floor", edit(SP, contact={"model": "coulomb", "mu": 0.3})),
    ("a residual-slide spectrum", edit(SP, contact={"model": "coulomb", "mu": 0.3}, residual_slide={"steps": 5})),
    ("a coulomb spectrum with the no-sliding one beside it",
     edit(SP, contact={"model": "coulomb", "mu": 0.3, "mu_kinetic": 0.25}, no_sliding_beside=True)),
    ("record spectrum on a coulomb floor", edit(RS, contact={"model": "coulomb", "mu": 0.4})),
    ("forensic query on a coulomb floor", edit(FO, contact={"model": "coulomb", "mu": 0.5, "mu_kinetic": 0.4})),
    ("forensic query with a seen slide", edit(FO, contact={"model": "coulomb", "mu": 0.3}, observations=[{"name": "cabinet", "b": 0.5, "h": 1.5, "overturned": False, "slid_m": [0.0, 0.05]}])),
    ("record forensic query with a seen slide", edit(FOR, contact={"model": "coulomb", "mu": 0.3}, observations=[{"name": "cabinet", "b": 0.5, "h": 1.5, "overturned": False, "slid_m": [0.01, 0.2]}])),
    ("fragility on a coulomb floor", edit(FG, contact={"model": "coulomb", "mu": 0.3})),
    ("spectrum in Hz and g", edit(SP, omega_ratio=DELETE, frequency_hz={"from": 0.5, "to": 1.0,
                                                                      "steps": 2},
                                  a_max_alpha_g=DELETE, a_max_g=0.5)),
    ("spectrum with the default amplitude", edit(SP, a_max_alpha_g=DELETE, omega_ratio=2.0)),
    ("mavroeidis_papageorgiou spectrum",
     edit(SP, pulse={"type": "mavroeidis_papageorgiou", "gamma": 3.0, "nu": 1.5708})),
    ("friction spectrum", FR),
    ("friction in rad/s and m/s2", edit(FR, omega_ratio=DELETE, omega_p=8.56, a_alpha_g=DELETE,
                                        a_p=[4.0, 5.0])),
    ("forensic", FO),
    ("record spectrum", RS),
    ("forensic on a record", FOR),
    ("survival", SU),
    ("fragility", FG),
    ("fragility by geometry on records, in PGV", edit(FG, block={"b": {"dist": "lognormal", "median": 0.5, "beta": 0.1},
                                                                 "h": 1.5, "eta": 0.9},
                                                       pulse=DELETE, im="pgv_m_s",
                                                       ground_motions=[{"name": "a", "dt": 0.01, "unit": "g",
                                                                        "acc": [0.0, 0.3, -0.2, 0.0]}])),
    ("survival of two rocks, an uncertain age", edit(SU, fragility=DELETE, age_years=DELETE, rocks=[
        {"name": "a", "fragility": {"median_g": 0.4, "beta": 0.3}, "age_years": 1000},
        {"fragility": {"median": 0.5, "beta": 0.0},
         "age_years": {"dist": "lognormal", "median": 9000, "beta": 0.3}}])),
    ("forensic on a record by scale, linear", edit(FOR, pga_g=DELETE, scale={"from": 0.5, "to": 4.0},
                                                  formulation="linear", tolerance=1e-3,
                                                  scan_step=0.05)),
    ("record spectrum in p and PGA", edit(RS, R_m=DELETE, p={"from": 2.0, "to": 4.0, "steps": 2},
                                          scale=DELETE, pga_g={"from": 0.1, "to": 1.0})),
    ("vertical ratio beside a pulse", edit(TH, vertical={"ratio": -0.5})),
    ("vertical pulse of its own", edit(TH, vertical={"type": "one_cosine", "omega_p": 9.0,
                                                     "a_p_g": 0.3, "delay_s": 0.1})),
    ("record with a vertical ratio", edit(GM, ground_motion__vertical={"ratio": 0.5})),
    ("record with vertical samples", edit(GM, ground_motion__vertical={"acc": [0.0, -0.1, 0.1],
                                                                       "unit": "g"})),
    ("spectrum with a vertical ratio", edit(SP, vertical={"ratio": 0.5})),
    ("friction spectrum with a vertical ratio", edit(FR, vertical={"ratio": -0.5})),
    ("forensic with a vertical ratio", edit(FO, vertical={"ratio": 0.5})),
    ("forensic on a record with a vertical ratio", edit(FOR, vertical={"ratio": 0.5})),
    ("record spectrum with a vertical ratio", edit(RS, vertical={"ratio": 0.5})),
    ("spectrum with a vertical pulse of its own",
     edit(SP, vertical={"type": "one_cosine", "amplitude_ratio": -0.4, "frequency_ratio": 2.0, "delay_s": 0.1})),
    ("record spectrum with the record's own vertical samples",
     edit(RS, ground_motion__vertical={"acc": [0.0, -0.1, 0.1, 0.0], "unit": "g"})),
    ("friction spectrum with a vertical pulse of its own",
     edit(FR, vertical={"type": "one_sine", "amplitude_ratio": 0.5, "omega_p": 12.0})),
    ("forensic with a vertical pulse of its own",
     edit(FO, vertical={"type": "one_sine", "amplitude_ratio": 0.3, "frequency_hz": 2.0, "delay_s": 0.05})),
    ("forensic on a record with its own vertical samples",
     edit(FOR, ground_motion__vertical={"acc": [0.0, -0.1, 0.1, 0.0], "unit": "g"})),
    ("fragility with a vertical ratio", edit(FG, vertical={"ratio": -0.5})),
    ("fragility with a distributed vertical ratio",
     edit(FG, vertical={"ratio": {"dist": "uniform", "min": -0.5, "max": 0.5}})),
    ("forensic with a block and a_p", edit(FO, observations=[
        {"block": {"alpha": 0.2, "p": 2.0}, "overturned": False}], a_p_g=DELETE,
        a_p={"from": 1.0, "to": 3.0})),
]


def record_cases(record):
    """Specs naming the stored record `record`: (bad, server only, good)."""
    named = {"kind": "time_history", "block": {"alpha": 0.15, "p": 2.0},
             "ground_motion": {"record": record}}
    suite = edit(FG, pulse=DELETE, ground_motions=[{"record": record}])
    bad = [
        ("a record id of three letters", edit(named, ground_motion__record="xyz"),
         "/ground_motion/record"),
        ("a record id in capitals", edit(named, ground_motion__record=record.upper()),
         "/ground_motion/record"),
        ("a record id that is a number", edit(named, ground_motion__record=7),
         "/ground_motion/record"),
        ("a record and its dt", edit(named, ground_motion__dt=0.01), "/ground_motion/dt"),
        ("a record and a unit", edit(named, ground_motion__unit="g"), "/ground_motion/unit"),
        ("a record and samples", edit(named, ground_motion__acc=[0.0, 0.1]),
         "/ground_motion/acc"),
        ("a record and allow_large_pga", edit(named, ground_motion__allow_large_pga=True),
         "/ground_motion/allow_large_pga"),
        ("a record and a name", edit(named, ground_motion__name="ridge"), "/ground_motion/name"),
        ("a file", edit(named, ground_motion={"file": "x.at2"}), "/ground_motion/file"),
        ("a file and a record", edit(named, ground_motion__file="x.at2"), "/ground_motion/file"),
        ("a file beside samples", edit(GM, ground_motion__file="x.at2"), "/ground_motion/file"),
        ("a record spectrum on a record id of three letters",
         edit(RS, ground_motion={"record": "xyz"}), "/ground_motion/record"),
        ("a forensic query on a record and its unit",
         edit(FOR, ground_motion={"record": record, "unit": "g"}), "/ground_motion/unit"),
        ("a suite member's record id of three letters",
         edit(suite, ground_motions=[{"record": "xyz"}]), "/ground_motions/0/record"),
        ("a suite member's record and its dt",
         edit(suite, ground_motions=[{"record": record, "dt": 0.01}]), "/ground_motions/0/dt"),
        ("a suite member's file", edit(suite, ground_motions=[{"file": "x.at2"}]),
         "/ground_motions/0/file"),
        ("a suite member's dt = 2 s",
         edit(suite, ground_motions=[{"dt": 2.0, "unit": "g", "acc": [0.0, 0.3, -0.2]}]),
         "/ground_motions/0/dt"),
        ("a suite member of one sample",
         edit(suite, ground_motions=[{"dt": 0.01, "unit": "g", "acc": [0.3]}]),
         "/ground_motions/0/acc"),
        ("an empty suite", edit(suite, ground_motions=[]), "/ground_motions"),
    ]
    server_only = [
        ("an unknown record", edit(named, ground_motion__record="0" * 32),
         "/ground_motion/record"),
        ("a suite member's unknown record",
         edit(suite, ground_motions=[{"record": "0" * 32}]), "/ground_motions/0/record"),
    ]
    good = [
        ("time history on a stored record", named),
        ("time history on a stored record, explicit nulls",
         edit(named, ground_motion={"record": record, "dt": None, "acc": None, "unit": None,
                                    "file": None, "allow_large_pga": None})),
        ("samples with an explicit null record and file",
         edit(GM, ground_motion__record=None, ground_motion__file=None)),
        ("record spectrum on a stored record", edit(RS, ground_motion={"record": record})),
        ("forensic query on a stored record", edit(FOR, ground_motion={"record": record})),
        ("fragility on stored records", edit(suite, ground_motions=[
            {"record": record}, {"record": record, "name": "ridge again"}])),
    ]
    return bad, server_only, good


def upload(base, path):
    """The id of the record file at `path` (POST /v1/records)."""
    request = urllib.request.Request(
        f"{base}/v1/records", data=open(path, "rb").read(), method="POST",
        headers={"Content-Type": "text/plain", "Accept": "application/json"})
    with urllib.request.urlopen(request, timeout=60) as response:
        return json.loads(response.read())["id"]


def post(base, spec):
    request = urllib.request.Request(
        f"{base}/v1/jobs", data=json.dumps(spec).encode(), method="POST",
        headers={"Content-Type": "application/json", "Accept": "application/json"})
    try:
        with urllib.request.urlopen(request, timeout=60) as response:
            return response.status, json.loads(response.read() or b"{}")
    except urllib.error.HTTPError as e:
        return e.code, json.loads(e.read() or b"{}")


def main():
    base = sys.argv[1].rstrip("/")
    with urllib.request.urlopen(f"{base}/openapi.yaml", timeout=10) as response:
        description = yaml.safe_load(response.read())
    schema = jsonschema_rs.validator_for(
        {"$ref": "#/components/schemas/JobSpec", "components": description["components"]})
    passed = failed = 0

    def check(what, ok, detail=""):
        nonlocal passed, failed
        print(f"{'ok  ' if ok else 'FAIL'} {what}{(': ' + detail) if detail and not ok else ''}")
        if ok:
            passed += 1
        else:
            failed += 1

    record = upload(base, os.path.join(ROOT, "specs", "records", "ridge_station_090.csv"))
    bad, server_only, good = record_cases(record)
    for what, spec, pointer in BAD + bad:
        refused = not schema.is_valid(spec)
        status, problem = post(base, spec)
        named = problem.get("pointer")
        check(f"bad: {what}: schema refuses, server {status} at {named}",
              refused and status in (400, 422) and named == pointer,
              f"schema {'refuses' if refused else 'ACCEPTS'}; server {status} "
              f"{problem.get('pointer')!r} (want {pointer!r}): {problem.get('detail')}")
    for what, spec, pointer in SERVER_ONLY + server_only:
        accepted = schema.is_valid(spec)
        status, problem = post(base, spec)
        named = problem.get("pointer")
        check(f"server only: {what}: server {status} at {named}",
              accepted and status == 422 and named == pointer,
              f"schema {'accepts' if accepted else 'REFUSES'}; server {status} "
              f"{named!r} (want {pointer!r}): {problem.get('detail')}")
    shipped = [(os.path.basename(p), json.load(open(p)))
               for p in sorted(glob.glob(os.path.join(ROOT, "specs", "*.json")))]
    for what, spec in shipped:
        errors = [f"{e.instance_path}: {e.message}" for e in schema.iter_errors(spec)]
        check(f"shipped spec {what}: schema accepts", not errors, "; ".join(errors)[:400])
    for what, spec in GOOD + good:
        errors = [f"{e.instance_path}: {e.message}" for e in schema.iter_errors(spec)]
        status, problem = post(base, spec)
        check(f"good: {what}: schema accepts, server {status}",
              not errors and status in (200, 201, 202, 303),
              f"{'; '.join(errors)[:400]} server {status}: {problem.get('detail')}")
    print(f"{passed} passed, {failed} failed")
    sys.exit(1 if failed else 0)


if __name__ == "__main__":
    main()
