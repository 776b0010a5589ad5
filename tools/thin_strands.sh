#!/bin/sh
# tools/thin_strands.sh — thin strands at a reduced projected size (default
# a quarter, hairview --size) against a 16x supersampled reference
# (--supersample 4, full detail): PSNR/SSIM of full detail, --lod auto,
# and both with --samples 4; full detail and --lod auto with --width-rule
# (a strand under a pixel drawn about a pixel wide, opacity scaled: per
# vertex where the tier can, else per draw), with and without --samples 4,
# and full detail with --width-rule=draw (per draw in every tier). The full
# measurement test_thin_strands makes cheaply (docs/lod.md). TIER=NAME draws
# every image in that tier (default: auto); EXTRA adds
# hairview options to all but the reference (e.g. "--context egl --api gles2").
#
#   tools/thin_strands.sh BUNDLE SCENE OUTDIR [SIZE]
set -u
b=$1; sc=$2; d=$3; size=${4:-0.25}
B=${HAIRTIER_BUILD:-build}
mkdir -p "$d"
ref="$B/hairview --bundle $b --scene $sc --size $size --frames 1 ${TIER:+--tier $TIER --strict}"
hv="$ref ${EXTRA:-}"
$ref --lod 0 --supersample 4 -o "$d/reference.png" >/dev/null 2>&1 || { echo "thin_strands: the reference failed"; exit 1; }
for v in "full:--lod 0" "auto:--lod auto" "full_ms4:--lod 0 --samples 4" "auto_ms4:--lod auto --samples 4" \
         "full_wr:--lod 0 --width-rule" "auto_wr:--lod auto --width-rule" "full_wr_ms4:--lod 0 --width-rule --samples 4" \
         "full_wr_draw:--lod 0 --width-rule=draw"; do
  n=${v%%:*}; a=${v#*:}
  lod=$($hv $a -o "$d/$n.png" 2>/dev/null | grep -E "^(lod|width_rule)=" | tr '\n' ' ') || { echo "$n: failed"; continue; }
  echo "$n $lod $("$B/png_metrics" "$d/reference.png" "$d/$n.png" | cut -d' ' -f1-4)"
done
