"""``sphsolid study paper|front``: the validation study of
docs/validation.md (figures, tables, results.json) and the accuracy front
of the options.  Both live in the checkout's top-level ``validation/``
package, not in the installed one: it is imported from the current
directory or its nearest parent that holds it."""
from __future__ import annotations

import argparse
import importlib
import importlib.util
import sys
from pathlib import Path

help = "validation study (docs/validation.md): figures, tables, results.json"


def add_arguments(parser) -> None:
    which = parser.add_subparsers(dest="study", required=True,
                                  metavar="{paper,front}")
    paper = which.add_parser("paper", help="the whole study")
    paper.add_argument("--out", type=Path, default=Path("docs/validation"))
    paper.add_argument("--quick", action="store_true",
                       help="coarser and shorter: a few minutes")
    # front's own options follow it; '+' as its prefix leaves every '-'
    # word to validation.front (its --help included)
    front = which.add_parser(
        "front", prefix_chars="+", add_help=False,
        help="the accuracy front of the options (python -m "
        "validation.front; its own arguments follow, --help lists them)")
    front.add_argument("arguments", nargs=argparse.REMAINDER)


def run(args) -> int:
    if args.study == "front":
        return validation_module("front").main(args.arguments) or 0
    validation_module("study").run_paper(
        args.out, quick=args.quick, log=lambda m: print(m, flush=True))
    return 0


def validation_module(name: str):
    """``validation.<name>``: importable as it is, or the ``validation``
    package of the current directory or a parent."""
    try:
        return importlib.import_module(f"validation.{name}")
    except ModuleNotFoundError as error:
        if error.name not in ("validation", f"validation.{name}"):
            raise
    for root in (Path.cwd(), *Path.cwd().parents):
        init = root / "validation" / "__init__.py"
        if (root / "validation" / f"{name}.py").is_file() and init.is_file():
            spec = importlib.util.spec_from_file_location(
                "validation", init,
                submodule_search_locations=[str(init.parent)])
            package = importlib.util.module_from_spec(spec)
            sys.modules["validation"] = package
            spec.loader.exec_module(package)
            return importlib.import_module(f"validation.{name}")
    raise SystemExit("sphsolid study: run it from a checkout of libsphsolid "
                     "(the study lives in its top-level validation/ folder)")
