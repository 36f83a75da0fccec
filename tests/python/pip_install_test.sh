#!/usr/bin/env bash
# `pip install .` of the checkout into a fresh venv of Debian's python3, offline (no index, no build
# isolation: setuptools and numpy from Debian), then the module imported from outside the checkout.
set -euo pipefail
source_dir=$1
python=${2:-/usr/bin/python3}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$python" -m venv --system-site-packages "$work/venv"
"$work/venv/bin/pip" install --quiet --no-build-isolation --no-index --no-deps "$source_dir"
cd "$work"
"$work/venv/bin/python" - "$work" <<'PY'
import sys
import numpy as np
import isoatlas
assert isoatlas.__file__.startswith(sys.argv[1]), isoatlas.__file__
data = np.zeros((24, 24, 24), dtype=np.float32)
data[6:18, 6:18, 6:18] = 100
mask, phi, report = isoatlas.segment(data, seeds=[(12, 12, 12, 3)], target=100, width=40, iterations=30, backend="cpu")
assert report["iterations"] == 30 and mask[12, 12, 12] == 1 and mask[1, 1, 1] == 0
print("pip install: isoatlas imported from", isoatlas.__file__)
PY
# The cohort runner's console script and module entry point, installed with the module.
"$work/venv/bin/isoatlas-cohort" --help | grep -q -- "--scheduler"
"$work/venv/bin/python" -m isoatlas.cohort --help | grep -q -- "--scheduler"
echo "pip install: isoatlas-cohort answers --help"
rm -rf "$source_dir/isoatlas.egg-info"
