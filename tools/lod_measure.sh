#!/bin/sh
# tools/lod_measure.sh — every (geometry LOD, tier) pair of a scene at
# several projected sizes (hairview --size), against (LOD 0, the first of
# TIERS) at the same size: frame cost and PSNR/SSIM/ΔE00 (png_metrics), the
# pop between adjacent levels of a tier (PSNR of level n against n - 1),
# and per size the pair the error:DB rule picks (the cheapest at >= DB dB,
# as ht_lod_pick_error does over measured cells). docs/lod.md's tables
# come from it.
#
#   tools/lod_measure.sh BUNDLE SCENE OUTDIR
#   environment: SIZES ("1 0.5 0.25"), LEVELS ("0 1 2 3 4"), TIERS ("full";
#                e.g. "full vertex fixed4 fixed gl11"), FRAMES (2), DB (30),
#                EXTRA (more hairview options for every image, the reference
#                too, e.g. "--samples 4" or "--width-rule"), REF (when set, the
#                reference is drawn apart, full detail in the first of TIERS with
#                these options instead of EXTRA, e.g. "--supersample 4": the
#                16x truth; image s<S>_ref.png)
# One line a cell: "size S lod N tier T strand_px W ms M cost C psnr_db=...
# ssim=... de00_mean=... de00_p95=... adjacent_psnr_db=..."; a level past
# the scene's last (hairview refuses it) prints "none". Then a line a size:
# "size S error:DB picks lod N tier T cost C psnr_db P" (or "none"). Run
# after `make`.
set -u
b=$1; sc=$2; d=$3
B=${HAIRTIER_BUILD:-build}
TIERS=${TIERS:-full}
ref=${TIERS%% *}
mkdir -p "$d"
cells=$d/cells.txt
: >"$cells"
for size in ${SIZES:-1 0.5 0.25}; do
  ref_ms=""
  refimg=$d/s${size}_${ref}_l0.png
  if [ -n "${REF:-}" ]; then
    refimg=$d/s${size}_ref.png
    "$B/hairview" --bundle "$b" --scene "$sc" --tier "$ref" --strict --lod 0 --size "$size" --frames 1 $REF \
      -o "$refimg" >/dev/null 2>&1 || { echo "size $size: the reference failed"; continue; }
  fi
  for t in $TIERS; do
    for l in ${LEVELS:-0 1 2 3 4}; do
      img=$d/s${size}_${t}_l$l.png
      out=$("$B/hairview" --bundle "$b" --scene "$sc" --tier "$t" --strict --lod "$l" --size "$size" \
            --frames "${FRAMES:-2}" ${EXTRA:-} -o "$img" 2>/dev/null) || { echo "size $size lod $l tier $t: none"; continue; }
      ms=$(echo "$out" | sed -n 's/frame_ms=//p'); px=$(echo "$out" | sed -n 's/.*strand_px=\([0-9.]*\).*/\1/p')
      [ -n "$ref_ms" ] || ref_ms=$ms
      cost=$(awk -v a="$ms" -v r="$ref_ms" 'BEGIN { printf "%.3f", a / r }')
      m=$("$B/png_metrics" "$refimg" "$img" | cut -d' ' -f1-4)
      prev=""
      [ "$l" -gt 0 ] && [ -f "$d/s${size}_${t}_l$((l - 1)).png" ] &&
        prev=$("$B/png_metrics" "$d/s${size}_${t}_l$((l - 1)).png" "$img" | sed 's/ .*//')
      line="size $size lod $l tier $t strand_px $px ms $ms cost $cost $m adjacent_$prev"
      echo "$line"
      echo "$line" >>"$cells"
    done
  done
  awk -v s="$size" -v db="${DB:-30}" '$2 == s {
      split($13, p, "="); psnr = p[2] == "inf" ? 1e9 : p[2] + 0
      if (psnr >= db && (best == "" || $12 + 0 < cost)) { best = "lod " $4 " tier " $6; cost = $12 + 0; bp = p[2] } }
    END { if (best == "") print "size " s " error:" db " picks none";
          else printf "size %s error:%s picks %s cost %.3f psnr_db %s\n", s, db, best, cost, bp }' "$cells"
done
