"""Shared fixtures. The tests use the installed ``sphsolid`` package; in a
source tree without an install they fall back to ``python/`` (the library
is then found through SPHSOLID_LIBRARY or build/libsphsolid/)."""
import sys
from pathlib import Path

import pytest

try:
    import sphsolid  # noqa: F401
except ImportError:
    sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "python"))
    import sphsolid  # noqa: F401

# The validation study (top-level validation/) is imported from the checkout.
sys.path.insert(0, str(Path(__file__).resolve().parents[2]))


@pytest.fixture
def rock():
    return sphsolid.scenes.paper_material()


@pytest.fixture
def coarse_piston():
    """The paper's piston scene at dx = 4 mm (a quick, coarse lattice)."""
    return sphsolid.scenes.uniaxial_piston(dx=4e-3)
