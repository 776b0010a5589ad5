#!/bin/sh
# test_summary.sh DIR — the closing lines of `make test` from the results
# tests/run_test.sh wrote in DIR: each failed run's log, then the failed
# runs and "binaries: N passed, N failed". Exits 1 if a run failed or none ran.
set -u
dir=$1
pass=0 fail=0 failed=""
for r in "$dir"/*; do
  case $r in *.log) continue;; esac
  [ -f "$r" ] || continue
  read -r status seconds cpu <"$r"
  if [ "$status" = pass ]; then
    pass=$((pass + 1))
  else
    fail=$((fail + 1))
    failed="$failed $(basename "$r")"
    echo
    echo "==== $(basename "$r"): FAILED after $seconds s; its output ($r.log):"
    cat "$r.log"
  fi
done
echo
[ -z "$failed" ] || echo "failed:$failed"
echo "binaries: $pass passed, $fail failed"
[ $fail -eq 0 ] && [ $pass -gt 0 ]
