#!/usr/bin/env python3
"""bench_large_volume: a volume read in place against the same voxels read whole into memory (issue 67).
bench/make_phantom.py writes an N^3 uint16 phantom of tubes and shells as an uncompressed .nii (which
`isoatlas segment` maps, reading each page's voxels as the band reaches it) and a .nhdr naming the same
bytes (which it reads whole); both are segmented from the phantom's seed on the CPU backend until
converged. Per case: the process's peak resident memory (the kernel's, by wait4: for the mapped file it
counts the file's pages read, which the system may reclaim), the segmentation's seconds, and the
seconds per iteration and voxel of the peak active pages, the two paths side by side. The masks must be
the same voxel for voxel.
    /usr/bin/python3 bench/large_volume_bench.py [N ...]   (default 512)"""
import gzip
import json
import os
import subprocess
import sys
import tempfile

from cohort_bench import machine

HERE = os.path.dirname(os.path.abspath(__file__))
ISOATLAS = os.path.join(HERE, "..", "build", "release", "isoatlas")
sys.path.insert(0, HERE)
import make_phantom  # noqa: E402  (beside this file)

PAGE_VOXELS = 8 ** 3  # segment's default page


def segment(volume, n, work, name):
    """Runs `isoatlas segment` on `volume`; its report, peak RSS (MiB) and mask bytes."""
    seed = ",".join(str(c) for c in make_phantom.seed_voxel(n))
    mask, report = os.path.join(work, name + ".mask.nii.gz"), os.path.join(work, name + ".json")
    args = [ISOATLAS, "segment", volume, "--seed", seed + ",3", "-T", "1000", "-e", "300", "-a", "0.5", "--converge",
            "--iterations", "20000", "--backend", "cpu", "-q", "-o", mask, "--report", report]
    child = subprocess.Popen(args)
    _, status, usage = os.wait4(child.pid, 0)
    child.returncode = os.waitstatus_to_exitcode(status)
    if child.returncode != 0:
        sys.exit(f"bench_large_volume: {' '.join(args)} failed (exit {child.returncode})")
    with open(report) as f:
        r = json.load(f)
    with gzip.open(mask) as f:
        voxels = f.read()[352:]
    return r, usage.ru_maxrss / 1024.0, voxels


def figure(case, metric, ours, theirs):
    print(json.dumps({"bench": "large_volume", "case": case, "metric": metric, "isoatlas": ours,
                      "peer": "the same voxels read whole into memory (.nhdr)", "peer_value": theirs,
                      "ratio": theirs / ours if ours else None, "machine": machine()}))
    sys.stdout.flush()


def main():
    sizes = [int(a) for a in sys.argv[1:]] or [512]
    for n in sizes:
        with tempfile.TemporaryDirectory() as work:
            nii = os.path.join(work, f"phantom{n}.nii")
            subprocess.run([sys.executable, os.path.join(HERE, "make_phantom.py"), str(n), nii], check=True)
            mapped, mapped_rss, mapped_mask = segment(nii, n, work, "mapped")
            whole, whole_rss, whole_mask = segment(nii[:-4] + ".nhdr", n, work, "whole")
        if mapped["volume_read"] != "in place (mapped)" or whole["volume_read"] != "into memory":
            sys.exit("bench_large_volume: the two runs did not read the volume as intended")
        if mapped_mask != whole_mask:
            sys.exit("bench_large_volume: the mask read in place differs from the one read into memory")
        case = f"phantom {n}^3 uint16 ({n ** 3 * 2 / 2 ** 20:.0f} MiB), one seed, cpu, {mapped['iterations']} iterations"

        def per_voxel(r):
            return r["seconds"] / (r["iterations"] * r["active_pages_peak"] * PAGE_VOXELS) * 1e9

        figure(case, "peak resident memory of the process (MiB)", mapped_rss, whole_rss)
        figure(case, "solver's physical_bytes_peak (MiB)", mapped["physical_bytes_peak"] / 2 ** 20, whole["physical_bytes_peak"] / 2 ** 20)
        figure(case, "segmentation seconds", mapped["seconds"], whole["seconds"])
        figure(case, "ns per iteration and voxel of the peak active pages", per_voxel(mapped), per_voxel(whole))


if __name__ == "__main__":
    main()
