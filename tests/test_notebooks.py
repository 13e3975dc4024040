"""Every notebook in notebooks/ runs top to bottom without errors (outputs are not kept)."""

from pathlib import Path

import nbformat
import pytest
from nbclient import NotebookClient

NOTEBOOKS = sorted((Path(__file__).parent.parent / "notebooks").glob("*.ipynb"))
SIMULATING = {"review_recording.ipynb", "design_study.ipynb"}   # simulations of several seconds


def test_there_are_notebooks():
    assert NOTEBOOKS


@pytest.mark.parametrize("path", [pytest.param(p, marks=pytest.mark.slow) if p.name in SIMULATING
                                  else p for p in NOTEBOOKS], ids=lambda p: p.name)
def test_notebook_runs(path, tmp_path, monkeypatch):
    monkeypatch.setenv("MPLBACKEND", "Agg")
    nb = nbformat.read(path, as_version=4)
    assert not any(cell.get("outputs") for cell in nb.cells), f"{path.name} is committed with outputs"
    NotebookClient(nb, timeout=600, kernel_name="python3",
                   resources={"metadata": {"path": str(tmp_path)}}).execute()
    errors = [o for c in nb.cells for o in c.get("outputs", []) if o.get("output_type") == "error"]
    assert not errors
