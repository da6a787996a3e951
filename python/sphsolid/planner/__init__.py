"""The planner: ask for an error, get the settings, the time and the
evidence.

:func:`plan` takes a scene factory ``scene_factory(dx, smoothing_ratio=...,
kernel=...)`` that builds the user's scene (bodies, materials, loads) at a
particle spacing ``dx``, and a request (an error on probe time series over
``[0, until]``), and returns a :class:`Plan`: the cheapest settings (dx,
h/dx, kernel, integrator, effects) predicted to meet the request, the
predicted error with its uncertainty, the predicted wall time and the runs
it is based on, or an honest refusal naming the best reachable error.

How (orchestration only; every run is the C library's):

1. **Options** are asked from the library at run time: kernels
   (:func:`kernel_names`), integrators (:func:`integrator_names`) and
   effects (:func:`sphsolid.effect_names`); a missing option is left out.
2. **Effects the scene calls for** (:func:`detect_effects`): one run at
   the coarsest spacing with no optional effect, for as many steps as the
   finest run the plan may choose (so a growth that only shows after many
   steps is seen), per integrator. Sustained tension -> artificial stress;
   large rotation -> kernel correction; a constant load on a body at rest
   that keeps ringing -> damping; a blow-up or rough probe series ->
   artificial viscosity; near-incompressible material is reported (the
   hard-case suite needs nothing extra for it). Each finding carries its
   reason and its measured cost per step.
3. **Calibration ladder**: every candidate setting at the spacings of
   ``ladder`` (coarse; 3 or more), to ``until`` (or a shorter
   ``calibration_until`` when the user knows that is sound).
4. **Error model** per setting (:class:`ErrorModel`): the probe series are
   smoothed (Gaussian, 1 µs) and put on one grid; the norms of the
   differences between consecutive levels are fitted by least squares to
   ``C (dx_i^q - dx_{i+1}^q)`` over every level (Eça & Hoekstra's
   least-squares order, written on differences: no extrapolated limit
   series, which for a sharpening front is itself 10-16 % off the exact
   one on the strip), giving ``E(dx) = C dx^q``. Predictions carry the
   safety factor of Eça & Hoekstra (1.25 for an order in [0.5, 2.1] with
   a good fit, 3 otherwise), because the request must be met, not just
   met on average. Self-convergence cannot see a bias that does not go
   away with dx (the lattice moment at fixed h/dx, a dissipation floor):
   where two settings differ by an amount that does not shrink with
   refinement, or by more than their own predicted errors explain, the
   difference is a **floor** added to the prediction
   (:func:`consistency_floors`).
5. **Cost model** per setting (:class:`CostModel`): process CPU seconds
   per step against particles, fitted on the ladder's own runs at the
   requested thread count (CPU time, because wall time on a loaded
   machine is mostly the load), with the wall/CPU ratio of the same runs
   for the wall-time prediction; a spacing finer than the ladder's is
   checked by timing steps there and at the finest calibrated spacing
   (cache effects make large scenes dearer per particle; within the
   ladder's sizes its whole runs are the better measurement). Settings
   are ranked by predicted CPU seconds.
6. The cheapest setting whose predicted upper error is within the request
   and whose predicted time is within ``max_seconds`` is returned.

The planner never extrapolates more than ``max_refinement`` (default 2)
times below the finest calibrated spacing: it calibrates finer levels for
the most promising settings, and for those whose ladder determines no
order (within ``calibration_seconds``), or says so.

The package is laid out along those jobs: :mod:`.settings` (options and
the setting), :mod:`.calibration` (building and running a setting's
scene), :mod:`.error_model`, :mod:`.cost_model`, :mod:`.detection`
(effects the scene calls for), :mod:`.search` (:func:`plan` itself),
:mod:`.record` (the verification record of every setting on the reference
scenes), :mod:`.cache` (calibration runs kept on disk between plans),
:mod:`.scenes` (the project's reference scenes),
:mod:`.deck` (LAMMPS decks) and :mod:`.estimate` (the per-run error
estimate). ``sphsolid.plan(...)`` calls :func:`plan`; ``sphsolid.plan.X``
reaches the names below.
"""
from .calibration import (LadderRun, build_scene, factory_options,
                          ladder_run, make_dynamics, run_scene)
from .._lib import SimulationError, UnsupportedError
from .cost_model import (REFERENCE_REPEAT_SECONDS, TIMING_SECONDS, CostModel,
                         reference_cost, time_steps)
from .detection import Finding, detect_effects
from .error_model import (FORMAL_ORDER, ErrorModel, consistency_floors,
                          fit_error_model, fit_order, repeating_factor)
from .scenes import (GRAVITY_SECTIONS, STRIP_HEIGHT, STRIP_PROBES,
                     STRIP_WIDTH_DX, PlanScene,
                     gravity_factory, gravity_sections, piston_factory,
                     project_scenes, strip_factory)
from .search import (Candidate, Plan, default_candidates,
                     detection_families, plan)
from .settings import (DEFAULT_INTEGRATOR, MANAGED_EFFECTS, OWN_SETTING,
                       SAFETY_GOOD, SAFETY_POOR, SMOOTHING_RATIOS, STANDARD,
                       Setting, integrator_names, kernel_names)

__all__ = ["plan", "Plan", "Setting", "ErrorModel", "CostModel", "Finding",
           "LadderRun", "Candidate", "fit_error_model", "fit_order",
           "repeating_factor", "consistency_floors", "kernel_names",
           "integrator_names", "detect_effects", "build_scene",
           "make_dynamics", "run_scene", "ladder_run", "factory_options",
           "reference_cost", "time_steps", "default_candidates",
           "detection_families", "project_scenes", "PlanScene",
           "piston_factory", "gravity_factory", "strip_factory",
           "gravity_sections", "STRIP_PROBES", "STRIP_HEIGHT", "STRIP_WIDTH_DX",
           "GRAVITY_SECTIONS",
           "DEFAULT_INTEGRATOR", "MANAGED_EFFECTS", "OWN_SETTING",
           "SAFETY_GOOD", "SAFETY_POOR", "SMOOTHING_RATIOS", "STANDARD",
           "FORMAL_ORDER", "REFERENCE_REPEAT_SECONDS", "TIMING_SECONDS",
           "SimulationError", "UnsupportedError", "deck", "estimate"]

from . import deck, estimate  # noqa: E402  (submodules, after the names)
