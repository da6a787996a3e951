"""A small scene file shared by the tests of scene files and the
command line: a square block of the paper's rock, optionally on a plate
under a piston, with one probe at its centre."""

def platens_toml(top: str = "top", velocity: str = "-1m/s") -> str:
    """A fixed plate under the block and a piston ``top`` over it moving
    at ``velocity`` along y (negative: squeezing)."""
    return f"""
[[bodies]]
name = "base"
shape = "plate"
under = "block"
[[bodies]]
name = "{top}"
shape = "piston"
over = "block"
motion = {{ velocity = [0, "{velocity}"] }}
"""


PLATENS = platens_toml()


def block_toml(half_mm: float, dx: str, until: str = "2us", platens=False,
               top: str = "", tail: str = "", probe_interval=None) -> str:
    """The block [-half, half] x [0, 2 half] mm at spacing ``dx``; ``top``
    goes before the tables, ``tail`` after them."""
    output = ("" if probe_interval is None
              else f"probe_interval = {probe_interval}\n")
    return f"""{top}
dimension = 2
until = "{until}"
[materials.rock]
K = "12.2GPa"
mu = "2.67GPa"
rho0 = 2300
[[bodies]]
name = "block"
shape = "rectangle"
x = ["-{half_mm:g}mm", "{half_mm:g}mm"]
y = ["0mm", "{2 * half_mm:g}mm"]
dx = "{dx}"
material = "rock"
{PLATENS if platens else ""}
[probes]
centre = [0, "{half_mm:g}mm"]
[output]
{output}figures = false
{tail}"""
