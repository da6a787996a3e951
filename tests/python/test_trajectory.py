"""Trajectory files: exact round trip, random access, probes, XDMF."""
import xml.etree.ElementTree as ET

import h5py
import numpy as np
import pytest

import sphsolid
from sphsolid import scenes


@pytest.fixture
def written(tmp_path):
    """A coarse piston run with a snapshot every 25 steps and copies of the
    scene's state taken at the same moments."""
    scene = scenes.uniaxial_piston(4e-3)
    probes = sphsolid.Probes(scene, scenes.PAPER_PROBES)
    dyn = sphsolid.ImprovedEuler(scene)
    path = tmp_path / "run.h5"
    traj = sphsolid.Trajectory(path, "w", scene, probe_interval=5)
    copies = []

    def keep():
        copies.append(dict(time=scene.time, step=scene.step,
                           positions=scene.positions.copy(),
                           velocities=scene.velocities.copy(),
                           density=scene.density.copy(),
                           deviatoric_stress=scene.deviatoric_stress.copy(),
                           pressure=scene.pressure,
                           von_mises=scene.von_mises))

    dyn.attach(traj, interval=25)
    dyn.attach(keep, interval=25)
    dyn.attach(probes, interval=5)
    dyn.run(steps=100)
    traj.close()
    return scene, path, copies, probes


def test_trajectory_round_trip_is_exact(written):
    scene, path, copies, _ = written
    with sphsolid.Trajectory(path) as traj:
        assert len(traj) == len(copies) == 5        # steps 0, 25, ..., 100
        for frame, copy in zip(traj, copies):
            assert frame.time == copy["time"]
            assert frame.step == copy["step"]
            for name in ("positions", "velocities", "density",
                         "deviatoric_stress", "pressure", "von_mises"):
                np.testing.assert_array_equal(getattr(frame, name),
                                              copy[name], err_msg=name)
        np.testing.assert_array_equal(traj[0].masses, scene.masses)
        np.testing.assert_array_equal(traj[0].body_ids, scene.body_ids)
        assert traj.body_names == ["specimen", "plate", "piston"]


def test_frames_load_back_into_the_library_exactly(written):
    scene, path, copies, _ = written
    fresh = scenes.uniaxial_piston(4e-3)
    fresh.freeze()
    with sphsolid.Trajectory(path) as traj:
        traj.load_into(fresh, 2)
    assert fresh.time == copies[2]["time"]
    assert fresh.step == copies[2]["step"]
    np.testing.assert_array_equal(fresh.positions, copies[2]["positions"])
    np.testing.assert_array_equal(fresh.deviatoric_stress,
                                  copies[2]["deviatoric_stress"])
    np.testing.assert_array_equal(fresh.von_mises, copies[2]["von_mises"])


def test_random_access_by_index_negative_index_and_slice(written):
    _, path, copies, _ = written
    with sphsolid.Trajectory(path) as traj:
        assert traj[-1].step == copies[-1]["step"] == 100
        assert [f.step for f in traj[1::2]] == [25, 75]
        assert traj.nearest(copies[3]["time"] * 1.01).step == 75
        with pytest.raises(IndexError):
            traj[5]


def test_probe_series_in_the_file_match_the_recorded_probes(written):
    _, path, _, probes = written
    with sphsolid.Trajectory(path) as traj:
        stored = traj.probes
    assert stored.names == ["A", "B", "C"]
    assert stored.columns[:2] == ["von_mises", "pressure"]
    np.testing.assert_array_equal(stored.steps, probes.steps)
    np.testing.assert_array_equal(stored.times, probes.times)
    for name in stored.names:
        np.testing.assert_array_equal(stored[name]["von_mises"],
                                      probes[name]["von_mises"])
    np.testing.assert_allclose(stored.points[1], scenes.PAPER_PROBES["B"])


def test_xdmf_sidecar_points_at_existing_datasets(written):
    _, path, copies, _ = written
    xmf = path.with_suffix(".xmf")
    root = ET.parse(xmf).getroot()
    grids = root.findall("./Domain/Grid/Grid")
    assert len(grids) == len(copies)
    times = [float(g.find("Time").get("Value")) for g in grids]
    assert times == [c["time"] for c in copies]
    with h5py.File(path, "r") as f:
        for item in root.iter("DataItem"):
            if item.get("Format") != "HDF":
                continue
            file_name, dataset = item.text.strip().split(":")
            assert file_name == path.name
            dims = tuple(int(d) for d in item.get("Dimensions").split())
            assert f[dataset].shape == dims, dataset
    names = {a.get("Name") for a in grids[0].findall("Attribute")}
    assert {"von_mises", "pressure", "density", "velocity", "S_xx", "S_yy",
            "S_zz", "S_xy", "body"} <= names


def test_xdmf_reads_back_exactly_through_vtk(written):
    """ParaView's XDMF reader (VTK's vtkXdmfReader) sees the frames' times,
    positions and fields exactly. Skipped without the vtk module."""
    vtk = pytest.importorskip("vtk")
    from vtkmodules.util.numpy_support import vtk_to_numpy
    from vtkmodules.vtkCommonExecutionModel import \
        vtkStreamingDemandDrivenPipeline as pipeline
    _, path, copies, _ = written
    reader = vtk.vtkXdmfReader()
    reader.SetFileName(str(path.with_suffix(".xmf")))
    reader.UpdateInformation()
    info = reader.GetOutputInformation(0)
    assert list(info.Get(pipeline.TIME_STEPS())) == [c["time"]
                                                      for c in copies]
    info.Set(pipeline.UPDATE_TIME_STEP(), copies[2]["time"])
    reader.Update()
    grid = reader.GetOutputDataObject(0)
    points = vtk_to_numpy(grid.GetPoints().GetData())
    np.testing.assert_array_equal(points[:, :2], copies[2]["positions"])
    data = grid.GetPointData()
    np.testing.assert_array_equal(vtk_to_numpy(data.GetArray("von_mises")),
                                  copies[2]["von_mises"])
    np.testing.assert_array_equal(vtk_to_numpy(data.GetArray("S_xy")),
                                  copies[2]["deviatoric_stress"][:, 3])


def test_write_mode_refuses_reading(tmp_path):
    scene = scenes.uniaxial_piston(4e-3)
    traj = sphsolid.Trajectory(tmp_path / "w.h5", "w", scene)
    with pytest.raises(ValueError, match="reading|mode 'r'"):
        len(traj)
    traj.close()
    with pytest.raises(ValueError, match="closed"):
        traj.write()


def test_checkpoint_resume_continues_bit_for_bit(tmp_path):
    """Run 30 steps, checkpoint, run 20 more; a fresh scene resumed from
    the checkpoint reaches the same state after the same 20 steps."""
    first = scenes.uniaxial_piston(4e-3)
    dyn = sphsolid.ImprovedEuler(first)
    dyn.run(steps=30)
    first.write_checkpoint(tmp_path / "run.chk")
    dyn.run(steps=20)
    resumed = scenes.uniaxial_piston(4e-3)
    again = sphsolid.ImprovedEuler(resumed)
    resumed.read_checkpoint(tmp_path / "run.chk")
    assert resumed.step == 30 and resumed.time == 30 * again.dt
    again.run(steps=20)
    np.testing.assert_array_equal(resumed.positions, first.positions)
    np.testing.assert_array_equal(resumed.deviatoric_stress,
                                  first.deviatoric_stress)
    assert resumed.time == first.time


def test_checkpoint_of_another_scene_is_refused(tmp_path):
    small = scenes.uniaxial_piston(4e-3)
    small.write_checkpoint(tmp_path / "small.chk")
    other = scenes.uniaxial_piston(2e-3)
    with pytest.raises(ValueError, match="small.chk"):
        other.read_checkpoint(tmp_path / "small.chk")
