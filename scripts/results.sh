#!/usr/bin/env bash
# Regenerates docs/results.md and docs/figures/ (the Table 4 analogue on the X-Cell 60 plant,
# the Figure 2-5 analogues, free-run errors, metrics.json, exported parameters). Every number
# in docs/results.md comes from this script: it flies the identification flight (seed 1, the
# four Table 2 sweeps, 255 s) and a verification flight (seed 2, 300 s), once with realistic
# sensors (noise, turbulence), once with three times the noise and once clean, and the envelope flights (seeds 1 and 2), then the
# hover and envelope pairs again on the second plant (`--plant flybarless600`); runs
# `rotorid-lab identify` on each pair and writes the document from the metrics files.
# Deterministic: same seeds, same bits.
set -euo pipefail
cd "$(dirname "$0")/.."
root=$(pwd)
start=$(date +%s)

# The plots need one TrueType font (plotters' `ttf` backend looks up "sans-serif").
if command -v fc-list >/dev/null 2>&1 && [ -z "$(fc-list 2>/dev/null | head -1)" ] \
  || ! command -v fc-list >/dev/null 2>&1; then
  SUDO=""
  [ "$(id -u)" -eq 0 ] || SUDO="sudo"
  $SUDO apt-get update -qq && DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq \
    fontconfig fonts-dejavu-core >/dev/null || echo "warning: could not install a font" >&2
fi

export CARGO_TARGET_DIR="${CARGO_TARGET_DIR:-$root/target}"
# The product's `rotorid` flies the flights; the studies' `rotorid-lab` identifies with the
# full catalogue (the ablations too, which the document's tables read) and writes the document.
cargo build -q --release -p rotorid-cli --bin rotorid -p rotorid-lab --bin rotorid-lab
bin="$CARGO_TARGET_DIR/release/rotorid"
lab="$CARGO_TARGET_DIR/release/rotorid-lab"

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"
"$bin" simulate --kind identification --seed 1 -o ident.csv
"$bin" simulate --kind verification --seed 2 --duration 300 -o verify.csv
"$bin" simulate --kind identification --seed 1 --clean -o ident-clean.csv
"$bin" simulate --kind verification --seed 2 --duration 300 --clean -o verify-clean.csv
"$bin" simulate --kind identification --seed 1 --noise-scale 3 -o ident-noisy.csv
"$bin" simulate --kind verification --seed 2 --duration 300 --noise-scale 3 -o verify-noisy.csv
"$bin" simulate --kind envelope --seed 1 -o envelope.csv
"$bin" simulate --kind envelope-verification --seed 2 -o envelope-verify.csv
# The second plant (docs/results.md "Second plant"): the hover pair and the envelope pair.
second=flybarless600
"$bin" simulate --plant $second --kind identification --seed 1 -o second-ident.csv
"$bin" simulate --plant $second --kind verification --seed 2 --duration 300 -o second-verify.csv
"$bin" simulate --plant $second --kind envelope --seed 1 -o second-envelope.csv
"$bin" simulate --plant $second --kind envelope-verification --seed 2 -o second-envelope-verify.csv

# "What limits the flight default": each pair again with one thing changed (no sensor noise in
# training, no sensor noise at all, still air and no noise), and the hover pair verified on
# other seeds, on both plants. Metrics land in conditions/ (not kept), the table in results.md.
conditions=()
for plant in xcell60 $second; do
  case $plant in xcell60) title="X-Cell 60" ;; *) title="flybarless 600" ;; esac
  p=(--plant $plant)
  "$bin" simulate "${p[@]}" --kind identification --seed 1 --noise-scale 0 -o $plant-ident-n0.csv
  "$bin" simulate "${p[@]}" --kind verification --seed 2 --duration 300 --noise-scale 0 -o $plant-verify-n0.csv
  "$bin" simulate "${p[@]}" --kind identification --seed 1 --clean -o $plant-ident-c.csv
  "$bin" simulate "${p[@]}" --kind verification --seed 2 --duration 300 --clean -o $plant-verify-c.csv
  "$bin" simulate "${p[@]}" --kind envelope --seed 1 --noise-scale 0 -o $plant-envelope-n0.csv
  "$bin" simulate "${p[@]}" --kind envelope-verification --seed 2 --noise-scale 0 -o $plant-envelope-verify-n0.csv
  "$bin" simulate "${p[@]}" --kind envelope --seed 1 --clean -o $plant-envelope-c.csv
  "$bin" simulate "${p[@]}" --kind envelope-verification --seed 2 --clean -o $plant-envelope-verify-c.csv
  if [ $plant = xcell60 ]; then hover=(ident.csv verify.csv); envelope=(envelope.csv envelope-verify.csv)
  else hover=(second-ident.csv second-verify.csv); envelope=(second-envelope.csv second-envelope-verify.csv); fi
  for kind in hover envelope; do
    if [ $kind = hover ]; then pair=("${hover[@]}"); t=ident; v=verify
    else pair=("${envelope[@]}"); t=envelope; v=envelope-verify; fi
    group="$title, $kind pair"
    while IFS='|' read -r label train verify extra; do
      out=conditions/$plant-$kind-$(echo "$label" | tr -c 'a-z0-9' '-')
      # shellcheck disable=SC2086 # $extra: identify's options, word-split on purpose
      "$lab" identify --train "$train" --verify "$verify" --out "$out" --no-plots $extra >/dev/null
      conditions+=(--condition "$group|$label|$out/metrics.json")
      if [ "$kind|$train|$extra" = "hover|${hover[0]}|" ]; then as_flown=$out; fi
    done <<EOF
as flown (noise and turbulence)|${pair[0]}|${pair[1]}|
as flown, free run not compensated for the gyro noise|${pair[0]}|${pair[1]}|--gyro-noise none
as flown, rates run free on the measured velocity|${pair[0]}|${pair[1]}|--free-run-velocity measured
trained without sensor noise, verified as flown|$plant-$t-n0.csv|${pair[1]}
no sensor noise (turbulence kept)|$plant-$t-n0.csv|$plant-$v-n0.csv
still air, no sensor noise|$plant-$t-c.csv|$plant-$v-c.csv
still air, no sensor noise, rates run free on the measured velocity|$plant-$t-c.csv|$plant-$v-c.csv|--free-run-velocity measured
EOF
  done
  conditions+=(--condition "$title, hover pair, other verification flights|verification seed 2 (the pair above)|$as_flown/metrics.json")
  for seed in 3 4 5; do
    "$bin" simulate "${p[@]}" --kind verification --seed $seed --duration 300 -o $plant-verify-$seed.csv
    out=conditions/$plant-seed-$seed
    "$lab" identify --train "${hover[0]}" --verify $plant-verify-$seed.csv --out $out --no-plots >/dev/null
    conditions+=(--condition "$title, hover pair, other verification flights|verification seed $seed|$out/metrics.json")
  done
done

# The same on another helicopter of the X-Cell's kind (docs/robustness.md, variation 2, where
# the flight default's hover free run of q misses): is its q model's hover speed stability
# learnt from the dynamics or from the sensors' noise?
group="X-Cell 60 variation 2 (docs/robustness.md), hover pair"
for tag in as-flown n0 c; do
  case $tag in as-flown) f=() ;; n0) f=(--noise-scale 0) ;; c) f=(--clean) ;; esac
  "$bin" simulate --plant-variation 2 --kind identification --seed 1 "${f[@]}" -o v2-ident-$tag.csv
  "$bin" simulate --plant-variation 2 --kind verification --seed 2 --duration 300 "${f[@]}" \
    -o v2-verify-$tag.csv
done
while IFS='|' read -r label train verify extra; do
  out=conditions/v2-$train-$verify-$(echo "$extra" | tr -c 'a-z0-9' '-')
  # shellcheck disable=SC2086 # $extra: identify's options, word-split on purpose
  "$lab" identify --train v2-ident-$train.csv --verify v2-verify-$verify.csv --out "$out" \
    --no-plots $extra >/dev/null
  conditions+=(--condition "$group|$label|$out/metrics.json")
done <<EOF
as flown (noise and turbulence)|as-flown|as-flown|
as flown, free run not compensated for the gyro noise|as-flown|as-flown|--gyro-noise none
trained without sensor noise, verified as flown|n0|as-flown
no sensor noise (turbulence kept)|n0|n0
still air, no sensor noise|c|c
EOF

mkdir -p "$root/docs/figures"
"$lab" identify --full --train ident.csv --verify verify.csv --out "$root/docs/figures" --plot-span 120
"$lab" identify --train ident-clean.csv --verify verify-clean.csv --out clean --no-plots
mkdir -p "$root/docs/figures/noisy"
"$lab" identify --train ident-noisy.csv --verify verify-noisy.csv --out "$root/docs/figures/noisy" \
  --no-plots
mkdir -p "$root/docs/figures/envelope"
"$lab" identify --train envelope.csv --verify envelope-verify.csv --out "$root/docs/figures/envelope" \
  --plot-span 60
mkdir -p "$root/docs/figures/$second" "$root/docs/figures/$second/envelope"
"$lab" identify --train second-ident.csv --verify second-verify.csv --out "$root/docs/figures/$second" \
  --no-plots
"$lab" identify --train second-envelope.csv --verify second-envelope-verify.csv \
  --out "$root/docs/figures/$second/envelope" --no-plots
# The documents keep the params-*.json; the same states as snapshot-*.ridx (the core's binary
# format) would only repeat them.
find "$root/docs/figures" -name 'snapshot-*.ridx' -delete
end=$(date +%s)
"$lab" report --realistic "$root/docs/figures/metrics.json" --clean clean/metrics.json \
  --envelope "$root/docs/figures/envelope/metrics.json" \
  --second-plant $second --second-hover "$root/docs/figures/$second/metrics.json" \
  --second-envelope "$root/docs/figures/$second/envelope/metrics.json" \
  --noisy-hover "$root/docs/figures/noisy/metrics.json" "${conditions[@]}" --elapsed $((end - start)) -o "$root/docs/results.md"
echo "wrote docs/results.md and docs/figures/ in $((end - start)) s"
