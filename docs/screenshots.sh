#!/usr/bin/env bash
# Screenshots of the web page (`/`) for the documentation, taken in headless
# Chromium at 1400×1000: a time history that overturns, an overturning
# spectrum, a forensic query on pulses and one on a record, a fragility, a
# survival job, each submitted from the form, and the list of jobs (see
# tests/e2e/screenshots.py). Writes docs/book/src/figures/page-*.png.
#
# Starts its own server (a temporary SQLite database, a free port) and
# browser, and stops both. Installs what is missing as tests/e2e/run.sh does
# (tests/e2e/setup.sh).
#
# Usage:
#   docs/screenshots.sh
#
# Environment:
#   TOPPLE_BIN       binary to serve; when unset, `cargo build` builds the
#                    debug binary (in $CARGO_TARGET_DIR, default target/)
#   CHROMIUM         browser (default /usr/bin/chromium)
#   PYTHON           interpreter for the venv (default python3)
#   SCREENSHOTS_OUT  directory of the PNGs (default docs/book/src/figures/)
#   E2E_TIMEOUT      seconds a job may take to show its plot (default 60)
set -euo pipefail

root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$root"

die() { echo "docs/screenshots.sh: $*" >&2; exit 2; }

# shellcheck source=tests/e2e/setup.sh
source "$root/tests/e2e/setup.sh"

export SCREENSHOTS_OUT=${SCREENSHOTS_OUT:-$root/docs/book/src/figures}
exec "$e2e_python" "$root/tests/e2e/screenshots.py"
