#!/usr/bin/env bash
# Prints (markdown) the flash an autopilot pays for rotorid: a minimal C firmware per kind
# (core/ffi/c/minimal/main.c: init + step, attitude as a quaternion, arm-none-eabi-gcc -Os,
# gc-sections, the thumbv7em library at its release profile, libgcc) built twice, with the
# generic calls (rotorid_init_<kind> + rotorid_step) and with the lean calls
# (rotorid_lean_init_<kind> + rotorid_lean_step_<kind>), each run under QEMU mps2-an386 (it
# must exit 0: every step accepted); the flight kind's flash by part for both; and the Rust
# equivalent (firmware-example's `minimal` binary) at three opt-levels; and each kind's lean
# step's instructions, counted by the same main.c built with -DROTORID_MINIMAL_COUNT (the
# flight kind's also with the library at opt-level 2). `scripts/cost.sh` embeds it in
# docs/cost.md.
set -euo pipefail
cd "$(dirname "$0")/.."
rustup target add thumbv7em-none-eabihf >/dev/null 2>&1 || true
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
cargo build -q --manifest-path core/ffi/Cargo.toml --release --target thumbv7em-none-eabihf
lib=core/ffi/target/thumbv7em-none-eabihf/release/librotorid_ffi.a
kinds="flight flight_plain paper_fuzzy paper_plain extended_fuzzy extended_plain paper_local extended_local"
# compile NAME LIB INIT STEP STORAGE [FLAG]: main.c against LIB into $out/NAME.elf, as an
# autopilot builds it (FLAG: -DROTORID_MINIMAL_COUNT for the counting firmware).
compile() {
  arm-none-eabi-gcc -mcpu=cortex-m4 -mthumb -mfloat-abi=hard -mfpu=fpv4-sp-d16 -std=c11 -Os \
    -ffp-contract=off -ffunction-sections -fdata-sections -nostartfiles -nostdlib ${6:-} \
    -DROTORID_MINIMAL_INIT="$3" -DROTORID_MINIMAL_STEP="$4" -DROTORID_MINIMAL_STORAGE="$5" \
    -I core/ffi/include core/ffi/c/minimal/main.c "$2" -lgcc -Wl,--gc-sections \
    -z noexecstack -L . -T core/ffi/c/firmware/link.ld -o "$out/$1.elf"
}
qemu() {
  timeout 300 qemu-system-arm -machine mps2-an386 -cpu cortex-m4 -display none -monitor none \
    -serial none -semihosting-config enable=on,target=native "$@"
}
# firmware NAME LIB INIT STEP STORAGE: prints "text bss", fails unless it runs.
firmware() {
  compile "$@"
  if ! qemu -kernel "$out/$1.elf"; then
    echo "the minimal firmware $1 ($3 + $4) failed under QEMU" >&2
    exit 1
  fi
  arm-none-eabi-size "$out/$1.elf" | tail -1 | awk '{print $1, $3}'
}
# count NAME LIB INIT STEP STORAGE: the counting firmware (SysTick around each step under
# -icount shift=0, 1 tick = 40 instructions; steps 100..200 of main.c's stream); prints "mean
# worst fnv" (instructions per step; FNV-1a of every step's prediction and innovation bits).
count() {
  compile "$@" -DROTORID_MINIMAL_COUNT
  local counted steps ticks worst fnv
  counted=$(qemu -icount shift=0 -kernel "$out/$1.elf" 2>&1) ||
    { echo "the counting firmware $1 failed: $counted" >&2; exit 1; }
  read -r steps ticks worst fnv < <(sed -n 's/^rotorid-minimal: steps \([0-9]*\) ticks \([0-9]*\) max \([0-9]*\) fnv \([0-9]*\)$/\1 \2 \3 \4/p' <<<"$counted")
  [ -n "${fnv:-}" ] || { echo "no count from the counting firmware $1: $counted" >&2; exit 1; }
  echo "$((ticks * 40 / steps)) $((worst * 40)) $fnv"
}
echo "| kind | generic calls: flash (text, B) | lean calls: flash (text, B) | saved (B) | RAM (bss, B) | runs | lean step: mean / worst instructions |"
echo "|---|---:|---:|---:|---:|:-:|---:|"
for k in $kinds; do
  storage="ROTORID_$(tr '[:lower:]' '[:upper:]' <<<"$k")_STORAGE_SIZE"
  read -r generic _ < <(firmware "generic-$k" "$lib" "rotorid_init_$k" rotorid_step "$storage")
  lean_calls=("rotorid_lean_init_$k" "rotorid_lean_step_$k" "$storage")
  read -r lean bss < <(firmware "lean-$k" "$lib" "${lean_calls[@]}")
  read -r mean worst fnv < <(count "count-$k" "$lib" "${lean_calls[@]}")
  echo "| \`$k\` | $generic | $lean | $((generic - lean)) | $bss | yes | $mean / $worst |"
  # The flight kind's row at the shipped level is the first of the opt-level table below.
  [ "$k" != flight ] || flight_s="$lean $mean $worst $fnv"
done
echo
# The lean flight firmware again with ROTORID_MINIMAL_COUNT: SysTick around each step under
# -icount shift=0 (1 tick = 40 instructions), steps 100..200 of main.c's stream; with the
# library at its release profile (opt-level "s") and rebuilt at opt-level 2 (own target dir).
echo "The lean flight step as a C autopilot gets it, counted by \`main.c\` built with \`-DROTORID_MINIMAL_COUNT\` (SysTick around each step under \`-icount shift=0\`, 1 tick = 40 instructions; steps 100..200 of its stream, forward and sideways speed a 0–10 m/s triangle, so that every speed rule fires), with the library at its release profile (opt-level \"s\", what \`core/ffi\`'s Cargo.toml ships) and rebuilt at opt-level 2 (\`CARGO_PROFILE_RELEASE_OPT_LEVEL=2\`; this script fails unless both compute the same bits):"
echo
echo "| library opt-level | flash (text, B) | steps | mean instructions/step | worst instructions/step | predictions (FNV-1a of the bits) |"
echo "|---|---:|---:|---:|---:|---|"
for level in s 2; do
  if [ "$level" = s ]; then
    read -r text mean worst fnv <<<"$flight_s"
  else
    CARGO_PROFILE_RELEASE_OPT_LEVEL=$level CARGO_TARGET_DIR="$out/ffi-$level" cargo build -q \
      --manifest-path core/ffi/Cargo.toml --release --target thumbv7em-none-eabihf
    levellib="$out/ffi-$level/thumbv7em-none-eabihf/release/librotorid_ffi.a"
    flight=(rotorid_lean_init_flight rotorid_lean_step_flight ROTORID_FLIGHT_STORAGE_SIZE)
    read -r text _ < <(firmware "lean-flight-$level" "$levellib" "${flight[@]}")
    read -r mean worst fnv < <(count "count-flight-$level" "$levellib" "${flight[@]}")
  fi
  # Every level must compute the same bits.
  [ -z "${first_fnv:-}" ] || [ "$fnv" = "$first_fnv" ] ||
    { echo "opt-level $level changed the predictions' bits ($fnv, not $first_fnv)" >&2; exit 1; }
  first_fnv=$fnv
  echo "| $level | $text | 100 | $mean | $worst | $(printf '%08x' "$fnv") |"
done
echo
echo "Flash of the flight kind's minimal C firmware by part (\`arm-none-eabi-nm -S\`, text and read-only data):"
echo
for v in generic lean; do arm-none-eabi-nm -S -C "$out/$v-flight.elf" >"$out/$v.nm"; done
python3 - "$out/generic.nm" "$out/lean.nm" <<'PY'
import sys, collections
parts = [
    ("the C interface's calls, with the core code inlined into them (the step, the constructor; generic: every method of the kind, through the view's vtable)", ("rotorid_ffi", "rotorid_", "<rotorid::hover::identifier::HoverIdentifier<f32,V,Q,R,P> as rotorid_ffi")),
    ("libm: sincosf and its argument reductions (Euler angles)", ("libm::math::sincos", "libm::math::rem_pio2", "libm::math::k_", "libm::math::generic::trig")),
    ("libm: the rest (expf; the square root is the FPU's)", ("libm",)),
    ("f64 soft-float (sincosf computes in f64; f64 constants converted at init)", ("__aeabi_d", "__muldf3", "__adddf3", "__aeabi_f2d", "__truncdfsf2", "__extendsfdf2", "compiler_builtins::float")),
    ("memory routines (memcpy, memset)", ("memcpy", "memset", "memclr", "__aeabi_mem", "compiler_builtins::mem")),
    ("the rotorid core", ("rotorid::", "<rotorid::")),
]
other = "start-up, vector table, main"
def tally(path):
    tot = collections.Counter()
    for line in open(path):
        p = line.split(None, 3)
        if len(p) < 4 or p[2] not in "tTrRW":
            continue
        name = p[3].strip()
        label = next((l for l, prefixes in parts if name.startswith(prefixes)), other)
        tot[label] += int(p[1], 16)
    return tot
generic, lean = tally(sys.argv[1]), tally(sys.argv[2])
print("| part | generic calls (B) | lean calls (B) |")
print("|---|---:|---:|")
for label, n in generic.most_common():
    print(f"| {label} | {n} | {lean[label]} |")
for label, n in lean.items():
    if label not in generic:
        print(f"| {label} | 0 | {n} |")
PY
echo
echo "The lean flight firmware's largest functions (\`arm-none-eabi-nm -S --size-sort\`; a generic core function is listed once per instantiation, its type parameters elided by the demangler):"
echo
echo "| function | flash (B) |"
echo "|---|---:|"
arm-none-eabi-nm -S -C --size-sort "$out/lean-flight.elf" | awk '$3 ~ /^[tTrRW]$/' | tail -16 | sort -k2,2r |
  while read -r _ size _ name; do echo "| \`${name}\` | $((16#$size)) |"; done
echo
echo "The Rust equivalent (\`firmware-example\`'s \`minimal\` binary: \`FlightIdentifier::flight\` and \`step\` with quaternions, fat LTO, \`cortex-m-rt\`), at three opt-levels:"
echo
echo "| opt-level | flash (text, B) | runs |"
echo "|---|---:|:-:|"
for level in 3 s z; do
  dir="$out/rust-$level"
  (cd firmware-example && CARGO_PROFILE_RELEASE_OPT_LEVEL=$level CARGO_TARGET_DIR="$dir" \
    cargo build -q --release --bin minimal --no-default-features)
  elf="$dir/thumbv7em-none-eabihf/release/minimal"
  read -r text _ < <(arm-none-eabi-size "$elf" | tail -1)
  runs=no
  if qemu -kernel "$elf"; then runs=yes; fi
  echo "| $level | $text | $runs |"
done
