#!/usr/bin/env bash
# A longer soak of the Coulomb floor's property test
# (tests/engine/contact_fuzz.rs): ROUNDS rounds of CASES random valid
# histories each, every round from a fresh seed. Prints each round's seed
# and result (with the cases that took over 0.5 s: a history, its mirror
# and pure rocking), then the totals; a failing round prints the case proptest
# shrank it to, and its seed reproduces it:
#
#   TOPPLE_FUZZ_SEED=<seed> TOPPLE_FUZZ_CASES=<cases> cargo test --test engine contact_fuzz
#
#   bash bench/contact_soak.sh [ROUNDS] [CASES]     (default 10 rounds of 500)
set -euo pipefail
cd "$(dirname "$0")/.."
rounds=${1:-10}; cases=${2:-500}
cargo test --test engine --no-run --quiet 2>/dev/null
passed=0; failed=0; started=$(date +%s)
for round in $(seq 1 "$rounds"); do
  seed=$(od -An -N6 -tu8 /dev/urandom | tr -d ' ')
  t0=$(date +%s)
  if out=$(TOPPLE_FUZZ_SEED=$seed TOPPLE_FUZZ_CASES=$cases \
      cargo test --quiet --test engine contact_fuzz -- --nocapture 2>&1); then
    passed=$((passed + 1))
    slow=$(echo "$out" | grep -c "slow case" || true)
    echo "round $round seed $seed: $cases cases, 0 failures, $slow over 0.5 s ($(( $(date +%s) - t0 )) s)"
    echo "$out" | grep "slow case" | cut -c1-400 || true
  else
    failed=$((failed + 1))
    echo "round $round seed $seed: FAILED"
    echo "$out" | grep -E "minimal failing input|Test failed|panicked" | head -5
  fi
done
echo "soak: $((rounds * cases)) cases in $rounds rounds, $failed failing rounds, $(( $(date +%s) - started )) s"
[ "$failed" -eq 0 ]
