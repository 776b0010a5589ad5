#!/bin/sh
# run_test.sh RESULT DRIVER CONTEXT COMMAND... — one run of `make test`:
# COMMAND on Mesa's DRIVER through CONTEXT (osmesa or egl), its output into
# RESULT.log, "pass SECONDS CPU" or "fail SECONDS CPU" into RESULT (wall and
# user+sys seconds), one line on stdout. Exits 0 whatever the test does: tests/test_summary.sh counts.
set -u
result=$1 driver=$2 context=$3
shift 3
name=$(basename "$result")
# llvmpipe's LLVM optimisation passes off: the same images (every tier of the
# shipped scenes compared byte for byte, docs/performance.md), shader compiles
# in half the time. Mesa's shader cache in the build folder: a fresh clone
# starts cold, as a fresh machine does, and later runs share it.
: "${GALLIVM_PERF:=nopt}" "${MESA_SHADER_CACHE_DIR:=$(cd "${HAIRTIER_BUILD:-build}" && pwd)/mesa-shader-cache}"
export GALLIVM_PERF MESA_SHADER_CACHE_DIR
start=$(date +%s%N)
if GALLIUM_DRIVER=$driver HAIRTIER_CONTEXT=$context EGL_PLATFORM=surfaceless "$@" >"$result.log" 2>&1; then
  status=pass
else
  status=fail
fi
seconds=$(( ($(date +%s%N) - start) / 10000000 ))
seconds=$(printf '%d.%02d' $((seconds / 100)) $((seconds % 100)))
# The children's user and system time: the second line of `times`.
times >"$result.times"
cpu=$(awk 'NR == 2 { for (i = 1; i <= 2; i++) { split($i, t, /[ms]/); s += t[1] * 60 + t[2] } printf "%.2f", s }' "$result.times")
rm -f "$result.times"
echo "$status $seconds $cpu" >"$result"
echo "== $name ($driver, $context): $status, $seconds s ($cpu s CPU)"
