#!/bin/sh
# tools/cards_measure.sh — a scene's cards (hairgen --cards, docs/lod.md)
# against full detail at several projected sizes (hairview --size): frame
# cost as a ratio of full detail's at that size and PSNR/SSIM/ΔE00
# (png_metrics). docs/lod.md's cards table comes from it.
#
#   tools/cards_measure.sh BUNDLE SCENE OUTDIR
#   environment: SIZES ("1 0.5 0.25"), CARDS (strands per card, "32 8"),
#                FRAMES (2), EXTRA (more hairview options, e.g. "--samples 4")
# One line a cell: "size S cards N count K ms T cost C psnr_db=... ssim=...
# de00_mean=... de00_p95=..."; full detail first ("cards 0"). The cards
# bundles are made in OUTDIR/cards-N (remade each run). Run after `make`.
set -u
b=$1; sc=$2; d=$3
B=${HAIRTIER_BUILD:-build}
mkdir -p "$d"
for n in ${CARDS:-32 8}; do
  rm -rf "$d/cards-$n"
  "$B/hairgen" --cards "$b" --scene "$sc" --strands-per-card "$n" -o "$d/cards-$n" >/dev/null || exit 1
done
for size in ${SIZES:-1 0.5 0.25}; do
  out=$("$B/hairview" --bundle "$b" --scene "$sc" --size "$size" --frames "${FRAMES:-2}" ${EXTRA:-} \
        -o "$d/s${size}_full.png" 2>/dev/null) || { echo "size $size full: failed"; exit 1; }
  ms0=$(echo "$out" | sed -n 's/frame_ms=//p')
  echo "size $size cards 0 ms $ms0 cost 1"
  for n in ${CARDS:-32 8}; do
    out=$("$B/hairview" --bundle "$d/cards-$n" --scene "$sc" --cards --size "$size" --frames "${FRAMES:-2}" \
          ${EXTRA:-} -o "$d/s${size}_cards$n.png" 2>/dev/null) || { echo "size $size cards $n: failed"; continue; }
    ms=$(echo "$out" | sed -n 's/frame_ms=//p'); k=$(echo "$out" | sed -n 's/.*kind=cards param=[0-9]* components=\([0-9]*\).*/\1/p')
    m=$("$B/png_metrics" "$d/s${size}_full.png" "$d/s${size}_cards$n.png" | cut -d' ' -f1-4)
    echo "size $size cards $n count $k ms $ms cost $(awk "BEGIN{printf \"%.3f\", $ms / $ms0}") $m"
  done
done
