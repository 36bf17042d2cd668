"""The benchmark of scripts/python_bench.sh: simulate LOGS short logs, identify them with
identify_many and on Dask at 1 and 2 workers, write the markdown table."""

import os
import platform
import sys
import tempfile
import time

import rotorid
from rotorid import fleet


def timed(f):
    """f's result, wall time (s) and this process's CPU time over it (s, every thread)."""
    start, cpu = time.perf_counter(), time.process_time()
    out = f()
    return out, time.perf_counter() - start, time.process_time() - cpu


def main() -> None:
    n, output = int(sys.argv[1]), sys.argv[2]
    from dask.distributed import Client, LocalCluster

    rows = []
    with tempfile.TemporaryDirectory() as work:
        paths = []
        for k in range(n):
            p = os.path.join(work, f"log{k:03d}.csv")
            rotorid.simulate("verification", seed=100 + k, plant_variation=1 + k % 3, duration=60.0, out=p)
            paths.append(p)
        reference = None
        for workers in (1, 2):
            load = os.getloadavg()[0]
            results, s, cpu = timed(lambda: rotorid.identify_many(paths, workers=workers, progress=False, plots=False))
            jsons = [r.to_json() for r in results]
            assert reference is None or jsons == reference, "results depend on the worker count"
            reference = jsons
            rows.append(("identify_many (threads)", workers, s, f"{cpu / s:.2f}", load))
        for workers in (1, 2):
            load = os.getloadavg()[0]
            with LocalCluster(n_workers=workers, threads_per_worker=1, dashboard_address=None) as cluster, Client(cluster) as client:
                client.gather(client.map(fleet.identify_log, paths[:2], ["warm"] * 2, [0, 1], pure=False))
                futures = lambda: client.gather(client.map(fleet.identify_log, paths, ["x"] * n, list(range(n))))
                _, s, _ = timed(futures)
            rows.append(("Dask LocalCluster (processes)", workers, s, "–", load))
    lines = [
        "# rotorid for Python: throughput",
        "",
        "Logs identified per second by the Python package (`bindings/python`) against the number",
        f"of workers, over the same {n} simulated logs (60 s verification flights at 50 Hz, three",
        "airframe variations; each log identified on its own with every variant and a 30 %",
        "hold-out, no files written). Threads: `rotorid.identify_many(paths, workers=W)`, the GIL",
        "released inside the Rust call. Dask: `client.map(rotorid.fleet.identify_log, paths)` on a",
        "`LocalCluster(n_workers=W, threads_per_worker=1)` (its start-up and a warm-up task not timed).",
        "",
        "CPU/wall: this process's CPU time (all threads) over the wall time, the cores the threads",
        "really got (Dask's work runs in other processes). Load: the machine's 1-minute load",
        "average just before (other jobs' too).",
        "",
        "| how | workers | seconds | logs/s | CPU/wall | load |",
        "| --- | ---: | ---: | ---: | ---: | ---: |",
    ]
    for how, w, s, ratio, load in rows:
        lines.append(f"| {how} | {w} | {s:.1f} | {n / s:.2f} | {ratio} | {load:.1f} |")
    lines += [
        "",
        f"Machine: {os.cpu_count()} CPUs ({platform.machine()}, {platform.system()}), Python "
        f"{platform.python_version()}; shared with other jobs when measured (see the load), so the",
        "speed-up from 1 to 2 workers is a lower bound of what an idle machine gives.",
        "",
        "Regenerate with `scripts/python.sh` (builds and installs the wheel) then",
        f"`scripts/python_bench.sh {n}`.",
        "",
    ]
    with open(output, "w", encoding="utf-8") as f:
        f.write("\n".join(lines))
    print("\n".join(lines))


if __name__ == "__main__":
    main()
