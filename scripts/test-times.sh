#!/usr/bin/env bash
# Where the test suite's time goes: runs `cargo test ARGS...` (default: the workspace in debug)
# and prints each test binary's run time, slowest first, as a markdown table, with the total
# wall time (build included). Usage: scripts/test-times.sh [cargo test arguments...]
set -euo pipefail
cd "$(dirname "$0")/.."
[ $# -gt 0 ] || set -- --workspace
log=$(mktemp)
start=$SECONDS
cargo test "$@" >"$log" 2>&1 || { tail -40 "$log"; exit 1; }
wall=$((SECONDS - start))
echo "\`cargo test $*\`: $((wall / 60)) min $((wall % 60)) s in all (build included)"
echo
echo "| test binary | run time (s) |"
echo "|---|---:|"
# cargo prints "Running <target> (<binary>)" then, after the tests, "test result: ... finished in Xs".
awk '/^ *Running /{bin=$NF; sub(/^.*\//,"",bin); sub(/-[0-9a-f]+\)$/,"",bin)
                    name=($2 == "unittests" ? "unit tests of " $3 : $2) " (" bin ")"}
     /^ *Doc-tests /{name="doc tests of "$2}
     /^test result:/{t=$NF; sub(/s$/,"",t); print t"\t"name}' "$log" |
  sort -rn | awk -F'\t' '$1 >= 1 {printf "| %s | %.1f |\n", $2, $1}'
rm -f "$log"
