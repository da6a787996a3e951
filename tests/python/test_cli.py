"""The shape of the ``sphsolid`` command: one module per command, the
parser built from them, the integrators' step rule and the presets read
from their registries."""
import argparse
import re
import sys

import pytest

from sphsolid import cli
from sphsolid._lib import integrator_registry
from sphsolid.presets import PRESETS


def _subparsers(parser):
    return next(a for a in parser._actions
                if isinstance(a, argparse._SubParsersAction))


def test_every_command_is_a_module_with_add_arguments_and_run():
    names = [cli.command_name(m) for m in cli.COMMANDS]
    assert len(set(names)) == len(names)
    for module in cli.COMMANDS:
        assert callable(module.add_arguments) and callable(module.run)
        assert isinstance(module.help, str) and module.help
    # the parser has those commands and no other
    choices = _subparsers(cli.build_parser()).choices
    assert sorted(choices) == sorted(names)


@pytest.mark.parametrize("argv", [
    ["piston", "--dx", "4mm"], ["gravity"], ["run", "scene.toml"],
    ["info", "f.h5"], ["xdmf", "f.h5"], ["build-plugin"],
    ["study", "paper", "--quick"], ["study", "front", "--dx", "0.002"],
    ["plan", "piston", "--error", "3%"], ["ucs", "--dx", "4mm"],
    ["brazilian", "--seed", "3"]])
def test_the_namespace_holds_only_the_options(argv):
    args = cli.build_parser().parse_args(argv)
    assert args.run is dict(
        (cli.command_name(m), m) for m in cli.COMMANDS)[argv[0]].run
    assert not [k for k in vars(args) if k.startswith("_")], vars(args)


@pytest.mark.parametrize("command", [None] + [
    cli.command_name(m) for m in cli.COMMANDS])
def test_every_help_prints(command, capsys):
    # argparse %-formats each help text: a bare % (a default of 0.8 %, a
    # 95 % interval) made --help itself fail
    argv = ([] if command is None else [command]) + ["--help"]
    with pytest.raises(SystemExit) as stop:
        cli.build_parser().parse_args(argv)
    assert stop.value.code == 0
    out = capsys.readouterr().out
    assert out.startswith("usage: sphsolid")
    assert "%%" not in out


def test_study_front_forwards_its_arguments():
    args = cli.build_parser().parse_args(
        ["study", "front", "--dx", "0.002", "0.001", "--no-doc"])
    assert args.arguments == ["--dx", "0.002", "0.001", "--no-doc"]


def test_negative_values_reach_the_option_check(capsys):
    with pytest.raises(SystemExit):
        cli.build_parser().parse_args(["piston", "--until", "-1ms"])
    assert "--until: '-1ms': must be finite and > 0" in capsys.readouterr().err


def test_dt_help_gives_every_integrators_default_step_from_the_registry():
    text = " ".join(_subparsers(cli.build_parser()).choices["piston"]
                    .format_help().split())
    registry = integrator_registry()
    assert {"improved_euler", "leapfrog"} <= set(registry)
    for name, info in registry.items():
        assert f"{info['default_factor']:g} h/c0 for {name}" in text


@pytest.mark.parametrize("command", ["piston", "gravity"])
def test_preset_help_lists_every_preset(command):
    text = " ".join(_subparsers(cli.build_parser()).choices[command]
                    .format_help().split())
    help_of_preset = text[text.index("--preset {"):]
    for name, chosen in PRESETS.items():
        assert re.search(rf"\b{name}: {chosen.integrator}\b",
                         help_of_preset), name


def test_study_imports_the_checkout_validation_without_sys_path(
        monkeypatch, tmp_path):
    from sphsolid.cli import study
    root = tmp_path / "checkout"
    (root / "validation").mkdir(parents=True)
    (root / "validation" / "__init__.py").write_text("")
    (root / "validation" / "probe_me.py").write_text("VALUE = 42\n")
    (root / "deep").mkdir()
    monkeypatch.chdir(root / "deep")
    for key in [k for k in sys.modules if k.split(".")[0] == "validation"]:
        monkeypatch.delitem(sys.modules, key)
    path = list(sys.path)
    try:
        assert study.validation_module("probe_me").VALUE == 42
    finally:
        for key in [k for k in sys.modules if k.split(".")[0] == "validation"]:
            del sys.modules[key]
    assert sys.path == path


@pytest.mark.parametrize("argv, key, value", [
    (["piston", "--speed", "1.5mm/s"], "speed", 1.5e-3),
    (["piston", "--dx", "2mm", "--until", "0.1ms", "--dt", "0.2us"], "dt",
     2e-7),
    (["piston", "--times", "0.1ms,200us"], "times", [1e-4, 2e-4]),
    (["gravity", "--g", "9.81m/s2"], "g", 9.81),
    (["gravity", "--damping", "2000Hz"], "damping", 2000.0),
    (["run", "s.toml", "--checkpoint-every", "50us"], "checkpoint_every",
     5e-5),
    (["plan", "piston", "--error", "3%", "--ladder", "4mm,3mm",
      "--max-seconds", "90s"], "max_seconds", 90.0),
    (["plan", "piston", "--error", "3%", "--ladder", "4mm,3mm"], "ladder",
     [4e-3, 3e-3]),
])
def test_options_take_units(argv, key, value):
    args = cli.build_parser().parse_args(argv)
    assert getattr(args, key) == pytest.approx(value, rel=1e-15)


def test_an_option_unit_of_the_wrong_kind_is_named(capsys):
    with pytest.raises(SystemExit):
        cli.build_parser().parse_args(["piston", "--speed", "1.5mm"])
    assert "'1.5mm' is a length" in capsys.readouterr().err


def test_build_plugin_names_a_build_type_it_does_not_know(tmp_path):
    from sphsolid.plugin import build_plugin
    with pytest.raises(ValueError, match="'Fast'.*Release, RelWithDebInfo, Debug"):
        build_plugin(build_dir=tmp_path, build_type="Fast", log=lambda m: None)
    args = cli.build_parser().parse_args(["build-plugin", "--build-type", "Debug"])
    assert args.build_type == "Debug"
    with pytest.raises(SystemExit):
        cli.build_parser().parse_args(["build-plugin", "--build-type", "Fast"])
