"""isoatlas-cohort: segment, mesh and model a cohort of scans on a Dask cluster, resumably, with a
results table (``python3 -m isoatlas.cohort`` is the same command; docs/cohort.md is the guide).

    isoatlas-cohort MANIFEST.csv --out DIR [--workers N] [--scheduler tcp://HOST:8786]
                    [--stages segment,extract,build,eval,render] [--config COHORT.json]

Each subject runs the module's own stages (the library calls the isoatlas command makes) as one Dask
task; its products go to DIR/ID/ (mask.nii.gz, surface.ply, model.isoatlas, thumbnail.png and
report.json, each written whole or not at all); DIR/cohort.csv holds a row per subject and
DIR/index.html shows them. ``run_cohort`` is the same from Python.
"""
from .manifest import InputError
from .runner import run_cohort

__all__ = ["run_cohort", "InputError", "main"]


def main(argv=None):
    from .__main__ import main as command
    return command(argv)
