"""A simulated fleet on Dask: three airframes (variations of the X-Cell 60), each flying
FLIGHTS short logs; airframe B's rotor is damaged from flight DAMAGED_FROM on (cyclic
control power × 0.75). Every log is simulated and identified on the cluster; the per-airframe
control powers are gathered into one table and the airframe whose powers drifted is flagged.

    python fleet_dask.py [--flights 34] [--workers 2]
"""

import argparse
import time

from dask.distributed import Client, LocalCluster

from rotorid import fleet

AIRFRAMES = {"A": 1, "B": 2, "C": 5}  # name → plant_variation seed


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--flights", type=int, default=34, help="logs per airframe")
    ap.add_argument("--workers", type=int, default=2, help="Dask worker processes")
    ap.add_argument("--damaged-from", type=int, default=20, help="first damaged flight of B")
    args = ap.parse_args()
    specs = fleet.fleet_specs(AIRFRAMES, args.flights, damaged="B", damaged_from=args.damaged_from)
    with LocalCluster(n_workers=args.workers, threads_per_worker=1) as cluster, Client(cluster) as client:
        start = time.perf_counter()
        rows = client.gather(client.map(fleet.simulate_and_identify, specs))
        elapsed = time.perf_counter() - start
    table = fleet.parameter_table(rows)
    drift = fleet.flag_drift(table)
    print(f"{len(rows)} logs in {elapsed:.1f} s on {args.workers} workers")
    print(table.groupby("airframe")[["L_lat", "M_lon", "N_ped"]].median().round(2))
    print(drift.round(3).to_string(index=False))
    print("flagged:", ", ".join(fleet.flagged_airframes(drift)) or "none")


if __name__ == "__main__":
    main()
