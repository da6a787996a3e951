"""The ASE-style examples run (at a coarse spacing) and write their files."""
import os
import subprocess
import sys
from pathlib import Path

import pytest

import sphsolid

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


@pytest.mark.parametrize("script, args, outputs", [
    ("uniaxial_piston/uniaxial_piston.py", ["4e-3", "2e-5"],
     ["uniaxial_piston.h5", "uniaxial_piston.xmf",
      "uniaxial_piston_probes.png", "uniaxial_piston_von_mises.png"]),
    ("gravity/gravity.py", ["4e-3", "2e-4"],
     ["gravity.h5", "gravity.xmf", "gravity_probes.png",
      "gravity_von_mises.png"]),
    ("pressure_piston/pressure_piston.py", ["4e-3", "2e-4"],
     ["pressure_piston.h5", "pressure_piston.xmf",
      "pressure_piston_probes.png", "pressure_piston_von_mises.png"]),
])
def test_example_runs_and_writes_its_figures(script, args, outputs,
                                             tmp_path):
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join(
        [str(Path(sphsolid.__file__).resolve().parents[1])]
        + [p for p in [env.get("PYTHONPATH")] if p])
    run = subprocess.run([sys.executable, str(EXAMPLES / script), *args],
                         cwd=tmp_path, env=env, capture_output=True,
                         text=True, timeout=600)
    assert run.returncode == 0, run.stderr
    for name in outputs:
        assert (tmp_path / name).stat().st_size > 0, name
    with sphsolid.Trajectory(tmp_path / outputs[0]) as traj:
        assert traj.times[-1] == pytest.approx(float(args[1]), rel=1e-12)
