#!/bin/sh
# tools/es1_accuracy.sh — GL ES 1.1 against desktop GL, each shipped scene
# at its shipped size, each fixed-function tier forced (strict): the same
# driver (EGL, llvmpipe unless GALLIUM_DRIVER says otherwise), bundle and
# tier on both contexts; prints a markdown table of png_metrics' numbers
# (docs/accuracy.md). Run from the repository root after `make`.
set -eu
OUT=${OUT:-out/es1-accuracy}
B=${BUILD:-build}
mkdir -p "$OUT"
export EGL_PLATFORM=surfaceless
field() { tr ' ' '\n' <"$1" | sed -n "s/^$2=//p" | head -1; }
echo "| scene | tier | PSNR dB | hair PSNR dB | max diff /255 |"
echo "| --- | --- | --- | --- | --- |"
for s in furball patches ratboy backlit; do
    m=dark-brown
    [ "$s" = backlit ] && m=brown-marschner
    "$B/hairgen" "materials/$m.json" --scene "scenes/$s.json" -o "$OUT/$s" -q
    for t in fixed4 fixed gl11; do
        for api in gl gles1; do
            "$B/hairview" --context egl --api "$api" --bundle "$OUT/$s" --scene "scenes/$s.json" --tier "$t" --strict \
                --frames 1 -o "$OUT/$s-$t-$api.png" >"$OUT/$s-$t-$api.txt" 2>&1
        done
        "$B/png_metrics" "$OUT/$s-$t-gl.png" "$OUT/$s-$t-gles1.png" >"$OUT/$s-$t.metrics"
        echo "| $s | $t | $(field "$OUT/$s-$t.metrics" psnr_db) | $(field "$OUT/$s-$t.metrics" hair_psnr_db) |" \
             "$(field "$OUT/$s-$t.metrics" max_diff) |"
    done
done
