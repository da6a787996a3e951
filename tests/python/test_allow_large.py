"""Scene(allow_large=...) reaches the library's memory limit
(sph_set_allow_large): half of the available memory by default, all of
it when allowed (the limits themselves: tests/c/test_bad_input.c)."""
from __future__ import annotations

import pytest

import sphsolid
from sphsolid._lib import lib
from sphsolid.cli import main

from scene_texts import block_toml


def test_allow_large_is_set_on_the_handle():
    assert lib.sph_allow_large(sphsolid.Scene(2)._handle) == 0
    assert lib.sph_allow_large(sphsolid.Scene(3, allow_large=True)._handle) == 1


def test_allowing_large_sets_the_default_of_every_scene_inside():
    with sphsolid.allowing_large():
        assert lib.sph_allow_large(sphsolid.scenes.uniaxial_piston(8e-3).handle) == 1
        # a scene's own value wins
        assert lib.sph_allow_large(sphsolid.Scene(2, allow_large=False)._handle) == 0
    assert lib.sph_allow_large(sphsolid.scenes.uniaxial_piston(8e-3).handle) == 0


class _Built(Exception):
    """Stops a command once its scene is built, carrying allow_large."""


@pytest.fixture
def built_scenes(monkeypatch):
    """sph_allow_large of every Scene the command builds."""
    seen = []
    original = sphsolid.Scene.__init__

    def recording(self, *args, **kwargs):
        original(self, *args, **kwargs)
        seen.append(lib.sph_allow_large(self._handle))

    monkeypatch.setattr(sphsolid.Scene, "__init__", recording)
    return seen


@pytest.mark.parametrize("words", [
    ["piston", "--dx", "8mm"], ["piston", "--dim", "3", "--dx", "9mm"],
    ["gravity", "--dx", "8mm"], ["ucs", "--dx", "8mm"],
    ["brazilian", "--dx", "5mm"], ["run", "SCENE", "--until", "1us"]])
def test_allow_large_on_the_command_line(words, built_scenes, monkeypatch, tmp_path):
    from sphsolid import fracture
    from sphsolid.cli import scene_run

    def stop(*args, **kwargs):
        raise _Built()

    monkeypatch.setattr(scene_run, "run_scene", stop)
    monkeypatch.setattr(fracture, "load_to_break", stop)
    monkeypatch.setattr("sphsolid.calculators.CLibrary.__init__", stop)
    scene = tmp_path / "block.toml"
    scene.write_text(block_toml(3, "1mm"))
    words = [str(scene) if w == "SCENE" else w for w in words]
    for flag in ([], ["--allow-large"]):
        built_scenes.clear()
        try:
            main(words + ["--out", str(tmp_path / "out"), "--threads", "1"] + flag)
        except _Built:
            pass
        assert built_scenes and set(built_scenes) == {1 if flag else 0}, (words, flag)


def test_a_refused_large_scene_names_the_option(monkeypatch, capsys):
    from sphsolid import scenes

    def refused(*args, **kwargs):
        raise MemoryError("body 'specimen': 1e+09 particles need about 2 TB ... a run this "
                          "large is refused unless allowed (sph_set_allow_large), or use a "
                          "coarser spacing")

    monkeypatch.setattr(scenes, "uniaxial_piston", refused)
    assert main(["piston", "--dx", "8mm"]) == 2
    assert "(on this command: --allow-large)" in capsys.readouterr().err
