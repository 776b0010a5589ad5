#!/bin/sh
# tools/lod_measure.sh — every geometry LOD of a scene at several projected
# sizes (hairview --size), against full detail at the same size: frame cost
# and PSNR/SSIM/ΔE00 (png_metrics), and the pop between adjacent levels
# (PSNR of level n against n - 1). docs/lod.md's tables come from it.
#
#   tools/lod_measure.sh BUNDLE SCENE OUTDIR
#   environment: SIZES ("1 0.5 0.25"), LEVELS ("0 1 2 3 4"), FRAMES (2),
#                EXTRA (more hairview options, e.g. "--samples 4")
# One line a cell: "size S lod N strand_px W ms T psnr_db=... ssim=...
# de00_mean=... de00_p95=... adjacent_psnr_db=..."; a level past the
# scene's last (hairview refuses it) prints "none". Run after `make`.
set -u
b=$1; sc=$2; d=$3
B=${HAIRTIER_BUILD:-build}
mkdir -p "$d"
for size in ${SIZES:-1 0.5 0.25}; do
  for l in ${LEVELS:-0 1 2 3 4}; do
    out=$("$B/hairview" --bundle "$b" --scene "$sc" --lod "$l" --size "$size" --frames "${FRAMES:-2}" ${EXTRA:-} \
          -o "$d/s${size}_l$l.png" 2>/dev/null) || { echo "size $size lod $l: none"; continue; }
    ms=$(echo "$out" | sed -n 's/frame_ms=//p'); px=$(echo "$out" | sed -n 's/.*strand_px=//p')
    m=$("$B/png_metrics" "$d/s${size}_l0.png" "$d/s${size}_l$l.png" | cut -d' ' -f1-4)
    prev=""
    [ "$l" -gt 0 ] && prev=$("$B/png_metrics" "$d/s${size}_l$((l - 1)).png" "$d/s${size}_l$l.png" | sed 's/ .*//')
    echo "size $size lod $l strand_px $px ms $ms $m adjacent_$prev"
  done
done
