#!/usr/bin/env bash
# Everything that has to be made again when the numbers change: a modelling change, a new
# default, anything that changes what an identifier learns or predicts. Re-blesses the golden
# files the tests compare bits with, then regenerates every generated document whose numbers
# come from what the identifiers learn, one step after another, and ends with the tests.
# What no script can do is listed at the end (the README's numbers, prose that quotes them).
#
# Usage: scripts/regenerate.sh [--list] [--from STEP] [STEP...]
#   --list       the steps, in order, with their run time when last measured (2 cores)
#   --from STEP  start at STEP (after an interruption: the steps before it are done)
#   STEP...      only these steps
# Each step is one script of scripts/ (its own usage says what it writes). The documents that
# do not depend on what is learnt are not made again here: docs/fuzzing.md, benchmarks.md,
# python.md, soak.md, reliability.md, power-cut.md (their scripts are in scripts/).
set -euo pipefail
cd "$(dirname "$0")/.."

# name | minutes when last measured | command
steps=(
  "core-golden|1|ROTORID_BLESS=1 cargo test -q -p rotorid --features std --test integration golden::"
  "c-interface|3|ROTORID_BLESS=1 cargo test -q --manifest-path core/ffi/Cargo.toml --release && ROTORID_BLESS=1 cargo test -q --manifest-path core/ffi/Cargo.toml --release --test header"
  "python-golden|1|scripts/python_golden.sh"
  "rate-orders|1|scripts/rate-orders.sh"
  "closed-loop|2|scripts/closed-loop.sh"
  "short-logs|2|scripts/short-logs.sh"
  "real-logs|2|scripts/real-logs.sh"
  "ardupilot-sitl|2|scripts/ardupilot-sitl.sh"
  "full-compensation|3|scripts/full-compensation.sh"
  "results|4|scripts/results.sh"
  "robustness|4|scripts/robustness.sh"
  "linear-plant|5|scripts/linear-plant.sh"
  "term-evidence|6|scripts/term-evidence.sh"
  "instructions|3|scripts/instructions.sh"
  "onboard-flights|3|scripts/onboard-flights.sh"
  "cost|9|scripts/cost.sh"
  "seeds|45|scripts/seeds.sh 10 docs/seeds.md 12"
  "tests|15|scripts/test.sh"
)

name_of() { echo "${1%%|*}"; }
minutes_of() {
  local rest=${1#*|}
  echo "${rest%%|*}"
}
command_of() {
  local rest=${1#*|}
  echo "${rest#*|}"
}

if [ "${1:-}" = "--list" ]; then
  total=0
  for s in "${steps[@]}"; do
    printf '%-18s %3s min   %s\n' "$(name_of "$s")" "$(minutes_of "$s")" "$(command_of "$s")"
    total=$((total + $(minutes_of "$s")))
  done
  echo "about $total min in all"
  exit 0
fi

from=""
if [ "${1:-}" = "--from" ]; then
  from=${2:?--from needs a step name (see --list)}
  shift 2
fi
only=("$@")
known() {
  local s
  for s in "${steps[@]}"; do [ "$(name_of "$s")" = "$1" ] && return 0; done
  return 1
}
for n in "${only[@]}" ${from:+"$from"}; do
  known "$n" || {
    echo "no step named $n (see --list)" >&2
    exit 2
  }
done

started=${from:+no}
for s in "${steps[@]}"; do
  n=$(name_of "$s")
  if [ -n "$from" ] && [ "$started" = no ]; then
    [ "$n" = "$from" ] || continue
    started=yes
  fi
  if [ ${#only[@]} -gt 0 ]; then
    wanted=no
    for o in "${only[@]}"; do [ "$o" = "$n" ] && wanted=yes; done
    [ "$wanted" = yes ] || continue
  fi
  echo "== $n: $(command_of "$s")" >&2
  t0=$(date +%s)
  if ! bash -c "$(command_of "$s")"; then
    echo "regenerate: step $n failed; after fixing it: scripts/regenerate.sh --from $n" >&2
    exit 1
  fi
  echo "== $n: $(($(date +%s) - t0)) s" >&2
done

cat >&2 <<'TODO'
Made again. What no script does:
  - README.md's "numbers to decide by" (host-tests/tests/readme_numbers.rs fails while one of
    them is no longer in the document it cites) and the paragraph on the real logs under it;
  - prose that quotes numbers: `git diff --stat docs/` shows which generated documents moved;
    grep the hand-written ones (docs/evidence.md, docs/cli.md, docs/derivatives.md,
    docs/c-interface.md, docs/log-format.md) for the old values;
  - scripts/demo.sh (the main job) compares the firmware with the host bit for bit: run it.
TODO
