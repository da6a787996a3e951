"""Compares two outputs of bench/probe_series to a bound (compare_probes.sh --bound).

    python3 scripts/probe_series_bound.py BASE HEAD BOUND

Each series line holds, as hexadecimal floats, the values of every probe
(von Mises, pressure, the stress components: SPH_PROBE_VALUES) and a pair
of checksums per state field (position, velocity, density, deviatoric
stress).  A value of HEAD agrees when it is within BOUND of the largest
magnitude its group (the probe, or the field's two checksums) reaches over
the BASE series: a component that is zero by symmetry holds rounding noise
only, and is judged against the stresses of its probe.  Prints the largest
difference per series found, and exits 1 if one exceeds BOUND or the two
outputs do not hold the same lines.
"""

import collections
import re
import sys


def parse(path):
    lines = {}
    with open(path) as f:
        for line in f:
            m = re.match(r"(.*? step \d+):(.*)$", line.rstrip("\n"))
            if not m:
                continue
            label, rest = m.groups()
            values = rest.split()
            stopped = values and values[0].startswith("stopped")
            lines[label] = None if stopped else [float.fromhex(v) for v in values]
    return lines


def groups(label, n):
    """Index groups of a line of n values: one per probe, one per field."""
    probe = 2 + (6 if label.startswith("cylinder") else 4)
    probes = (n - 8) // probe
    out = [list(range(p * probe, (p + 1) * probe)) for p in range(probes)]
    return out + [[probes * probe + 2 * f, probes * probe + 2 * f + 1] for f in range(4)]


def main(base_path, head_path, bound):
    base, head = parse(base_path), parse(head_path)
    if set(base) != set(head):
        print("probe_series_bound: the two outputs hold different lines")
        return 1
    series = collections.defaultdict(list)
    for label in base:
        series[re.sub(r" step \d+$", "", label)].append(label)
    worst, failed = [], False
    for name, labels in series.items():
        rows = [base[k] for k in labels if base[k] is not None]
        if any((base[k] is None) != (head[k] is None) for k in labels):
            print(f"probe_series_bound: {name}: one side stopped, the other did not")
            failed = True
            continue
        if not rows:
            continue
        scale = [0.0] * len(rows[0])
        for g in groups(name, len(rows[0])):
            s = max(abs(r[i]) for r in rows for i in g)
            for i in g:
                scale[i] = s
        d = max(
            (
                abs(x - y) / scale[i]
                for k in labels
                if base[k] is not None
                for i, (x, y) in enumerate(zip(base[k], head[k]))
                if scale[i] > 0.0
            ),
            default=0.0,
        )
        worst.append((d, name))
        failed |= d > bound
    worst.sort(reverse=True)
    for d, name in worst[:3]:
        print(f"probe_series_bound: {d:.3g} of the largest value in {name}")
    verdict = "exceed" if failed else "within"
    print(f"probe_series_bound: {len(base)} series lines {verdict} {bound:g} of the base")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1], sys.argv[2], float(sys.argv[3])))
