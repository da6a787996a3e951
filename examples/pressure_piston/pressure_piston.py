"""The specimen loaded by a piston under a constant pressure (python3 pressure_piston.py [dx_m] [until_s] [lammps]).

The piston is a rigid body pushed by p x width (Pressure motion); damping
brings the specimen to the steady state, where every section carries the
load and the mean sigma_yy is -p.  Add "lammps" to run it through the
LAMMPS plugin (fix sphsolid/force) instead of the C library.
"""
import sys
from sphsolid import ImprovedEuler, Material, Pressure, Probes, Scene, Trajectory, figures
from sphsolid.build import piston, plate, rectangle

dx = float(sys.argv[1]) if len(sys.argv) > 1 else 2e-3      # m
until = float(sys.argv[2]) if len(sys.argv) > 2 else 3e-3    # s
pressure = 1e6                                                # Pa on the piston's face
rock = Material(K=12.2e9, mu=2.67e9, rho0=2300)                  # Pa, Pa, kg/m^3
specimen = rectangle(x=(-0.043, 0.043), y=(0, 0.140), dx=dx, material=rock)
scene = Scene(2, [specimen, plate(under=specimen, layers=3),
                  piston(over=specimen, layers=3, motion=Pressure(pressure))],
              effects={"artificial_viscosity": {"alpha": 1.0, "beta": 0.0},
                       "damping": {"rate": 1e4}})               # 1/s: about a third of critical
if "lammps" in sys.argv[3:]:
    from sphsolid.lammps import Lammps
    scene.calc = Lammps()
probes = Probes(scene, {"A": (0, 0.070), "B": (0.0215, 0.1035), "C": (0.0215, 0.070)})
dyn = ImprovedEuler(scene)
traj = Trajectory("pressure_piston.h5", "w", scene, probe_interval=20)
dyn.attach(probes, interval=20)
dyn.attach(traj, interval=max(1, round(until / 2 / dyn.dt)))
dyn.run(until=until)
traj.write()                                                      # the final state
traj.close()
mean_syy = scene.stress[scene.body_slice("specimen"), 1].mean()
print(f"mean sigma_yy of the specimen: {mean_syy:.6g} Pa (applied: {-pressure:g} Pa)")
figures.probe_curves(probes.times, {n: probes[n]["sigma_yy"] for n in "ABC"},
                     "pressure_piston_probes.png", quantity="sigma_yy")
with Trajectory("pressure_piston.h5") as t:
    figures.von_mises_map(t[-1], "pressure_piston_von_mises.png", mask=lambda f: f.body_ids == 0)
