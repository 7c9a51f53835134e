#!/usr/bin/env bash
# Regenerates the pictures in docs/images/ from the shipped scenarios, as they
# render by default: the flagship's frame 40 and contact sheet (README), and
# docs/images/scenarios_sheet.png, two frames (the middle and the last) of
# every scenario in scenarios/ (those that render nothing by themselves:
# every 4th frame, 960x600), each labelled with its name; and the retraction
# and the flagship with the linear law beside their shipped nonlinear one
# (docs/images/*_laws.png). Needs ffmpeg
# (./scripts/install-deps.sh --video) for the labelled grid.
#   scripts/docs_images.sh build/softcut
set -euo pipefail
bin=$(realpath "${1:?usage: scripts/docs_images.sh PATH/TO/softcut}")
cd "$(dirname "$0")/.."
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
font=$(fc-match -f '%{file}' 'DejaVu Sans:bold' 2>/dev/null || true)
tiles=()
for s in scenarios/*.lua; do
  name=$(basename "$s" .lua)
  "$bin" run "$s" --quiet --out "$work/$name" >/dev/null
  # A scenario that renders nothing by itself: every 4th frame at the default size.
  [ -d "$work/$name/frames" ] || "$bin" run "$s" --quiet --out "$work/$name" --render-every 4 --size 960x600 >/dev/null
  mapfile -t frames < <(ls "$work/$name/frames"/frame_*.png | sort)
  n=${#frames[@]}
  for f in "${frames[$((n / 2))]}" "${frames[$((n - 1))]}"; do
    tile="$work/tile_${#tiles[@]}.png"
    label="$name, frame $(basename "$f" .png | sed 's/frame_0*//; s/^$/0/')"
    text=""
    [ -n "$font" ] && text=",drawtext=fontfile=$font:text='$label':x=8:y=8:fontsize=15:fontcolor=white:box=1:boxcolor=black@0.55:boxborderw=4"
    ffmpeg -v error -y -i "$f" -vf "scale=400:250:force_original_aspect_ratio=decrease,pad=400:250:(ow-iw)/2:(oh-ih)/2:color=0x333842$text" "$tile"
    tiles+=("$tile")
  done
done
cp "$work/incision_drag_poke/frames/frame_000040.png" docs/images/incision_drag_poke_040.png
# The paper's linear law (--set model=linear) beside the shipped nonlinear one,
# where the two differ most: the lobe lifted (retraction, last frame), the lip
# dragged open (flagship, frame 40). docs/fidelity.md shows them.
for pair in liver_retraction:60:corotational incision_drag_poke:40:neo-Hookean; do
  IFS=: read -r name frame law <<<"$pair"
  "$bin" run "scenarios/$name.lua" --quiet --out "$work/$name.linear" --set model=linear >/dev/null
  f=$(printf 'frame_%06d.png' "$frame")
  label() { [ -n "$font" ] && echo ",drawtext=fontfile=$font:text='$1':x=10:y=10:fontsize=22:fontcolor=white:box=1:boxcolor=black@0.55:boxborderw=5"; }
  ffmpeg -v error -y -i "$work/$name.linear/frames/$f" -i "$work/$name/frames/$f" -filter_complex \
    "[0]scale=640:-2$(label "linear law (the paper)")[a];[1]scale=640:-2$(label "$law (as shipped)")[b];[a][b]hstack" \
    "docs/images/${name}_laws.png"
done
cp "$work/incision_drag_poke/contact_sheet.png" docs/images/incision_drag_poke_sheet.png
# The grid: 4 tiles a row.
inputs=() layout=()
for i in "${!tiles[@]}"; do
  inputs+=(-i "${tiles[$i]}")
  layout+=("$((i % 4 * 400))_$((i / 4 * 250))")
done
while [ $(( ${#layout[@]} % 4 )) -ne 0 ]; do  # fill the last row
  i=${#layout[@]}
  inputs+=(-f lavfi -i "color=c=0x1a1a1a:s=400x250:d=1")
  layout+=("$((i % 4 * 400))_$((i / 4 * 250))")
done
(IFS='|'; ffmpeg -v error -y "${inputs[@]}" -filter_complex "xstack=inputs=${#layout[@]}:layout=${layout[*]}" \
  -frames:v 1 docs/images/scenarios_sheet.png)
echo "docs/images: incision_drag_poke_040.png, incision_drag_poke_sheet.png, scenarios_sheet.png (${#tiles[@]} tiles), liver_retraction_laws.png, incision_drag_poke_laws.png"
