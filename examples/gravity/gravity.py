"""The specimen settling under gravity on the plate (python3 gravity.py [dx_m] [until_s])."""
import sys
from sphsolid import ImprovedEuler, Material, Probes, Scene, Trajectory, figures
from sphsolid.build import plate, rectangle

dx = float(sys.argv[1]) if len(sys.argv) > 1 else 2e-3      # m
until = float(sys.argv[2]) if len(sys.argv) > 2 else 20e-3   # s
rock = Material(K=12.2e9, mu=2.67e9, rho0=2300)                  # Pa, Pa, kg/m^3
specimen = rectangle(x=(-0.043, 0.043), y=(0, 0.140), dx=dx, material=rock)
scene = Scene(2, [specimen, plate(under=specimen, layers=3)],
              effects={"gravity": {"gy": -9.81},                  # m/s^2
                       "artificial_viscosity": {"alpha": 1.0, "beta": 0.0},
                       "damping": {"rate": 2000.0}})              # 1/s: settle fast
probes = Probes(scene, {"A": (0, 0.070), "B": (0.0215, 0.1035), "C": (0.0215, 0.070)})
dyn = ImprovedEuler(scene)
traj = Trajectory("gravity.h5", "w", scene, probe_interval=50)
dyn.attach(probes, interval=50)
dyn.attach(traj, interval=max(1, round(until / 2 / dyn.dt)))
dyn.run(until=until)
traj.write()                                                      # the final state
traj.close()
figures.probe_curves(probes.times, {n: probes[n]["von_mises"] for n in "ABC"}, "gravity_probes.png")
with Trajectory("gravity.h5") as t:
    figures.von_mises_map(t[-1], "gravity_von_mises.png", mask=lambda f: f.body_ids == 0)
