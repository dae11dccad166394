"""The example notebook in docs/ runs clean, top to bottom, in a fresh kernel, and shows pictures."""

from __future__ import annotations

import warnings
from pathlib import Path

import pytest

nbclient = pytest.importorskip("nbclient", reason="the notebook needs nbclient and ipykernel (pip install '.[test]')")
nbformat = pytest.importorskip("nbformat")
pytest.importorskip("ipykernel", reason="the notebook needs an IPython kernel (pip install '.[test]')")

NOTEBOOK = Path(__file__).resolve().parents[1] / "docs" / "notebook.ipynb"


def test_the_notebook_runs_clean_and_shows_pictures(tmp_path: Path) -> None:
    notebook = nbformat.read(NOTEBOOK, as_version=4)
    nbclient.NotebookClient(notebook, timeout=300, kernel_name="python3",
                            resources={"metadata": {"path": str(tmp_path)}}).execute()
    outputs = [output for cell in notebook.cells if cell.cell_type == "code" for output in cell.outputs]
    assert not [output for output in outputs if output.output_type == "error"]
    pictures = [output for output in outputs if "image/png" in output.get("data", {})]
    assert len(pictures) >= 6, "every viewer shown, and every render, is a picture"
    printed = "".join(output.get("text", "") for output in outputs if output.output_type == "stream")
    assert "colour (" in printed, "the probe's numbers are printed"


def test_the_notebook_is_valid_as_nbformat_will_require() -> None:
    """Every cell has an id: nbformat warns of one without, and will refuse it."""
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        nbformat.validate(nbformat.read(NOTEBOOK, as_version=4))
