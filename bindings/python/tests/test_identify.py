"""identify: byte-identical to `rotorid identify`, the result's tables, identify_many."""

import json
import os
import subprocess

import pandas as pd
import pytest

import rotorid


def cli_metrics(rotorid_bin, cwd, args):
    subprocess.run(
        [rotorid_bin, "identify", "--no-plots", *args, "--out", "cli-out"],
        cwd=cwd,
        check=True,
        capture_output=True,
    )
    with open(os.path.join(cwd, "cli-out", "metrics.json"), encoding="utf-8") as f:
        return f.read()


@pytest.mark.parametrize("with_verify", [True, False])
def test_to_json_is_the_cli_metrics_byte_for_byte(rotorid_bin, logs, with_verify, monkeypatch):
    monkeypatch.chdir(logs["dir"])  # relative paths, as a user types them
    if with_verify:
        expected = cli_metrics(rotorid_bin, logs["dir"], ["--train", "train.csv", "--verify", "verify.csv"])
        result = rotorid.identify("train.csv", verify="verify.csv")
    else:
        expected = cli_metrics(rotorid_bin, logs["dir"], ["train.csv", "verify.csv"])
        result = rotorid.identify(["train.csv", "verify.csv"])
    assert result.to_json() == expected
    # The files written with `out` are the command's too.
    result = rotorid.identify(["train.csv", "verify.csv"] if not with_verify else "train.csv",
                              verify="verify.csv" if with_verify else None,
                              out="py-out", plots=False)
    for name in os.listdir("cli-out"):
        with open(os.path.join("cli-out", name), "rb") as a, open(os.path.join("py-out", name), "rb") as b:
            assert a.read() == b.read(), name


def test_flight_selecteds_snapshot_imports_into_the_premises_of_its_params(logs, monkeypatch):
    monkeypatch.chdir(logs["dir"])
    rotorid.identify("train.csv", verify="verify.csv", out="out", plots=False)
    premises = rotorid.flight_premises("out/params-flight-selected.json")
    with open("out/snapshot-flight-selected.ridx", "rb") as f:
        snapshot = f.read()
    chosen = rotorid.Identifier("flight", premises=premises)
    chosen.import_(snapshot)
    assert chosen.export() == snapshot
    # What the selection chose here: some model has one rule (the unscheduled sets' left
    # shoulder at 10⁵ m/s) or its rules on another speed; so not the flight default's sets.
    assert premises != [("speed", [0.0, 5.0, 10.0], [2.5, 2.5, 2.5])] * 4
    # A params file of another structure is not a flight model's premises.
    with pytest.raises(rotorid.InputError):
        rotorid.flight_premises("out/params-paper-fuzzy.json")


def test_the_commands_options_give_its_bytes(rotorid_bin, logs, monkeypatch):
    monkeypatch.chdir(logs["dir"])
    first = rotorid.identify("train.csv", out="warm", plots=False)
    assert os.path.exists("warm/params-paper-fuzzy.json")
    flags = ["--free-run-velocity", "measured", "--gyro-noise", "0.25,0.5,0.75",
             "--observer-gain", "0.5", "--warm-start", "warm/params-paper-fuzzy.json",
             "--window", "1.5", "--control-delay", "0.04", "--train", "train.csv",
             "--verify", "verify.csv"]
    expected = cli_metrics(rotorid_bin, logs["dir"], flags)
    result = rotorid.identify("train.csv", verify="verify.csv", free_run_velocity="measured",
                              gyro_noise=(0.25, 0.5, 0.75), observer_gain=0.5,
                              warm_start="warm/params-paper-fuzzy.json", window=1.5,
                              control_delay=0.04)
    assert result.to_json() == expected
    assert json.loads(result.to_json())["control_delay"]["delay_s"] == 0.04
    assert result.to_json() != first.to_json()
    for bad in [dict(gyro_noise="loud"), dict(gyro_noise=(1, 2)), dict(observer_gain=1.5),
                dict(free_run_velocity="fast"), dict(control_delay=2.0)]:
        with pytest.raises(rotorid.InputError):
            rotorid.identify("train.csv", **bad)


def test_result_tables(logs):
    r = rotorid.identify(logs["train"], verify=logs["verify"], plots=False)
    m = json.loads(r.to_json())
    assert r.model == m["verdict"]["model"]
    assert r.model in {v["name"] for v in m["variants"]}
    assert "Model to fly" in r.report
    assert any(n.startswith("identifying at 50 Hz") for n in r.notes)
    vm = r.variant_metrics()
    assert len(vm) == 6 * len(m["variants"])
    assert (vm["one_step"] >= 0).all() and (vm["hold_free_run"] >= 0).all()
    p = r.parameters("flight")
    assert set(p["model"]) == {"velocity", "q", "r", "p"}
    assert p["theta"].notna().all()
    d = r.derivatives()
    assert {"L_lat", "M_lon", "N_ped"} <= set(d["symbol"])
    fitted = d["se"].notna()
    assert fitted.sum() >= 10 and (d.loc[fitted, "se"] >= 0).all()
    with pytest.raises(rotorid.InputError):
        r.parameters("no such variant")


def test_identify_many_equals_one_by_one(logs):
    d = logs["dir"]
    paths = []
    for k in range(3):
        paths.append(rotorid.simulate("verification", seed=40 + k, duration=30.0, out=d / f"m{k}.csv"))
    one = [rotorid.identify(p, plots=False).to_json() for p in paths]
    many = rotorid.identify_many(paths, workers=2, progress=False, plots=False)
    assert [r.to_json() for r in many] == one
    with_bad = rotorid.identify_many(paths[:1] + [str(d / "missing.csv")], workers=2, progress=False,
                                     errors="return", plots=False)
    assert with_bad[0].to_json() == one[0]
    assert isinstance(with_bad[1], rotorid.LogError)
    with pytest.raises(rotorid.LogError):
        rotorid.identify_many([str(d / "missing.csv")], workers=1, progress=False)


def test_identify_errors(logs, tmp_path):
    with pytest.raises(rotorid.LogError) as e:
        rotorid.identify(tmp_path / "nope.csv")
    assert "nope.csv" in str(e.value) and e.value.kind == "Import"
    with pytest.raises(rotorid.IdentifyError) as e:
        rotorid.identify(logs["train"], window=0)
    assert e.value.kind == "Window"
    with pytest.raises(rotorid.IdentifyError):
        rotorid.identify([])
    with pytest.raises(rotorid.InputError):
        rotorid.identify(logs["train"], holdout=1.5)
    with pytest.raises(rotorid.InputError):
        rotorid.identify(logs["train"], rate=33.3)


def test_identify_releases_the_gil(logs):
    """While one thread identifies, another keeps running Python: the longest pause between
    its ticks stays far below the identification's duration (were the GIL held, the pause
    would be the whole call)."""
    import threading
    import time

    done = threading.Event()
    took = []

    def work():
        start = time.perf_counter()
        rotorid.identify(logs["train"], verify=logs["verify"], plots=False)
        took.append(time.perf_counter() - start)
        done.set()

    worker = threading.Thread(target=work)
    last = time.perf_counter()
    longest = 0.0
    worker.start()
    while not done.is_set():
        now = time.perf_counter()
        longest = max(longest, now - last)
        last = now
        time.sleep(0.001)
    worker.join()
    # A tenth of a second is well above the ticking thread's own pauses (a few ms); the
    # product's nine variants take about 0.17 s on this log on an idle 2-core machine.
    assert took[0] > 0.1, "identification too short to tell"
    assert longest < took[0] / 2
