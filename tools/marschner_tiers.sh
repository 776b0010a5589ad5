#!/bin/sh
# marschner_tiers.sh — how close each lower tier of a Marschner material
# comes to its marschner tier, per scene: hairgen writes the bundle (the
# lower tiers' constants fitted under that scene's lights), hairview renders
# every tier at the scene's shipped size, png_metrics compares each with
# marschner. Prints one line per scene: TIER=HAIR_PSNR/WHOLE_FRAME_PSNR (dB).
#
#   tools/marschner_tiers.sh OUT_DIR [MATERIAL.json [SCENE_NAME...]]
#   (defaults: materials/brown-marschner.json; backlit furball patches ratboy)
# Run from the repository root after `make build/hairgen build/hairview build/png_metrics`.
set -e
out=$1
[ -n "$out" ] || { echo "usage: $0 OUT_DIR [MATERIAL.json [SCENE...]]" >&2; exit 2; }
material=${2:-materials/brown-marschner.json}
[ $# -ge 2 ] && shift 2 || shift $#
scenes=${*:-backlit furball patches ratboy}
mkdir -p "$out"
for s in $scenes; do
  build/hairgen "$material" --scene "scenes/$s.json" -o "$out/$s" > /dev/null
  for t in marschner full vertex fixed4 fixed gl11; do
    build/hairview --bundle "$out/$s" --scene "scenes/$s.json" --tier "$t" --strict --frames 1 -o "$out/$s-$t.png" \
      > "$out/$s-$t.log" 2>&1 || { cat "$out/$s-$t.log" >&2; exit 1; }
  done
  line="$s"
  for t in full vertex fixed4 fixed gl11; do
    m=$(build/png_metrics "$out/$s-marschner.png" "$out/$s-$t.png")
    hair=$(echo "$m" | tr ' ' '\n' | sed -n 's/^hair_psnr_db=//p')
    whole=$(echo "$m" | tr ' ' '\n' | sed -n 's/^psnr_db=//p')
    line="$line $t=$hair/$whole"
  done
  echo "$line"
done
