"""isoatlas from Python: segment a scan, edit it, extract and model its surface.

Volumes are numpy arrays indexed (x, y, z) with a 4 x 4 affine to world millimetres (RAS), exactly
as nibabel gives them: ``read_volume`` returns an ``isoatlas.Volume`` whose ``.data`` shares its
voxels and whose ``.affine`` equals nibabel's; anywhere a volume is taken, a Volume, a nibabel image
or an array (with ``affine=``) will do. Each stage is the library call the ``isoatlas`` command
makes, so results equal the command's.

    import nibabel as nib, isoatlas
    img = nib.load("ch2.nii.gz")
    mask, phi, report = isoatlas.segment(img, seeds=[(64, 115, 101, 4)], target=112, width=14, alpha=0.8)
    vertices, triangles = isoatlas.extract(phi, iso=0, affine=img.affine)

Bad input raises ValueError with the command's message (a missing file FileNotFoundError); long
calls release the GIL, report progress to ``progress(task, fraction)`` and stop on Ctrl-C.
``isoatlas.eval`` is left out of ``__all__`` so that ``from isoatlas import *`` keeps Python's eval.
"""
from ._isoatlas import (LevelSet, Model, Volume, build, edit, eval, extract, load_model, probe, read_mesh, read_volume, render, segment,
                        set_max_memory, max_memory, set_quiet, set_threads, surface_figures, write_mesh, write_png, write_volume)

__all__ = ["Volume", "read_volume", "write_volume", "probe", "segment", "LevelSet", "extract", "read_mesh", "write_mesh", "surface_figures",
           "build", "Model", "load_model", "edit", "render", "write_png", "set_quiet", "set_threads",
           "set_max_memory", "max_memory"]
