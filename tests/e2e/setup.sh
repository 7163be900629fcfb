# What the page's browser checks need, installed when missing; sourced by
# tests/e2e/run.sh and docs/screenshots.sh from the repository root.
#
# - Chromium from the distribution's packages (as root) unless $CHROMIUM is
#   an executable (default /usr/bin/chromium);
# - a venv under target/e2e-venv with exactly the versions of
#   tests/e2e/requirements.txt (reused while that file is unchanged);
# - the binary under test: $TOPPLE_BIN, or the debug build (built here) in
#   $CARGO_TARGET_DIR (default target/).
#
# Sets and exports CHROMIUM and TOPPLE_BIN; sets e2e_python (the venv's
# interpreter). Needs `root` (the repository) and a `die` function.

# --- Chromium ------------------------------------------------------------------
export CHROMIUM=${CHROMIUM:-/usr/bin/chromium}
if [[ ! -x $CHROMIUM ]]; then
  [[ $(id -u) -eq 0 ]] || die "no $CHROMIUM; install the Debian package chromium (as root) or set CHROMIUM"
  echo "installing chromium from the distribution's packages" >&2
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -qq
  apt-get install -y -qq chromium >/dev/null
  [[ -x $CHROMIUM ]] || die "chromium was installed but $CHROMIUM is missing; set CHROMIUM"
fi

# --- Python and the venv ---------------------------------------------------------
e2e_base_python=${PYTHON:-python3}
command -v "$e2e_base_python" >/dev/null 2>&1 || die "no Python interpreter ($e2e_base_python); set PYTHON"
e2e_venv=$root/target/e2e-venv
e2e_requirements=$root/tests/e2e/requirements.txt
e2e_want=$("$e2e_base_python" -c 'import hashlib, sys; print(hashlib.sha256(open(sys.argv[1], "rb").read()).hexdigest())' "$e2e_requirements")
e2e_stamp=$e2e_venv/.requirements.sha256
if [[ "$(cat "$e2e_stamp" 2>/dev/null)" != "$e2e_want" ]] || ! "$e2e_venv/bin/python" -c 'import websocket' 2>/dev/null; then
  echo "installing $(tr '\n' ' ' <"$e2e_requirements")into ${e2e_venv#"$root"/}" >&2
  if ! "$e2e_venv/bin/python" -c '' 2>/dev/null; then
    "$e2e_base_python" -m venv --clear "$e2e_venv" || die "cannot create a venv (on Debian: apt-get install python3-venv)"
  fi
  "$e2e_venv/bin/python" -m pip install --disable-pip-version-check --no-input -q -r "$e2e_requirements"
  echo "$e2e_want" >"$e2e_stamp"
fi
e2e_python=$e2e_venv/bin/python

# --- The binary ---------------------------------------------------------------------
if [[ -z ${TOPPLE_BIN:-} ]]; then
  cargo build --bin topple
  TOPPLE_BIN=${CARGO_TARGET_DIR:-$root/target}/debug/topple
fi
[[ -x $TOPPLE_BIN ]] || die "not an executable: $TOPPLE_BIN"
export TOPPLE_BIN
