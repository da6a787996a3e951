"""Ensembles of flaw draws: a strength with error bars (docs/ensembles.md).

One run of a fracture test is one draw of its flaws, so its strength is a
sample.  :func:`ensemble` runs ``members`` draws of one test (member i's
flaws come from hash(seed, i), the ``damage`` effect's ``member``
parameter), in parallel processes, and summarises a quantity: mean,
standard deviation and a bootstrap 95 % interval of the mean.

Layout of the output directory::

    DIR/ensemble.json             what the ensemble is (test, dx, seed, ...)
    DIR/member_0000/load.csv      the member's load history
    DIR/member_0000/summary.json  its results, written last (tmp + rename)
    ...
    DIR/summary.json              quantity, members, mean, std, ci95_low,
                                  ci95_high, values (per member), ...
    DIR/histogram.png             the quantity's histogram

A member whose ``summary.json`` exists and proves itself whole is
finished: a rerun into the same directory keeps it and runs the others (a
killed ensemble continues where it stopped).  Each member's summary
carries its own ``checksum`` (SHA-256 of the rest of the summary, which
holds the SHA-256 of its load.csv, ``load_csv_sha256``): a summary that is
not a JSON object, is truncated, was edited by hand, belongs to another
member or ensemble, or whose load.csv changed is run again, the file and
the reason named (:func:`check_member`).  Each member runs on one thread, so it is bitwise the same
run whether it ran alone, in the pool or after a resume.
"""
from __future__ import annotations

import json
import math
import os
import time
from concurrent.futures import ProcessPoolExecutor, as_completed
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from .. import _lib
from .specimens import TESTS, test_scene

__all__ = ["ensemble", "run_member", "bootstrap_mean_interval", "summarise",
           "histogram", "QUANTITIES", "Ensemble", "check_member",
           "member_checksum", "cost"]
#: Quantities of a member's summary an ensemble summarises, and their unit.
#: strength_Pa is the UCS, the Brazilian disc's 2P/(pi D t) or the tensile
#: bar's strength, by test.
QUANTITIES = {"strength": ("strength_Pa", "Pa"),
              "strain_at_peak": ("strain_at_peak", "1"),
              "fragments": ("fragments", "1"),
              "onset_stress": ("damage_onset_stress_Pa", "Pa"),
              "peak_load": ("peak_load_N", "N/m")}
#: Seed of the bootstrap's random numbers (the interval is reproducible).
BOOTSTRAP_SEED = 20240530
#: Bootstrap resamples of the mean.
BOOTSTRAP_RESAMPLES = 10000


def _member_dir(out: Path, member: int) -> Path:
    return out / f"member_{member:04d}"


def _sha256(data: bytes) -> str:
    import hashlib
    return hashlib.sha256(data).hexdigest()


def member_checksum(summary: dict) -> str:
    """SHA-256 of a member's summary without its ``checksum`` key, over
    its JSON with sorted keys (what :func:`run_member` stores)."""
    rest = {k: v for k, v in summary.items() if k != "checksum"}
    return _sha256(json.dumps(rest, sort_keys=True,
                              separators=(",", ":")).encode())


def check_member(path, config: dict, member: int) -> tuple[dict | None, str]:
    """A member's summary.json read back and proved whole: (summary, "")
    when it is a JSON object whose checksum holds, of this member of this
    ensemble, with its load.csv as it was written; else (None, the
    reason), naming the file."""
    path = Path(path)
    try:
        data = path.read_bytes()
    except OSError as error:
        return None, f"{path}: cannot be read ({error.strerror or error})"
    try:
        summary = json.loads(data.decode("utf-8"))
    except (UnicodeDecodeError, ValueError) as error:
        return None, (f"{path}: not a complete JSON file ({error}; "
                      "truncated?)")
    if not isinstance(summary, dict):
        return None, (f"{path}: holds a JSON {type(summary).__name__}, not "
                      "a member's summary (an object)")
    if "checksum" not in summary:
        return None, f"{path}: has no checksum (an earlier version's?)"
    if summary["checksum"] != member_checksum(summary):
        return None, (f"{path}: fails its checksum (edited after it was "
                      "written?)")
    expected = {"test": config["test"], "dx_m": config["dx_m"],
                "seed": config["seed"], "member": member}
    for key, value in expected.items():
        if summary.get(key) != value:
            return None, (f"{path}: is of {key}={summary.get(key)!r}, this "
                          f"ensemble's member has {key}={value!r}")
    load = path.with_name("load.csv")
    try:
        digest = _sha256(load.read_bytes())
    except OSError:
        return None, f"{path}: its {load.name} is missing"
    if summary.get("load_csv_sha256") != digest:
        return None, f"{path}: its {load.name} fails the summary's checksum"
    return summary, ""


def _write_atomic(path: Path, text: str) -> None:
    tmp = path.with_name(path.name + ".tmp")
    tmp.write_text(text)
    os.replace(tmp, path)


def run_member(config: dict, member: int, out: Path | None = None) -> dict:
    """Runs member ``member`` of the ensemble ``config`` (the contents of
    ensemble.json) on one thread; with ``out``, writes its load history
    and, last and atomically, its summary.json into out/member_XXXX.
    Returns the member's summary (with the SHA-256 of its load.csv and its
    own ``checksum``, :func:`member_checksum`)."""
    from . import specimens as fracture
    from ..calculators import CLibrary
    scene = test_scene(config["test"], config["dx_m"], config["seed"],
                       member, **config.get("scene_options", {}))
    scene.calc = CLibrary(threads=1)
    start, cpu = time.perf_counter(), time.process_time()
    run = fracture.load_to_break(
        scene, max_strain=config["max_strain"], drop=config["drop"],
        samples_per_strain=config["samples_per_strain"])
    wall = time.perf_counter() - start
    cpu = time.process_time() - cpu
    summary = run.summary()
    summary.update(test=config["test"], dx_m=config["dx_m"],
                   seed=config["seed"], member=member,
                   steps=int(scene.step), wall_s=wall, cpu_s=cpu,
                   particles=int(sum(scene.body_counts().values())),
                   effects=scene.effects)
    lines = ["time_s,strain,load_N_per_m"]
    lines += [f"{float(t)!r},{float(e)!r},{float(f)!r}"
              for t, e, f in zip(run.time, run.strain, run.load)]
    text = "\n".join(lines) + "\n"
    summary["load_csv_sha256"] = _sha256(text.encode())
    summary["checksum"] = member_checksum(summary)
    if out is not None:
        where = _member_dir(Path(out), member)
        where.mkdir(parents=True, exist_ok=True)
        _write_atomic(where / "load.csv", text)
        _write_atomic(where / "summary.json", json.dumps(summary, indent=2))
    return summary


def _run_member_job(config: dict, member: int, out: str) -> dict:
    return run_member(config, member, Path(out))


def bootstrap_mean_interval(values, confidence: float = 0.95,
                            resamples: int = BOOTSTRAP_RESAMPLES,
                            seed: int = BOOTSTRAP_SEED):
    """The bootstrap-t (studentized bootstrap) interval of the mean of
    ``values`` at ``confidence`` (Efron & Tibshirani 1993, ch. 12.5): over
    ``resamples`` resamples with replacement, drawn with a fixed seed,
    t* = (mean* - mean) / (s* / sqrt(n)); the interval is
    mean - t*_(1+c)/2 s / sqrt(n) .. mean - t*_(1-c)/2 s / sqrt(n).

    Unlike the percentile interval (the quantiles of mean*), which is too
    narrow for small samples (coverage 0.90 instead of 0.95 for 10 normal
    values, 0.85 for 10 exponential ones), it covers the mean close to its
    rate from about 10 values on (0.946 and 0.935 over 2000 samples;
    ``python -m validation.ensembles --coverage``, docs/ensembles.md).
    Resamples with s* = 0 (all picks equal) carry no t* and are left out
    (so an interval of very few values is wide, as Student's t is);
    values that are all equal give the interval [mean, mean]."""
    x = np.asarray(values, dtype=float)
    if x.ndim != 1 or x.size < 2:
        raise ValueError(f"bootstrap: needs at least 2 values, got "
                         f"{x.size}")
    if not np.all(np.isfinite(x)):
        raise ValueError("bootstrap: values must be finite")
    if not 0.0 < confidence < 1.0:
        raise ValueError(f"confidence={confidence!r} must be in (0, 1)")
    if resamples < 100:
        raise ValueError(f"resamples={resamples!r} must be >= 100")
    n, mean = x.size, float(x.mean())
    se = float(x.std(ddof=1)) / math.sqrt(n)
    if se == 0.0:
        return mean, mean
    rng = np.random.Generator(np.random.PCG64(seed))
    t = np.empty(resamples)
    chunk = max(1, 2_000_000 // n)
    for start in range(0, resamples, chunk):
        stop = min(resamples, start + chunk)
        picks = x[rng.integers(0, n, size=(stop - start, n))]
        s = picks.std(axis=1, ddof=1)
        # all picks equal: s* is zero up to rounding
        tied = s <= 1e-9 * se * math.sqrt(n)
        with np.errstate(divide="ignore", invalid="ignore"):
            t[start:stop] = np.where(
                tied, np.nan,
                (picks.mean(axis=1) - mean) / (s / math.sqrt(n)))
    t = t[np.isfinite(t)]
    alpha = 0.5 * (1.0 - confidence)
    low_t, high_t = np.quantile(t, [alpha, 1.0 - alpha])
    return mean - float(high_t) * se, mean - float(low_t) * se


def summarise(values, quantity: str, unit: str,
              confidence: float = 0.95) -> dict:
    """mean, std (ddof 1), the bootstrap interval of the mean and the
    per-member values."""
    x = np.asarray(values, dtype=float)
    low, high = bootstrap_mean_interval(x, confidence)
    return {"quantity": quantity, "unit": unit, "members": int(x.size),
            "mean": float(x.mean()), "std": float(x.std(ddof=1)),
            "ci95_low": low, "ci95_high": high,
            "values": [float(v) for v in x]}


@dataclass
class Ensemble:
    """The result of :func:`ensemble`: the summary (as DIR/summary.json),
    the members' summaries and the members run now (not kept)."""

    summary: dict
    members: list
    ran: list
    #: members whose summary.json was found but failed
    #: :func:`check_member` and were run again: member -> the reason
    rejected: dict = field(default_factory=dict)

    @property
    def mean(self) -> float:
        return self.summary["mean"]

    @property
    def interval(self) -> tuple:
        return self.summary["ci95_low"], self.summary["ci95_high"]


def _config(test, dx, seed, max_strain, drop, scene_options) -> dict:
    default_dx, default_strain, samples = TESTS[test]
    return {"test": test, "dx_m": float(default_dx if dx is None else dx),
            "seed": int(seed),
            "max_strain": float(default_strain if max_strain is None
                                else max_strain),
            "drop": float(drop), "samples_per_strain": samples,
            "scene_options": dict(scene_options or {})}


def _check(test, members, jobs, seed, dx, quantity):
    if test not in TESTS:
        raise ValueError(f"test {test!r}: not one of {', '.join(TESTS)}")
    if quantity not in QUANTITIES:
        raise ValueError(f"quantity {quantity!r}: not one of "
                         f"{', '.join(QUANTITIES)}")
    for name, value, low in (("members", members, 2), ("jobs", jobs, 1)):
        if isinstance(value, bool) or not isinstance(value, int) \
                or value < low:
            raise ValueError(f"{name}={value!r} must be an integer >= {low}")
    if isinstance(seed, bool) or not isinstance(seed, int) \
            or not 0 <= seed < 2**53:
        raise ValueError(f"seed={seed!r} must be an integer in [0, 2^53)")
    if dx is not None and not (math.isfinite(dx) and dx > 0):
        raise ValueError(f"dx={dx!r} must be finite and > 0")


#: Bytes of one row of a member's load.csv (three reprs of doubles), and
#: of its summary.json and a file's least allocation.
_ROW_BYTES = 70
_FILE_BYTES = 4096


def cost(test: str, members: int, out=None, dx: float | None = None,
         jobs: int = 1, seed: int = 1, max_strain: float | None = None,
         drop: float = 0.5, scene_options: dict | None = None) -> dict:
    """What an ensemble would cost before it starts: member 0's scene is
    built and timed over a few steps on one thread, so the estimate is of
    this machine.  Returns ``particles``, ``steps`` (per member, at most:
    to max_strain; a member stops earlier at the load drop),
    ``step_s``, ``member_s`` (at most), ``to_run`` (the members out holds
    no summary of), ``seconds`` (wall time at most, on ``jobs``
    processes), ``bytes`` (disk of the members to run) and ``free_bytes``
    (free on out's file system)."""
    import shutil
    _check(test, members, jobs, seed, dx, "strength")
    config = _config(test, dx, seed, max_strain, drop, scene_options)
    from ..calculators import CLibrary
    from ..dynamics import ImprovedEuler
    scene = test_scene(config["test"], config["dx_m"], config["seed"], 0,
                       **config["scene_options"])
    scene.calc = CLibrary(threads=1)
    dyn = ImprovedEuler(scene, progress=False)
    dyn.run(steps=1)                       # the first neighbour build
    start = time.perf_counter()
    dyn.run(steps=3)
    step_s = (time.perf_counter() - start) / 3
    info = scene.failure
    steps = math.ceil(config["max_strain"] * info["length"] / info["speed"]
                      / dyn.dt)
    rows = math.ceil(config["max_strain"] * config["samples_per_strain"]) + 1
    to_run = members
    where = None
    if out is not None:
        out = Path(out)
        to_run = sum(1 for i in range(min(members, 100000))
                     if not (_member_dir(out, i) / "summary.json").exists())
        to_run += max(0, members - 100000)
        where = out
        while not where.exists() and where != where.parent:
            where = where.parent
    member_s = steps * step_s
    return {"particles": int(sum(scene.body_counts().values())),
            "steps": steps, "step_s": step_s, "member_s": member_s,
            "to_run": to_run,
            "seconds": math.ceil(to_run / jobs) * member_s,
            "bytes": to_run * (rows * _ROW_BYTES + 3 * _FILE_BYTES),
            "free_bytes": (shutil.disk_usage(where).free if where is not None
                           else None)}


def _progress(total: int, done: int, show: bool):
    if not show:
        return None
    from tqdm import tqdm
    return tqdm(total=total, initial=done, unit="member", dynamic_ncols=True)


def ensemble(test: str, members: int, out, dx: float | None = None,
             jobs: int = 1, seed: int = 1, quantity: str = "strength",
             max_strain: float | None = None, drop: float = 0.5,
             progress: bool = False, figure: bool = True,
             scene_options: dict | None = None, log=None) -> Ensemble:
    """Runs members 0 .. members-1 of fracture test ``test`` (ucs,
    brazilian, tensile) with flaws drawn from hash(``seed``, member), in
    ``jobs`` processes, into directory ``out``; keeps the members an
    earlier call finished there.  Summarises ``quantity`` (strength,
    strain_at_peak, fragments, peak_load) into out/summary.json and
    out/histogram.png.

    ``dx``, ``max_strain``: default that of ``sphsolid <test>``;
    ``scene_options``: keyword arguments of the scene's builder
    (e.g. ``strain_rate``, ``width``, ``length``).  A member whose
    summary.json fails :func:`check_member` is run again, the reason (the
    file named) passed to ``log`` (default: a warning) and kept in the
    result's ``rejected``.
    """
    _check(test, members, jobs, seed, dx, quantity)
    progress = _lib.flag(progress, "progress")
    figure = _lib.flag(figure, "figure")
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    config = _config(test, dx, seed, max_strain, drop, scene_options)
    record = out / "ensemble.json"
    if record.exists():
        earlier = json.loads(record.read_text())
        for key, value in config.items():
            if earlier.get(key) != value:
                raise ValueError(
                    f"{out}: holds an ensemble with {key}="
                    f"{earlier.get(key)!r}, this one has {key}={value!r}; "
                    f"use another directory")
    else:
        _write_atomic(record, json.dumps(config, indent=2))
    results: dict[int, dict] = {}
    rejected: dict[int, str] = {}
    for i in range(members):
        path = _member_dir(out, i) / "summary.json"
        if not path.exists():
            continue
        summary, reason = check_member(path, config, i)
        if summary is not None:
            results[i] = summary
            continue
        rejected[i] = reason
        message = f"{reason}; member {i} runs again"
        if log is None:
            import warnings
            warnings.warn(message, stacklevel=2)
        else:
            log(message)
    todo = [i for i in range(members) if i not in results]
    bar = _progress(members, members - len(todo), progress)
    try:
        if jobs == 1 or len(todo) <= 1:
            for i in todo:
                results[i] = run_member(config, i, out)
                if bar is not None:
                    bar.update(1)
        else:
            import multiprocessing
            context = multiprocessing.get_context("spawn")
            with ProcessPoolExecutor(max_workers=jobs,
                                     mp_context=context) as pool:
                futures = {pool.submit(_run_member_job, config, i,
                                       str(out)): i for i in todo}
                for future in as_completed(futures):
                    results[futures[future]] = future.result()
                    if bar is not None:
                        bar.update(1)
    finally:
        if bar is not None:
            bar.close()
    ordered = [results[i] for i in range(members)]
    key, unit = QUANTITIES[quantity]
    missing = [i for i, m in enumerate(ordered) if m.get(key) is None]
    if missing:
        raise ValueError(f"quantity {quantity}: members {missing} have no "
                         f"{key} (no damage before the run stopped?)")
    summary = summarise([m[key] for m in ordered], quantity, unit)
    summary.update(test=test, dx_m=config["dx_m"], seed=seed,
                   confidence=0.95,
                   bootstrap={"resamples": BOOTSTRAP_RESAMPLES,
                              "seed": BOOTSTRAP_SEED},
                   member_wall_s=[m["wall_s"] for m in ordered],
                   member_cpu_s=[m["cpu_s"] for m in ordered],
                   member_steps=[m["steps"] for m in ordered],
                   others={name: summarise([m[k] for m in ordered], name, u)
                           for name, (k, u) in QUANTITIES.items()
                           if name != quantity
                           and all(m.get(k) is not None for m in ordered)})
    _write_atomic(out / "summary.json", json.dumps(summary, indent=2))
    if figure:
        histogram(out / "histogram.png", summary)
    return Ensemble(summary=summary, members=ordered, ran=todo,
                    rejected=rejected)


def histogram(path, summary: dict) -> None:
    """The histogram of the members' values, with the mean and its
    interval."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    scale, unit = ((1e-6, "MPa") if summary["unit"] == "Pa"
                   else (1.0, summary["unit"]))
    x = np.asarray(summary["values"]) * scale
    fig, ax = plt.subplots(figsize=(5.5, 3.8))
    ax.hist(x, bins=max(5, int(math.sqrt(x.size)) + 1), color="0.7",
            edgecolor="0.3")
    ax.axvline(summary["mean"] * scale, color="C3", label="mean")
    ax.axvspan(summary["ci95_low"] * scale, summary["ci95_high"] * scale,
               color="C3", alpha=0.2, label="95 % interval of the mean")
    ax.set_xlabel(f"{summary['quantity']} [{unit}]")
    ax.set_ylabel("members")
    ax.set_title(f"{summary['test']}, dx = {summary['dx_m'] * 1e3:g} mm, "
                 f"{summary['members']} members")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
