"""Identifiers: exports byte-identical to the C interface's (committed golden made by
scripts/python_golden.sh from the C library), step == step_many, import_, typed errors."""

import hashlib
import json
import pathlib

import numpy as np
import pytest

import rotorid

GOLDEN = pathlib.Path(__file__).parent / "golden"


def stream():
    rec = np.fromfile(GOLDEN / "stream.bin", dtype=[("t", "<u8"), ("f", "<f4", 13)])
    f = rec["f"]
    return {
        "time_us": rec["t"].copy(),
        "attitude": f[:, 0:3],
        "velocity": f[:, 3:6],
        "rates": f[:, 6:9],
        "controls": f[:, 9:13],
    }


CLASSES = {
    "flight": rotorid.FlightIdentifier,
    "flight_plain": rotorid.FlightPlainIdentifier,
    "paper_fuzzy": rotorid.PaperFuzzyIdentifier,
    "paper_plain": rotorid.PaperPlainIdentifier,
    "extended_fuzzy": rotorid.ExtendedFuzzyIdentifier,
    "extended_plain": rotorid.ExtendedPlainIdentifier,
    "paper_local": rotorid.PaperLocalIdentifier,
    "extended_local": rotorid.ExtendedLocalIdentifier,
}


@pytest.mark.parametrize("kind", sorted(CLASSES))
def test_export_is_the_c_interfaces(kind):
    golden = json.loads((GOLDEN / "exports.json").read_text())[kind]
    ident = CLASSES[kind]()
    assert ident.kind == kind and ident.kind_code == rotorid.KINDS.index(kind) + 1
    fresh = ident.export()
    out = ident.step_many(**stream())
    assert np.isfinite(out["prediction"]).all()
    b = ident.export()
    assert b != fresh  # it learnt
    assert len(b) == golden["length"] == ident.export_size
    assert hashlib.sha256(b).hexdigest() == golden["sha256"]
    # import_ into a fresh one gives the same state back.
    other = CLASSES[kind]()
    other.import_(b)
    assert other.export() == b


def test_step_equals_step_many():
    s = stream()
    a = rotorid.FlightIdentifier()
    preds = []
    for k in range(len(s["time_us"])):
        p, i = a.step(int(s["time_us"][k]), s["attitude"][k], s["velocity"][k], s["rates"][k], s["controls"][k])
        assert (i is None) == (k == 0)
        preds.append(p)
    b = rotorid.Identifier("flight")
    out = b.step_many(**s)
    assert np.array_equal(np.array(preds, dtype=np.float32), out["prediction"])
    assert np.isnan(out["innovation"][0]).all() and np.isfinite(out["innovation"][1:]).all()
    assert a.export() == b.export()
    b.reset()
    assert b.export() == rotorid.FlightIdentifier().export()


def test_log_frames_step_as_identify_converts_them():
    df = rotorid.simulate("verification", seed=11, duration=6.0)
    s = rotorid.hover_samples(df)
    assert s["time_us"].dtype == np.uint64 and s["rates"].dtype == np.float32
    # paper axes: v_y is up, so it is minus the down velocity
    assert np.allclose(s["velocity"][:, 1], -df["v_down_mps"], atol=1e-5)
    # rates in deg/s, [q r p]
    assert np.allclose(s["rates"][:, 2], np.degrees(df["p_radps"]), rtol=1e-5, atol=1e-4)
    out = rotorid.PaperPlainIdentifier().step_many(**s)
    assert out["prediction"].shape == (len(df), 6)


DEFAULT_PREMISES = [("speed", [0.0, 5.0, 10.0], [2.5, 2.5, 2.5])] * 4


def test_flight_premises_on_the_default_speed_are_the_flight_default():
    s = stream()
    default = rotorid.FlightIdentifier()
    given = rotorid.Identifier("flight", premises=DEFAULT_PREMISES)
    also = rotorid.FlightIdentifier(premises=DEFAULT_PREMISES)
    assert given.kind == "flight" and given.kind_code == default.kind_code
    outs = [i.step_many(**s)["prediction"] for i in (default, given, also)]
    assert np.array_equal(outs[0], outs[1]) and np.array_equal(outs[0], outs[2])
    assert default.export() == given.export() == also.export()


def test_flight_premises_move_the_rules_and_bad_ones_raise():
    s = stream()
    # The velocity model's rules on the vertical speed, roll's on the side speed: another
    # model. An export carries θ and P, not the sets: it imports into any flight identifier,
    # and predicts as learnt only in one built with the same premises.
    moved = [("vertical_speed", [-1.0, 0.0, 1.0], [0.5, 0.5, 0.5]), DEFAULT_PREMISES[1],
             DEFAULT_PREMISES[2], ("side_speed", [-2.0, 0.0, 2.0], [1.0, 1.0, 1.0])]
    a = rotorid.Identifier("flight", premises=moved)
    b = rotorid.FlightIdentifier()
    pa = a.step_many(**s)["prediction"]
    pb = b.step_many(**s)["prediction"]
    assert np.isfinite(pa).all() and not np.array_equal(pa, pb)
    same = rotorid.Identifier("flight", premises=moved)
    other = rotorid.FlightIdentifier()
    for ident in (same, other):
        ident.import_(a.export())
        assert ident.export() == a.export()
    k = len(s["time_us"]) // 2
    sample = [s[f][k] for f in ("attitude", "velocity", "rates", "controls")]
    ps, _ = same.step(int(s["time_us"][k]), *sample)
    po, _ = other.step(int(s["time_us"][k]), *sample)
    assert np.isfinite(ps).all() and np.isfinite(po).all() and po != ps
    with pytest.raises(rotorid.InputError):
        rotorid.Identifier("flight_plain", premises=DEFAULT_PREMISES)
    with pytest.raises(rotorid.InputError):
        rotorid.Identifier("flight", premises=DEFAULT_PREMISES[:3])
    with pytest.raises(rotorid.InputError):
        rotorid.Identifier("flight", premises=[("sideways", [0, 5, 10], [2.5] * 3)] * 4)
    # The velocity model's premise has no side speed.
    with pytest.raises(rotorid.ConfigError):
        rotorid.Identifier("flight", premises=[("side_speed", [0, 5, 10], [2.5] * 3)] * 4)


def test_bad_input_raises_typed_errors():
    s = stream()
    ident = rotorid.FlightIdentifier()
    with pytest.raises(rotorid.InputError):
        ident.step_many(**{**s, "time_us": s["time_us"].astype(float)})
    with pytest.raises(rotorid.InputError):
        ident.step_many(**{**s, "rates": s["rates"][:, :2]})
    with pytest.raises(rotorid.InputError):
        ident.step_many(**{**s, "controls": s["controls"].astype(str)})
    with pytest.raises(rotorid.InputError):
        ident.step_many(**{**s, "velocity": s["velocity"][:-1]})
    nan = {k: v.copy() for k, v in s.items()}
    nan["rates"][10, 0] = np.nan
    with pytest.raises(rotorid.NonFiniteError) as e:
        ident.step_many(**nan)
    assert e.value.kind == "NonFinite" and "sample 10" in str(e.value)
    assert isinstance(e.value, rotorid.CoreError) and isinstance(e.value, rotorid.RotoridError)
    back = rotorid.FlightIdentifier()
    t = s["time_us"].copy()
    t[5] = t[3]
    with pytest.raises(rotorid.NonMonotonicTimeError):
        back.step_many(**{**s, "time_us": t})
    gap = rotorid.FlightIdentifier()
    t = s["time_us"].copy()
    t[20:] += 5_000_000
    with pytest.raises(rotorid.TimeStepError):
        gap.step_many(**{**s, "time_us": t})
    with pytest.raises(rotorid.OutOfRangeError):
        rotorid.FlightIdentifier().step(0, [0, 0, 0], [500, 0, 0], [0, 0, 0], [0.5, 0, 0, 0])
    with pytest.raises(ValueError, match="length 3"):  # PyO3's argument check
        rotorid.FlightIdentifier().step(0, [0, 0], [0, 0, 0], [0, 0, 0], [0.5, 0, 0, 0])
    with pytest.raises(rotorid.InputError):
        rotorid.Identifier("helicopter")


def test_import_refuses_foreign_or_damaged_exports():
    a = rotorid.FlightIdentifier()
    a.step_many(**stream())
    b = a.export()
    plain = rotorid.PaperPlainIdentifier()
    before = plain.export()
    with pytest.raises(rotorid.IncompatibleError):
        plain.import_(b)
    assert plain.export() == before
    flipped = bytearray(b)
    flipped[100] ^= 0x01
    fresh = rotorid.FlightIdentifier()
    with pytest.raises(rotorid.IncompatibleError):
        fresh.import_(bytes(flipped))
    with pytest.raises(rotorid.IncompatibleError):
        fresh.import_(b[:-1])
    assert fresh.export() == rotorid.FlightIdentifier().export()


def test_compensate_removes_the_gyro_noise_per_rate():
    learnt = rotorid.FlightIdentifier()
    learnt.step_many(**stream())
    b = learnt.export()

    def copy():
        c = rotorid.FlightIdentifier()
        c.import_(b)
        return c

    # Small enough against the stream's rates that rules compensate (at 0.5 deg/s the full
    # compensation is refused on all of this short stream's rules, so it equals damping).
    sigma = [0.05, 0.05, 0.05]
    damping = copy()
    compensated, refused = damping.compensate(sigma)
    assert compensated > 0 and compensated + refused == 9  # three rules on each of three rates
    assert damping.export() != b  # the rate models' parameters were replaced
    # The default is the damping term's on every rate, said once or per rate.
    for how in ("damping", ["damping"] * 3):
        other = copy()
        assert other.compensate(sigma, how) == (compensated, refused)
        assert other.export() == damping.export()
    full = copy()
    full.compensate(sigma, "full")
    assert full.export() != damping.export()
    # Per rate: full on q only differs from both.
    mixed = copy()
    mixed.compensate(sigma, ["full", "damping", "damping"])
    assert mixed.export() not in (damping.export(), full.export())
    # Refused input leaves the identifier unchanged.
    for bad_sigma, how, error in [
        ([-1.0, 0.05, 0.05], None, rotorid.CoreError),
        ([float("nan"), 0.05, 0.05], None, rotorid.CoreError),
        (sigma, "fully", rotorid.InputError),
        (sigma, ["full", "damping"], rotorid.InputError),
    ]:
        untouched = copy()
        with pytest.raises(error):
            untouched.compensate(bad_sigma, how)
        assert untouched.export() == b
