#!/usr/bin/env python3
"""Decodes a rotorid MAVLink 2 stream with pymavlink and checks it against the Rust side.

usage: mavlink_decode.py DIALECT_XML STREAM EXPECTED_JSON WORK_DIR

pymavlink's own generator (mavgen) builds a Python module from the same dialect XML the Rust
bindings come from; pymavlink's parser (CRC, CRC_EXTRA, MAVLink 2 zero truncation) then decodes
the stream. Every frame must be a message listed in EXPECTED_JSON, in order, with the same
sequence, system and component ids and every listed field equal: floats bit for bit (as f32),
integers and text exactly. Prints one summary line; exits 1 on the first difference.
"""
import importlib.util
import json
import struct
import sys

from pymavlink.generator import mavgen


def f32_bits(x):
    return struct.unpack("<I", struct.pack("<f", x))[0]


def same(expected, got, where):
    if isinstance(expected, dict) and "f32" in expected:
        bits = f32_bits(got)
        if bits != expected["f32"]:
            raise AssertionError(f"{where}: f32 bits {bits:#010x} != {expected['f32']:#010x} ({got!r})")
    elif isinstance(expected, list):
        if len(got) != len(expected):
            raise AssertionError(f"{where}: {len(got)} values, expected {len(expected)}")
        for i, (e, g) in enumerate(zip(expected, got)):
            same(e, g, f"{where}[{i}]")
    elif isinstance(expected, str):
        text = got.decode("utf-8") if isinstance(got, bytes) else got
        if text.rstrip("\0") != expected:
            raise AssertionError(f"{where}: {text!r} != {expected!r}")
    elif got != expected:
        raise AssertionError(f"{where}: {got!r} != {expected!r}")


def main():
    xml, stream, expected_json, work = sys.argv[1:5]
    out = f"{work}/rotorid_dialect.py"
    opts = mavgen.Opts(out, wire_protocol="2.0", language="Python3", validate=False)
    if not mavgen.mavgen(opts, [xml]):
        sys.exit(f"mavgen failed on {xml}")
    spec = importlib.util.spec_from_file_location("rotorid_dialect", out)
    dialect = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(dialect)

    mav = dialect.MAVLink(None)
    mav.robust_parsing = False  # a bad CRC or unknown id raises instead of being skipped
    with open(stream, "rb") as f:
        data = f.read()
    msgs = mav.parse_buffer(data) or []
    expected = json.load(open(expected_json))
    if len(msgs) != len(expected):
        sys.exit(f"decoded {len(msgs)} messages, Rust encoded {len(expected)}")
    counts = {}
    try:
        for k, (m, e) in enumerate(zip(msgs, expected)):
            where = f"message {k} ({e['type']})"
            if m.get_type() != e["type"]:
                raise AssertionError(f"{where}: decoded as {m.get_type()}")
            same(e["seq"], m.get_seq(), f"{where} seq")
            same(e["sys"], m.get_srcSystem(), f"{where} system id")
            same(e["comp"], m.get_srcComponent(), f"{where} component id")
            if m.get_signed():
                raise AssertionError(f"{where}: signed")
            for name, value in e["fields"].items():
                same(value, getattr(m, name), f"{where} .{name}")
            counts[e["type"]] = counts.get(e["type"], 0) + 1
    except AssertionError as err:
        sys.exit(f"mismatch: {err}")
    floats = sum(1 for m in msgs if m.get_type() == "DEBUG_FLOAT_ARRAY") * 58
    summary = ", ".join(f"{n} {t}" for t, n in sorted(counts.items()))
    print(f"pymavlink decoded {len(msgs)} messages ({len(data)} bytes): {summary}; "
          f"every field equal ({floats} array floats bit for bit)")


if __name__ == "__main__":
    main()
