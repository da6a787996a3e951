"""Specimens loaded until they break, and the strength they give:

- :mod:`.specimens`: the compression test, the Brazilian disc and the
  tensile bar with the library's ``damage`` effect, the rock with Weibull
  flaws (:func:`fracture_material`) and :func:`load_to_break`, which loads
  one of them until it breaks (docs/fracture.md);
- :mod:`.ensemble`: many flaw draws of one test, a strength with error bars
  (``sphsolid.ensemble``, docs/ensembles.md);
- :mod:`.strength`: dx and the number of draws chosen together for a
  requested error on the strength (``sphsolid plan ucs --quantity
  strength``), imported when used.

The names of :mod:`.specimens` are this package's (``sphsolid.fracture.ucs``
as before the package existed); ``sphsolid.ensemble`` and
``sphsolid.planner.strength`` still import (:mod:`sphsolid._moved`)."""
from .specimens import *  # noqa: F401,F403
from .specimens import OPTIONAL_EFFECTS, __all__  # noqa: F401
from . import ensemble  # noqa: E402,F401
