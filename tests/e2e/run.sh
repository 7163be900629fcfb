#!/usr/bin/env bash
# End-to-end test of the web page (`/`) in headless Chromium: see page_test.py.
#
# Installs what is missing: Chromium from the distribution's packages (as
# root), and a venv under target/e2e-venv with exactly the versions of
# tests/e2e/requirements.txt (reused while that file is unchanged).
#
# Usage:
#   tests/e2e/run.sh
#
# Environment:
#   TOPPLE_BIN   binary under test; when unset, `cargo build` builds
#                target/debug/topple
#   CHROMIUM     browser (default /usr/bin/chromium)
#   PYTHON       interpreter for the venv (default python3)
#   E2E_OUT      screenshots (default target/e2e)
#   E2E_TIMEOUT  seconds the time history may take to show its plot (default 60)
set -euo pipefail

root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
cd "$root"

log() { echo "e2e/run.sh: $*" >&2; }
die() { log "$*"; exit 2; }

# --- Chromium ------------------------------------------------------------------
export CHROMIUM=${CHROMIUM:-/usr/bin/chromium}
if [[ ! -x $CHROMIUM ]]; then
  [[ $(id -u) -eq 0 ]] || die "no $CHROMIUM; install the Debian package chromium (as root) or set CHROMIUM"
  log "installing chromium from the distribution's packages"
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -qq
  apt-get install -y -qq chromium >/dev/null
  [[ -x $CHROMIUM ]] || die "chromium was installed but $CHROMIUM is missing; set CHROMIUM"
fi

# --- Python and the venv ---------------------------------------------------------
python=${PYTHON:-python3}
command -v "$python" >/dev/null 2>&1 || die "no Python interpreter ($python); set PYTHON"
venv=$root/target/e2e-venv
requirements=$root/tests/e2e/requirements.txt
want=$("$python" -c 'import hashlib, sys; print(hashlib.sha256(open(sys.argv[1], "rb").read()).hexdigest())' "$requirements")
stamp=$venv/.requirements.sha256
if [[ "$(cat "$stamp" 2>/dev/null)" != "$want" ]] || ! "$venv/bin/python" -c 'import websocket' 2>/dev/null; then
  log "installing $(tr '\n' ' ' <"$requirements")into ${venv#"$root"/}"
  if ! "$venv/bin/python" -c '' 2>/dev/null; then
    "$python" -m venv --clear "$venv" || die "cannot create a venv (on Debian: apt-get install python3-venv)"
  fi
  "$venv/bin/python" -m pip install --disable-pip-version-check --no-input -q -r "$requirements"
  echo "$want" >"$stamp"
fi

# --- The binary ---------------------------------------------------------------------
if [[ -z ${TOPPLE_BIN:-} ]]; then
  cargo build --bin topple
  TOPPLE_BIN=$root/target/debug/topple
fi
[[ -x $TOPPLE_BIN ]] || die "not an executable: $TOPPLE_BIN"
export TOPPLE_BIN

exec "$venv/bin/python" "$root/tests/e2e/page_test.py"
