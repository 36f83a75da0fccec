"""One subject's stages, run on a worker by the module's own calls (the library calls the isoatlas
command makes), its products written into OUT/ID/ each whole or not at all, report.json last.

A report.json says whether the subject is done, failed on its input (retried only when the input or
its parameters change) or failed otherwise (retried on the next run), and carries the hash of what
made it, so that a later run skips a subject that would come out the same.
"""
import contextlib
import hashlib
import json
import os
import socket
import sys
import time
import warnings

import numpy as np

import isoatlas

from .files import remove_partials, write_atomically

REPORT = "report.json"
# Each stage's products, in the subject's folder (the edited mask only where there are edits).
PRODUCTS = {"segment": ["mask.nii.gz"], "extract": ["surface.ply"], "build": ["model.isoatlas"], "eval": [],
            "render": ["thumbnail.png"]}
LOG_TOPIC = "isoatlas-cohort"


def folder_of(out_dir, subject):
    return os.path.join(out_dir, subject.id)


def _files_under(folder):
    """Every file under folder, its subfolders' included, in an order that does not depend on the
    file system's (a flat folder's: its names sorted, as before subfolders were searched)."""
    found = []
    for root, dirs, names in os.walk(folder):
        dirs.sort()
        found += [os.path.join(root, n) for n in names]
    return sorted(found, key=lambda p: os.path.relpath(p, folder).split(os.sep))


def input_hash(subject, config, stages):
    """What decides the subject's outputs: the volume's bytes (a DICOM folder's files with its
    subfolders', as the reader searches them: paths and bytes), the row and the config, the stages."""
    h = hashlib.sha256()
    files = _files_under(subject.volume) if os.path.isdir(subject.volume) else [subject.volume]
    for path in files:
        if path != subject.volume:  # a file of a folder: its path there too (a single file's hash stays as it was)
            h.update(os.path.relpath(path, subject.volume).encode() + b"\0")
        try:
            with open(path, "rb") as f:
                for block in iter(lambda: f.read(1 << 20), b""):
                    h.update(block)
        except OSError as e:
            h.update(f"unreadable: {e}".encode())
    settings = {k: config[k] for k in ("iterations", "half_resolution_start", "base_ratio", "chart_size", "samples", "thumbnail")}
    if config["topology"] != "free":  # left out when free, so that the hashes of cohorts from before it stay
        settings["topology"] = config["topology"]
    h.update(json.dumps([subject.parameters(), settings, stages], sort_keys=True).encode())
    return h.hexdigest()


def read_report(out_dir, subject):
    try:
        with open(os.path.join(folder_of(out_dir, subject), REPORT), encoding="utf-8") as f:
            return json.load(f)
    except (OSError, ValueError):
        return None


def is_settled(report, digest, out_dir, subject, stages):
    """Whether a run with this hash need not run the subject again: done with every product there,
    or failed on its input (which has not changed)."""
    if not report or report.get("hash") != digest:
        return False
    if report.get("status") == "failed":
        return report.get("bad_input", False)
    folder = folder_of(out_dir, subject)
    return report.get("status") == "done" and all(os.path.isfile(os.path.join(folder, p)) for p in products(subject, stages))


def products(subject, stages):
    names = [p for s in stages for p in PRODUCTS[s]]
    if subject.edits and "segment" in stages:
        names.append("mask_edited.nii.gz")
    return names


def _worker():
    """The Dask worker running this task, or None in a plain process."""
    try:
        from distributed import get_worker
        return get_worker()
    except (ImportError, ValueError):
        return None


def _log(subject_id, stage, seconds, detail):
    """One line per stage: to the client through Dask's events on a worker, else to stderr."""
    message = {"id": subject_id, "stage": stage, "seconds": seconds, "detail": detail}
    worker = _worker()
    if worker:
        worker.log_event(LOG_TOPIC, message)
    else:
        print(format_log(message), file=sys.stderr, flush=True)


def format_log(message):
    return f"cohort: {message['id']}: {message['stage']} {message['seconds']:.1f} s: {message['detail']}"


def started_event(subject_id, worker):
    """Where a subject starts: the client names a subject started twice (its worker lost)."""
    return {"id": subject_id, "started_on": worker.address, "pid": os.getpid()}


def _world_to_voxel(affine, seed):
    """A seed ball (x, y, z, r) in world mm as (i, j, k, r) in voxel indices (r over the mean spacing)."""
    x, y, z, r = seed
    ijk = np.linalg.solve(affine, [x, y, z, 1.0])[:3]
    spacing = float(np.mean(np.linalg.norm(affine[:3, :3], axis=0)))
    return (float(ijk[0]), float(ijk[1]), float(ijk[2]), r / spacing)


@contextlib.contextmanager
def _naming_world_seeds(seeds):
    """The module's messages give seeds in voxel indices; the manifest gave them in world mm: say both."""
    try:
        yield
    except ValueError as e:
        if not str(e).startswith(("seeds", "probe: at")):
            raise
        world = "; ".join(",".join(f"{x:g}" for x in seed) for seed in seeds)
        raise ValueError(f"{e} (the manifest's seeds {world} in world mm)") from None


class _Stages:
    """The stages of one subject, each a method, sharing what the last one made."""

    def __init__(self, subject, config, folder, figures):
        self.subject, self.config, self.folder, self.figures = subject, config, folder, figures

    def path(self, name):
        return os.path.join(self.folder, name)

    def segment(self):
        s, c = self.subject, self.config
        volume = isoatlas.read_volume(s.volume, volume=s.volume_index, series=s.series)
        self.affine = volume.affine
        seeds = [_world_to_voxel(volume.affine, seed) for seed in s.seeds]
        target, width = s.target, s.width
        with _naming_world_seeds(s.seeds):
            if target is None or width is None:  # as `isoatlas probe` suggests them, in the first seed's ball
                probed = isoatlas.probe(volume, at=list(seeds[0][:3]), radius=seeds[0][3])
                target = probed["target"] if target is None else target
                width = probed["width"] if width is None else width
            mask, self.phi, report = isoatlas.segment(volume, seeds=[list(seed) for seed in seeds], target=target, width=width,
                                                      alpha=s.alpha, backend=s.backend, iterations=c["iterations"], converge=True,
                                                      half_resolution_start=c["half_resolution_start"], topology=c["topology"])
        self.figures.update(target=target, width=width, alpha=s.alpha, iterations=report["iterations"], converged=report["converged"])
        if c["half_resolution_start"]:
            self.figures.update(half_resolution_iterations=report["half_resolution_iterations"])
        if not report["converged"]:
            raise RuntimeError(f"the segmentation still moved after {c['iterations']} iterations (raise 'iterations' in the config, "
                               "or check the seeds, target and width)")
        isoatlas.write_volume(self.path("mask.nii.gz"), mask, volume.affine)
        self.mask = mask
        if s.edits:
            self.mask, _ = isoatlas.edit(mask, s.edits, backend=s.backend, affine=volume.affine)
            isoatlas.write_volume(self.path("mask_edited.nii.gz"), self.mask, volume.affine)
        voxels = int(np.count_nonzero(self.mask))
        self.figures.update(voxels=voxels, volume_mm3=voxels * abs(float(np.linalg.det(volume.affine[:3, :3]))))
        return f"{voxels} voxels in {report['iterations']} iterations (T {target:g}, eps {width:g})"

    def extract(self):
        # As isoatlas run does: phi at 0 (the edited mask at 0.5 where there are edits), the largest part;
        # with the topology preserved, every part (one per seed).
        source, iso = (self.mask, 0.5) if self.subject.edits else (self.phi, 0.0)
        largest = self.config["topology"] == "free"
        self.vertices, self.triangles = isoatlas.extract(source, iso=iso, largest=largest, backend=self.subject.backend, affine=self.affine)
        isoatlas.write_mesh(self.path("surface.ply"), self.vertices, self.triangles)
        surface = isoatlas.surface_figures(self.vertices, self.triangles)
        self.figures.update(triangles=surface["triangles"], area_mm2=surface["area_mm2"], components=surface["components"],
                            genus=surface["genus"], closed=surface["closed"])
        return f"{surface['triangles']} triangles, genus {surface['genus']}, {surface['area_mm2']:.0f} mm^2"

    def build(self):
        c = self.config
        self.model = isoatlas.build(self.vertices, self.triangles, base_ratio=c["base_ratio"], chart_size=c["chart_size"], hausdorff=False)
        self.model.save(self.path("model.isoatlas"))
        self.figures.update(model_bytes=os.path.getsize(self.path("model.isoatlas")), top_level=self.model.max_level,
                            base_vertices=self.model.report.get("base_vertices"))
        return f"{self.figures['base_vertices']} base vertices, {self.figures['model_bytes']} bytes"

    def eval(self):
        top = self.model.max_level
        levels = isoatlas.eval(self.model, self.vertices, self.triangles, levels=f"0,{top}", samples=self.config["samples"])
        self.figures.update(psnr_level0_db=levels[0]["psnr_db"], psnr_top_db=levels[-1]["psnr_db"])
        return f"PSNR {levels[0]['psnr_db']:.1f} dB at level 0, {levels[-1]['psnr_db']:.1f} dB at level {top}"

    def render(self):
        width, height = self.config["thumbnail"]
        isoatlas.write_png(self.path("thumbnail.png"), isoatlas.render(self.model, width=width, height=height))
        return "thumbnail.png"


def run_subject(subject, config, stages, out_dir, digest):
    """Runs the stages of one subject (on a Dask worker, or in this process); returns its report,
    also written to OUT/ID/report.json. A failure is reported, not raised."""
    folder = folder_of(out_dir, subject)
    os.makedirs(folder, exist_ok=True)
    remove_partials(folder)
    worker = _worker()
    if worker:
        isoatlas.set_quiet(True)  # the stage lines go to the client instead
        isoatlas.set_threads(config["threads_per_worker"])  # N workers on N cores, not N times N threads
        worker.log_event(LOG_TOPIC, started_event(subject.id, worker))
    report = {"id": subject.id, "hash": digest, "stages": stages, "seconds": {}, "figures": {},
              "worker": worker.address if worker else f"{socket.gethostname()}:{os.getpid()}"}
    work = _Stages(subject, config, folder, report["figures"])
    started = time.perf_counter()
    try:
        for stage in stages:
            t = time.perf_counter()
            with warnings.catch_warnings(record=True) as said:  # "no GPU: using the CPU backend": into the stage's line
                warnings.simplefilter("always")
                detail = getattr(work, stage)()
            report["seconds"][stage] = time.perf_counter() - t
            _log(subject.id, stage, report["seconds"][stage], "; ".join([detail, *sorted({str(w.message) for w in said})]))
        report["status"] = "done"
    except (ValueError, FileNotFoundError) as e:  # the module's bad input: the command's message
        report.update(status="failed", error=str(e), bad_input=True)
    except Exception as e:  # noqa: BLE001 - any other failure is the subject's, not the cohort's
        report.update(status="failed", error=str(e) or type(e).__name__, bad_input=False)
    report["seconds"]["total"] = time.perf_counter() - started
    write_atomically(os.path.join(folder, REPORT), json.dumps(report, indent=2, sort_keys=True))
    return report
