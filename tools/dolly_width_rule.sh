#!/bin/sh
# tools/dolly_width_rule.sh — a moving camera through one ht_lod_chain
# (hairview --lod auto --distance A:B: the eye dollied from the scene's
# distance to FAR times it over FRAMES frames, the level re-picked every
# frame) with the width rule off, per draw and per vertex: the mean frame
# (select, uploads and draw, each ended by glFinish) and the last frame's
# PSNR against full detail supersampled 4 x 4 at the far distance
# (docs/lod.md, "In the chain, per frame"); with ASYNC=1 per draw and per
# vertex again with hairview --lod-async (the level's sort or widened copy
# on a thread, docs/lod.md "A switch off the frame"), side by side.
#
#   tools/dolly_width_rule.sh BUNDLE SCENE OUTDIR NEAR
#   NEAR: the scene's eye-to-target distance (scenes/furball.json: 3.3508)
#   environment: TIER (full), SIZE (hairview --size, 1), FAR (4), FRAMES (48),
#                ASYNC (1: the async rows too),
#                EXTRA (more hairview options, e.g. "--context egl"),
#                HAIRTIER_BUILD (build; the device run: .device/bin's parent)
# One line a rule: "RULE frame_ms=M max_frame_ms=X max_select_ms=S switches=N psnr_db=P"
# (the mean frame; the longest frame and select after the first: a switch's stall).
set -u
b=$1; sc=$2; d=$3; near=$4
B=${HAIRTIER_BUILD:-build}
mkdir -p "$d"
hv="$B/hairview --bundle $b --scene $sc --size ${SIZE:-1} --tier ${TIER:-full} --strict ${EXTRA:-}"
far=$(awk "BEGIN { print $near * ${FAR:-4} }")
$hv --lod 0 --distance "$far" --supersample 4 --frames 1 -o "$d/truth.png" >/dev/null 2>&1 ||
  { echo "dolly_width_rule: the reference failed"; exit 1; }
rows="off:--width-rule=off draw:--width-rule=draw vertex:--width-rule"
[ "${ASYNC:-0}" = 1 ] && rows="$rows draw-async:--width-rule=draw:--lod-async vertex-async:--width-rule:--lod-async"
for v in $rows; do
  n=${v%%:*}; a=$(echo "${v#*:}" | tr : ' ')
  if ! $hv --lod auto --distance "$near:$far" --frames "${FRAMES:-48}" $a -o "$d/$n.png" >"$d/$n.txt" 2>&1; then
    echo "$n failed: $(tail -1 "$d/$n.txt")"; continue
  fi
  echo "$n $(grep -o '^frame_ms=[0-9.]*' "$d/$n.txt") $(grep -o 'max_frame_ms=[0-9.]*' "$d/$n.txt")" \
       "$(grep -o 'max_select_ms=[0-9.]*' "$d/$n.txt") switches=$(grep -c '^lod_pair' "$d/$n.txt")" \
       "$("$B/png_metrics" "$d/truth.png" "$d/$n.png" | cut -d' ' -f1)"
done
