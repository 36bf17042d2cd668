#!/usr/bin/env bash
# Coverage-guided fuzzing of rotorid (cargo-fuzz, libFuzzer, nightly toolchain), then
# docs/fuzzing.md with the executions, coverage and crashes of each target.
#
# Usage: scripts/fuzz.sh [SECONDS] [--no-report]
#        scripts/fuzz.sh --build-only   (only the targets' build: CI begins it early, niced)
#   SECONDS       fuzzing time per target (default 60), from a random seed;
#   FUZZ_RUNS=N   instead: exactly N executions per target from seed 1 (reproducible; CI runs
#                 20 000, the full campaign 10 000 000: FUZZ_RUNS=10000000 scripts/fuzz.sh);
#   FUZZ_TARGETS="a b"  only these targets (the report keeps the other targets' last rows).
# Each target starts from its corpus, host-tests/fuzz/corpus/<target>/, kept in the
# repository and grown by each campaign (minimised with `cargo fuzz cmin` after a full one).
# A crash leaves its input in host-tests/fuzz/artifacts/<target>/ and fails the script; turn it
# into a regression test before fixing it.
set -euo pipefail
cd "$(dirname "$0")/.."
build_only=0
[ "${1:-}" = "--build-only" ] && build_only=1
seconds="${1:-60}"
report=1
[ "${2:-}" = "--no-report" ] && report=0
# Installed once (CI installs it first); not updated here, so that campaigns side by side do
# not race to replace it.
rustup toolchain list | grep -q '^nightly' || rustup toolchain install nightly --profile minimal

command -v cargo-fuzz >/dev/null 2>&1 || cargo install cargo-fuzz --locked
all=(frame_decoder messages csv_log identifier_step parameter_import import_then_step c_interface
     ulog_log dataflash_log)
read -r -a targets <<<"${FUZZ_TARGETS:-${all[*]}}"
results="$PWD/docs/fuzzing.tsv"
# The C interface's target runs its unsafe FFI code under AddressSanitizer; the others are
# safe Rust, where a sanitizer finds nothing a panic would not, and costs four times the
# executions.
# FUZZ_SANITIZER=none|address overrides that for every target (a long campaign of the C
# interface's target without it, say). Each sanitizer builds into its own directory, so that
# switching does not rebuild; the report keeps a row per target and sanitizer.
sanitizer() {
  if [ -n "${FUZZ_SANITIZER:-}" ]; then
    echo "$FUZZ_SANITIZER"
  elif [ "$1" = c_interface ]; then
    echo address
  else
    echo none
  fi
}
flags() { echo "--release -s $(sanitizer "$1") --target-dir target/$(sanitizer "$1")"; }
cd host-tests/fuzz
# shellcheck disable=SC2046 # flags: word-split on purpose
cargo +nightly fuzz build $(flags ulog_log) >/dev/null
# shellcheck disable=SC2046
cargo +nightly fuzz build $(flags c_interface) c_interface >/dev/null
[ "$build_only" = 1 ] && exit 0
status=0
# FUZZ_JOBS=N (with FUZZ_RUNS): N processes side by side on the same corpus, seeds 1…N, each
# FUZZ_RUNS/N executions; the row sums their executions and takes their best coverage.
jobs="${FUZZ_JOBS:-1}"
for t in "${targets[@]}"; do
  mkdir -p "corpus/$t"
  extra=()
  # Log readers: inputs up to 8 KiB hold every structure of their formats (headers,
  # definitions, records of each kind) and keep the executions fast. The C interface: a
  # call sequence of up to about 100 calls per input (each call copies the storage to check
  # that a refused one changed nothing, so long sequences are slow).
  case "$t" in
    ulog_log | dataflash_log | csv_log) extra+=(-max_len=8192) ;;
    c_interface) extra+=(-max_len=512) ;;
  esac
  if [ -n "${FUZZ_RUNS:-}" ]; then
    what="$FUZZ_RUNS runs from seed 1"
    [ "$jobs" -gt 1 ] && what="$FUZZ_RUNS runs in $jobs processes from seeds 1 to $jobs"
  else
    jobs=1
    what="$seconds s"
  fi
  start=$(date +%s)
  logs=()
  pids=()
  for j in $(seq 1 "$jobs"); do
    log=$(mktemp)
    logs+=("$log")
    if [ -n "${FUZZ_RUNS:-}" ]; then
      budget=(-runs="$((FUZZ_RUNS / jobs))" -seed="$j")
    else
      budget=(-max_total_time="$seconds")
    fi
    # shellcheck disable=SC2046
    cargo +nightly fuzz run $(flags "$t") "$t" "corpus/$t" -- "${budget[@]}" "${extra[@]}" \
      -print_final_stats=1 >"$log" 2>&1 &
    pids+=($!)
  done
  result="no crash"
  for k in "${!pids[@]}"; do
    if ! wait "${pids[$k]}"; then
      result="**crash** (see host-tests/fuzz/artifacts/$t)"
      status=1
      tail -n 30 "${logs[$k]}" >&2
    fi
  done
  elapsed=$(($(date +%s) - start))
  runs=0
  cov=0
  ft=0
  for log in "${logs[@]}"; do
    r=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -n 1)
    c=$(grep -o 'cov: [0-9]*' "$log" | tail -n 1 | sed 's/cov: //')
    f=$(grep -o 'ft: [0-9]*' "$log" | tail -n 1 | sed 's/ft: //')
    runs=$((runs + ${r:-0}))
    [ "${c:-0}" -gt "$cov" ] && cov=$c
    [ "${f:-0}" -gt "$ft" ] && ft=$f
    rm -f "$log"
  done
  echo "$t: ${runs:-?} executions in ${elapsed} s, coverage ${cov:-?} edges, ${ft:-?} features: $result"
  if [ "$report" = 1 ]; then
    # Under a lock: campaigns of different targets may run side by side.
    (
      flock 9
      touch "$results"
      key="$t	$(sanitizer "$t")"
      grep -v "^$key	" "$results" >"$results.new" || true
      printf '%s\t%s\t%s\t%s\t%s\t%s\t%s\n' "$key" "${runs:-?}" "${cov:-?}" "${ft:-?}" \
        "$result" "$what, ${elapsed} s" "$(date -u +%Y-%m-%d)" >>"$results.new"
      mv "$results.new" "$results"
    ) 9>"$results.lock"
  fi
done
cd ../..
if [ "$report" = 1 ]; then
  rows=""
  for t in "${all[@]}"; do
    while IFS=$'\t' read -r name san runs cov ft result budget day; do
      rows+="| \`$name\` | $san | $runs | $cov | $ft | $result | $budget | $day |"$'\n'
    done < <(grep "^$t	" "$results" || true)
  done
  cat > docs/fuzzing.md <<MD
# Fuzzing (generated by \`scripts/fuzz.sh\`; do not edit)

cargo-fuzz (libFuzzer) on $(rustc +nightly --version), on $(uname -m). Each row is the last
run of its target (\`docs/fuzzing.tsv\`): the full campaign is
\`FUZZ_RUNS=10000000 scripts/fuzz.sh\` (or \`FUZZ_TARGETS="ulog_log dataflash_log"\` for some
targets); CI runs 20 000 executions of each from seed 1 and the committed corpus
(\`host-tests/fuzz/corpus/\`), every target under AddressSanitizer (one build instead of two). Targets are in \`host-tests/fuzz/fuzz_targets/\`; each checks
properties, not only the absence of panics:

* \`frame_decoder\`: arbitrary bytes into the frame decoder; every delivered frame re-encodes to
  a frame that decodes to itself; the statistics count every byte.
* \`messages\`: every message parser of \`rotorid-link\`; whatever parses writes back to exactly
  the same bytes.
* \`csv_log\`: the CLI's CSV log importer and its warnings (inputs up to 8 KiB).
* \`identifier_step\`: arbitrary sample streams into the flight and the paper's fuzzy
  identifiers; a refused sample changes nothing, an accepted one never gives a non-finite
  prediction.
* \`parameter_import\`: arbitrary exported states into \`import\`; a refused one changes nothing,
  an accepted one keeps the predictions finite.
* \`import_then_step\`: hostile exported states into \`import\`, then steps, resumes and
  compensations: every refused call leaves every bit of the identifier as it was.
* \`c_interface\`: random call sequences on the C interface (every kind's init, step, resume,
  export, import of hostile bytes) with random damage to the handle's storage between calls:
  no crash, and every refused call changes no byte of the storage (inputs up to 512 bytes:
  sequences of up to about 100 calls).
* \`ulog_log\`: arbitrary bytes into the ULog reader and importer (inputs up to 8 KiB); on
  success every channel's time stamps are finite and increasing.
* \`dataflash_log\`: arbitrary bytes into the format detection and the DataFlash and PX4
  sdlog2 readers and importers (inputs up to 8 KiB); the same property.

| target | sanitizer | executions | coverage (edges) | features | result | budget, time | date |
|---|---|---:|---:|---:|---|---|---|
${rows}
MD
  echo "wrote docs/fuzzing.md"
fi
exit $status
