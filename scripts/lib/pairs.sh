# Sourced by scripts/seeds.sh, scripts/short-logs.sh and scripts/ab.sh: the hover and envelope pairs of a
# plant and seed pair, flown by `rotorid simulate` and scored by `rotorid identify`.
# Needs `bin` (the `rotorid` binary). TRAIN_S, when set, keeps only the first TRAIN_S seconds
# of both training flights (short-logs.sh). IDENTIFY, when set, is the identifying command in
# place of `$bin identify` (term-evidence.sh: `rotorid-lab identify-terms`).

# seeds_work: prints the directory the flights go to: SEEDS_WORK (made if missing, and kept)
# or a new temporary one, which the caller removes when SEEDS_WORK is unset.
seeds_work() {
  if [ -n "${SEEDS_WORK:-}" ]; then
    mkdir -p "$SEEDS_WORK" && realpath "$SEEDS_WORK"
  else
    mktemp -d
  fi
}

# pair_kept DIR: whether DIR already holds a pair's flights and identifications (the envelope's
# identification is the last made), which fly_pair then keeps.
pair_kept() {
  [ -f "$1/envelope/metrics.json" ]
}

# kept_pairs WORK: how many pairs under WORK fly_pairs would keep (a kept SEEDS_WORK's).
kept_pairs() {
  local dir n=0
  for dir in "$1"/*/; do
    if pair_kept "$dir"; then n=$((n + 1)); fi
  done
  echo "$n"
}

# fly_pair PLANT VARIATION|"" K DIR: the four flights of seed pair K (training seed K,
# verification seed 100 + K) and the two identifications, in DIR (kept when DIR already has
# them: seeds.sh's SEEDS_WORK); a failure is told, not fatal.
fly_pair() {
  local plant=$1 variation=$2 k=$3 dir=$4 v=$((100 + $3))
  local pv=() duration=()
  [ -z "$variation" ] || pv=(--plant-variation "$variation")
  [ -z "${TRAIN_S:-}" ] || duration=(--duration "$TRAIN_S")
  pair_kept "$dir" && return 0
  mkdir -p "$dir"
  (
    cd "$dir"
    "$bin" simulate --plant "$plant" "${pv[@]}" --kind identification --seed "$k" "${duration[@]}" -o ident.csv
    "$bin" simulate --plant "$plant" "${pv[@]}" --kind verification --seed "$v" --duration 300 -o verify.csv
    if [ -n "${TRAIN_S:-}" ]; then
      # The envelope flight's schedule has a fixed length: it is cut after simulating (its
      # 50 Hz rows and the header).
      "$bin" simulate --plant "$plant" "${pv[@]}" --kind envelope --seed "$k" -o envelope-full.csv
      head -n "$((TRAIN_S * 50 + 1))" envelope-full.csv >envelope.csv
    else
      "$bin" simulate --plant "$plant" "${pv[@]}" --kind envelope --seed "$k" -o envelope.csv
    fi
    "$bin" simulate --plant "$plant" "${pv[@]}" --kind envelope-verification --seed "$v" -o envelope-verify.csv
    local identify=("$bin" identify)
    [ -z "${IDENTIFY:-}" ] || read -r -a identify <<<"$IDENTIFY"
    "${identify[@]}" --train ident.csv --verify verify.csv --out hover --no-plots
    "${identify[@]}" --train envelope.csv --verify envelope-verify.csv --out envelope --no-plots
  ) >"$dir.log" 2>&1 || echo "$plant ${variation:+variation $variation }pair $k: failed (see its log)" >&2
}

# spawn CMD...: runs CMD in the background, two at a time (one per core); wait_spawned waits for
# the rest. A failed job is not fatal (each job tells its own failure).
spawned=()
spawn() {
  "$@" &
  spawned+=($!)
  if [ ${#spawned[@]} -ge 2 ]; then wait "${spawned[0]}" || true; spawned=("${spawned[@]:1}"); fi
}
wait_spawned() {
  local p
  for p in "${spawned[@]}"; do wait "$p" || true; done
  spawned=()
}

# fly_pairs WORK PAIRS VARIATIONS: both airframes, the airframe itself and its variations
# 1..VARIATIONS, each through seed pairs 1..PAIRS, two at a time (one per core), into
# WORK/PLANT[-vVARIATION]-K.
fly_pairs() {
  local work=$1 pairs=$2 variations=$3 plant variation k
  for plant in xcell60 flybarless600; do
    for variation in "" $(seq 1 "$variations"); do
      for k in $(seq 1 "$pairs"); do
        spawn fly_pair "$plant" "$variation" "$k" "$work/$plant${variation:+-v$variation}-$k"
      done
    done
  done
  wait_spawned
}
