#!/bin/sh
# tools/flip_order.sh — do PSNR and FLIP rank a bundle's tiers alike? For
# every shipped material × scene pair (or the pairs named, MATERIAL:SCENE),
# `hairgen --measure` at the scene's size, then one Markdown row: the tiers
# best first by PSNR (higher better) and by FLIP mean (lower better), and
# whether they agree: no two tiers ranked strictly the other way round by
# the two (a tie in either is no disagreement). Run from the repository
# root after `make`; each pair takes a minute or more on llvmpipe.
#
#   tools/flip_order.sh [MATERIAL:SCENE ...]      (HAIRGEN, OUT override)
set -eu
HAIRGEN=${HAIRGEN:-build/hairgen}
OUT=${OUT:-$(mktemp -d "${TMPDIR:-/tmp}/flip-order.XXXXXX")}
mkdir -p "$OUT"
if [ $# -eq 0 ]; then
    for m in materials/*.json; do
        for s in scenes/*.json; do set -- "$@" "$(basename "$m" .json):$(basename "$s" .json)"; done
    done
fi
echo "| material | scene | by PSNR | by FLIP mean | agree |"
echo "| --- | --- | --- | --- | --- |"
for pair in "$@"; do
    m=${pair%%:*} s=${pair##*:}
    "$HAIRGEN" "materials/$m.json" --scene "scenes/$s.json" --measure -o "$OUT/$m-$s" >"$OUT/$m-$s.txt" 2>&1 ||
        { echo "| $m | $s | hairgen failed: $(tail -n 1 "$OUT/$m-$s.txt") | | |"; continue; }
    # The measured table: tier frame_ms cost psnr_db ssim de00_mean de00_p95 flip_mean flip_p95.
    sed -n '/^tier  *frame_ms/,$p' "$OUT/$m-$s.txt" | awk -v m="$m" -v s="$s" '
        NR > 1 && NF >= 9 { n++; name[n] = $1; psnr[n] = ($4 == "same" ? 1e9 : $4 + 0); flip[n] = $8 + 0 }
        function order(key, sign,   i, j, k, t, idx, out) {
            for (i = 1; i <= n; i++) idx[i] = i
            for (i = 2; i <= n; i++)      # insertion sort, stable: the bundle order breaks ties
                for (j = i; j > 1 && sign * key[idx[j]] > sign * key[idx[j - 1]]; j--) { t = idx[j]; idx[j] = idx[j - 1]; idx[j - 1] = t }
            out = name[idx[1]]
            for (k = 2; k <= n; k++) out = out (key[idx[k]] == key[idx[k - 1]] ? " = " : " > ") name[idx[k]]
            return out
        }
        END {
            bad = ""
            for (i = 1; i <= n; i++)
                for (j = i + 1; j <= n; j++)
                    if ((psnr[i] - psnr[j]) * (flip[j] - flip[i]) < 0) bad = bad (bad == "" ? "" : ", ") name[i] "/" name[j]
            printf "| %s | %s | %s | %s | %s |\n", m, s, order(psnr, 1), order(flip, -1), (bad == "" ? "yes" : "no: " bad)
        }'
done
