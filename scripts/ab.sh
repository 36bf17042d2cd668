#!/usr/bin/env bash
# A modelling change judged as the brief asks: over many seed pairs and plant variations, not
# one pair. Flies the flights of scripts/seeds.sh (both airframes, seed pairs 1..PAIRS, plant
# variations 1..VARIATIONS), identifies each with this tree's `rotorid` and with BASE's (a git
# revision, built in a worktree of its own), and prints (markdown) per plant the median and
# worst over the pairs of VARIANT's free run ÷ extended plain's and ÷ holding the measured
# state, base → this tree (scripts/ab_report.py).
#
# Usage: scripts/ab.sh BASE [PAIRS [VARIATIONS [VARIANT [OUTPUT]]]]
#   (defaults 10 pairs, 12 variations, `flight selected`, stdout; about 45 min on 2 cores with
#   the defaults)
# Env: SEEDS_WORK=DIR keeps the flights and both identifications there (a kept DIR is
# reused: its flights and identifications are not made again). AB_BASE_TARGET: the target
# directory BASE is built in (default target/ab-base; scripts/ab-patch.sh keeps it outside
# its temporary tree).
set -euo pipefail
cd "$(dirname "$0")/.."
root=$(pwd)
base=${1:?usage: scripts/ab.sh BASE [PAIRS [VARIATIONS [VARIANT [OUTPUT]]]]}
pairs=${2:-10}
variations=${3:-12}
variant=${4:-flight selected}
output=${5:-/dev/stdout}
export CARGO_TARGET_DIR="${CARGO_TARGET_DIR:-$root/target}"
cargo build -q --release -p rotorid-cli --bin rotorid
bin="$CARGO_TARGET_DIR/release/rotorid"
# BASE's binary, in a worktree and a target directory of its own (kept: the next comparison
# against the same base builds nothing).
# shellcheck source=scripts/lib/pairs.sh
. scripts/lib/pairs.sh
work=$(seeds_work)
base_rev=$(git rev-parse --short "$base")
tree=$(mktemp -d)
trap 'git worktree remove --force "$tree"; [ -n "${SEEDS_WORK:-}" ] || rm -rf "$work"' EXIT
git worktree add -q --detach "$tree" "$base_rev"
base_target="${AB_BASE_TARGET:-$root/target/ab-base}"
(cd "$tree" && CARGO_TARGET_DIR="$base_target" cargo build -q --release -p rotorid-cli --bin rotorid)
base_bin="$base_target/release/rotorid"
start=$(date +%s)
fly_pairs "$work" "$pairs" "$variations"
# identify_base DIR: BASE's identifications of the pair in DIR (kept when already there).
identify_base() {
  local dir=$1
  [ -f "$dir/envelope-base/metrics.json" ] && return 0
  (
    cd "$dir"
    "$base_bin" identify --train ident.csv --verify verify.csv --out hover-base --no-plots
    "$base_bin" identify --train envelope.csv --verify envelope-verify.csv --out envelope-base --no-plots
  ) >"$dir-base.log" 2>&1 || echo "$dir: BASE's identification failed (see its log)" >&2
}
for dir in "$work"/*/; do
  spawn identify_base "${dir%/}"
done
wait_spawned
python3 scripts/ab_report.py "$work" "$pairs" "$variations" "$variant" "$base_rev" \
  "$(git rev-parse --short HEAD)$(git diff --quiet HEAD || echo +)" "$(($(date +%s) - start))" >"$output"
