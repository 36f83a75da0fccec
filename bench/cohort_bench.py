#!/usr/bin/env python3
"""bench_cohort: subjects per minute of isoatlas-cohort on the docs' example (the three MNI-space brains
ch2, ch2bet and ch2better with the demo's seeds, every stage), on a local cluster of 1 and of 2 worker
processes, each from an empty output folder. Prints one JSON line per figure, as the C++ benchmarks do
(bench/update_results.py files them); the 1-worker run is the peer of the 2-worker one.
    PYTHONPATH=build/release/python python3 bench/cohort_bench.py [DATA_DIR]"""
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
EXAMPLE = os.path.join(HERE, "..", "docs", "cohort")


def machine():
    model = "unknown CPU"
    with open("/proc/cpuinfo") as f:
        for line in f:
            if line.startswith("model name"):
                model = line.split(":", 1)[1].strip()
                break
    return f"{model}, {os.cpu_count()} cores"


def run(workers, out):
    """Seconds for the whole cohort; its stderr (progress and stage lines) kept in OUT/cohort.log."""
    started = time.perf_counter()
    os.makedirs(out)
    with open(os.path.join(out, "cohort.log"), "w") as log:
        result = subprocess.run([sys.executable, "-m", "isoatlas.cohort", os.path.join(EXAMPLE, "mni.csv"), "--out", out,
                                 "--workers", str(workers), "--config", os.path.join(EXAMPLE, "mni.json")], stderr=log)
    seconds = time.perf_counter() - started
    if result.returncode != 0:
        sys.exit(f"bench_cohort: the cohort failed with {workers} workers (exit {result.returncode}); see {out}/cohort.csv")
    return seconds


def main():
    data = sys.argv[1] if len(sys.argv) > 1 else "data"
    if not os.path.isfile(os.path.join(data, "volumes", "ch2better.nii.gz")):
        sys.exit(f"bench_cohort: {data}/volumes has no ch2better.nii.gz (scripts/fetch-data)")
    subjects = 3
    with tempfile.TemporaryDirectory() as work:
        seconds = {w: run(w, os.path.join(work, f"out{w}")) for w in (2, 1)}
        keep = os.environ.get("ISOATLAS_COHORT_BENCH_KEEP")  # the 2-worker run's folder, for the docs
        if keep:
            shutil.rmtree(keep, ignore_errors=True)
            shutil.copytree(os.path.join(work, "out2"), keep)
    per_minute = {w: subjects * 60 / s for w, s in seconds.items()}
    for metric, ours, theirs in (("subjects per minute, 2 workers", per_minute[2], per_minute[1]),):
        print(json.dumps({"bench": "cohort", "case": "ch2, ch2bet, ch2better (MNI; segment, extract, build, eval, render)",
                          "metric": metric, "isoatlas": ours, "peer": "the same with 1 worker", "peer_value": theirs,
                          "ratio": ours / theirs, "machine": machine()}))
    print(json.dumps({"bench": "cohort", "case": "ch2, ch2bet, ch2better (MNI; segment, extract, build, eval, render)",
                      "metric": "seconds for the cohort, 2 workers", "isoatlas": seconds[2], "peer": "the same with 1 worker",
                      "peer_value": seconds[1], "ratio": seconds[1] / seconds[2], "machine": machine()}))


if __name__ == "__main__":
    main()
