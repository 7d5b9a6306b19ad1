#!/usr/bin/env python3
"""Summarises finished `arttrack run` output folders (their summary.json) as
the table docs/accuracy.md shows: per scenario and method, runs, lost runs,
converged translation error of the worst end effector (p50, p75, p99, mm),
median time to converge, and 2-sigma consistency of angles, biases and
camera offset.

  tools/accuracy_table.py out/paper/*    (each argument: a run's --out folder)

Exit status 1 if a folder has no readable summary.json.
"""
import json
import statistics
import sys


def mm(v):
    return "-" if v is None else f"{1e3 * v:.1f}"


def pct(v):
    return "-" if v is None else f"{100 * v:.0f}%"


def main(folders):
    status = 0
    print("| scenario | method | runs | lost | converged p50 / p75 / p99, mm | "
          "median time to converge, s | within 2 sigma: angles / biases / camera |")
    print("|---|---|---|---|---|---|---|")
    for folder in folders:
        try:
            with open(f"{folder}/summary.json") as f:
                s = json.load(f)
        except (OSError, ValueError) as e:
            print(f"accuracy_table: {folder}: {e}", file=sys.stderr)
            status = 1
            continue
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
            k = m["consistency"]
            print(f"| {s['scenario']} | {name} | {m['lost']['of']} | {m['lost']['runs']} | "
                  f"{mm(c['p50'])} / {mm(c['p75'])} / {mm(c['p99'])} | {ttc} | "
                  f"{pct(k['angles'])} / {pct(k['biases'])} / {pct(k['camera_offset'])} |")
    return status


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
