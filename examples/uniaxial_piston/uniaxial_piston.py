"""The paper's uniaxial piston test, scripted ASE-style (python3 uniaxial_piston.py [dx_m] [until_s])."""
import sys
from sphsolid import ImprovedEuler, Material, Probes, Scene, Trajectory, figures
from sphsolid.build import piston, plate, rectangle

dx = float(sys.argv[1]) if len(sys.argv) > 1 else 1e-3      # m
until = float(sys.argv[2]) if len(sys.argv) > 2 else 1e-3   # s
rock = Material(K=12.2e9, mu=2.67e9, rho0=2300)                  # Pa, Pa, kg/m^3
specimen = rectangle(x=(-0.043, 0.043), y=(0, 0.140), dx=dx, material=rock)
scene = Scene(2, [specimen, plate(under=specimen, layers=3),      # fixed plate
                  piston(over=specimen, layers=3, velocity=(0, -1.5e-3))],
              effects={"artificial_viscosity": {"alpha": 1.0, "beta": 0.0}})
probes = Probes(scene, {"A": (0, 0.070), "B": (0.0215, 0.1035), "C": (0.0215, 0.070)})
dyn = ImprovedEuler(scene)                                        # dt = 0.5 h / c0
traj = Trajectory("uniaxial_piston.h5", "w", scene, probe_interval=10)
dyn.attach(probes, interval=10)
dyn.attach(traj, interval=max(1, round(until / 4 / dyn.dt)))
dyn.run(until=until)
traj.write()                                                      # the final state
traj.close()
figures.probe_curves(probes.times, {n: probes[n]["von_mises"] for n in "ABC"}, "uniaxial_piston_probes.png")
with Trajectory("uniaxial_piston.h5") as t:
    figures.von_mises_map(t[1:], "uniaxial_piston_von_mises.png", mask=lambda f: f.body_ids == 0)
