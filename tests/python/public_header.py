"""The text of the library's public header as a user's compiler reads it:
sphsolid.h and the parts it includes (libsphsolid/include/sphsolid/*.h),
in its include order."""
import re
from pathlib import Path

INCLUDE = Path(__file__).resolve().parents[2] / "libsphsolid" / "include"


def public_header_text() -> str:
    top = (INCLUDE / "sphsolid.h").read_text()
    parts = re.findall(r'#include "(sphsolid/\w+\.h)"', top)
    return "\n".join([top] + [(INCLUDE / p).read_text() for p in parts])
