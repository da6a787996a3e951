"""Outputs that prove they are whole: every dataset the library writes
carries HDF5's Fletcher32 checksum, and ``sphsolid info`` (``--verify``,
its default) and ``sphsolid xdmf`` read every dataset back, failing with
the dataset named when a byte of it changed.

The file is a pulled block with the damage effect and a probe (every
series the library writes, fragment and damage included); 4 KiB of it
are overwritten at places and the commands run on the copy."""
from __future__ import annotations

import shutil

import h5py
import numpy as np
import pytest

from sphsolid.cli import main
from sphsolid.trajectory import verify

from scene_texts import block_toml, platens_toml

PULLED = platens_toml("puller", "20m/s")


@pytest.fixture(scope="module")
def output(tmp_path_factory):
    out = tmp_path_factory.mktemp("verify")
    text = block_toml(6, "2mm", until="20us", probe_interval=5).replace(
        "rho0 = 2300\n", "rho0 = 2300\nweibull_k = 1e28\nweibull_m = 9\n",
        1).replace("[probes]", PULLED + "[probes]", 1)
    text = text.replace("figures = false", "figures = false\n"
                        'snapshot_every = "2us"')
    text += "[effects]\ndamage = { seed = 1 }\n"
    (out / "pull.toml").write_text(text)
    assert main(["run", str(out / "pull.toml"), "--out", str(out),
                 "--no-progress"]) == 0
    return out / "pull.h5"


def _datasets(path) -> dict:
    found = {}
    with h5py.File(path, "r") as f:
        f.visititems(lambda name, obj: found.__setitem__(name, obj[()])
                     if isinstance(obj, h5py.Dataset) else None)
    return found


def _flip(source, target, start, size=4096) -> None:
    """A copy of source with `size` bytes from `start` replaced by random
    ones (seeded by the offset).  Not inverted: Fletcher32 sums in ones'
    complement, so a chunk inverted whole with its checksum passes."""
    shutil.copy(source, target)
    rng = np.random.Generator(np.random.PCG64(start))
    with open(target, "r+b") as f:
        f.seek(start)
        length = len(f.read(size))
        f.seek(start)
        f.write(rng.integers(0, 256, length, dtype=np.uint8).tobytes())


def test_every_dataset_is_chunked_with_the_checksum(output):
    with h5py.File(output, "r") as f:
        names = []
        f.visititems(lambda name, obj: names.append(name)
                     if isinstance(obj, h5py.Dataset) else None)
        assert "particles/all/fragment/value" in names
        assert "observables/probes/value" in names
        for name in names:
            d = f[name]
            if d.size:
                assert d.fletcher32 and d.chunks is not None, name
    checked = verify(output)
    assert checked["datasets"] == len(names)
    assert checked["unchecked"] == []


def test_info_verifies_a_whole_file_by_default(output, capsys):
    assert main(["info", str(output)]) == 0
    out = capsys.readouterr().out
    n = len(_datasets(output))
    assert f"verified: {n} datasets" in out and "each checksum holds" in out
    assert main(["info", "--no-verify", str(output)]) == 0
    assert "verified" not in capsys.readouterr().out


def _chunk_at(path, where: str) -> tuple[str, int]:
    """The dataset and file offset of the chunk nearest the middle of the
    file ('middle') or the last chunk in it ('end')."""
    size = output_size = path.stat().st_size
    chunks = []
    with h5py.File(path, "r") as f:
        def visit(name, obj):
            if isinstance(obj, h5py.Dataset) and obj.chunks and obj.size:
                for k in range(obj.id.get_num_chunks()):
                    info = obj.id.get_chunk_info(k)
                    chunks.append((info.byte_offset, info.size, name))
        f.visititems(visit)
    if where == "middle":
        offset, _, name = min(chunks, key=lambda c: abs(c[0] - size / 2))
    else:
        offset, _, name = max(chunks)
    assert offset < output_size
    return name, offset


@pytest.mark.parametrize("where", ["middle", "end"])
def test_a_corrupted_dataset_fails_info_and_xdmf_naming_it(output, where,
                                                           tmp_path, capsys):
    """4 KiB overwritten from a chunk in the middle of the file, or from its
    last chunk (a fragment or damage series, written last): the copy
    reads differently, and info and xdmf fail naming the dataset and its
    checksum; xdmf writes no companion."""
    name, offset = _chunk_at(output, where)
    damaged = tmp_path / "damaged.h5"
    _flip(output, damaged, offset)
    assert main(["info", str(damaged)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1, err
    assert f"damaged.h5: damaged: dataset /{name} (fails its Fletcher32 " \
        "checksum" in err, err
    assert main(["xdmf", str(damaged)]) == 2
    assert f"dataset /{name}" in capsys.readouterr().err
    assert not damaged.with_suffix(".xmf").exists()
    assert main(["info", "--no-verify", str(damaged)]) == 0
    capsys.readouterr()


def test_no_flipped_page_goes_unnoticed(output, tmp_path, capsys):
    """Every 4 KiB page of the file overwritten in turn: info fails (with
    status 2, one line, naming the file), or every dataset reads back
    exactly as it was written; never different values with status 0."""
    original = _datasets(output)
    size = output.stat().st_size
    damaged = tmp_path / "page.h5"
    failed = 0
    for start in range(0, size, 4096):
        _flip(output, damaged, start)
        code = main(["info", str(damaged)])
        err = capsys.readouterr().err
        if code != 0:
            assert code == 2 and err.count("\n") == 1, (start, err)
            assert "page.h5" in err, (start, err)
            failed += 1
            continue
        now = _datasets(damaged)
        assert now.keys() == original.keys(), start
        for key, value in original.items():
            assert np.array_equal(now[key], value), (start, key)
    assert failed > 0.9 * (size // 4096), (failed, size)


def test_format_1_files_still_read_and_say_they_carry_no_checksum(capsys):
    """tests/data/format1_output.h5 (libsphsolid 0.1.0, before checksums):
    info reads it and says its datasets carry none."""
    from pathlib import Path
    old = Path(__file__).resolve().parents[1] / "data" / "format1_output.h5"
    assert main(["info", str(old)]) == 0
    out = capsys.readouterr().out
    assert "0 carry a checksum and hold it, 26 carry none" in out
