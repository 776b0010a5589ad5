#!/bin/sh
# tools/lod_file_psnr.sh — what lods.bin's quantized vertices (HTLODS3)
# do to images: every stored level of a scene drawn from a bundle that
# stores them (hairgen --scene) against the same level built in memory at
# run time (a --no-lods bundle of the same material), each tier, one frame
# at the scene's size; png_metrics of the pair. docs/lod.md's table comes
# from it.
#
#   tools/lod_file_psnr.sh MATERIAL SCENE OUTDIR
#   environment: TIERS ("full vertex fixed4 fixed gl11"), LEVELS ("1 2 3 4")
# One line a cell: "lod N tier T psnr_db=... hair_psnr_db=... max_diff=...";
# a level past the scene's last prints "none". Run after `make`.
set -u
m=$1; sc=$2; d=$3
B=${HAIRTIER_BUILD:-build}
mkdir -p "$d"
rm -rf "$d/stored" "$d/built"
"$B/hairgen" -q "$m" --scene "$sc" -o "$d/stored" || exit 1
"$B/hairgen" -q "$m" --scene "$sc" --no-lods -o "$d/built" || exit 1
for t in ${TIERS:-full vertex fixed4 fixed gl11}; do
  for l in ${LEVELS:-1 2 3 4}; do
    if ! "$B/hairview" --bundle "$d/stored" --scene "$sc" --tier "$t" --strict --lod "$l" --frames 1 \
         -o "$d/stored_${t}_$l.png" >"$d/log" 2>&1; then
      echo "lod $l tier $t none"; continue
    fi
    grep -q "stored kind=strands" "$d/log" || { echo "lod $l tier $t: not drawn from lods.bin"; exit 1; }
    "$B/hairview" --bundle "$d/built" --scene "$sc" --tier "$t" --strict --lod "$l" --frames 1 \
      -o "$d/built_${t}_$l.png" >"$d/log" 2>&1 || { cat "$d/log"; exit 1; }
    echo "lod $l tier $t $("$B/png_metrics" "$d/built_${t}_$l.png" "$d/stored_${t}_$l.png")"
  done
done
