#!/bin/sh
# tools/device_nvidia.sh — the same runtime, bundles and
# scenes on NVIDIA's GL driver through EGL (headless, no X), compared tier by
# tier with llvmpipe. Two halves, run from the repository root:
#
#   tools/device_nvidia.sh prepare        here (Debian, with a package registry):
#       builds, renders the llvmpipe reference images (OSMesa), and gathers
#       into .device/ (ignored by git) what the device lacks: the programs,
#       the shared libraries ldd names beyond glibc (cJSON, libpng, zlib,
#       libstdc++), the glvnd packages (libegl1 libglvnd0 libopengl0 libgl1
#       libglx0 libgles2), the bundles and the references.
#   tools/device_nvidia.sh run [images|bench|cells|dolly|all]   there (carry .device):
#       images: every scene with every tier forced (strict), auto
#       selection, and the gl13 and gl20 device profiles
#       (HAIRTIER_DEVICE_PROFILE: NVIDIA has no MESA_GL_VERSION_OVERRIDE),
#       each image's PSNR against llvmpipe's of the same tier/profile; the
#       shader tiers on EGL ES 2.0 and 3.x contexts (--api gles2|gles3)
#       and the fixed-function tiers on an ES 1.1 context (--api gles1)
#       against NVIDIA's desktop GL image of the same tier; a tier sheet.
#       bench: bench_frame on the fur ball at 8 000, 200 000 and 1 000 000
#       hairs (512x512), its --lods pairs (4 samples) at 8 000 and
#       1 000 000 hairs at 256 and 128, the dense groom's with --width-rule
#       --truth (against the 16x truth, full-rule beside), plain and
#       --soft=6 and 8, at 256 and 128, and on ES 1.1, 2.0 and 3.x at 8 000
#       and 200 000. cells: the dense groom's (level, tier) cells measured
#       by hairgen --measure-lods against the 16x truth, and the pair
#       hairview's error:30 picks from them at 1/2 and 1/4 size. dolly:
#       the 200 000-hair fur ball dollied through the chain, full and gl11,
#       the width rule off / per draw / per vertex, sync and --lod-async.
#       Writes to $OUT (default out/device):
#       summary.md (the tables), run.log (everything printed) and
#       images.tar.gz (every PNG, the references too): three files, within
#       the device tool's eight.
#
# The device call, once prepared and committed code is in the tree:
#   carry [".device"], command
#   "sh tools/device_nvidia.sh run all"   (split into "run images" and
#   "run bench" if ten minutes are not enough).
set -eu

DEV=.device
SCENES="furball patches ratboy backlit"
TIERS="full vertex fixed4 fixed gl11"
# The material each scene is drawn with, and its tiers: backlit shows the
# Marschner material, whose bundle has the marschner tier above full.
material_for() { if [ "$1" = backlit ]; then echo brown-marschner; else echo dark-brown; fi; }
# The tiers an ES context runs: the shader tiers on ES 2.0/3.x, the
# fixed-function ones on ES 1.1.
es_tiers_for() {
    if [ "$2" = gles1 ]; then echo "fixed4 fixed gl11"
    elif [ "$1" = backlit ]; then echo "marschner full vertex"
    else echo "full vertex"; fi
}
tiers_for() { if [ "$1" = backlit ]; then echo "marschner $TIERS"; else echo "$TIERS"; fi; }
PROFILES="gl13 gl20"
# Overridable to try the script on a small machine (Mesa's EGL works too),
# or set empty to leave a series out.
BENCH_HAIRS=${BENCH_HAIRS-"8000 200000 1000000"}
BENCH_ES_HAIRS=${BENCH_ES_HAIRS-"8000 200000"}
# The (LOD, tier) pairs of bench_frame --lods (docs/lod.md), at half and a
# quarter of 512, 4 samples: issue 23's cost target.
BENCH_LOD_HAIRS=${BENCH_LOD_HAIRS-"8000 1000000"}
BENCH_LOD_SIZES=${BENCH_LOD_SIZES-"256 128"}
FRAMES=${FRAMES:-20}   # timed frames per image run

die() { echo "device_nvidia: $*" >&2; exit 1; }

if [ ! -f Makefile ] || [ ! -d scenes ]; then die "run from the repository root"; fi

prepare() {
    HAIRVIEW=build/hairview
    make -j2 all >/dev/null || die "make failed"
    exclude="$(git rev-parse --git-common-dir)/info/exclude"
    grep -qx "/$DEV/" "$exclude" 2>/dev/null || echo "/$DEV/" >>"$exclude"
    rm -rf "${DEV:?}/bin" "${DEV:?}/lib" "${DEV:?}/ref" "${DEV:?}/bundles"
    mkdir -p "$DEV/bin" "$DEV/lib" "$DEV/gl" "$DEV/ref" "$DEV/bundles"
    cp build/hairgen build/hairview build/bench_frame build/tier_sheet build/png_metrics "$DEV/bin/"
    # the dense groom (docs/lod.md): its scene names the .hair beside it
    mkdir -p "$DEV/dense" && cp build/gen/dense.json build/gen/dense.hair "$DEV/dense/"
    # Every library ldd names except glibc's own and glvnd's (from the
    # packages below, or the device's): the device image has neither this
    # Debian's cJSON nor necessarily its libpng.
    for b in "$DEV"/bin/*; do ldd "$b"; done | awk '$3 ~ /^\// { print $3 }' | sort -u | while read -r lib; do
        case "$(basename "$lib")" in
            libc.so.*|libm.so.*|libdl.so.*|libpthread.so.*|librt.so.*|ld-linux*|libEGL.so.*|libGLdispatch.so.*) ;;
            *) cp -L "$lib" "$DEV/lib/" ;;
        esac
    done
    # glvnd's loaders, amd64, as the device README says (no registry there).
    if ! ls "$DEV"/gl/libegl1_*.deb >/dev/null 2>&1; then
        o='-oAPT::Architecture=amd64 -oAPT::Architectures=amd64 -oDir::State::Lists=/tmp/amd64'
        mkdir -p /tmp/amd64/partial
        # shellcheck disable=SC2086
        if ! apt-get $o update >/dev/null ||
           ! (cd "$DEV/gl" && apt-get $o download libegl1 libglvnd0 libopengl0 libgl1 libglx0 libgles2 >/dev/null 2>&1); then
            die "apt-get download of the glvnd packages failed"
        fi
    fi
    for s in $SCENES; do
        build/hairgen "materials/$(material_for "$s").json" --scene "scenes/$s.json" -o "$DEV/bundles/$s" >/dev/null ||
            die "hairgen $s"
        for t in $(tiers_for "$s") auto $PROFILES; do
            render osmesa "$s" "$t" "$DEV/ref/$s-$t.png" 1 >"$DEV/ref/$s-$t.txt" 2>&1 || die "llvmpipe $s $t: $(tail -1 "$DEV/ref/$s-$t.txt")"
        done
    done
    du -sh "$DEV"
    echo "device_nvidia: prepared $DEV (carry it; run: sh tools/device_nvidia.sh run all)"
}

# render CONTEXT SCENE TIER|auto|PROFILE OUT.png FRAMES: hairview, its stdout and stderr to ours.
render() {
    rwhat=$3
    set -- --context "$1" --bundle "$DEV/bundles/$2" --scene "scenes/$2.json" --frames "$5" -o "$4"
    case " $PROFILES " in *" $rwhat "*) HAIRTIER_DEVICE_PROFILE=$rwhat "$HAIRVIEW" "$@"; return ;; esac
    if [ "$rwhat" = auto ]; then "$HAIRVIEW" "$@"; else "$HAIRVIEW" "$@" --tier "$rwhat" --strict; fi
}

# The value of KEY=VALUE in a text (hairview's and png_metrics's lines).
field() { tr ' ' '\n' <"$1" | sed -n "s/^$2=//p" | head -1; }

setup_device() {
    [ -d "$DEV/bin" ] || die "no $DEV/bin: run 'prepare' here first and carry $DEV"
    # The loaders only where NVIDIA's driver is mounted (the device): a
    # machine with its own glvnd keeps it (this lets the script be tried on Mesa).
    if [ -d /usr/local/nvidia ] && ls "$DEV"/gl/*.deb >/dev/null 2>&1; then
        for f in "$DEV"/gl/*.deb; do dpkg -x "$f" /; done
        ldconfig
    fi
    export LD_LIBRARY_PATH="$PWD/$DEV/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
    HAIRVIEW="$DEV/bin/hairview"
    OUT=${OUT:-out/device}
    WORK="$OUT/work"
    mkdir -p "$WORK"
    LOG="$OUT/run.log"
    # glvnd finds NVIDIA's EGL through its vendor file; where the image does
    # not install one where glvnd looks, name the driver's own.
    probe="$WORK/probe.png"
    if ! render egl furball auto "$probe" 1 >"$WORK/probe.txt" 2>&1; then
        nv=/usr/local/nvidia/share/glvnd/egl_vendor.d/10_nvidia.json
        [ -f "$nv" ] || die "EGL: $(grep -m1 'hairview:' "$WORK/probe.txt") (and no $nv)"
        export __EGL_VENDOR_LIBRARY_FILENAMES="$nv"
        render egl furball auto "$probe" 1 >"$WORK/probe.txt" 2>&1 ||
            die "EGL with $nv: $(grep -m1 'hairview:' "$WORK/probe.txt")"
    fi
    {
        echo "== device"
        nvidia-smi -L 2>&1 || true
        nvidia-smi --query-gpu=driver_version --format=csv,noheader 2>&1 || true
        grep -E 'hairview: context|hairtier: device' "$WORK/probe.txt"
        echo "__EGL_VENDOR_LIBRARY_FILENAMES=${__EGL_VENDOR_LIBRARY_FILENAMES:-}"
    } >>"$LOG"
}

images() {
    {
        echo "## Images: NVIDIA (EGL) vs llvmpipe (OSMesa), same bundle, scene, tier"
        echo
        echo "$(grep -m1 'hairtier: device' "$WORK/probe.txt" | sed 's/^hairtier: //') vs $(grep -m1 'hairtier: device' "$DEV/ref/furball-full.txt" | sed 's/^hairtier: //')"
        echo
        echo "| scene | run | tier (NVIDIA) | tier (llvmpipe) | NVIDIA frame ms | PSNR dB | hair PSNR dB | SSIM | ΔE00 mean | max diff /255 |"
        echo "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |"
    } >"$WORK/images.md"
    for s in $SCENES; do
        for t in $(tiers_for "$s") auto $PROFILES; do
            nvpng="$WORK/$s-$t-nvidia.png" txt="$WORK/$s-$t-nvidia.txt"
            echo "== $s $t (NVIDIA)" >>"$LOG"
            if render egl "$s" "$t" "$nvpng" "$FRAMES" >"$txt" 2>&1; then
                "$DEV/bin/png_metrics" "$DEV/ref/$s-$t.png" "$nvpng" >"$WORK/$s-$t-metrics.txt" 2>&1 || true
                m="$WORK/$s-$t-metrics.txt"
                echo "| $s | $t | $(field "$txt" tier) | $(field "$DEV/ref/$s-$t.txt" tier) | $(field "$txt" frame_ms) |" \
                     "$(field "$m" psnr_db) | $(field "$m" hair_psnr_db) | $(field "$m" ssim) | $(field "$m" de00_mean) |" \
                     "$(field "$m" max_diff) |" >>"$WORK/images.md"
            else
                echo "| $s | $t | failed: $(tail -1 "$txt") | $(field "$DEV/ref/$s-$t.txt" tier) | | | | | | |" >>"$WORK/images.md"
            fi
            cat "$txt" "$WORK/$s-$t-metrics.txt" >>"$LOG" 2>/dev/null || true
        done
    done
    es_images
    echo "== tier_sheet furball (NVIDIA)" >>"$LOG"
    "$DEV/bin/tier_sheet" --context egl --bundle "$DEV/bundles/furball" --scene scenes/furball.json --frames 5 \
        -o "$WORK/furball-sheet-nvidia.png" >>"$LOG" 2>&1 || echo "tier_sheet failed" >>"$LOG"
}

# The GL ES tiers on NVIDIA's ES contexts (EGL): each tier the context
# runs forced and auto, against the same tier on NVIDIA's desktop GL
# (images() made those first).
es_images() {
    {
        echo
        echo "## GL ES on NVIDIA (EGL ES contexts) vs desktop GL on NVIDIA, same bundle, scene, tier"
        echo
        echo "| scene | api | run | tier | frame ms | PSNR dB | hair PSNR dB | max diff /255 |"
        echo "| --- | --- | --- | --- | --- | --- | --- | --- |"
    } >>"$WORK/images.md"
    for s in $SCENES; do
        for api in gles1 gles2 gles3; do
            for t in $(es_tiers_for "$s" "$api") auto; do
                png="$WORK/$s-$t-$api.png" txt="$WORK/$s-$t-$api.txt" m="$WORK/$s-$t-$api-metrics.txt"
                echo "== $s $t $api (NVIDIA)" >>"$LOG"
                set -- --context egl --api "$api" --bundle "$DEV/bundles/$s" --scene "scenes/$s.json" --frames "$FRAMES" -o "$png"
                # against desktop GL's image of the tier the ES context drew (auto on ES 1.1: fixed4)
                if [ "$t" = auto ]; then "$HAIRVIEW" "$@" >"$txt" 2>&1; else "$HAIRVIEW" "$@" --tier "$t" --strict >"$txt" 2>&1; fi &&
                    "$DEV/bin/png_metrics" "$WORK/$s-$(field "$txt" tier)-nvidia.png" "$png" >"$m" 2>&1 &&
                    echo "| $s | $api | $t | $(field "$txt" tier) | $(field "$txt" frame_ms) | $(field "$m" psnr_db) |" \
                         "$(field "$m" hair_psnr_db) | $(field "$m" max_diff) |" >>"$WORK/images.md" ||
                    echo "| $s | $api | $t | failed: $(tail -1 "$txt") | | | | |" >>"$WORK/images.md"
                cat "$txt" "$m" >>"$LOG" 2>/dev/null || true
            done
        done
    done
}

bench() {
    {
        echo "## bench_frame on NVIDIA (EGL), fur ball x 16 joints, 512x512, median of 9 frames"
        echo
    } >"$WORK/bench.md"
    for h in $BENCH_HAIRS; do
        echo "== bench_frame --hairs $h (NVIDIA)" >>"$LOG"
        if "$DEV/bin/bench_frame" --context egl --hairs "$h" --size 512 --frames 9 >"$WORK/bench-$h.txt" 2>&1; then
            { echo '```'; cat "$WORK/bench-$h.txt"; echo '```'; echo; } >>"$WORK/bench.md"
        else
            echo "bench_frame --hairs $h failed: $(tail -1 "$WORK/bench-$h.txt")" >>"$WORK/bench.md"
        fi
        cat "$WORK/bench-$h.txt" >>"$LOG"
    done
    # (LOD, tier) pairs beside full detail, and the pair error:30 picks among
    # them: plain levels, then soft ones (lod.h's ht_lod_soft_level).
    for h in $BENCH_LOD_HAIRS; do
        for sz in $BENCH_LOD_SIZES; do
            for soft in "" --soft; do
                name="bench-lods$soft-$h-$sz"
                echo "== bench_frame --lods $soft --samples 4 --hairs $h --size $sz (NVIDIA)" >>"$LOG"
                # shellcheck disable=SC2086 # $soft: no option or one word
                if "$DEV/bin/bench_frame" --context egl --lods $soft --samples 4 --no-orbit --hairs "$h" --size "$sz" \
                    --frames 9 >"$WORK/$name.txt" 2>&1; then
                    { echo '```'; cat "$WORK/$name.txt"; echo '```'; echo; } >>"$WORK/bench.md"
                else
                    echo "bench_frame --lods $soft --hairs $h --size $sz failed: $(tail -1 "$WORK/$name.txt")" >>"$WORK/bench.md"
                fi
                cat "$WORK/$name.txt" >>"$LOG"
            done
        done
    done
    # The dense groom's pairs, levels under a pixel drawn with the width rule
    # as the runtime ships them, against the 16x truth (docs/lod.md): plain,
    # then soft by hairgen's other default factors (lod.h's HT_LOD_DEFAULT_SOFTENS).
    for sz in $BENCH_LOD_SIZES; do
        for soft in "" --soft=6 --soft=8; do
            name="bench-lods-dense$soft-$sz"
            echo "== bench_frame --scene dense.json --lods $soft --width-rule --truth --samples 4 --size $sz (NVIDIA)" >>"$LOG"
            # shellcheck disable=SC2086 # $soft: no option or one word
            if "$DEV/bin/bench_frame" --context egl --scene "$DEV/dense/dense.json" --lods $soft --width-rule --truth \
                --samples 4 --no-orbit --size "$sz" --frames 9 >"$WORK/$name.txt" 2>&1; then
                { echo '```'; cat "$WORK/$name.txt"; echo '```'; echo; } >>"$WORK/bench.md"
            else
                echo "bench_frame --lods $soft --width-rule dense $sz failed: $(tail -1 "$WORK/$name.txt")" >>"$WORK/bench.md"
            fi
            cat "$WORK/$name.txt" >>"$LOG"
        done
    done
    # The ES tiers against the ES geometry floor (fixed tiers run on ES 1.1
    # only, the shader tiers on ES 2.0/3.x only).
    for api in gles1 gles2 gles3; do
        for h in $BENCH_ES_HAIRS; do
            echo "== bench_frame --api $api --hairs $h (NVIDIA)" >>"$LOG"
            if "$DEV/bin/bench_frame" --context egl --api "$api" --hairs "$h" --size 512 --frames 9 >"$WORK/bench-$api-$h.txt" 2>&1; then
                { echo '```'; cat "$WORK/bench-$api-$h.txt"; echo '```'; echo; } >>"$WORK/bench.md"
            else
                echo "bench_frame --api $api --hairs $h failed: $(tail -1 "$WORK/bench-$api-$h.txt")" >>"$WORK/bench.md"
            fi
            cat "$WORK/bench-$api-$h.txt" >>"$LOG"
        done
    done
}

# The dense groom's cells measured on the device (hairgen --measure-lods
# against the 16x truth, docs/lod.md), and the pair error:30 picks from
# them at half and a quarter of the scene's size.
cells() {
    b="$WORK/dense-cells"
    echo "== hairgen --scene dense.json --measure-lods --lod-samples 4 --lod-reference supersample (NVIDIA)" >>"$LOG"
    if ! HAIRTIER_CONTEXT=egl "$DEV/bin/hairgen" materials/dark-brown.json --scene "$DEV/dense/dense.json" \
        --measure-lods --lod-samples 4 --lod-reference supersample -o "$b" >"$WORK/cells.txt" 2>&1; then
        echo "hairgen --measure-lods dense failed: $(tail -1 "$WORK/cells.txt")" >>"$WORK/cells.md"
        cat "$WORK/cells.txt" >>"$LOG"
        return
    fi
    { echo '```'; cat "$WORK/cells.txt"; echo '```'; echo; } >>"$WORK/cells.md"
    for size in 0.5 0.25; do
        "$HAIRVIEW" --context egl --bundle "$b" --scene "$DEV/dense/dense.json" --size "$size" --lod auto \
            --policy error:30 --width-rule --samples 4 --frames 9 -o "$WORK/dense-pick-$size.png" >"$WORK/pick.txt" 2>&1
        { echo "hairview --size $size --lod auto --policy error:30 --width-rule --samples 4 (exit $?):"; echo '```';
          grep -v '^hairtier: ' "$WORK/pick.txt"; echo '```'; echo; } >>"$WORK/cells.md"
    done
    cat "$WORK/cells.txt" "$WORK/cells.md" >>"$LOG"
}

# A moving camera through the chain (tools/dolly_width_rule.sh) on the
# 200 000-hair fur ball, full and gl11: the width rule off, per draw and
# per vertex, each per-draw and per-vertex row again with --lod-async.
dolly() {
    sc="$WORK/furball-200000.json"
    sed 's/"hairs": 8000/"hairs": 200000/' scenes/furball.json >"$sc"
    for t in full gl11; do
        echo "== dolly_width_rule.sh 200 000 hairs, $t, ASYNC=1 (NVIDIA)" >>"$LOG"
        EXTRA="--context egl" TIER=$t ASYNC=1 FRAMES=48 HAIRTIER_BUILD="$DEV/bin" \
            sh tools/dolly_width_rule.sh "$DEV/bundles/furball" "$sc" "$WORK/dolly-$t" 3.3508 >"$WORK/dolly-$t.txt" 2>&1
        { echo "dolly_width_rule.sh, 200 000 hairs, $t:"; echo '```'; cat "$WORK/dolly-$t.txt"; echo '```'; echo; } >>"$WORK/dolly.md"
        cat "$WORK/dolly-$t.txt" >>"$LOG"
    done
}

case "${1:-}" in
    prepare) prepare ;;
    run)
        what=${2:-all}
        case $what in images|bench|cells|dolly|all) ;; *) die "run takes images, bench, cells, dolly or all, not '$what'" ;; esac
        setup_device
        case $what in images|all) images ;; esac
        case $what in bench|all) bench ;; esac
        case $what in cells|all) cells ;; esac
        case $what in dolly|all) dolly ;; esac
        cat "$WORK"/images.md "$WORK"/bench.md "$WORK"/cells.md "$WORK"/dolly.md >"$OUT/summary.md" 2>/dev/null || true
        for f in "$DEV"/ref/*.png; do cp "$f" "$WORK/$(basename "$f" .png)-llvmpipe.png"; done
        rm -f "$WORK/probe.png"
        (cd "$WORK" && find . -name '*.png' | sort | tar -czf "../images.tar.gz" -T -)
        rm -rf "$WORK"
        echo "device_nvidia: wrote $OUT/summary.md, $OUT/run.log, $OUT/images.tar.gz"
        cat "$OUT/summary.md"
        ;;
    *) echo "usage: tools/device_nvidia.sh prepare | run [images|bench|cells|dolly|all]" >&2; exit 2 ;;
esac
