#!/usr/bin/env bash
# End-to-end test of the web page (`/`) in headless Chromium: see page_test.py.
#
# Installs what is missing (see setup.sh): Chromium from the distribution's
# packages (as root), and a venv under target/e2e-venv with exactly the
# versions of tests/e2e/requirements.txt (reused while that file is unchanged).
#
# Usage:
#   tests/e2e/run.sh
#
# Environment:
#   TOPPLE_BIN   binary under test; when unset, `cargo build` builds
#                the debug binary (in $CARGO_TARGET_DIR, default target/)
#   CHROMIUM     browser (default /usr/bin/chromium)
#   PYTHON       interpreter for the venv (default python3)
#   E2E_OUT      screenshots (default target/e2e)
#   E2E_TIMEOUT  seconds a job may take to show its plot (default 60)
set -euo pipefail

root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
cd "$root"

die() { echo "e2e/run.sh: $*" >&2; exit 2; }

# shellcheck source=tests/e2e/setup.sh
source "$root/tests/e2e/setup.sh"

exec "$e2e_python" "$root/tests/e2e/page_test.py"
