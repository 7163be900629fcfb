#!/usr/bin/env python3
"""The cost of a vertical ground motion, counted in instructions: each case of
the criterion group `vertical` (benches/engine.rs) run under valgrind's
callgrind, its instructions per simulation (inclusive of `simulate`, divided
by its calls) printed beside the same case without a vertical motion. Counts
are repeatable for one binary whatever else the machine does, where
wall-clock times on a shared 2-core machine move by 30 % from run to run.

    python3 bench/vertical_cost.py [--bench-binary PATH] [--cases REGEX]

Without --bench-binary the engine bench is built (cargo bench --no-run) and
its binary used. Give another build's binary (an older commit with the same
cases) to compare the cases without a vertical motion across commits.
"""
import argparse
import glob
import os
import re
import subprocess
import sys
import tempfile

CASES = [
    "pulse/none/outcome", "pulse/ratio/outcome", "pulse/own_same/outcome", "pulse/own/outcome",
    "pulse/none/full", "pulse/ratio/full", "pulse/own_same/full", "pulse/own/full",
    "record/none/outcome", "record/ratio/outcome", "record/own/outcome",
]


def bench_binary():
    out = subprocess.run(
        ["cargo", "bench", "--bench", "engine", "--no-run", "--message-format=json"],
        capture_output=True, text=True, check=True).stdout
    for line in out.splitlines():
        m = re.search(r'"executable":"([^"]+)"', line)
        if m and "/engine-" in m.group(1):
            return m.group(1)
    sys.exit("no engine bench binary built")


def per_simulation(binary, case, group="vertical", root="topple::dynamics::simulate::simulate"):
    """Instructions per call of `root` in the criterion case `group/case`."""
    with tempfile.TemporaryDirectory() as d:
        out = os.path.join(d, "cg.out")
        subprocess.run(
            ["valgrind", "--tool=callgrind", f"--callgrind-out-file={out}", binary,
             "--bench", f"^{group}/{case}$", "--profile-time", "1"],
            capture_output=True, check=True)
        annotated = subprocess.run(["callgrind_annotate", "--inclusive=yes", out],
                                   capture_output=True, text=True, check=True).stdout
        inclusive = None
        for line in annotated.splitlines():
            if re.search(re.escape(root) + r"( \[|$)", line.rstrip()):
                inclusive = int(line.split()[0].replace(",", ""))
                break
        names, calls, callee = {}, 0, None
        with open(out) as f:
            for line in f:
                m = re.match(r"(c?fn)=\((\d+)\)(?: (.*))?", line.rstrip("\n"))
                if m:
                    if m.group(3):
                        names[m.group(2)] = m.group(3)
                    callee = names.get(m.group(2), "") if m.group(1) == "cfn" else None
                    continue
                if line.startswith("calls=") and callee and callee.endswith(root.split("::", 1)[1]):
                    calls += int(line.split("=")[1].split()[0])
        if not inclusive or not calls:
            sys.exit(f"{case}: no {root} calls found")
        return inclusive / calls


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--bench-binary")
    ap.add_argument("--cases", default=".")
    args = ap.parse_args()
    binary = args.bench_binary or bench_binary()
    cases = [c for c in CASES if re.search(args.cases, c)]
    counts = {}
    print(f"{'case':28} {'instructions/sim':>17} {'× none':>8}")
    for case in cases:
        try:
            counts[case] = per_simulation(binary, case)
        except subprocess.CalledProcessError:
            print(f"{case:28} {'(not in this build)':>17}")
            continue
        motion, _, tag = case.split("/")
        none = counts.get(f"{motion}/none/{tag}")
        ratio = f"{counts[case] / none:8.3f}" if none else ""
        print(f"{case:28} {counts[case]:17,.0f} {ratio}")


if __name__ == "__main__":
    main()
