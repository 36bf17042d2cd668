"""Fleet scale on Dask: a LocalCluster of 2 workers simulates and identifies 102 short logs
of 3 airframes, one of which loses cyclic control power from its 21st flight on; the drift
rule (fleet.flag_drift) must flag exactly that airframe, on the powers that changed."""

import pytest

from rotorid import fleet

distributed = pytest.importorskip("dask.distributed")

AIRFRAMES = {"A": 1, "B": 2, "C": 5}
FLIGHTS = 34  # 3 × 34 = 102 logs


def test_dask_fleet_flags_the_damaged_airframe():
    specs = fleet.fleet_specs(AIRFRAMES, FLIGHTS, damaged="B", damaged_from=20, duration=60.0)
    assert len(specs) >= 100
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster:
        with distributed.Client(cluster) as client:
            rows = client.gather(client.map(fleet.simulate_and_identify, specs))
    table = fleet.parameter_table(rows)
    assert len(table) == len(specs)
    assert set(table["airframe"]) == set(AIRFRAMES)
    # Most logs give the pitch control power (an axis not fitted is NaN, not an error).
    assert table["M_lon"].notna().mean() > 0.8
    drift = fleet.flag_drift(table)
    print(drift.to_string())
    assert fleet.flagged_airframes(drift) == ["B"]
    b = drift[(drift["airframe"] == "B") & (drift["power"] == "M_lon")].iloc[0]
    # Lower control power, by about the simulated factor (0.75: −25 %).
    assert b["flagged"] and -0.4 < b["change"] < -0.1
