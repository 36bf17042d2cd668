"""The example notebook runs from top to bottom (nbclient) and ends with the verdict's model."""

import os
import pathlib

import pytest

nbformat = pytest.importorskip("nbformat")
nbclient = pytest.importorskip("nbclient")

NOTEBOOK = pathlib.Path(__file__).parent.parent / "examples" / "identify_log.ipynb"


def test_example_notebook_executes():
    nb = nbformat.read(NOTEBOOK, as_version=4)
    nbclient.NotebookClient(nb, timeout=600, kernel_name="python3").execute()
    last = nb.cells[-1]["outputs"]
    text = "".join(o.get("text", "") for o in last)
    assert "bytes exported; model to fly:" in text
    assert "1900 bytes" in text  # ROTORID_FLIGHT_EXPORT_SIZE
    errors = [o for c in nb.cells if c.cell_type == "code" for o in c["outputs"] if o.output_type == "error"]
    assert not errors
    images = [o for c in nb.cells if c.cell_type == "code" for o in c["outputs"]
              if "image/png" in o.get("data", {})]
    assert len(images) >= 3  # the log, the bar chart, the prediction
