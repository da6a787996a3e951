"""Notebook habits: the example notebook runs and shows its figures inline;
short reprs; probes as a pandas table."""
from __future__ import annotations

import shutil
from pathlib import Path

import numpy as np
import pytest

import sphsolid
from sphsolid import scenes

REPOSITORY = Path(__file__).resolve().parents[2]
NOTEBOOK = REPOSITORY / "examples" / "notebook" / "paper_figures.ipynb"


def test_example_notebook_runs_and_shows_figures_inline(tmp_path):
    nbformat = pytest.importorskip("nbformat")
    nbclient = pytest.importorskip("nbclient")
    shutil.copy(NOTEBOOK, tmp_path / NOTEBOOK.name)
    notebook = nbformat.read(tmp_path / NOTEBOOK.name, as_version=4)
    client = nbclient.NotebookClient(notebook, timeout=600,
                                     kernel_name="python3",
                                     resources={"metadata": {"path": str(tmp_path)}})
    client.execute()               # raises CellExecutionError on any error
    code = [c for c in notebook.cells if c.cell_type == "code"]
    images = [c for c in code if any("image/png" in o.get("data", {})
                                     for o in c.outputs)]
    # probe curves, the piston's maps, the gravity map: inline images
    assert len(images) == 3, [c.source[:40] for c in code]
    texts = "\n".join(o["data"].get("text/plain", "") for c in code
                      for o in c.outputs if "data" in o)
    assert "Scene(2D" in texts and "Probes([A, B, C]" in texts
    assert "Frame(" in texts
    assert not any(o.get("name") == "stderr" and "Warning" in o.get("text", "")
                   for c in code for o in c.outputs)
    assert (tmp_path / "piston.xmf").is_file()   # written by the library


def test_short_reprs_and_pandas_table(tmp_path):
    scene = scenes.uniaxial_piston(dx="8mm")
    assert repr(scene).startswith("Scene(2D, ")
    assert "specimen: " in repr(scene)
    probes = sphsolid.Probes(scene, scenes.PAPER_PROBES)
    assert repr(probes) == "Probes([A, B, C], 0 samples)"
    dyn = sphsolid.ImprovedEuler(scene)
    traj = sphsolid.Trajectory(tmp_path / "r.h5", "w", scene)
    dyn.attach(probes, interval=5)
    dyn.run(steps=10)
    traj.close()
    assert repr(probes).startswith("Probes([A, B, C], 3 samples, t = 0 .. ")
    assert "step 10" in repr(scene)
    with sphsolid.Trajectory(tmp_path / "r.h5") as reader:
        assert "2 frames" in repr(reader)         # frame 0 and the final one
        frame = reader[-1]
        assert repr(frame).startswith("Frame(1, t=")
        assert len(repr(frame)) < 120
    assert "closed" in repr(reader)
    pandas = pytest.importorskip("pandas")
    table = probes.to_pandas()
    assert isinstance(table, pandas.DataFrame)
    np.testing.assert_array_equal(table.index.to_numpy(), probes.times)
    np.testing.assert_array_equal(table["step"].to_numpy(), [0, 5, 10])
    np.testing.assert_array_equal(table["B"]["von_mises"].to_numpy(),
                                  probes["B"]["von_mises"])


def test_progress_bar_counts_every_step_of_a_run_until(capsys):
    # a forced bar on run(until=...), which ends with a shortened step
    scene = scenes.uniaxial_piston(dx="8mm")
    dyn = sphsolid.ImprovedEuler(scene, progress=True)
    taken = dyn.run(until=10.5 * dyn.dt)
    assert taken == 11
    err = capsys.readouterr().err
    assert "11/11" in err
