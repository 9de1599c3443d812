"""Which λ makes the Quality knob's choice land on the brute-force hull, on whole sequences.

    tools/rd/quality_lambda_study.py HULL_RESULTS

HULL_RESULTS is the results folder of cfg/rd/geometry-hull.toml (GridBits x MotionQuantStep over
the object, with the B meshes Quality codes). For each sequence and Quality 0, 10 .. 80 it forms
Quality's four candidates (encoder/quality.h: target step Δ = S / 2^P, P = 5 + Quality / 10,
grids of B .. B + 3 bits, B = max(round(P), 8), MotionQuantStep = round(Δ / grid step)), takes
their whole-sequence rate R and distortion D (squared vertex error in units of Δ²) from the
sweep, and chooses by J = D + λ·R under three rules:

  model   λ = ln 2 / 6, an entropy-coded uniform quantiser of step Δ at high rate;
  finer   the model's choice, then λ = the slope between it and its grid at half its step
          (3dvo-enc's rule since issue 21's windows-and-slope change);
  coarser the same with twice the step.

and prints each choice's excess over the hull at its KG error (quality_hull.py's measure). The
encoder chooses from trial windows, not whole sequences: this isolates the rule from the trial.
A candidate the sweep lacks (a step outside 1 .. 64 or not a power of two) is left out and said.
"""

import argparse
import csv
import json
import math
import os
import sys

from quality_hull import hull_rate, lower_hull

RULES = ("model", "finer", "coarser")


def fail(message):
    sys.exit("quality_lambda_study: error: %s" % message)


def candidates(size, quality):
    """Quality's candidates (grid bits, step) for an object of size `size` (S), and Δ."""
    precision = 5.0 + quality / 10.0
    delta = size / 2.0 ** precision
    base = max(int(math.floor(precision + 0.5)), 8)
    out = []
    for bits in range(base, base + 4):
        step = size / (2.0 ** bits - 1)
        out.append((bits, int(min(max(math.floor(delta / step + 0.5), 1), 65535))))
    return out, delta


def choose(points, cands, rule):
    """The candidate of least J under `rule`; points: (bits, step) -> (R bits, D in Δ²)."""
    model = math.log(2.0) / 6.0
    have = [c for c in cands if c in points]
    if not have:
        return None
    best = min(have, key=lambda c: points[c][1] + model * points[c][0])
    if rule == "model":
        return best
    other = (best[0], best[1] // 2 if rule == "finer" else best[1] * 2)
    if other == best or other not in points:
        return best
    fine, coarse = (other, best) if rule == "finer" else (best, other)
    (r_fine, d_fine), (r_coarse, d_coarse) = points[fine], points[coarse]
    if not (r_fine > r_coarse and d_fine < d_coarse):
        return best
    slope = (d_coarse - d_fine) / (r_fine - r_coarse)
    return min(have, key=lambda c: points[c][1] + slope * points[c][0])


def main(argv):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("hull_results")
    args = parser.parse_args(argv)
    path = os.path.join(args.hull_results, "rd.csv")
    try:
        with open(path, newline="", encoding="utf-8") as f:
            rows = list(csv.DictReader(f))
    except OSError as e:
        fail("%s: cannot read (%s); 3dvo-rd run writes it" % (path, e.strerror))
    by_sequence = {}
    for r in rows:
        if not r["kg_error"] or not r["mode"].startswith("g"):
            continue
        bits = int(r["mode"][1:])
        step = int(r["setting"].split("=")[1])
        job = os.path.join(args.hull_results, "jobs", r["key"] + ".json")
        try:
            with open(job, encoding="utf-8") as f:
                grid = json.load(f)["encoder_summary"]["grid"]  # "13 bits, step 0.00084"
        except (OSError, KeyError, ValueError) as e:
            fail("%s: no grid in its summary (%s)" % (job, e))
        size = float(grid.split("step ")[1]) * (2.0 ** bits - 1)  # the object spans 2^bits - 1
        entry = by_sequence.setdefault(r["sequence"], {"size": size, "rows": {}})
        entry["rows"][(bits, step)] = (float(r["bytes"]) * 8, float(r["vertex_rmse"]) ** 2 *
                                       float(r["vertices"]), float(r["kbit_s"]),
                                       float(r["kg_error"]))
    if not by_sequence:
        fail("%s: no GridBits x MotionQuantStep rows" % path)
    worst = dict.fromkeys(RULES, 0.0)
    print("| sequence | Quality | " + " | ".join("%s: choice, excess" % r for r in RULES) + " |")
    print("|---|---|" + "---|" * len(RULES))
    for sequence in sorted(by_sequence):
        entry = by_sequence[sequence]
        hull = lower_hull([(v[2], v[3]) for v in entry["rows"].values()])
        for quality in range(0, 81, 10):
            cands, delta = candidates(entry["size"], quality)
            points = {c: (v[0], v[1] / delta ** 2) for c, v in entry["rows"].items()}
            missing = [c for c in cands if c not in points]
            cells = []
            for rule in RULES:
                c = choose(points, cands, rule)
                if c is None:
                    cells.append("-")
                    continue
                rate, kg = entry["rows"][c][2], entry["rows"][c][3]
                at = hull_rate(hull, kg)
                excess = rate / at - 1 if at else float("nan")
                if at:
                    worst[rule] = max(worst[rule], excess)
                cells.append("%d/%d %+.1f %%" % (c[0], c[1], 100 * excess))
            note = (" (not swept: %s)" % ", ".join("%d/%d" % c for c in missing)) if missing else ""
            print("| %s | %d%s | %s |" % (sequence, quality, note, " | ".join(cells)))
    print()
    print("Largest excess: " + ", ".join("%s %+.1f %%" % (r, 100 * worst[r]) for r in RULES))


if __name__ == "__main__":
    main(sys.argv[1:])
