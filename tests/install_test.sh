#!/bin/sh
# install_test.sh — `make install` as a packager and an application use it
# (make test runs it; BUILD, CC and SAN come from the Makefile):
#   1. DESTDIR staging: make install DESTDIR=T/stage PREFIX=/opt/hairtier-test
#      installs exactly the expected files, the .pc files name the PREFIX (not
#      the staging directory), and make uninstall leaves none of them.
#   2. A real prefix: make install PREFIX=T/prefix; the installed hairgen
#      writes a bundle, the installed hairview renders it, and programs
#      built with nothing but pkg-config against that prefix run: one draws
#      a frame through OSMesa (from the header the installed hairgen
#      --emit-header wrote, compiled in, then from the directory), one
#      generates a material in memory, both static (--static) and shared; a
#      C++ program including every public header links shared through
#      pkg-config and shared and static through CMake's
#      find_package(hairtier) (the static pkg-config link is install_smoke_gen's
#      in C, which names libstdc++ itself). Then make uninstall, checked again.
# The pkg-config builds link with LD_GOLD (the Makefile's -fuse-ld=gold, as
# its own programs do; bfd spends most of a link reading libOSMesa's LLVM);
# the CMake ones with the toolchain's default linker.
set -eu
BUILD=${BUILD:-build}
CC=${CC:-cc}
SAN=${SAN:-}
LD_GOLD=${LD_GOLD:-}
MAKE=make
tmp=$(mktemp -d "${TMPDIR:-/tmp}/hairtier-install.XXXXXX")
trap 'rm -rf "$tmp"' EXIT
fail() { echo "install_test: FAIL: $*" >&2; exit 1; }

expected="bin/hairgen bin/hairview include/hairtier/export.h include/hairtier/hairgen.h include/hairtier/hairtier.h \
include/hairtier/ht_limits.h include/hairtier/image.h include/hairtier/lod.h include/hairtier/model.h \
include/hairtier/model_marschner.h include/hairtier/scene.h \
include/hairtier/strands.h lib/cmake/hairtier/hairtierConfig.cmake lib/cmake/hairtier/hairtierConfigVersion.cmake \
lib/libhairgen.a lib/libhairgen.so lib/libhairgen.so.0 lib/libhairgen.so.0.1 \
lib/libhairtier.a lib/libhairtier.so lib/libhairtier.so.0 lib/libhairtier.so.0.1 \
lib/pkgconfig/hairgen.pc lib/pkgconfig/hairtier.pc"
files_under() { (cd "$1" && find . \( -type f -o -type l \) | sed 's|^\./||' | LC_ALL=C sort | tr '\n' ' ' | sed 's/ $//'); }
mk() { env -u MAKEFLAGS -u MFLAGS $MAKE -s --no-print-directory BUILD="$BUILD" "$@" >/dev/null; }

# 1. staged
stage=$tmp/stage
mk install DESTDIR="$stage" PREFIX=/opt/hairtier-test
[ -d "$stage/opt/hairtier-test" ] || fail "DESTDIR install wrote nothing under $stage/opt/hairtier-test"
got=$(files_under "$stage")
want=$(echo "$expected" | tr ' ' '\n' | sed 's|^|opt/hairtier-test/|' | tr '\n' ' ' | sed 's/ $//')
[ "$got" = "$want" ] || fail "staged install: got [$got], expected [$want]"
grep -qx 'prefix=/opt/hairtier-test' "$stage/opt/hairtier-test/lib/pkgconfig/hairtier.pc" ||
  fail "hairtier.pc does not say prefix=/opt/hairtier-test"
mk uninstall DESTDIR="$stage" PREFIX=/opt/hairtier-test
left=$(files_under "$stage")
[ -z "$left" ] || fail "staged uninstall left: $left"
[ ! -e "$stage/opt/hairtier-test/include/hairtier" ] || fail "staged uninstall left include/hairtier/"
echo "install_test: staged install of $(echo "$expected" | wc -w) files and uninstall: ok"

# 2. a prefix an application builds against
prefix=$tmp/prefix
mk install PREFIX="$prefix"
got=$(files_under "$prefix")
[ "$got" = "$expected" ] || fail "install: got [$got], expected [$expected]"
# The bundle and the same bundle as a header, from one run.
"$prefix/bin/hairgen" materials/dark-brown.json --scene tests/data/valgrind-scene.json -o "$tmp/bundle" \
  --emit-header "$tmp/smoke_bundle.h" --header-symbol smoke_bundle >/dev/null || fail "installed hairgen failed"
[ -s "$tmp/smoke_bundle.h" ] || fail "installed hairgen --emit-header wrote no header"
"$prefix/bin/hairview" --bundle "$tmp/bundle" --scene tests/data/valgrind-scene.json -o "$tmp/frame.png" >/dev/null ||
  fail "installed hairview failed"
[ -s "$tmp/frame.png" ] || fail "installed hairview wrote no frame"

export PKG_CONFIG_PATH="$prefix/lib/pkgconfig"
# --static: the archives, taken over the shared libraries beside them.
static_libs() { echo "$1" | sed -E 's/-l(hairgen|hairtier)( |$)/-Wl,-Bstatic -l\1 -Wl,-Bdynamic /g'; }
flags=$(static_libs "$(pkg-config --cflags --libs --static hairtier)") || fail "pkg-config hairtier"
case "$flags" in *-I"$PWD"*|*-Iruntime*|*-Ishadergen*) fail "pkg-config hairtier names the source tree: $flags";; esac
# Only the installed headers and libraries: -I and -L into the source tree
# are absent, so a public header that included an internal one would fail here.
# It draws the header's bundle compiled in, then the directory's.
$CC -std=c11 -Wall -Wextra -Werror $SAN -DSMOKE_HEADER='"smoke_bundle.h"' -DSMOKE_ENTRY=smoke_bundle -I"$tmp" \
  tests/data/install_smoke.c $LD_GOLD $flags -lOSMesa -o "$tmp/smoke" || fail "install_smoke.c does not build with: $flags -lOSMesa"
"$tmp/smoke" "$tmp/bundle" || fail "install_smoke (the header, then the directory) failed"
gflags=$(static_libs "$(pkg-config --cflags --libs --static hairgen)") || fail "pkg-config hairgen"
$CC -std=c11 -Wall -Wextra -Werror $SAN tests/data/install_smoke_gen.c $LD_GOLD $gflags -o "$tmp/smoke_gen" ||
  fail "install_smoke_gen.c does not build with: $gflags"
"$tmp/smoke_gen" materials/dark-brown.json || fail "install_smoke_gen failed"
! ldd "$tmp/smoke_gen" | grep -q libhair || fail "the --static build of install_smoke_gen needs a shared hairtier library"
echo "install_test: built with: $flags"

# Shared: plain pkg-config --libs, the loader finding the libraries by soname.
export LD_LIBRARY_PATH="$prefix/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
$CC -std=c11 -Wall -Wextra -Werror $SAN tests/data/install_smoke.c $LD_GOLD $(pkg-config --cflags --libs hairtier) -lOSMesa \
  -o "$tmp/smoke_shared" || fail "install_smoke.c does not build with pkg-config --libs hairtier"
ldd "$tmp/smoke_shared" | grep -q "libhairtier.so.0 => $prefix/lib/" || fail "install_smoke does not load libhairtier.so.0"
"$tmp/smoke_shared" "$tmp/bundle" || fail "install_smoke (shared) failed"
CXX=${CXX:-c++}
$CXX -Wall -Wextra -Werror $SAN tests/data/install_every_header.cpp $LD_GOLD $(pkg-config --cflags --libs hairgen) \
  -o "$tmp/every_shared" || fail "install_every_header.cpp does not build with pkg-config --libs hairgen"
"$tmp/every_shared" >/dev/null || fail "install_every_header (shared, pkg-config) failed"
# Only what the headers declare with HT_API is exported.
nm -D --defined-only "$prefix/lib/libhairtier.so" | grep -q ' ht_renderer_create$' || fail "libhairtier.so does not export ht_renderer_create"
! nm -D --defined-only "$prefix/lib/libhairtier.so" | grep -q ' ht_gl_load$' || fail "libhairtier.so exports the internal ht_gl_load"
echo "install_test: C with pkg-config --libs (shared) and C++ of every public header (shared): ok"

# CMake: find_package(hairtier) and its imported targets, shared and static.
if [ -n "$SAN" ]; then
  echo "install_test: the CMake consumer is skipped under sanitizers (its flags are CMake's)"
else
  # Ninja where it is installed (make test's depfile check uses it): fewer processes than Makefiles.
  generator=; command -v ninja >/dev/null 2>&1 && generator="-G Ninja"
  cmake $generator -S tests/data/cmake_consumer -B "$tmp/cmake" -DCMAKE_PREFIX_PATH="$prefix" -DCMAKE_BUILD_TYPE=Release \
    >"$tmp/cmake.log" 2>&1 &&
    cmake --build "$tmp/cmake" >>"$tmp/cmake.log" 2>&1 || { cat "$tmp/cmake.log"; fail "the CMake consumer does not build"; }
  "$tmp/cmake/every_header_shared" >/dev/null || fail "CMake every_header_shared failed"
  "$tmp/cmake/every_header_static" >/dev/null || fail "CMake every_header_static failed"
  ldd "$tmp/cmake/every_header_shared" | grep -q libhairgen.so.0 || fail "CMake's hairtier::hairgen is not the shared library"
  ! ldd "$tmp/cmake/every_header_static" | grep -q libhair || fail "CMake's hairgen_static needs a shared hairtier library"
  echo "install_test: find_package(hairtier), shared and static: ok"
fi

mk uninstall PREFIX="$prefix"
left=$(files_under "$prefix")
[ -z "$left" ] || fail "uninstall left: $left"
echo "install_test: ok"
