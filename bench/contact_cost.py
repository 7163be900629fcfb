#!/usr/bin/env python3
"""The cost of the Coulomb contact model, counted in instructions: each case
of the criterion group `contact` (benches/engine.rs) under valgrind's
callgrind, its instructions per history (inclusive of `simulate` for pure
rocking, of `run_coulomb` on a Coulomb floor, divided by its calls), beside
pure rocking of the same case.

    python3 bench/contact_cost.py [--bench-binary PATH]
"""
import argparse

from vertical_cost import bench_binary, per_simulation

CASES = [
    ("rests/no_sliding", "topple::dynamics::simulate::simulate"),
    ("rests/coulomb_mu_10", "topple::dynamics::floor::run_coulomb"),
    ("strong/no_sliding", "topple::dynamics::simulate::simulate"),
    ("strong/coulomb_mu_0.2_slides", "topple::dynamics::floor::run_coulomb"),
    ("strong/coulomb_mu_0.3_slide_rocks", "topple::dynamics::floor::run_coulomb"),
]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--bench-binary")
    args = ap.parse_args()
    binary = args.bench_binary or bench_binary()
    counts = {}
    print(f"{'case':36} {'instructions':>13} {'× pure rocking':>15}")
    for case, root in CASES:
        counts[case] = per_simulation(binary, case.replace(".", "\\."), "contact", root)
        pure = counts.get(case.split("/")[0] + "/no_sliding")
        print(f"{case:36} {counts[case]:13,.0f} {counts[case] / pure:15.2f}")


if __name__ == "__main__":
    main()
