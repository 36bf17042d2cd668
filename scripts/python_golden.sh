#!/usr/bin/env bash
# Regenerates bindings/python/tests/golden/: the C interface's exports (every kind) after the
# committed sample stream, as SHA-256 and length (exports.json), which the Python package's
# exports must equal (bindings/python/tests/test_identifier.py). Needs a C compiler and the
# venv of scripts/python.sh (for a new stream only: `--new-stream`).
#
# Usage: scripts/python_golden.sh [--new-stream]
set -euo pipefail
cd "$(dirname "$0")/.."
root=$(pwd)
target="${CARGO_TARGET_DIR:-$root/target}"
golden=bindings/python/tests/golden
if [ "${1:-}" = "--new-stream" ]; then
  # 10 s of a verification flight (seed 7), as the core's samples: 60-byte records.
  "$target/python-venv/bin/python" - "$golden/stream.bin" <<'PY'
import sys, numpy as np, rotorid
s = rotorid.hover_samples(rotorid.simulate("verification", seed=7, duration=10.0))
rec = np.zeros(len(s["time_us"]), dtype=[("t", "<u8"), ("f", "<f4", 13)])
rec["t"] = s["time_us"]
rec["f"] = np.concatenate([s["attitude"], s["velocity"], s["rates"], s["controls"]], axis=1)
rec.tofile(sys.argv[1])
PY
fi
CARGO_TARGET_DIR="$target/ffi" cargo build -q --release --manifest-path core/ffi/Cargo.toml
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cc -std=c11 -O2 -Wall -Wextra -Werror -ffp-contract=off -I core/ffi/include \
  "$golden/c_export.c" "$target/ffi/release/librotorid_ffi.a" -o "$work/c_export"
"$work/c_export" "$golden/stream.bin" "$work"
python3 - "$work" "$golden/exports.json" <<'PY'
import hashlib, json, os, sys
work, out = sys.argv[1:]
kinds = ["flight", "flight_plain", "paper_fuzzy", "paper_plain", "extended_fuzzy",
         "extended_plain", "paper_local", "extended_local"]
table = {}
for k in kinds:
    b = open(os.path.join(work, k + ".bin"), "rb").read()
    table[k] = {"length": len(b), "sha256": hashlib.sha256(b).hexdigest()}
json.dump(table, open(out, "w"), indent=2)
open(out, "a").write("\n")
PY
echo "wrote $golden/exports.json"
