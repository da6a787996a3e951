"""python -m validation paper [--out DIR] [--quick]: the validation study."""
import sys

from sphsolid.cli import main

sys.exit(main(["study", *sys.argv[1:]]))
