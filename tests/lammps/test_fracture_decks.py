"""The fracture decks: examples/ucs/in.ucs and examples/brazilian/in.brazilian
run to failure at a very coarse dx and print their strength; their atoms
are the library scenes' particles in the same order, so a deck's member
is the library's member (the same damage field, bitwise); and the flaw
ensemble as one LAMMPS job (examples/ensemble/in.ensemble, -partition 2x1):
member i of the job is bitwise member i run alone.
"""
from __future__ import annotations

import math
import os
import re
import subprocess

import numpy as np
import pytest

from conftest import REPOSITORY, lmp_command, run_deck

UCS = REPOSITORY / "examples" / "ucs" / "in.ucs"
BRAZILIAN = REPOSITORY / "examples" / "brazilian" / "in.brazilian"
ENSEMBLE = REPOSITORY / "examples" / "ensemble" / "in.ensemble"


def printed(log: str, label: str) -> float:
    return float(re.search(rf"^{re.escape(label)}\s*(\S+)", log, re.M).group(1))


@pytest.mark.parametrize("deck,dx,width", [(UCS, 0.006, 0.086), (BRAZILIAN, 0.004, None)],
                         ids=["ucs", "brazilian"])
def test_deck_loads_past_the_peak_and_prints_the_strength(tmp_path, plugin, deck, dx, width):
    run_deck(deck, tmp_path, {"dx": dx}, plugin)
    log = (tmp_path / "log.lammps").read_text()
    load = np.loadtxt(next(tmp_path.glob("*_load.txt")), comments="#", ndmin=2)
    peak = printed(log, "peak load:")
    onset = printed(log, "damage onset:")
    # the peak is the largest sample, damage began before the stop, and the
    # run stopped once the load fell below half the peak
    assert peak == pytest.approx(load[:, 3].max(), rel=1e-9)
    assert 0 < onset < load[-1, 1]
    assert load[-1, 3] < 0.5 * peak and load[-1, 4] == 1.0
    if width is not None:
        assert printed(log, "UCS:") == pytest.approx(peak / width, rel=1e-9)
    else:
        strength = printed(log, "indirect tensile strength 2P/(pi D t):")
        assert strength == pytest.approx(2 * peak / (math.pi * 0.05), rel=1e-9)
    # the damage field: some atoms fully damaged, some whole; the fragments
    # the deck counts are the labels that equal their atom's ID
    field = np.loadtxt(next(tmp_path.glob("*_damage.txt")), skiprows=9)
    D, F = field[:, 3], field[:, 4]
    assert (D == 1.0).any() and (D == 0.0).any()
    assert ((F == -1) == (D == 1)).all()
    assert printed(log, "fragments:") == (F == field[:, 0]).sum() >= 1


@pytest.mark.parametrize("deck,dx,t_end", [(UCS, 0.006, 0.0035), (BRAZILIAN, 0.004, 0.0085)],
                         ids=["ucs", "brazilian"])
def test_deck_member_is_the_library_member(tmp_path, plugin, deck, dx, t_end):
    # The library scene (sphsolid.fracture) with the damage effect's member
    # 1, run as long as the deck (past the peak; the deck's stop at the
    # drop is switched off: the loads it would stop on are taken at
    # another stage than the library's, so the stop can fall a sample
    # apart).  The deck's specimen atoms are the scene's particles in its
    # order (ID = index + 1), so they draw the same flaws, and the damage
    # field and the fragments come out bitwise the same.
    from sphsolid import ImprovedEuler, _lib, fracture

    run_deck(deck, tmp_path, {"dx": dx, "member": 1, "t_end": t_end, "drop": -1e30}, plugin)
    log = (tmp_path / "log.lammps").read_text()
    field = np.loadtxt(next(tmp_path.glob("*_damage.txt")), skiprows=9)
    steps = int(np.loadtxt(next(tmp_path.glob("*_load.txt")), ndmin=2)[-1, 0])
    scene = fracture.ucs(dx) if deck == UCS else fracture.brazilian_disc(dx)
    _lib.check(_lib.lib.sph_effect(scene.handle, b"damage", b"seed=1 flaws=10 member=1"),
               scene.handle, "member")
    ImprovedEuler(scene, progress=False).run(steps=steps)
    n = len(field)
    D = scene.damage[:n]
    assert 10 < (D > 0).sum() < n - 10 and (D == 1).any()
    np.testing.assert_array_equal(field[:, 3], D)
    np.testing.assert_allclose(field[:, 1:3], scene.positions[:n], rtol=0, atol=1e-9)
    fragments = scene.fragments[:n]
    assert printed(log, "fragments:") == fragments.max() + 1


def test_two_partitions_give_each_member_bitwise_as_alone(tmp_path, plugin):
    dx = 0.006
    job = tmp_path / "job"
    job.mkdir()
    cmd = lmp_command(2) + ["-partition", "2x1", "-in", str(ENSEMBLE), "-log", "log.lammps",
                            "-screen", "none", "-nocite", "-var", "plugin", str(plugin),
                            "-var", "members", "2", "-var", "dx", str(dx),
                            "-var", "deck", str(UCS)]
    done = subprocess.run(cmd, cwd=job, capture_output=True, text=True, timeout=600,
                          env=dict(os.environ, OMP_NUM_THREADS="1"))
    assert done.returncode == 0, done.stdout[-2000:] + done.stderr[-2000:]
    assert "Running on 2 partitions" in done.stdout + (job / "log.lammps").read_text()
    rows = np.loadtxt(job / "ensemble_summary.txt", ndmin=2)
    assert sorted(rows[:, 0]) == [0, 1]
    for member in (0, 1):
        alone = tmp_path / f"alone{member}"
        alone.mkdir()
        run_deck(UCS, alone, {"dx": dx, "member": member}, plugin)
        for ours, theirs in (("ucs_damage.txt", f"ensemble_member{member}_damage.txt"),
                             ("ucs_load.txt", f"ensemble_member{member}_load.txt")):
            assert (alone / ours).read_bytes() == (job / theirs).read_bytes(), (member, ours)
        log = (alone / "log.lammps").read_text()
        row = rows[rows[:, 0] == member][0]
        assert row[2] == pytest.approx(printed(log, "UCS:"), rel=1e-9)
        assert row[5] == printed(log, "fragments:")
    # two members: two draws, two damage fields
    assert ((job / "ensemble_member0_damage.txt").read_bytes()
            != (job / "ensemble_member1_damage.txt").read_bytes())


def test_slurm_example_runs_the_ensemble_deck():
    script = (REPOSITORY / "examples" / "ensemble" / "slurm.sh").read_text()
    assert "-partition" in script and "in.ensemble" in script
    assert re.search(r"^#SBATCH --ntasks=", script, re.M)
    done = subprocess.run(["bash", "-n", str(REPOSITORY / "examples" / "ensemble" / "slurm.sh")],
                          capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
