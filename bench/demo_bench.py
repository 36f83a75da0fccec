#!/usr/bin/env python3
"""bench_demo: the demo's seconds, stage by stage, beside the speed issue's target for the whole (30 s
on 2 cores), and eval's beside its own (8 s): `isoatlas run` on ch2 as scripts/run-demo runs it, from an empty output folder, the
binary already built. Prints one JSON line per figure, as the C++ benchmarks do (bench/update_results.py
files them).
    python3 bench/demo_bench.py [DATA_DIR]"""
import json
import os
import subprocess
import sys
import tempfile

from cohort_bench import machine

HERE = os.path.dirname(os.path.abspath(__file__))
ISOATLAS = os.path.join(HERE, "..", "build", "release", "isoatlas")
TARGET_SECONDS = 30
EVAL_TARGET_SECONDS = 8  # the faithful-model issue's: eval of the demo's six levels on 2 cores
CASE = "the demo (isoatlas run ch2: segment, extract, build, eval, renders)"


def figure(metric, ours, peer, theirs, ratio):
    print(json.dumps({"bench": "demo", "case": CASE, "metric": metric, "isoatlas": ours, "peer": peer,
                      "peer_value": theirs, "ratio": ratio, "machine": machine()}))


def main():
    data = sys.argv[1] if len(sys.argv) > 1 else "data"
    volume = os.path.join(data, "volumes", "ch2.nii.gz")
    if not os.path.isfile(volume):
        sys.exit(f"bench_demo: {volume} is missing (scripts/fetch-data)")
    with tempfile.TemporaryDirectory() as work:
        out = os.path.join(work, "demo")
        report = os.path.join(work, "run-report.json")
        result = subprocess.run([ISOATLAS, "run", volume, "-o", out, "--report", report, "-q"])
        if result.returncode != 0:
            sys.exit(f"bench_demo: isoatlas run failed (exit {result.returncode})")
        with open(report) as f:
            run = json.load(f)
    total = run["seconds"]
    figure("seconds, whole demo", total, "the speed issue's target", TARGET_SECONDS, TARGET_SECONDS / total)
    for stage in run["stages"]:
        figure(f"seconds {stage['name']}", stage["seconds"], "seconds, whole demo", total, stage["seconds"] / total)
    for key, seconds in sorted(run.get("model", {}).items()):  # the model's stage, step by step
        if key.startswith("seconds_"):
            figure(f"seconds of the model: {key[len('seconds_'):]}", seconds, "seconds, whole demo", total, seconds / total)
    levels = len(run["model"]["levels"])
    figure(f"seconds of eval, {levels} levels", run["model"]["seconds_eval"], "the faithful-model issue's target", EVAL_TARGET_SECONDS,
           EVAL_TARGET_SECONDS / run["model"]["seconds_eval"])


if __name__ == "__main__":
    main()
