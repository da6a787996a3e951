# Over 600 lines: the studies of docs/ensembles.md, one function per study and its table.
"""The ensembles' studies (docs/ensembles.md): the size effect, the rate
effect, and a confident strength planned and achieved.

    python -m validation.ensembles --size  [--seeds 30] [--dx 4mm] [--flaws 10]
                                           [--m 9 6] [--strain-rate 1]
    python -m validation.ensembles --rate  [--seeds 16] [--dx 4mm] [--rates ...]
    python -m validation.ensembles --plan  [--error 0.05] [--reference 20]
                                           [--scene ucs] [--ladder ...] [--pilot 10]
                                           [--finer 3mm ...]
    python -m validation.ensembles --coverage [--repeats 2000]
    python -m validation.ensembles --anatomy (where the bars start to fail)
    python -m validation.ensembles --doc [--tables NAME ...]
                                             (docs/ensembles.md's tables)
    (common: [--jobs 1] [--runs DIR] [--out docs/ensembles])

Each runs its ensembles with sphsolid.ensemble into ``--runs`` (default
``validation_runs/ensembles``; resumable: a rerun reuses finished
members), writes ``OUT/<study>.json`` and a figure ``OUT/<study>.png``,
and prints the Markdown table docs/ensembles.md quotes.

--size: tensile bars of areas A and 8A (plane strain, 1 m deep: volumes
8x apart; 20 x 80 mm and sqrt(8) times that) for Weibull exponents m = 9
and 6, at 1/s; k is set so that a 2 mm particle (V = 4e-6 m^3) expects
one flaw at strain 3e-3 for both m.  Weakest link: the mean strengths'
ratio is (V2/V1)^(1/m) (Weibull 1939; the mean of a Weibull minimum
scales as V^(-1/m)).

``--flaws F`` (the damage effect's expected flaws per particle, default
10), ``--m M ...`` (default 9 6) and ``--strain-rate R`` (default 1/s)
vary the size study; their results are ``OUT/size_flawsF_mM_rateR.json``
(each part only when off its default).

--rate: the 20 x 80 mm bar (m = 9) at strain rates 1, 10, 100 and
1000 /s (``--rates``); the fitted exponent of strength against rate, to compare with
Grady & Kipp's 3/(m + 3).

--coverage: how often the 95 % interval of the mean of n values (n = 10,
30; normal and exponential draws) contains the true mean, for the
ensembles' bootstrap-t interval and for the plain percentile interval.

--doc: writes the tables of the saved results (OUT/*.json) and the cost
of every ensemble in ``--runs`` between the markers of docs/ensembles.md
(``--tables``: only those named, as the markers name them).

--plan: ``sphsolid plan SCENE --quantity strength --error E``, the planned
ensemble run, and reference ensembles at the plan's ladder spacings, at
the planned dx and finer; the converged mean is the extrapolation
mu(dx) = mu_inf + C dx^q fitted to every level's mean.
"""
from __future__ import annotations

import argparse
import json
import math
from pathlib import Path

import numpy as np

import sphsolid
from sphsolid.ensemble import bootstrap_mean_interval

ROOT = Path(__file__).resolve().parent.parent
#: Strain at which a 2 mm plane-strain particle expects one flaw.
EPS_REF, V_REF = 3e-3, 4e-6


def weibull_k(m: float) -> float:
    """k [m^-3] with k V_REF EPS_REF^m = 1."""
    return 1.0 / (V_REF * EPS_REF ** m)


def _length(text: str) -> float:
    from sphsolid.units import quantity
    return quantity(text, "length", "dx")


def _bar(runs: Path, name: str, seeds: int, dx: float, jobs: int,
         **options):
    return sphsolid.ensemble("tensile", seeds, runs / name, dx=dx,
                             jobs=jobs, progress=True, figure=False,
                             scene_options=options)


def size_study(args) -> dict:
    rows = []
    for m in args.m:
        per = {}
        for name, scale in (("small", 1.0), ("large", math.sqrt(8.0))):
            width, length = 0.020 * scale, 0.080 * scale
            result = _bar(args.runs, f"size_m{m:g}_{name}_{args.dx * 1e3:g}mm"
                          + _size_tag(args, m=False), args.seeds, args.dx,
                          args.jobs,
                          weibull_k=weibull_k(m), weibull_m=m, width=width,
                          length=length, strain_rate=args.strain_rate,
                          flaws=args.flaws)
            s = result.summary
            n_x, n_y = round(width / args.dx), round(length / args.dx)
            onset = s["others"]["onset_stress"]
            per[name] = {"width_m": width, "length_m": length,
                         "volume_m3": n_x * n_y * args.dx ** 2,
                         "mean": s["mean"], "std": s["std"],
                         "ci95": [s["ci95_low"], s["ci95_high"]],
                         "values": s["values"],
                         "onset_mean": onset["mean"],
                         "onset_ci95": [onset["ci95_low"],
                                        onset["ci95_high"]],
                         "cpu_s": float(np.mean(s["member_cpu_s"]))}
        small, large = per["small"], per["large"]
        volume_ratio = large["volume_m3"] / small["volume_m3"]
        row = {"m": m, "k": weibull_k(m), "small": small, "large": large,
               "volume_ratio": volume_ratio,
               "weakest_link": volume_ratio ** (1.0 / m)}
        for what, mean, ci in (("ratio", "mean", "ci95"),
                               ("onset_ratio", "onset_mean", "onset_ci95")):
            ratio = small[mean] / large[mean]
            # the ratio's 95 % interval: each mean's bootstrap-t interval,
            # combined in log space (independent ensembles)
            # (none when an interval reaches zero: onsets at the first
            # damaged sample can fall after the drop, see the doc)
            row[what] = ratio
            if min(p[ci][0] for p in (small, large)) <= 0:
                row[what + "_ci95"] = None
                continue
            half = math.hypot(*(
                (math.log(p[ci][1]) - math.log(p[ci][0])) / 2
                for p in (small, large)))
            row[what + "_ci95"] = [ratio * math.exp(-half),
                                   ratio * math.exp(half)]
        rows.append(row)
    return {"dx_m": args.dx, "seeds": args.seeds,
            "strain_rate": args.strain_rate, "flaws": args.flaws,
            "rows": rows}


def _size_tag(args, m: bool = True) -> str:
    """The name suffix of a size study off the default flaws, exponents
    (``m``: whether to name them) and rate."""
    tag = "" if args.flaws == 10.0 else f"_flaws{args.flaws:g}"
    if m and list(args.m) != [9.0, 6.0]:
        tag += "_m" + "_".join(f"{m:g}" for m in args.m)
    return tag + ("" if args.strain_rate == 1.0
                  else f"_rate{args.strain_rate:g}")


def weakest_link_onset(k: float, m: float, volume: float) -> float:
    """The mean stress [Pa] at which the weakest flaw of a volume under
    uniform uniaxial stress (plane strain) activates: the weakest strain
    is Weibull with scale (k V)^(-1/m), mean Gamma(1 + 1/m) (k V)^(-1/m),
    and the largest principal strain is sigma (1 - nu^2) / E."""
    from sphsolid.fracture import fracture_material
    mat = fracture_material()
    E = 9.0 * mat.K * mat.mu / (3.0 * mat.K + mat.mu)
    nu = (3.0 * mat.K - 2.0 * mat.mu) / (2.0 * (3.0 * mat.K + mat.mu))
    strain = math.gamma(1.0 + 1.0 / m) * (k * volume) ** (-1.0 / m)
    return E / (1.0 - nu * nu) * strain


def size_table(data: dict) -> str:
    lines = ["| m | quantity | V2/V1 | small: mean [MPa] (95 % CI) | "
             "large: mean [MPa] (95 % CI) | measured ratio small/large "
             "(95 % CI) | (V2/V1)^(1/m) |",
             "|---|---|---|---|---|---|---|"]

    def mpa(p, mean, ci):
        return (f"{p[mean] / 1e6:.2f} ({p[ci][0] / 1e6:.2f}-"
                f"{p[ci][1] / 1e6:.2f})")
    for r in data["rows"]:
        s, g = r["small"], r["large"]
        s["weakest_link_onset"] = weakest_link_onset(r["k"], r["m"],
                                                     s["volume_m3"])
        g["weakest_link_onset"] = weakest_link_onset(r["k"], r["m"],
                                                     g["volume_m3"])
        for label, what, mean, ci in (
                ("peak (strength)", "ratio", "mean", "ci95"),
                ("damage onset", "onset_ratio", "onset_mean", "onset_ci95")):
            band = r[what + "_ci95"]
            band = ("(-)" if band is None else
                    f"({band[0]:.3f}-{band[1]:.3f})")
            lines.append(
                f"| {r['m']:g} | {label} | {r['volume_ratio']:.3f} | "
                f"{mpa(s, mean, ci)} | {mpa(g, mean, ci)} | {r[what]:.3f} "
                f"{band} | {r['weakest_link']:.3f} |")
    lines.append("")
    lines.append(f"dx = {data['dx_m'] * 1e3:g} mm, "
                 f"{data.get('flaws', 10.0):g} expected flaws per particle, "
                 f"strain rate {data.get('strain_rate', 1.0):g}/s, "
                 f"{data['seeds']} seeds per ensemble.  "
                 "Weakest-link onset under uniform stress, E/(1 - nu^2) "
                 "Gamma(1 + 1/m) (k V)^(-1/m): "
                 + "; ".join(f"m = {r['m']:g}: small "
                             f"{r['small']['weakest_link_onset'] / 1e6:.2f}"
                             f" MPa, large "
                             f"{r['large']['weakest_link_onset'] / 1e6:.2f}"
                             " MPa" for r in data["rows"]) + ".")
    return "\n".join(lines)


def size_figure(data: dict, path: Path) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(1, 2, figsize=(10, 4), sharex=True)
    for ax, (mean_key, ci_key, what) in zip(axes, (
            ("mean", "ci95", "peak (strength)"),
            ("onset_mean", "onset_ci95", "damage onset"))):
        for i, r in enumerate(data["rows"]):
            bars = (r["small"], r["large"])
            v = [b["volume_m3"] for b in bars]
            mean = np.array([b[mean_key] for b in bars]) / 1e6
            low = mean - np.array([b[ci_key][0] for b in bars]) / 1e6
            high = np.array([b[ci_key][1] for b in bars]) / 1e6 - mean
            ax.errorbar(v, mean, yerr=[low, high], marker="o", capsize=3,
                        color=f"C{i}", label=f"measured, m = {r['m']:g}")
            if mean_key == "mean":
                ax.plot(v, [mean[0], mean[0] / r["weakest_link"]], "--",
                        color=f"C{i}",
                        label=f"weakest link V^(-1/{r['m']:g})")
            else:
                ax.plot(v, [weakest_link_onset(r["k"], r["m"], x) / 1e6
                            for x in v], "--", color=f"C{i}",
                        label="uniform-stress weakest link")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("specimen volume [m^3 per m depth]")
        ax.set_ylabel(f"mean {what} stress [MPa]")
        ax.set_title(what)
        ax.legend(fontsize=7)
    fig.suptitle(f"size effect, tensile bars, dx = {data['dx_m'] * 1e3:g} "
                 f"mm, {data['seeds']} seeds each")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


RATES = (1.0, 10.0, 100.0, 1000.0)


def rate_study(args) -> dict:
    m = 9.0
    rows = []
    for rate in args.rates:
        result = _bar(args.runs, f"rate_{rate:g}_{args.dx * 1e3:g}mm",
                      args.seeds, args.dx, args.jobs, weibull_k=weibull_k(m),
                      weibull_m=m, strain_rate=rate)
        s = result.summary
        rows.append({"rate": rate, "mean": s["mean"], "std": s["std"],
                     "ci95": [s["ci95_low"], s["ci95_high"]],
                     "strain_at_peak": s["others"]["strain_at_peak"]["mean"],
                     "fragments": s["others"]["fragments"]["mean"],
                     "cpu_s": float(np.mean(s["member_cpu_s"]))})
    x = np.log([r["rate"] for r in rows])
    y = np.log([r["mean"] for r in rows])
    fits = {"all": float(np.polyfit(x, y, 1)[0]),
            "per_step": [float((y[i + 1] - y[i]) / (x[i + 1] - x[i]))
                         for i in range(len(rows) - 1)]}
    # the model's growth-limited asymptote: a particle needs
    # tau = k_R h / (0.4 c_l) to reach D = 1 after its flaws activate, so
    # at high rates the strain at peak grows by rate * tau
    from sphsolid.fracture import fracture_material
    mat = fracture_material()
    c_l = math.sqrt((mat.K + 4.0 * mat.mu / 3.0) / mat.rho0)
    tau = 2.0 * 1.2 * args.dx / (0.4 * c_l)
    return {"dx_m": args.dx, "seeds": args.seeds, "m": m, "rows": rows,
            "fitted_exponent": fits, "grady_kipp": 3.0 / (m + 3.0),
            "growth_time_s": tau,
            "rate_tau": [r["rate"] * tau for r in rows]}


def rate_table(data: dict) -> str:
    lines = ["| strain rate [1/s] | mean strength [MPa] (95 % CI) | std "
             "[MPa] | strain at peak | rate x tau | fragments | CPU s per "
             "member |",
             "|---|---|---|---|---|---|---|"]
    for r, rt in zip(data["rows"], data["rate_tau"]):
        lines.append(
            f"| {r['rate']:g} | {r['mean'] / 1e6:.2f} ({r['ci95'][0] / 1e6:.2f}"
            f"-{r['ci95'][1] / 1e6:.2f}) | {r['std'] / 1e6:.2f} | "
            f"{r['strain_at_peak']:.4f} | {rt:.1e} | {r['fragments']:.1f} | "
            f"{r['cpu_s']:.2f} |")
    fit = data["fitted_exponent"]
    lines.append("")
    lines.append(f"Fitted exponent of strength against rate: "
                 f"{fit['all']:.3f} over all rates; between consecutive "
                 "rates "
                 + ", ".join(f"{e:.3f}" for e in fit.get(
                     "per_step", fit.get("per_decade", [])))
                 + f"; Grady-Kipp 3/(m+3) = {data['grady_kipp']:.3f} "
                 f"(m = {data['m']:g}); growth time tau = k_R h / (0.4 c_l) "
                 f"= {data['growth_time_s'] * 1e6:.2f} us.")
    return "\n".join(lines)


def rate_figure(data: dict, path: Path) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(5.5, 4))
    rate = np.array([r["rate"] for r in data["rows"]])
    mean = np.array([r["mean"] for r in data["rows"]]) / 1e6
    low = mean - np.array([r["ci95"][0] for r in data["rows"]]) / 1e6
    high = np.array([r["ci95"][1] for r in data["rows"]]) / 1e6 - mean
    ax.errorbar(rate, mean, yerr=[low, high], marker="o", capsize=3,
                label="measured (95 % CI of the mean)")
    gk = data["grady_kipp"]
    ax.plot(rate, mean[-1] * (rate / rate[-1]) ** gk, "--",
            label=f"Grady-Kipp slope 3/(m+3) = {gk:.2f}")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("strain rate [1/s]")
    ax.set_ylabel("mean tensile strength [MPa]")
    ax.set_title(f"rate effect, tensile bar, dx = {data['dx_m'] * 1e3:g} mm,"
                 f" m = {data['m']:g}")
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def plan_study(args) -> dict:
    from sphsolid.planner.strength import plan_strength
    scene = args.scene
    plan = plan_strength(scene, args.error, work=args.runs / "plan_cache",
                         ladder=args.ladder, pilot=args.pilot,
                         jobs=args.jobs, log=print)
    print(plan.summary())
    if not plan.feasible:
        return {"plan": plan.to_dict()}
    tag = "" if scene == "ucs" else f"_{scene}"
    achieved = sphsolid.ensemble(scene, plan.seeds,
                                 args.runs / f"plan_run{tag}"
                                 f"_{plan.dx * 1e3:.4g}mm",
                                 dx=plan.dx, jobs=args.jobs, progress=True,
                                 figure=False)
    sphsolid.ensemble.histogram(args.out / f"plan{tag}_histogram.png",
                                achieved.summary)
    # references: the ladder (pilot members) and finer levels
    levels = [(lv["dx"], lv["mean"], lv["std"], lv["members"])
              for lv in plan.ladder]
    s = achieved.summary
    levels.append((plan.dx, s["mean"], s["std"], s["members"]))
    for dx in args.finer:
        ref = sphsolid.ensemble(scene, args.reference,
                                args.runs / f"plan_ref{tag}_{dx * 1e3:g}mm",
                                dx=dx, jobs=args.jobs, progress=True,
                                figure=False)
        r = ref.summary
        levels.append((dx, r["mean"], r["std"], r["members"]))
    levels.sort(reverse=True)
    h = np.array([lv[0] for lv in levels])
    mu = np.array([lv[1] for lv in levels])
    w = np.array([lv[3] / lv[2] ** 2 for lv in levels])
    best = None
    for q in np.arange(0.3, 3.001, 0.01):
        a = np.vstack([np.ones_like(h), h ** q]).T
        coef, *_ = np.linalg.lstsq(a * np.sqrt(w)[:, None], mu * np.sqrt(w),
                                   rcond=None)
        res = float(np.sum(w * (mu - a @ coef) ** 2))
        if best is None or res < best[0]:
            best = (res, q, coef)
    _, q, (mu_inf, c) = best
    error = abs(s["mean"] - mu_inf) / abs(mu_inf)
    low, high = bootstrap_mean_interval(s["values"])
    return {"plan": plan.to_dict(),
            "achieved": {"dx": plan.dx, "seeds": plan.seeds,
                         "mean": s["mean"], "ci95": [low, high],
                         "cpu_s": float(np.sum(s["member_cpu_s"])),
                         "error_vs_converged": error},
            "levels": [{"dx": lv[0], "mean": lv[1], "std": lv[2],
                        "members": lv[3]} for lv in levels],
            "converged": {"mean": float(mu_inf), "order": float(q),
                          "coefficient": float(c)},
            "met": bool(error <= args.error)}


def plan_table(data: dict) -> str:
    p = data["plan"]
    if "achieved" not in data:
        return f"no plan: {p['reason']}"
    a, c = data["achieved"], data["converged"]
    finest = min(data["levels"], key=lambda lv: lv["dx"])
    off = abs(a["mean"] - finest["mean"]) / abs(finest["mean"])
    means = [lv["mean"] for lv in sorted(data["levels"],
                                         key=lambda lv: -lv["dx"])]
    steps = np.sign(np.diff(means))
    monotone = bool(np.all(steps == steps[0]))
    inside = a["ci95"][0] <= c["mean"] <= a["ci95"][1]
    lines = ["| | dx [mm] | seeds | error | CPU s |", "|---|---|---|---|---|",
             f"| plan (--error {p['error']:.3g}) | "
             f"{p['settings']['dx'] * 1e3:.3g} | {p['seeds']} | "
             f"{p['predicted_error']:.4f} (discretisation "
             f"{p['discretisation_error']:.4f} + statistical "
             f"{p['statistical_error']:.4f}) | {p['predicted_seconds']:.0f} |",
             f"| achieved | {a['dx'] * 1e3:.3g} | {a['seeds']} | "
             f"{a['error_vs_converged']:.4f} vs the converged mean | "
             f"{a['cpu_s']:.0f} |",
             "",
             f"Achieved mean {a['mean'] / 1e6:.3f} MPa, 95 % interval "
             f"{a['ci95'][0] / 1e6:.3f}-{a['ci95'][1] / 1e6:.3f} MPa; "
             f"converged mean {c['mean'] / 1e6:.3f} MPa (mu_inf + C dx^q "
             f"fitted to every level, q = {c['order']:.2f}); request "
             f"{'met' if data['met'] else 'NOT met'} against it, and the "
             f"interval {'contains' if inside else 'does NOT contain'} "
             "it.  Against "
             f"the finest reference ({finest['dx'] * 1e3:g} mm, "
             f"{finest['members']} members, {finest['mean'] / 1e6:.3f} MPa):"
             f" {off:.4f}, request "
             f"{'met' if off <= p['error'] else 'NOT met'}.  The means are "
             f"{'monotone' if monotone else 'not monotone'} in dx.",
             "",
             "| dx [mm] | members | mean [MPa] | std [MPa] |",
             "|---|---|---|---|"]
    for lv in data["levels"]:
        lines.append(f"| {lv['dx'] * 1e3:.3g} | {lv['members']} | "
                     f"{lv['mean'] / 1e6:.3f} | {lv['std'] / 1e6:.3f} |")
    return "\n".join(lines)


def _percentile_interval(x, rng, resamples=1000, confidence=0.95):
    means = x[rng.integers(0, x.size, size=(resamples, x.size))].mean(1)
    alpha = (1.0 - confidence) / 2
    return np.quantile(means, [alpha, 1.0 - alpha])


def coverage_study(args) -> dict:
    rng = np.random.Generator(np.random.PCG64(11))
    rows = []
    for n in (10, 30):
        for name, draw in (("normal", lambda: rng.normal(3.0, 2.0, n)),
                           ("exponential", lambda: rng.exponential(3.0, n))):
            hits = {"bootstrap_t": 0, "percentile": 0}
            for r in range(args.repeats):
                x = draw()
                low, high = bootstrap_mean_interval(x, 0.95, resamples=1000,
                                                    seed=r)
                hits["bootstrap_t"] += low <= 3.0 <= high
                low, high = _percentile_interval(x, rng)
                hits["percentile"] += low <= 3.0 <= high
            rows.append({"n": n, "distribution": name,
                         **{k: v / args.repeats for k, v in hits.items()}})
    return {"repeats": args.repeats, "confidence": 0.95,
            "binomial_sd": math.sqrt(0.95 * 0.05 / args.repeats),
            "rows": rows}


def coverage_table(data: dict) -> str:
    lines = ["| n | distribution | bootstrap-t (sphsolid.ensemble) | "
             "percentile |", "|---|---|---|---|"]
    for r in data["rows"]:
        lines.append(f"| {r['n']} | {r['distribution']} | "
                     f"{r['bootstrap_t']:.3f} | {r['percentile']:.3f} |")
    lines.append("")
    lines.append(f"Share of {data['repeats']} samples whose 95 % interval "
                 f"contains the mean (binomial standard deviation "
                 f"{data['binomial_sd']:.4f}).")
    return "\n".join(lines)


def anatomy_study(args) -> dict:
    """Member 0 of the size study's bars (m = 9): where the first damage
    appears, at what share of the peak load, and how many particles are
    damaged (D > 0) and failed (D = 1) at the peak."""
    from sphsolid import fracture
    rows = []
    for name, scale in (("small", 1.0), ("large", math.sqrt(8.0))):
        width, length = 0.020 * scale, 0.080 * scale
        scene = fracture.test_scene(
            "tensile", args.dx, weibull_k=weibull_k(9.0), weibull_m=9.0,
            width=width, length=length, strain_rate=1.0)
        scene.calc = sphsolid.CLibrary(threads=1)
        bar = scene.body_slice("specimen")
        seen = {}

        def on_sample(scene, t, load, peak):
            damage = scene.damage[bar]
            if "onset" not in seen and damage.max() > 0:
                where = scene.positions[bar][np.argmax(damage)]
                seen["onset"] = (load, float(where[0] / width),
                                 float(where[1] / length))
            if load >= peak:
                seen["peak"] = (int((damage > 0).sum()),
                                int((damage >= 1.0).sum()))
        run = fracture.load_to_break(scene, max_strain=0.01,
                                     on_sample=on_sample)
        load, x, y = seen["onset"]
        rows.append({"bar": name, "particles": int(bar.stop - bar.start),
                     "onset_share_of_peak": load / run.peak_load_N,
                     "onset_x_over_width": x, "onset_y_over_length": y,
                     "damaged_at_peak": seen["peak"][0],
                     "failed_at_peak": seen["peak"][1]})
    return {"dx_m": args.dx, "m": 9.0, "member": 0, "rows": rows}


def anatomy_table(data: dict) -> str:
    lines = ["| bar | particles | first damage at (x/W, y/L) | load there / "
             "peak | damaged at the peak | failed at the peak |",
             "|---|---|---|---|---|---|"]
    for r in data["rows"]:
        lines.append(f"| {r['bar']} | {r['particles']} | "
                     f"({r['onset_x_over_width']:.2f}, "
                     f"{r['onset_y_over_length']:.2f}) | "
                     f"{r['onset_share_of_peak']:.2f} | "
                     f"{r['damaged_at_peak']} | {r['failed_at_peak']} |")
    return "\n".join(lines)


def cost_table(runs: Path) -> str:
    """CPU seconds per member of every ensemble under ``runs`` (one row per
    test, dx and scene options: the largest such ensemble)."""
    rows = {}
    for path in sorted(runs.glob("**/summary.json")):
        if path.parent.name.startswith("member_"):
            continue
        s = json.loads(path.read_text())
        config = json.loads((path.parent / "ensemble.json").read_text())
        options = config["scene_options"]
        cpu = float(np.mean(s["member_cpu_s"]))
        steps = float(np.mean(s["member_steps"]))
        rate = ("" if config["test"] == "brazilian"
                else f"{options.get('strain_rate', 1.0):g}")
        size = (f"x{options['length'] / 0.08:.2f}" if "length" in options
                else "1")
        m = f"{options.get('weibull_m', 9.0):g}"
        key = (config["test"], s["dx_m"], rate, size, m)
        if key not in rows or rows[key][0] < s["members"]:
            rows[key] = (s["members"], steps, cpu)
    lines = ["| test | dx [mm] | strain rate [1/s] | size | m | members | "
             "steps per member | CPU s per member | 10 members | 30 members "
             "| 100 members |", "|---|---|---|---|---|---|---|---|---|---|---|"]
    for key in sorted(rows, key=lambda k: (k[0], -k[1], float(k[2] or 0),
                                           k[3], k[4])):
        test, dx, rate, size, m = key
        members, steps, cpu = rows[key]
        lines.append(f"| {test} | {dx * 1e3:g} | {rate or '-'} | {size} | "
                     f"{m} | {members} | {steps:.0f} | {cpu:.3g} | "
                     f"{10 * cpu:.3g} | {30 * cpu:.3g} | {100 * cpu:.3g} |")
    lines.append("")
    lines.append("The last three columns are N times the measured CPU "
                 "seconds per member (s); the ucs rows at 8, 6 and 4 mm "
                 "and the brazilian rows are the planner's pilot ensembles "
                 "(the disc is loaded at 20 mm/s).")
    return "\n".join(lines)


def write_doc(args) -> None:
    doc = ROOT / "docs" / "ensembles.md"
    text = doc.read_text()
    wanted = set(args.tables or ())
    tables = {} if wanted and "cost" not in wanted else \
        {"cost": cost_table(args.runs)}
    makers = {"size": size_table, "anatomy": anatomy_table,
              "rate": rate_table, "plan": plan_table,
              "coverage": coverage_table}
    for path in sorted(args.out.glob("*.json")):
        make = makers.get(path.stem.split("_")[0])
        if wanted and path.stem not in wanted:
            continue
        if make is not None and f"<!-- {path.stem}:begin -->" in text:
            tables[path.stem] = make(json.loads(path.read_text()))
    for name, table in tables.items():
        begin, end = f"<!-- {name}:begin -->", f"<!-- {name}:end -->"
        head, rest = text.split(begin)
        _, tail = rest.split(end)
        text = f"{head}{begin}\n{table}\n{end}{tail}"
    doc.write_text(text)
    print(f"wrote {doc}: {', '.join(tables)}")


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(
        prog="python -m validation.ensembles",
        description=__doc__.split("\n\n")[0])
    what = parser.add_mutually_exclusive_group(required=True)
    what.add_argument("--size", action="store_true")
    what.add_argument("--rate", action="store_true")
    what.add_argument("--plan", action="store_true")
    what.add_argument("--coverage", action="store_true")
    what.add_argument("--doc", action="store_true")
    what.add_argument("--anatomy", action="store_true")
    parser.add_argument("--repeats", type=int, default=2000)
    parser.add_argument("--seeds", type=int, default=None,
                        help="members per ensemble (default 30 for --size, "
                        "16 for --rate)")
    parser.add_argument("--dx", type=_length, default=4e-3)
    parser.add_argument("--rates", type=float, nargs="+", default=RATES,
                        help="strain rates of --rate [1/s] (default 1 10 "
                        "100 1000)")
    parser.add_argument("--error", type=float, default=0.05)
    parser.add_argument("--reference", type=int, default=20,
                        help="members of the finer reference ensembles of "
                        "--plan (default 20)")
    parser.add_argument("--finer", type=_length, nargs="*", default=[3e-3],
                        help="spacings of the reference ensembles of --plan "
                        "besides the ladder and the plan's (default 3mm)")
    parser.add_argument("--scene", choices=("ucs", "brazilian"),
                        default="ucs", help="the test --plan plans")
    parser.add_argument("--ladder", type=_length, nargs="*", default=None,
                        help="the pilot ladder of --plan (default the "
                        "planner's)")
    parser.add_argument("--pilot", type=int, default=10,
                        help="members per pilot ensemble of --plan")
    parser.add_argument("--flaws", type=float, default=10.0,
                        help="expected flaws per particle of --size "
                        "(the damage effect's flaws)")
    parser.add_argument("--m", type=float, nargs="+", default=[9.0, 6.0],
                        help="Weibull exponents of --size (default 9 6)")
    parser.add_argument("--strain-rate", type=float, default=1.0,
                        help="strain rate of --size [1/s]")
    parser.add_argument("--tables", nargs="*", default=None,
                        help="the tables --doc rewrites (default every "
                        "marked one: cost and each OUT/*.json)")
    parser.add_argument("--jobs", type=int, default=1)
    parser.add_argument("--runs", type=Path,
                        default=ROOT / "validation_runs" / "ensembles")
    parser.add_argument("--out", type=Path, default=ROOT / "docs" / "ensembles")
    args = parser.parse_args(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    if args.doc:
        write_doc(args)
        return 0
    if args.size:
        args.seeds = args.seeds or 30
        data = size_study(args)
        name = ("size" + ("" if args.dx == 4e-3 else f"_{args.dx * 1e3:g}mm")
                + _size_tag(args))
        table = size_table(data)
        size_figure(data, args.out / f"{name}.png")
    elif args.rate:
        args.seeds = args.seeds or 16
        data = rate_study(args)
        name = "rate" if args.dx == 4e-3 else f"rate_{args.dx * 1e3:g}mm"
        table = rate_table(data)
        rate_figure(data, args.out / f"{name}.png")
    elif args.anatomy:
        data = anatomy_study(args)
        name, table = "anatomy", anatomy_table(data)
    elif args.coverage:
        data = coverage_study(args)
        name, table = "coverage", coverage_table(data)
    else:
        data = plan_study(args)
        name = ("plan" if args.scene == "ucs" and args.error == 0.05 else
                f"plan_{args.scene}_{args.error * 100:g}pct_check")
        table = plan_table(data)
    (args.out / f"{name}.json").write_text(json.dumps(data, indent=2))
    print(table)
    print(f"wrote {args.out / (name + '.json')}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
