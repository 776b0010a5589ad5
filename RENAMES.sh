#!/bin/sh
# RENAMES.sh — the scripted renames of branch issue6-manifest, to replay on a
# branch that still uses the old names (run from the repository root; safe to
# run twice). Delete after the merge.
#   runtime reader:  bundle.h / ht_bundle*  ->  manifest.h / ht_manifest*
#   generator:       ht_bundle_generate     ->  ht_generate_bundle
#   scene:           ht_scene and ht_geometry_kind move from hairtier.h to scene.h
#                    (files that use them include "scene.h")
set -e
[ -f runtime/bundle.h ] && git mv runtime/bundle.h runtime/manifest.h
[ -f runtime/bundle.c ] && git mv runtime/bundle.c runtime/manifest_read.c
[ -f shadergen/bundle.c ] && git mv shadergen/bundle.c shadergen/generate.c
git grep -lE 'ht_bundle|HT_BUNDLE_|"bundle\.h"' -- '*.c' '*.h' | xargs -r sed -i \
  -e 's/\bht_bundle_generate\b/ht_generate_bundle/g' \
  -e 's/\bht_bundle\b/ht_manifest/g' \
  -e 's/\bht_bundle_/ht_manifest_/g' \
  -e 's/\bHT_BUNDLE_/HT_MANIFEST_/g' \
  -e 's/"bundle\.h"/"manifest.h"/g'
# ht_scene / ht_geometry_kind now live in runtime/scene.h (hairgen.h includes
# it). A file outside shadergen/ that uses them without including hairgen.h
# needs: #include "scene.h"  (no sed: add it by hand where the compiler asks).
