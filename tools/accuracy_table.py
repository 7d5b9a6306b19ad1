#!/usr/bin/env python3
"""Summarises finished `arttrack run` output folders (their summary.json) as
the table docs/accuracy.md shows: per scenario and method, runs, lost runs,
converged translation error of the worst end effector (p50, p75, p99, mm),
median time to converge, and 2-sigma consistency of angles, biases and
camera offset twice: over every sample (summary.json's "consistency", the
first seconds' convergence included) and from converged_after_s on
("converged_consistency"). The two differ: a filter can be too sure while
it converges and too cautious after (docs/accuracy.md, "Coverage over
time"). Last, the same two of the end-effector poses' position and rotation
components against their reported covariance.

  tools/accuracy_table.py out/paper/*    (each argument: a run's --out folder)
  tools/accuracy_table.py --pool out/a out/b
      one row per scenario and method over all the folders of that
      scenario (e.g. the same file run with --seed 11 and --seed 13): runs
      and lost runs summed; the converged percentiles over all their
      samples, from timeseries.csv, as the scorer takes them (the worst end
      effector per sample, linear interpolation); the median of the runs'
      times to converge; both consistencies weighted by runs. A method is pooled
      over the folders that ran it.

  tools/accuracy_table.py --camera-axes out/realistic/*
      per folder and method, the camera offset's share within 2 sigma per
      virtual joint (x / y / z / roll / pitch / yaw), all samples and
      converged: the pooled camera column can sit in the band while one
      axis is never covered (docs/accuracy.md, "The camera's axes").

Exit status 1 if a folder has no readable summary.json (or, with --pool,
timeseries.csv), or if pooled folders score differently.
"""
import csv
import json
import math
import statistics
import sys

# summary.json's camera_offset_axes keys, in the scorer's order (kCameraOffsetAxes).
CAMERA_AXES = ("x", "y", "z", "roll", "pitch", "yaw")


def mm(v):
    return "-" if v is None else f"{1e3 * v:.1f}"


def pct(v):
    """A share within 2 sigma, to a tenth of a percent: the band asked is
    80-99%, and a whole percent would print 99.4% (over it) as 99%."""
    return "-" if v is None else f"{100 * v:.1f}%"


def print_header():
    print("| scenario | method | runs | lost | converged p50 / p75 / p99, mm | "
          "median time to converge, s | within 2 sigma, all samples: angles / biases / camera | "
          "the same, converged | end effectors within 2 sigma, position / rotation: all samples, "
          "converged |")
    print("|---|---|---|---|---|---|---|---|---|")


def shares(k):
    """Angles / biases / camera of a consistency keyed as in summary.json
    (None: the summary has none, written before it had)."""
    if k is None:
        return "- / - / -"
    return f"{pct(k['angles'])} / {pct(k['biases'])} / {pct(k['camera_offset'])}"


def end_effector_shares(k):
    """Position / rotation of a consistency (None or no such keys: "-")."""
    k = k or {}
    return f"{pct(k.get('end_effector_position'))} / {pct(k.get('end_effector_rotation'))}"


def print_row(scenario, method, runs, lost, p50, p75, p99, ttc, consistency, converged):
    """One table row: errors in m, ttc as text, the two consistencies."""
    print(f"| {scenario} | {method} | {runs} | {lost} | "
          f"{mm(p50)} / {mm(p75)} / {mm(p99)} | {ttc} | {shares(consistency)} | "
          f"{shares(converged)} | {end_effector_shares(consistency)}, "
          f"{end_effector_shares(converged)} |")


def percentile(values, p):
    """numpy's default (linear) percentile of unsorted values, p in [0, 1]."""
    v = sorted(values)
    k = (len(v) - 1) * p
    lo = math.floor(k)
    hi = min(lo + 1, len(v) - 1)
    return v[lo] + (v[hi] - v[lo]) * (k - lo)


def worst_series(folder, summary):
    """Per (method, run): times and the worst end effector's translation error."""
    columns = [f"translation_m_{e}" for e in summary["end_effectors"]]
    series = {}
    with open(f"{folder}/timeseries.csv", newline="") as f:
        for row in csv.DictReader(f):
            # A lost estimate (NaN, or no value) is the worst.
            errors = [float(row[c]) if row[c] else math.nan for c in columns]
            worst = max(math.inf if math.isnan(e) else e for e in errors)
            key = (row["method"], int(row["run"]))
            series.setdefault(key, ([], []))
            series[key][0].append(float(row["time_s"]))
            series[key][1].append(worst)
    return series


def time_to_converge(times, errors, threshold):
    """First time after which the error stays below threshold; None: never."""
    first = len(errors)
    while first > 0 and errors[first - 1] < threshold:
        first -= 1
    return None if first == len(errors) else times[first]


def pool(folders):
    groups = {}
    for folder in folders:
        with open(f"{folder}/summary.json") as f:
            s = json.load(f)
        groups.setdefault(s["scenario"], []).append((folder, s, worst_series(folder, s)))
    print_header()
    for scenario, members in groups.items():
        scoring = members[0][1]["scoring"]
        ends = members[0][1]["end_effectors"]
        for folder, s, _ in members:
            if s["scoring"] != scoring or s["end_effectors"] != ends:
                raise ValueError(f"{folder}: scored differently from {members[0][0]}")
        names = []
        for _, s, _ in members:
            names += [n for n in s["methods"] if n not in names]
        for name in names:  # each method over the folders that ran it
            runs = lost = 0
            samples, times = [], []
            keys = ("angles", "biases", "camera_offset", "end_effector_position",
                    "end_effector_rotation")
            weighted = {(f, k): 0.0 for f in ("consistency", "converged_consistency") for k in keys}
            known = dict.fromkeys(weighted, 0)
            for _, s, series in members:
                if name not in s["methods"]:
                    continue
                m = s["methods"][name]
                runs += m["lost"]["of"]
                lost += m["lost"]["runs"]
                for f, k in weighted:
                    if m.get(f) and m[f].get(k) is not None:
                        weighted[f, k] += m[f][k] * m["lost"]["of"]
                        known[f, k] += m["lost"]["of"]
                for (method, _), (t, e) in series.items():
                    if method != name:
                        continue
                    samples += [v for ti, v in zip(t, e) if ti >= scoring["converged_after_s"]]
                    times.append(time_to_converge(t, e, scoring["convergence_threshold_m"]))
            converged = [t for t in times if t is not None]
            # Half the runs or more never converging makes the median "never".
            ttc = (f"{statistics.median(converged + [math.inf] * (len(times) - len(converged))):.1f}"
                   if len(converged) * 2 > len(times) else "never")
            p = [percentile(samples, q) if samples else None for q in (0.5, 0.75, 0.99)]
            k = [{key: weighted[f, key] / known[f, key] if known[f, key] else None for key in keys}
                 for f in ("consistency", "converged_consistency")]
            print_row(scenario, name, runs, lost, *p, ttc, *k)


def read_summaries(folders):
    """The folders' summary.json, and 1 if one was unreadable (named on stderr), else 0."""
    summaries, status = [], 0
    for folder in folders:
        try:
            with open(f"{folder}/summary.json") as f:
                summaries.append(json.load(f))
        except (OSError, ValueError) as e:
            print(f"accuracy_table: {folder}: {e}", file=sys.stderr)
            status = 1
    return summaries, status


def camera_axes(folders):
    """The --camera-axes table; 1 if a folder has no readable summary.json."""
    summaries, status = read_summaries(folders)
    print("| scenario | method | runs | camera within 2 sigma, x / y / z / roll / pitch / yaw: "
          "all samples | the same, converged |")
    print("|---|---|---|---|---|")
    for s in summaries:
        for name, m in s["methods"].items():
            cells = []
            for key in ("consistency", "converged_consistency"):
                axes = (m.get(key) or {}).get("camera_offset_axes") or {}
                cells.append(" / ".join(pct(axes.get(a)) for a in CAMERA_AXES))
            print(f"| {s['scenario']} | {name} | {m['lost']['of']} | {cells[0]} | {cells[1]} |")
    return status


def main(folders):
    if folders and folders[0] == "--camera-axes":
        return camera_axes(folders[1:])
    if folders and folders[0] == "--pool":
        try:
            pool(folders[1:])
        except (OSError, ValueError, KeyError) as e:
            print(f"accuracy_table: {e}", file=sys.stderr)
            return 1
        return 0
    summaries, status = read_summaries(folders)
    print_header()
    for s in summaries:
        for name, m in s["methods"].items():
            c = m["converged_translation_m"]
            ttc_values = m["convergence_time_s"]
            if not isinstance(ttc_values, list):
                ttc_values = [ttc_values]
            times = [t for t in ttc_values if t is not None]
            never = len(ttc_values) - len(times)
            ttc = f"{statistics.median(times):.1f}" if times else "never"
            if never and times:
                ttc += f" ({never} never)"
            print_row(s["scenario"], name, m["lost"]["of"], m["lost"]["runs"], c["p50"],
                      c["p75"], c["p99"], ttc, m["consistency"],
                      m.get("converged_consistency"))
    return status


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
