"""What goes to and comes from files: trajectories (HDF5 in libsphsolid's
layout, with the XDMF companion for ParaView, :mod:`.trajectory`), scenes
described by a TOML file (:mod:`.scenefile`, ``sphsolid run``),
checkpoints of command-line and scene-file runs (:mod:`.checkpoint`) and
the paper's figures (:mod:`.figures`).

Nothing here computes physics: writing goes through the library, reading
uses h5py.  The submodules are imported when used (h5py and matplotlib
load only then); their old paths (``sphsolid.trajectory``, ...) still
import (:mod:`sphsolid._moved`)."""
