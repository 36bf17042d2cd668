"""read_log and simulate: columns, units, attrs; bad files raise LogError, never crash."""

import numpy as np
import pandas as pd
import pytest

import rotorid


def test_simulate_and_read_back(tmp_path):
    df = rotorid.simulate("verification", seed=3, duration=12.0)
    assert list(df.columns) == rotorid.LOG_COLUMNS
    assert len(df) == 600
    assert np.allclose(np.diff(df["time_s"]), 0.02, atol=0.011)
    path = rotorid.simulate("verification", seed=3, duration=12.0, out=tmp_path / "a.csv")
    back = rotorid.read_log(path)
    assert list(back.columns) == ["segment"] + rotorid.LOG_COLUMNS
    assert back.attrs["format"] == "Csv" and back.attrs["rate_hz"] == 50.0
    assert set(back["segment"]) == {1}
    # CSV keeps enough digits for the values the identification sees.
    common = back.merge(df, on="time_s", suffixes=("", "_sim"))
    assert len(common) >= 590
    for c in rotorid.LOG_COLUMNS[1:]:
        assert np.allclose(common[c], common[c + "_sim"], rtol=1e-6, atol=1e-9), c


def test_cuts_and_time_window(tmp_path):
    path = rotorid.simulate("verification", seed=5, duration=20.0, out=tmp_path / "b.csv")
    part = rotorid.read_log(path, from_s=5.0, to_s=15.0)
    assert part["time_s"].min() >= 5.0 and part["time_s"].max() <= 15.0
    slow = rotorid.read_log(path, rate=10)
    assert slow.attrs["rate_hz"] == 10.0
    assert abs(len(slow) - 200) <= 2
    assert isinstance(part.attrs["cuts"], list) and isinstance(part.attrs["notes"], list)


def write(tmp_path, name, text):
    p = tmp_path / name
    p.write_text(text)
    return p


def good_rows(n=10):
    rows = []
    for k in range(n):
        rows.append(f"{k * 0.02:.2f},0.5,0,0,0,0,0,0,0,0,0,0,0,0")
    return rows


@pytest.mark.parametrize(
    "name,content",
    [
        ("missing-column.csv", ",".join(rotorid.LOG_COLUMNS[:-1]) + "\n" + "\n".join(r.rsplit(",", 1)[0] for r in good_rows())),
        ("nan.csv", ",".join(rotorid.LOG_COLUMNS) + "\n" + "\n".join(good_rows(5) + ["0.10,0.5,NaN,0,0,0,0,0,0,0,0,0,0,0"] + good_rows(3))),
        ("text.csv", ",".join(rotorid.LOG_COLUMNS) + "\n" + "0.00,half,0,0,0,0,0,0,0,0,0,0,0,0\n"),
        ("corrupt.bin", "\x00\x01garbage" * 50),
        ("empty.csv", ""),
    ],
)
def test_bad_files_raise_log_error(tmp_path, name, content):
    p = write(tmp_path, name, content)
    with pytest.raises(rotorid.LogError) as e:
        rotorid.read_log(p)
    assert name in str(e.value)
    assert len(str(e.value)) < 2000


def test_corrupt_ulog_header(tmp_path):
    p = tmp_path / "broken.ulg"
    p.write_bytes(b"ULog\x01\x12\x35" + bytes(range(256)) * 4)
    with pytest.raises(rotorid.LogError):
        rotorid.read_log(p)


def test_argument_errors(tmp_path):
    with pytest.raises(rotorid.InputError):
        rotorid.read_log(tmp_path / "x.csv", rate=7.0)
    with pytest.raises(rotorid.InputError):
        rotorid.simulate("hover-dance")
    with pytest.raises(rotorid.InputError):
        rotorid.simulate("verification", plant="cessna")
    with pytest.raises(rotorid.SimulateError):
        rotorid.simulate("verification", cyclic_power=0.0)
    with pytest.raises(rotorid.SimulateError):
        rotorid.simulate("envelope", duration=10.0)
    with pytest.raises(OverflowError):  # PyO3's argument check: seeds are u64
        rotorid.simulate("verification", seed=-1)
    with pytest.raises(rotorid.InputError):
        rotorid.hover_samples(pd.DataFrame({"time_s": [0.0]}))
    bad = rotorid.simulate("verification", duration=1.0).astype({"u_col": object})
    bad.loc[0, "u_col"] = "x"
    with pytest.raises(rotorid.InputError):
        rotorid.hover_samples(bad)


def test_cyclic_power_changes_the_flight_only_when_asked():
    """The damage option: a factor of 1 is the undamaged flight bit for bit, another factor
    another flight (that it lowers the identified control power is test_fleet_dask's)."""
    full = rotorid.simulate("verification", seed=9, duration=30.0, clean=True)
    weak = rotorid.simulate("verification", seed=9, duration=30.0, clean=True, cyclic_power=0.6)
    assert np.array_equal(full["time_s"], weak["time_s"])
    same = rotorid.simulate("verification", seed=9, duration=30.0, clean=True, cyclic_power=1.0)
    assert full.equals(same)
    assert not full.equals(weak)
