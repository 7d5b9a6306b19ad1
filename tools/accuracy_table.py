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

  tools/accuracy_table.py --error-over-sd out/s*/FILE
      per scenario and method over all the folders (as --pool), how wide
      the reported standard deviations are against the errors, from
      converged_after_s on: per run and joint (and camera axis) the mean of
      (estimate - truth) / reported sd over its samples, then over those
      pairs their RMS, the largest and how many are beyond 2; last, the
      RMS of (estimate - truth) / sd over every sample. A systematic
      error (a robot off its URDF) is nearly constant in a run, so a share
      within 2 sigma of 100% says only that each mean is under 2; an RMS of
      0.4 says the reported sds are about 2.5 times what they should be
      (1 is honest, over 1 too sure; docs/accuracy.md, stop 83). An error
      that wanders about 0 from sample to sample averages out of the
      means, not out of the samples: there the last figure is the one to
      read (an exact robot: docs/accuracy.md, stop 85).

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


def scenario_groups(folders):
    """Per scenario, in order, its folders and their summary.json; a folder
    scored differently (scoring or end effectors) from its group's first is
    a ValueError naming both."""
    groups = {}
    for folder in folders:
        with open(f"{folder}/summary.json") as f:
            s = json.load(f)
        groups.setdefault(s["scenario"], []).append((folder, s))
    for members in groups.values():
        first_folder, first = members[0]
        for folder, s in members:
            if (s["scoring"] != first["scoring"] or
                    s.get("end_effectors") != first.get("end_effectors")):
                raise ValueError(f"{folder}: scored differently from {first_folder}")
    return groups


def method_names(summaries):
    """The methods any of the summaries ran, in the order they first appear."""
    names = []
    for s in summaries:
        names += [n for n in s["methods"] if n not in names]
    return names


def pool(folders):
    groups = {scenario: [(folder, s, worst_series(folder, s)) for folder, s in members]
              for scenario, members in scenario_groups(folders).items()}
    print_header()
    for scenario, members in groups.items():
        scoring = members[0][1]["scoring"]
        for name in method_names(s for _, s, _ in members):  # each over the folders that ran it
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


def ratio_sums(folder, converged_after_s):
    """Per (method, run, quantity) the sum, the sum of squares and the count
    of (estimate - truth) / reported sd from converged_after_s on, over the
    samples where all three are numbers and the sd is positive; quantity is
    ("joint", name) or ("camera", axis)."""
    sums = {}
    with open(f"{folder}/timeseries.csv", newline="") as f:
        reader = csv.DictReader(f)
        triples = []
        for c in reader.fieldnames or []:
            for unit in ("_rad", "_m"):
                if c.endswith("_true" + unit) and not c.startswith("cam_"):
                    name = c[:-len("_true" + unit)]
                    triples.append((("joint", name), c, f"{name}_est{unit}", f"{name}_std{unit}"))
        for axis in CAMERA_AXES:
            unit = "_m" if axis in ("x", "y", "z") else "_rad"
            triples.append((("camera", axis), f"cam_true_{axis}{unit}", f"cam_{axis}{unit}",
                            f"cam_{axis}_std{unit}"))
        names = set(reader.fieldnames or [])
        triples = [t for t in triples if all(c in names for c in t[1:])]
        for row in reader:
            if float(row["time_s"]) < converged_after_s:
                continue
            for quantity, true, est, std in triples:
                try:
                    error = float(row[est]) - float(row[true])
                    sd = float(row[std])
                except ValueError:  # an empty cell: no estimate
                    continue
                if not (math.isfinite(error) and sd > 0 and math.isfinite(sd)):
                    continue
                key = (row["method"], int(row["run"]), quantity)
                total, square, count = sums.get(key, (0.0, 0.0, 0))
                ratio = error / sd
                sums[key] = (total + ratio, square + ratio * ratio, count + 1)
    return sums


def error_over_sd(folders):
    """The --error-over-sd table, pooled per scenario as --pool."""
    groups = scenario_groups(folders)
    print("| scenario | method | runs | joints: pairs, RMS of the mean error / sd, largest, "
          "beyond 2, RMS over samples | camera axes: the same |")
    print("|---|---|---|---|---|")

    def cell(sums):
        if not sums:
            return "- "
        means = [total / count for total, _, count in sums]
        rms = math.sqrt(sum(m * m for m in means) / len(means))
        largest = max(abs(m) for m in means)
        beyond = sum(1 for m in means if abs(m) > 2)
        per_sample = math.sqrt(sum(sq for _, sq, _ in sums) / sum(n for _, _, n in sums))
        return f"{len(means)}, {rms:.2f}, {largest:.2f}, {beyond}, {per_sample:.2f} "

    for scenario, members in groups.items():
        after_s = members[0][1]["scoring"]["converged_after_s"]
        sums_per_folder = [ratio_sums(folder, after_s) for folder, _ in members]  # each read once
        for name in method_names(s for _, s in members):
            runs = 0
            sums = {"joint": [], "camera": []}
            for (_, s), folder_sums in zip(members, sums_per_folder):
                if name not in s["methods"]:
                    continue
                runs += s["methods"][name]["lost"]["of"]
                for (method, _, (kind, _)), run_sums in sorted(folder_sums.items()):
                    if method == name:
                        sums[kind].append(run_sums)
            print(f"| {scenario} | {name} | {runs} | {cell(sums['joint'])}| "
                  f"{cell(sums['camera'])}|")


def pooled(table, folders):
    """Runs a pooled table (--pool, --error-over-sd); 1 on an unreadable or
    mismatched folder, named on stderr."""
    try:
        table(folders)
    except (OSError, ValueError, KeyError) as e:
        print(f"accuracy_table: {e}", file=sys.stderr)
        return 1
    return 0


def main(folders):
    if folders and folders[0] == "--error-over-sd":
        return pooled(error_over_sd, folders[1:])
    if folders and folders[0] == "--camera-axes":
        return camera_axes(folders[1:])
    if folders and folders[0] == "--pool":
        return pooled(pool, folders[1:])
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
