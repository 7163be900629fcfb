#!/usr/bin/env bash
# Regenerates the figures in docs/book/src/figures/ (all but precision.svg, which
# `topple precision` writes) from the specs in specs/ with `topple run --plot`,
# and renders each to PNG in headless Chromium for looking at: at its own size
# (NAME.png) and as the web page shows it, scaled to an 800 px wide pane
# (NAME.page.png).
#
# Usage:
#   docs/figures.sh
#
# Environment:
#   TOPPLE_BIN   the binary; when unset, `cargo build --release` builds it
#   CHROMIUM     browser (default /usr/bin/chromium; no PNGs without one)
#   FIGURES_PNG  where the PNGs go (default target/figures)
#   PANE         width of the page's plot pane, px (default 800)
set -euo pipefail

root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$root"

log() { echo "figures.sh: $*" >&2; }

# docs/book/src/figures/NAME.svg  specs/SPEC.json
figures=(
  "time_history_locomotive locomotive_nonlinear"
  "spectrum_locomotive_nonlinear locomotive_spectrum_nonlinear"
  "friction_locomotive locomotive_friction"
  "friction_one_cosine one_cosine_friction"
  "forensic_point_reyes point_reyes_forensic"
  "forensic_record_point_reyes point_reyes_forensic_record"
  "survival_power_law survival_power_law"
  "fragility_pbr pbr_fragility"
  "record_spectrum_ridge records/record_spectrum_ridge"
  "record_spectrum_valley records/valley_record_spectrum"
  "forensic_record_valley records/valley_forensic_cabinet"
  "spectrum_vertical_down locomotive_spectrum_vertical_down"
  "spectrum_vertical_none locomotive_spectrum_vertical_none"
  "spectrum_vertical_up locomotive_spectrum_vertical_up"
  "spectrum_coulomb_beside locomotive_spectrum_coulomb_beside"
)

if [[ -z ${TOPPLE_BIN:-} ]]; then
  cargo build --release --bin topple
  TOPPLE_BIN=${CARGO_TARGET_DIR:-$root/target}/release/topple
fi
[[ -x $TOPPLE_BIN ]] || { log "not an executable: $TOPPLE_BIN"; exit 2; }

for pair in "${figures[@]}"; do
  read -r name spec <<<"$pair"
  "$TOPPLE_BIN" run --plot "docs/book/src/figures/$name.svg" "specs/$spec.json" >/dev/null
  log "docs/book/src/figures/$name.svg from specs/$spec.json"
done

chromium=${CHROMIUM:-/usr/bin/chromium}
if [[ ! -x $chromium ]]; then
  log "no $chromium: SVGs written, no PNGs (tests/e2e/run.sh installs Chromium)"
  exit 0
fi
out=${FIGURES_PNG:-$root/target/figures}
pane=${PANE:-800}
mkdir -p "$out"
flags=(--headless --disable-gpu --hide-scrollbars --force-device-scale-factor=1)
[[ $(id -u) -eq 0 ]] && flags+=(--no-sandbox)

# Width and height of an SVG, from its opening tag.
size() { sed -n '1s/.*width="\([0-9]*\)" height="\([0-9]*\)".*/\1 \2/p' "$1"; }

shoot() { # PNG, WIDTH, HEIGHT, URL
  "$chromium" "${flags[@]}" --window-size="$2,$3" --screenshot="$1" "$4" >/dev/null 2>&1
}

for pair in "${figures[@]}"; do
  read -r name _ <<<"$pair"
  svg=$root/docs/book/src/figures/$name.svg
  read -r w h <<<"$(size "$svg")"
  shoot "$out/$name.png" "$w" "$h" "file://$svg"
  # As the page shows it: scaled to the pane's width.
  ph=$(( (h * pane + w - 1) / w ))
  page=$out/$name.page.html
  printf '<!doctype html><style>body{margin:0}img{width:%dpx;display:block}</style><img src="file://%s">\n' \
    "$pane" "$svg" >"$page"
  shoot "$out/$name.page.png" "$pane" "$ph" "file://$page"
  log "$out/$name.png, $name.page.png (${w}x${h}, shown at ${pane} px)"
done
