#!/usr/bin/env bash
# The cost of verifying intervals (src/spectrum/verify.rs): forensic queries
# and record spectra on the project's two records, run by two builds side
# by side in one run, alternating.
#
#   bash bench/verification_cost.sh BEFORE_BIN AFTER_BIN [ROUNDS]
#
# BEFORE_BIN: a build without verification (e.g. of commit 2c28bfc), AFTER_BIN
# this one. Prints, per spec and build, the simulations, those verifying, and
# the best wall time of ROUNDS runs (default 1).
set -euo pipefail
before=$(realpath "$1"); after=$(realpath "$2"); rounds=${3:-1}
cd "$(dirname "$0")/../specs/records"
specs=(ridge_forensic_cabinet.json valley_forensic_cabinet.json record_spectrum_ridge.json valley_record_spectrum.json)
printf '%-30s %-7s %12s %10s %9s\n' spec build simulations verifying wall_s
for spec in "${specs[@]}"; do
  for build in before after; do
    bin=$before; [ "$build" = after ] && bin=$after
    best=""
    out=$(mktemp)
    for _ in $(seq "$rounds"); do
      "$bin" run "$spec" 2>/dev/null >"$out"
      wall=$(python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["numerics"]["wall_time_s"])' "$out")
      if [ -z "$best" ] || python3 -c "import sys; sys.exit(0 if $wall < $best else 1)"; then best=$wall; fi
    done
    python3 -c '
import json, sys
d = json.load(open(sys.argv[1])); n = d["numerics"]
print("%-30s %-7s %12d %10s %9.2f" % (sys.argv[2], sys.argv[3], n["simulations"],
      n.get("verification_simulations", "-"), float(sys.argv[4])))' "$out" "$spec" "$build" "$best"
    rm -f "$out"
  done
done
