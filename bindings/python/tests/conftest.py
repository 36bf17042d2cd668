"""Shared fixtures: simulated logs (written once per session) and the `rotorid` binary the
package is compared with (ROTORID_BIN, set by scripts/python.sh)."""

import os
import shutil

import pytest

import rotorid


@pytest.fixture(scope="session")
def rotorid_bin() -> str:
    path = os.environ.get("ROTORID_BIN") or shutil.which("rotorid")
    if not path or not os.path.exists(path):
        pytest.fail(
            "the rotorid binary is needed to compare with: set ROTORID_BIN "
            "(scripts/python.sh builds it: cargo build --release -p rotorid-cli)"
        )
    return path


@pytest.fixture(scope="session")
def logs(tmp_path_factory):
    """A short training log (40 s identification sweeps) and a verification log (30 s)."""
    d = tmp_path_factory.mktemp("logs")
    train = rotorid.simulate("identification", seed=1, duration=40.0, out=d / "train.csv")
    verify = rotorid.simulate("verification", seed=2, duration=30.0, out=d / "verify.csv")
    return {"dir": d, "train": train, "verify": verify}
