"""The Python module against nibabel and the isoatlas command: volumes read with nibabel's affine and
shared voxels, every array layout and scalar type, segment and extract equal to the CLI's outputs,
bad input raising, the GIL released while a stage runs."""
import json
import os
import signal
import subprocess
import sys
import threading
import time

import nibabel as nib
import numpy as np
import pytest

import isoatlas

EXE = os.environ["ISOATLAS_EXE"]


def phantom():
    """A ch2-like head: a bright ellipsoid in a darker shell, 1.5 mm voxels, an oblique-free RAS affine."""
    x, y, z = np.meshgrid(np.arange(36), np.arange(40), np.arange(30), indexing="ij")
    brain = ((x - 18) / 11.0) ** 2 + ((y - 20) / 13.0) ** 2 + ((z - 15) / 9.0) ** 2 < 1
    head = ((x - 18) / 15.0) ** 2 + ((y - 20) / 17.0) ** 2 + ((z - 15) / 13.0) ** 2 < 1
    rng = np.random.default_rng(5)
    data = np.where(brain, 100, np.where(head, 160, 20)) + rng.normal(0, 3, brain.shape)
    affine = np.diag([1.5, 1.5, 1.5, 1.0])
    affine[:3, 3] = [-27.0, -30.0, -22.5]
    return data.astype(np.int16), affine


def cli(*args):
    result = subprocess.run([EXE, *args], capture_output=True, text=True)
    assert result.returncode == 0, result.stderr
    return result


def read_off(path):
    with open(path) as f:
        words = [w for line in f if not line.startswith("#") for w in line.split()]
    assert words[0] == "OFF"
    nv, nf = int(words[1]), int(words[2])
    values = words[4:]
    vertices = np.array(values[: 3 * nv], dtype=float).reshape(nv, 3)
    faces = np.array(values[3 * nv :], dtype=np.int64).reshape(nf, 4)
    assert (faces[:, 0] == 3).all()
    return vertices, faces[:, 1:]


def command_surface(tmp_path):
    """The phantom segmented and extracted by the command: (mask path, surface path as OFF)."""
    data, affine = phantom()
    path = str(tmp_path / "head.nii.gz")
    nib.save(nib.Nifti1Image(data, affine), path)
    mask, surface = str(tmp_path / "mask.nii.gz"), str(tmp_path / "surface.off")
    cli("segment", path, "--seed", "18,20,15,3", "--target", "100", "--width", "30", "--iterations", "60", "--backend", "cpu", "-o", mask)
    cli("extract", mask, "--backend", "cpu", "-o", surface)
    return mask, surface


def test_volumes_read_as_nibabel_sees_them(tmp_path):
    data, affine = phantom()
    path = str(tmp_path / "head.nii.gz")
    nib.save(nib.Nifti1Image(data, affine), path)
    v = isoatlas.read_volume(path)
    img = nib.load(path)
    assert tuple(v.shape) == (36, 40, 30)
    np.testing.assert_array_equal(v.data, np.asanyarray(img.dataobj))
    np.testing.assert_allclose(v.affine, img.affine)
    np.testing.assert_allclose(v.spacing, [1.5, 1.5, 1.5])
    assert not v.data.flags.owndata and v.data.flags.f_contiguous, "the voxels are shared, not copied"
    # write_volume takes an array and its affine; nibabel reads back the same.
    out = str(tmp_path / "copy.nii.gz")
    isoatlas.write_volume(out, data, affine=affine)
    np.testing.assert_array_equal(np.asanyarray(nib.load(out).dataobj), data)
    np.testing.assert_allclose(nib.load(out).affine, affine)


@pytest.mark.parametrize("dtype", ["u1", "i1", "u2", "i2", "u4", "i4", "f4", "f8", "bool"])
@pytest.mark.parametrize("order", ["C", "F"])
def test_every_layout_and_scalar_type(dtype, order):
    base = np.arange(4 * 5 * 6).reshape(4, 5, 6) % 2 if dtype == "bool" else np.arange(4 * 5 * 6).reshape(4, 5, 6) % 100
    array = np.array(base, dtype=dtype, order=order)
    v = isoatlas.Volume(array, np.eye(4))
    np.testing.assert_array_equal(v.data, array)
    strided = np.array(base, dtype=dtype)[::-1, :, ::2]  # neither C nor Fortran order
    np.testing.assert_array_equal(isoatlas.Volume(strided).data, strided)


def test_nan_and_infinite_voxels_read_as_the_background(tmp_path):
    array = np.arange(60, dtype=np.float32).reshape(3, 4, 5) + 7
    array[0, 1, 2] = np.nan
    array[2, 3, 4] = np.inf
    v = isoatlas.Volume(array, np.eye(4))
    assert v.non_finite_voxels == 2
    expected = np.where(np.isfinite(array), array, 7)
    np.testing.assert_array_equal(v.data, expected)
    nib.save(nib.Nifti1Image(array, np.eye(4)), tmp_path / "nan.nii.gz")
    read = isoatlas.read_volume(str(tmp_path / "nan.nii.gz"))
    assert read.non_finite_voxels == 2
    np.testing.assert_array_equal(read.data, expected)


def test_one_volume_of_a_4d_series_is_read(tmp_path):
    series = np.arange(3 * 4 * 5 * 3, dtype=np.int16).reshape(3, 4, 5, 3)
    nib.save(nib.Nifti1Image(series, np.eye(4)), tmp_path / "series.nii.gz")
    for k in range(3):
        np.testing.assert_array_equal(isoatlas.read_volume(str(tmp_path / "series.nii.gz"), volume=k).data, series[..., k])
    with pytest.raises(ValueError, match="holds 3 volumes"):
        isoatlas.read_volume(str(tmp_path / "series.nii.gz"))
    with pytest.raises(ValueError, match="past the last"):
        isoatlas.read_volume(str(tmp_path / "series.nii.gz"), volume=3)


def test_a_gifti_surface_samples_the_masks_boundary_in_world_space(tmp_path):
    """A ball of 10 mm drawn in world space through a rotated, anisotropic affine: the surface extract
    writes as GIfTI, read by nibabel, lies on the ball's sphere in world millimetres."""
    turn_z, turn_x = np.radians(30), np.radians(20)
    rz = np.array([[np.cos(turn_z), -np.sin(turn_z), 0], [np.sin(turn_z), np.cos(turn_z), 0], [0, 0, 1]])
    rx = np.array([[1, 0, 0], [0, np.cos(turn_x), -np.sin(turn_x)], [0, np.sin(turn_x), np.cos(turn_x)]])
    affine = np.eye(4)
    affine[:3, :3] = rz @ rx @ np.diag([0.8, 1.3, 2.0])
    affine[:3, 3] = [12.0, -40.0, 7.5]
    dims = (48, 30, 20)
    ijk = np.stack(np.meshgrid(*[np.arange(n) for n in dims], indexing="ij"), axis=-1).reshape(-1, 3)
    world = ijk @ affine[:3, :3].T + affine[:3, 3]
    centre = affine[:3, :3] @ np.array([23.5, 14.5, 9.5]) + affine[:3, 3]
    radius = 10.0
    mask = (np.linalg.norm(world - centre, axis=1) < radius).reshape(dims).astype(np.uint8)
    nib.save(nib.Nifti1Image(mask, affine), tmp_path / "ball.nii.gz")
    cli("extract", str(tmp_path / "ball.nii.gz"), "--backend", "cpu", "-o", str(tmp_path / "ball.surf.gii"))
    points, _ = nib.load(str(tmp_path / "ball.surf.gii")).agg_data(("pointset", "triangle"))
    distance = np.linalg.norm(points - centre, axis=1)
    assert abs(distance.mean() - radius) < 0.5, distance.mean()
    assert np.abs(distance - radius).max() < 1.2, np.abs(distance - radius).max()  # within the coarsest voxel side


def test_bad_input_raises():
    with pytest.raises(ValueError, match="int64"):
        isoatlas.Volume(np.zeros((3, 3, 3), dtype=np.int64))
    with pytest.raises(ValueError, match="3D"):
        isoatlas.Volume(np.zeros((3, 3)))
    with pytest.raises(ValueError, match="affine"):
        isoatlas.Volume(np.zeros((3, 3, 3), dtype=np.uint8), affine=np.eye(3))
    with pytest.raises(ValueError, match="every voxel is NaN or infinite"):
        isoatlas.Volume(np.full((3, 3, 3), np.nan, dtype=np.float32))
    with pytest.raises(FileNotFoundError):
        isoatlas.read_volume("/nonexistent/head.nii.gz")
    data, affine = phantom()
    with pytest.raises(ValueError, match=r"^width eps must be > 0 \(got -1"):
        isoatlas.segment(data, seeds=[(18, 20, 15)], target=100, width=-1, affine=affine)
    with pytest.raises(ValueError, match="seeds"):
        isoatlas.segment(data, seeds=[(180, 20, 15)], target=100, width=30, affine=affine)
    # The whole sentence that names the keyword and the volume's bounds, not a word any message holds.
    with pytest.raises(ValueError, match=r"^probe: at \(18\.0+, 20\.0+, 99\.0+\) lies outside the volume, whose voxel indices run 0\.\.35, 0\.\.39, 0\.\.29$"):
        isoatlas.probe(data, at=(18, 20, 99), affine=affine)


def test_segment_and_extract_equal_the_command(tmp_path):
    data, affine = phantom()
    path = str(tmp_path / "head.nii.gz")
    nib.save(nib.Nifti1Image(data, affine), path)
    img = nib.load(path)
    probed = isoatlas.probe(img, at=(18, 20, 15), radius=3)
    assert abs(probed["mean"] - 100) < 3
    cli("segment", path, "--seed", "18,20,15,3", "--target", "100", "--width", "30", "--alpha", "0.6", "--iterations", "60",
        "--backend", "cpu", "-o", str(tmp_path / "mask.nii.gz"), "--phi", str(tmp_path / "phi.nii.gz"))
    mask, phi, report = isoatlas.segment(img, seeds=[(18, 20, 15, 3)], target=100, width=30, alpha=0.6, iterations=60, backend="cpu")
    np.testing.assert_array_equal(mask, np.asanyarray(nib.load(str(tmp_path / "mask.nii.gz")).dataobj))
    np.testing.assert_array_equal(phi, np.asanyarray(nib.load(str(tmp_path / "phi.nii.gz")).dataobj))
    assert report["iterations"] == 60 and report["backend"] == "cpu"
    from_volume, _, _ = isoatlas.segment(isoatlas.read_volume(path), seeds=[(18, 20, 15, 3)], target=100, width=30, alpha=0.6,
                                         iterations=60, backend="cpu")  # an isoatlas.Volume, read in place
    np.testing.assert_array_equal(from_volume, mask)
    assert mask.sum() > 1000, "the seed grew"
    # A path: an uncompressed NIfTI is read in place (page by page), a compressed one into memory; the same mask.
    uncompressed = tmp_path / "head.nii"
    nib.save(nib.Nifti1Image(data, affine), str(uncompressed))
    for given, read in ((uncompressed, "in place (mapped)"), (path, "into memory")):
        from_path, _, path_report = isoatlas.segment(given, seeds=[(18, 20, 15, 3)], target=100, width=30, alpha=0.6,
                                                     iterations=60, backend="cpu")
        np.testing.assert_array_equal(from_path, mask)
        assert path_report["volume_read"] == read
    with pytest.raises(ValueError, match="affine= places an array"):
        isoatlas.segment(path, seeds=[(18, 20, 15, 3)], target=100, width=30, affine=affine)
    with pytest.raises(FileNotFoundError):
        isoatlas.segment(str(tmp_path / "none.nii"), seeds=[(18, 20, 15, 3)], target=100, width=30)

    # Until converged from the solution at half resolution, both alike, and the full-resolution start agrees.
    cli("segment", path, "--seed", "18,20,15,3", "--target", "100", "--width", "30", "--alpha", "0.6", "--iterations", "400",
        "--converge", "--half-resolution-start", "--backend", "cpu", "-o", str(tmp_path / "converged.nii.gz"))
    converged, _, report = isoatlas.segment(img, seeds=[(18, 20, 15, 3)], target=100, width=30, alpha=0.6, iterations=400,
                                            converge=True, half_resolution_start=True, backend="cpu")
    np.testing.assert_array_equal(converged, np.asanyarray(nib.load(str(tmp_path / "converged.nii.gz")).dataobj))
    assert report["half_resolution_iterations"] > 0 and report["converged"]
    full, _, full_report = isoatlas.segment(img, seeds=[(18, 20, 15, 3)], target=100, width=30, alpha=0.6, iterations=400,
                                            converge=True, backend="cpu")
    assert full_report["half_resolution_iterations"] == 0
    with pytest.raises(ValueError, match="half_resolution_start needs converge"):
        isoatlas.segment(img, seeds=[(18, 20, 15, 3)], target=100, width=30, half_resolution_start=True, backend="cpu")
    dice = 2 * np.logical_and(full, converged).sum() / (full.sum() + converged.sum())
    assert dice >= 0.99, dice

    cli("extract", str(tmp_path / "mask.nii.gz"), "--backend", "cpu", "-o", str(tmp_path / "surface.off"))
    vertices, triangles = isoatlas.extract(mask, affine=affine, backend="cpu")
    expected_vertices, expected_triangles = read_off(str(tmp_path / "surface.off"))
    np.testing.assert_allclose(vertices, expected_vertices, atol=1e-4)
    np.testing.assert_array_equal(triangles, expected_triangles)


def test_a_preserved_topology_equals_the_command_and_stays_a_sphere(tmp_path):
    """A ball seeded in a solid torus: free, it fills the torus (genus 1); preserved, it stops as a
    sphere, and the Python call gives the command's mask."""
    x, y, z = np.meshgrid(np.arange(40), np.arange(40), np.arange(20), indexing="ij")
    ring = (np.hypot(x - 19.5, y - 19.5) - 12) ** 2 + (z - 9.5) ** 2 < 16
    data = np.where(ring, 100, 40).astype(np.int16)
    path = str(tmp_path / "torus.nii.gz")
    nib.save(nib.Nifti1Image(data, np.eye(4)), path)
    args = dict(seeds=[(31.5, 19.5, 9.5, 2)], target=100, width=30, alpha=0.7, iterations=800, converge=True, backend="cpu")
    cli("segment", path, "--seed", "31.5,19.5,9.5,2", "--target", "100", "--width", "30", "--alpha", "0.7", "--iterations", "800",
        "--converge", "--topology", "preserve", "--backend", "cpu", "-o", str(tmp_path / "kept.nii.gz"))
    kept, kept_phi, report = isoatlas.segment(data, topology="preserve", **args)
    np.testing.assert_array_equal(kept, np.asanyarray(nib.load(str(tmp_path / "kept.nii.gz")).dataobj))
    assert report["topology"] == "preserve"
    free, free_phi, _ = isoatlas.segment(data, **args)
    genus = lambda phi: isoatlas.surface_figures(*isoatlas.extract(phi, iso=0.0, backend="cpu"))["genus"]
    assert genus(free_phi) == 1 and genus(kept_phi) == 0
    assert 2 * np.logical_and(kept, free).sum() / (kept.sum() + free.sum()) >= 0.97
    with pytest.raises(ValueError, match="^topology='wrong': say free or preserve$"):
        isoatlas.segment(data, topology="wrong", **args)


def test_long_calls_release_the_gil_and_report_progress():
    data, affine = phantom()
    result = {}

    # Without a progress callback, which would hand the interpreter time of its own: only a released
    # GIL lets this thread spin in the middle of the call (the interpreter's own switching covers its
    # start and end).
    def run():
        result["start"] = time.perf_counter()
        result["mask"] = isoatlas.segment(data, seeds=[(18, 20, 15, 3)], target=100, width=30, iterations=400, backend="cpu",
                                          affine=affine)[0]
        result["end"] = time.perf_counter()

    worker = threading.Thread(target=run)
    spins = []
    worker.start()
    while worker.is_alive():
        spins.append(time.perf_counter())
    worker.join()
    assert "mask" in result
    start, end = result["start"], result["end"]
    middle = [t for t in spins if start + 0.2 * (end - start) < t < end - 0.2 * (end - start)]
    assert len(middle) > 1000, "the solver held the GIL"

    fractions = []
    isoatlas.segment(data, seeds=[(18, 20, 15, 3)], target=100, width=30, iterations=400, backend="cpu", affine=affine,
                     progress=lambda task, f: fractions.append(f))
    assert fractions and fractions[-1] == 1.0 and fractions == sorted(fractions)


def test_two_threads_segment_extract_and_build_as_one_does():
    """Calls from two threads at once (on the CPU backend; the GIL is released while they work) give
    what one thread gets, and each call's progress reaches its own callback only: a thread's progress
    observer is its own (core/progress.h)."""
    data, affine = phantom()
    heard = {}

    def pipeline(k=None):
        def progress(task, fraction):
            heard.setdefault(k, []).append((threading.get_ident(), fraction))
        mask = isoatlas.segment(data, seeds=[(18, 20, 15, 3)], target=100, width=30, iterations=200, backend="cpu",
                                affine=affine, progress=progress)[0]
        vertices, triangles = isoatlas.extract(mask, backend="cpu", affine=affine)[:2]
        model = isoatlas.build(vertices, triangles, base_ratio=0.05, chart_size=9, hausdorff=False)
        return mask, model.mesh_at_level(2)

    serial_mask, (serial_vertices, serial_triangles) = pipeline()
    results = [None, None]

    def run(k):
        heard[k] = [(threading.get_ident(), None)]  # the thread's own id first
        results[k] = pipeline(k)

    threads = [threading.Thread(target=run, args=(k,)) for k in range(2)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    for k in range(2):  # every report of a call came to its own callback, on its own thread, in order, to the end
        own, reports = heard[k][0][0], heard[k][1:]
        fractions = [f for _, f in reports]
        assert reports and all(ident == own for ident, _ in reports), k
        assert fractions == sorted(fractions) and fractions[-1] == 1.0, fractions
    for mask, (vertices, triangles) in results:
        np.testing.assert_array_equal(mask, serial_mask)
        np.testing.assert_array_equal(vertices, serial_vertices)
        np.testing.assert_array_equal(triangles, serial_triangles)


def test_ctrl_c_stops_the_main_threads_call_and_not_another_threads():
    """Ctrl-C reaches the call on the main thread (Python runs signal handlers there), not a helper
    thread's call at the same time, which ends with what it gets alone; and each call's callback hears
    only its own stages' names."""
    data, affine = phantom()
    mask = isoatlas.segment(data, seeds=[(18, 20, 15, 3)], target=100, width=30, iterations=200, backend="cpu", affine=affine)[0]
    vertices, triangles = isoatlas.extract(mask, backend="cpu", affine=affine)[:2]
    alone = isoatlas.build(vertices, triangles, base_ratio=0.05, chart_size=9, hausdorff=False).mesh_at_level(2)
    helper_tasks, main_tasks, result = set(), set(), {}
    helper_running, signal_sent = threading.Event(), threading.Event()

    def heard_by_helper(task, fraction):
        helper_tasks.add(task)
        helper_running.set()

    def helper():
        model = isoatlas.build(vertices, triangles, base_ratio=0.05, chart_size=9, hausdorff=False, progress=heard_by_helper)
        result["level"] = model.mesh_at_level(2)

    def progress(task, fraction):
        main_tasks.add(task)
        if not signal_sent.is_set():
            assert helper_running.wait(60)
            result["helper in flight"] = "level" not in result
            signal_sent.set()
            os.kill(os.getpid(), signal.SIGINT)  # as a terminal's Ctrl-C (raised here, or at the call's next check)

    thread = threading.Thread(target=helper)
    thread.start()
    with pytest.raises(KeyboardInterrupt):
        isoatlas.segment(data, seeds=[(18, 20, 15, 3)], target=100, width=30, iterations=1000000, backend="cpu", affine=affine,
                         progress=progress)
    thread.join()
    assert result["helper in flight"], "the helper's call ended before Ctrl-C: the test proves nothing"
    np.testing.assert_array_equal(result["level"][0], alone[0])
    np.testing.assert_array_equal(result["level"][1], alone[1])
    assert main_tasks and helper_tasks and not main_tasks & helper_tasks, (main_tasks, helper_tasks)


def test_two_threads_segment_on_the_gpu_as_one_does():
    """backend="gpu" from two threads at once: each thread gets a GL context of its own (one is current
    on one thread at a time), and both give the one thread's mask (llvmpipe here)."""
    data, affine = phantom()

    def segment():
        return isoatlas.segment(data, seeds=[(18, 20, 15, 3)], target=100, width=30, iterations=60, backend="gpu", affine=affine)

    alone, _, report = segment()
    assert report["backend"] == "gpu"
    results, errors = [None, None], []

    def run(k):
        try:
            results[k] = segment()[0]
        except Exception as e:  # noqa: BLE001 - the test reports it
            errors.append(repr(e))

    threads = [threading.Thread(target=run, args=(k,)) for k in range(2)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert not errors, errors
    for mask in results:
        np.testing.assert_array_equal(mask, alone)


def test_a_steered_level_set_is_the_segmentation(tmp_path):
    data, affine = phantom()
    mask, phi, _ = isoatlas.segment(data, seeds=[(18, 20, 15, 3)], target=100, width=30, alpha=0.6, iterations=40, backend="cpu",
                                    affine=affine)
    ls = isoatlas.LevelSet(data, target=100, width=5, alpha=0.6, backend="cpu", affine=affine)
    ls.add_sphere((18, 20, 15), 3)
    ls.set_params(width=30)  # steered before it runs
    ls.step(25)
    ls.step(15)
    assert ls.iterations == 40 and ls.active_pages > 0
    np.testing.assert_array_equal(ls.mask(), mask)
    np.testing.assert_array_equal(ls.phi(), phi)
    ls.add_sphere((18, 20, 15), 2, add=False)
    assert ls.mask().sum() < mask.sum()
    with pytest.raises(ValueError, match="alpha"):
        ls.set_params(alpha=2)


def test_build_equals_the_command_and_renders(tmp_path):
    _, surface = command_surface(tmp_path)
    cli("build", surface, "--chart", "9", "--base-ratio", "0.05", "-o", str(tmp_path / "cli.isoatlas"))
    vertices, triangles = read_off(surface)
    # The command's mesh readers keep positions as float32 (OpenMesh's): the same numbers here.
    vertices = vertices.astype(np.float32).astype(np.float64)
    model = isoatlas.build(vertices, triangles, base_ratio=0.05, chart_size=9)
    model.save(str(tmp_path / "py.isoatlas"))
    with open(tmp_path / "cli.isoatlas", "rb") as a, open(tmp_path / "py.isoatlas", "rb") as b:
        assert a.read() == b.read(), "the model file is the command's, byte for byte"
    assert len(model.report) > 0, "what build measured"
    loaded = isoatlas.load_model(str(tmp_path / "cli.isoatlas"))
    base_vertices, base_triangles = loaded.mesh_at_level(0)
    assert len(base_triangles) == 2 * loaded.tiles
    quad_vertices, quads = loaded.base_mesh
    assert quads.shape == (loaded.tiles, 4) and len(quad_vertices) == len(base_vertices)
    fine_vertices, fine_triangles = loaded.mesh_at_level(loaded.max_level)
    assert len(fine_triangles) == 2 * loaded.tiles * (loaded.chart_size - 1) ** 2
    assert loaded.atlas_positions.shape[2] == 3
    picture = isoatlas.render(loaded, width=96, height=64)
    assert picture.shape == (64, 96, 3) and picture.dtype == np.uint8
    assert (picture < 240).any(axis=2).mean() > 0.1, "the model covers part of the picture"
    away = isoatlas.render(loaded, width=96, height=64, camera=(500, 0, 0, 900, 0, 0, 30))  # looking away from it
    assert (away >= 250).all()
    with pytest.raises(ValueError, match="camera"):
        isoatlas.render(loaded, camera=(0, 0, 0))
    with pytest.raises(ValueError, match="chart"):
        isoatlas.build(vertices, triangles, chart_size=10)
    with pytest.raises(ValueError, match="triangles"):
        isoatlas.build(vertices, np.array([[0, 1, len(vertices)]]))


def test_bad_models_and_meshes_raise_as_the_command_refuses_them(tmp_path):
    _, surface = command_surface(tmp_path)
    path = str(tmp_path / "m.isoatlas")
    cli("build", surface, "--chart", "9", "--base-ratio", "0.05", "-o", path)
    with open(path, "rb") as f:
        good = f.read()
    with pytest.raises(FileNotFoundError):
        isoatlas.load_model(str(tmp_path / "missing.isoatlas"))
    with open(tmp_path / "cut.isoatlas", "wb") as f:
        f.write(good[:100])
    with pytest.raises(ValueError, match="cut.isoatlas.*truncated"):
        isoatlas.load_model(str(tmp_path / "cut.isoatlas"))
    with open(tmp_path / "v1.isoatlas", "wb") as f:
        f.write(good[:8] + (1).to_bytes(4, "little") + good[12:])  # a version this isoatlas no longer reads
    with pytest.raises(ValueError, match="build the model again"):
        isoatlas.load_model(str(tmp_path / "v1.isoatlas"))
    # The memory budget, as the command's --max-memory: a model whose charts would take more is refused.
    saved = isoatlas.max_memory()
    try:
        isoatlas.set_max_memory("4K")
        assert isoatlas.max_memory() == 4096
        with pytest.raises(ValueError, match=r"m\.isoatlas: the atlas's \d+ charts of 9 x 9 texels would take [\d.]+ [KM]iB, "
                                             r"more than the memory budget of 4 KiB \(--max-memory\)$"):
            isoatlas.load_model(path)
        with pytest.raises(ValueError, match="is not a size in bytes"):
            isoatlas.set_max_memory("lots")
        isoatlas.set_max_memory(saved)
        assert isoatlas.max_memory() == saved
    finally:
        isoatlas.set_max_memory(saved)
    model = isoatlas.load_model(path)
    with pytest.raises(ValueError, match="level 99 is outside"):
        model.mesh_at_level(99)
    vertices, triangles = read_off(surface)
    with pytest.raises(ValueError, match="not the mesh this model was built from"):
        isoatlas.eval(model, vertices.astype(np.float32).astype(np.float64) * 1.1, triangles, levels="0")


def test_write_png_writes_a_png_and_refuses_other_shapes(tmp_path):
    image = np.zeros((5, 7, 3), dtype=np.uint8)
    image[1, 2] = (255, 128, 3)
    path = str(tmp_path / "p.png")
    isoatlas.write_png(path, image)
    with open(path, "rb") as f:
        assert f.read(8) == b"\x89PNG\r\n\x1a\n"
    with pytest.raises(ValueError, match="H x W"):
        isoatlas.write_png(path, np.zeros((5, 7)))


def test_edit_and_eval_equal_the_command(tmp_path):
    mask_path, surface = command_surface(tmp_path)
    cli("edit", mask_path, "--subtract", "sphere:6,0,0,6", "--union", "box:-3,-3,-3,3,3,20", "--backend", "cpu",
        "-o", str(tmp_path / "edited.nii.gz"))
    mask = nib.load(mask_path)
    edited, report = isoatlas.edit(mask, [("subtract", "sphere:6,0,0,6"), ("union", "box:-3,-3,-3,3,3,20")], backend="cpu")
    np.testing.assert_array_equal(edited, np.asanyarray(nib.load(str(tmp_path / "edited.nii.gz")).dataobj))
    assert report["nodes"] > 0 and edited.sum() != np.asanyarray(mask.dataobj).sum()
    with pytest.raises(ValueError, match="sphere"):
        isoatlas.edit(mask, [("subtract", "sphere:1,2")])
    with pytest.raises(ValueError, match="union"):
        isoatlas.edit(mask, [("add", "sphere:1,2,3,4")])
    # Refused, as the command refuses them: too deep for the node limit, past the tree's depth.
    with pytest.raises(ValueError, match="node limit"):
        isoatlas.edit(mask, [("union", "sphere:0,0,0,6")], depth=45, backend="cpu")
    with pytest.raises(ValueError, match="past the tree's limit"):
        isoatlas.edit(mask, [("union", "sphere:0,0,0,6")], depth=60, backend="cpu")

    cli("build", surface, "--chart", "9", "--base-ratio", "0.05", "-o", str(tmp_path / "m.isoatlas"))
    cli("eval", str(tmp_path / "m.isoatlas"), "--dense", surface, "--levels", "0,4", "--report", str(tmp_path / "eval.json"))
    vertices, triangles = read_off(surface)
    levels = isoatlas.eval(isoatlas.load_model(str(tmp_path / "m.isoatlas")), vertices.astype(np.float32).astype(np.float64), triangles,
                           levels="0,4")
    with open(tmp_path / "eval.json") as f:
        expected = json.load(f)["levels"]
    assert [l["level"] for l in levels] == [0, 4]
    for mine, theirs in zip(levels, expected):
        assert mine["triangles"] == theirs["triangles"]
        assert mine["hausdorff"] == pytest.approx(theirs["hausdorff"], rel=1e-9)


def test_ctrl_c_stops_a_long_call():
    """A segment of many iterations in a child Python, interrupted as a user would: KeyboardInterrupt
    soon after, not when the solver has finished."""
    code = (
        "import sys, numpy as np, isoatlas\n"
        "data = np.zeros((64, 64, 64), dtype=np.float32); data[8:56, 8:56, 8:56] = 100\n"
        "print('ready', flush=True)\n"
        "try:\n"
        "    isoatlas.segment(data, seeds=[(32, 32, 32, 3)], target=100, width=50, iterations=200000, backend='cpu')\n"
        "except KeyboardInterrupt:\n"
        "    print('interrupted', flush=True); sys.exit(0)\n"
        "print('finished', flush=True)\n")
    child = subprocess.Popen([sys.executable, "-c", code], stdout=subprocess.PIPE, text=True, env=os.environ)
    assert child.stdout.readline().strip() == "ready"
    import time
    time.sleep(1.0)
    child.send_signal(signal.SIGINT)
    out, _ = child.communicate(timeout=60)
    assert out.strip() == "interrupted"


def test_auto_without_a_gpu_falls_back_with_a_warning():
    """backend="auto" on a machine whose only GL is a software rasteriser runs on the CPU and warns,
    as the command says it; on a real GPU it runs there without a warning."""
    code = (
        "import warnings, numpy as np, isoatlas\n"
        "data = np.zeros((16, 16, 16), dtype=np.float32); data[4:12, 4:12, 4:12] = 100\n"
        "with warnings.catch_warnings(record=True) as caught:\n"
        "    warnings.simplefilter('always')\n"
        "    _, _, report = isoatlas.segment(data, seeds=[(8, 8, 8, 2)], target=100, width=40, iterations=5, backend='auto')\n"
        "print(report['backend'], len([w for w in caught if 'no GPU' in str(w.message)]))\n")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=os.environ)
    assert out.returncode == 0, out.stderr
    backend, warned = out.stdout.split()
    assert (backend, warned) in (("cpu", "1"), ("gpu", "0"))


def torus_mesh(big=3.0, small=1.0, n=48, m=24):
    """A closed torus of n x m quads split in two, outward: (vertices, triangles)."""
    u, v = np.meshgrid(2 * np.pi * np.arange(n) / n, 2 * np.pi * np.arange(m) / m, indexing="ij")
    vertices = np.stack([(big + small * np.cos(v)) * np.cos(u), (big + small * np.cos(v)) * np.sin(u), small * np.sin(v)], -1).reshape(-1, 3)
    i, j = np.meshgrid(np.arange(n), np.arange(m), indexing="ij")
    a, b = i * m + j, ((i + 1) % n) * m + j
    c, d = ((i + 1) % n) * m + (j + 1) % m, i * m + (j + 1) % m
    triangles = np.concatenate([np.stack([a, b, c], -1).reshape(-1, 3), np.stack([a, c, d], -1).reshape(-1, 3)])
    return vertices, triangles


def test_meshes_round_trip_and_report_their_figures(tmp_path):
    vertices, triangles = torus_mesh()
    figures = isoatlas.surface_figures(vertices, triangles)
    assert figures["closed"] and figures["manifold"] and figures["components"] == 1
    assert figures["genus"] == 1 and figures["euler"] == 0 and figures["triangles"] == len(triangles)
    # The polyhedron's area approaches 4 pi^2 R r from below as the grid refines (within 1 % at 48 x 24).
    assert figures["area_mm2"] == pytest.approx(4 * np.pi**2 * 3.0, rel=0.01) and figures["area_mm2"] < 4 * np.pi**2 * 3.0
    for name in ("t.ply", "t.off", "t.obj"):
        isoatlas.write_mesh(str(tmp_path / name), vertices, triangles)
        v, t = isoatlas.read_mesh(str(tmp_path / name))
        np.testing.assert_allclose(v, vertices, atol=1e-6)  # the PLY stores float32
        np.testing.assert_array_equal(t, triangles)
    isoatlas.write_mesh(str(tmp_path / "t.vtk"), vertices, triangles)
    head = (tmp_path / "t.vtk").read_bytes().split(b"\n")
    assert b"SPACE=RAS" in head[1] and head[4] == b"POINTS %d float" % len(vertices)
    start = (tmp_path / "t.vtk").read_bytes().index(b"float\n") + 6
    points = np.frombuffer((tmp_path / "t.vtk").read_bytes()[start:start + 12 * len(vertices)], dtype=">f4").reshape(-1, 3)
    np.testing.assert_array_equal(points, vertices.astype(np.float32))
    isoatlas.write_mesh(str(tmp_path / "t.surf.gii"), vertices, triangles)
    gifti = nib.load(str(tmp_path / "t.surf.gii"))
    points, faces = gifti.agg_data(("pointset", "triangle"))
    np.testing.assert_array_equal(points, vertices.astype(np.float32))
    np.testing.assert_array_equal(faces, triangles)
    frame = gifti.darrays[0].coordsys
    assert frame.dataspace == frame.xformspace == 1 and np.array_equal(frame.xform, np.eye(4))  # NIFTI_XFORM_SCANNER_ANAT, as is
    isoatlas.write_mesh(str(tmp_path / "lps.ply"), vertices, triangles, space="lps")
    v, t = isoatlas.read_mesh(str(tmp_path / "lps.ply"))
    np.testing.assert_allclose(v, vertices * [-1, -1, 1], atol=1e-6)
    np.testing.assert_array_equal(t, triangles)
    with pytest.raises(ValueError, match="space"):
        isoatlas.write_mesh(str(tmp_path / "t.ply"), vertices, triangles, space="xyz")
    with pytest.raises(ValueError, match="t.xyz"):
        isoatlas.write_mesh(str(tmp_path / "t.xyz"), vertices, triangles)
    with pytest.raises(ValueError, match="row 0 names a vertex"):
        isoatlas.surface_figures(vertices, triangles + len(vertices))
    with pytest.raises(FileNotFoundError, match="none.ply"):
        isoatlas.read_mesh(str(tmp_path / "none.ply"))
    assert not [p for p in os.listdir(tmp_path) if ".partial." in p]


def test_build_takes_the_commands_default_base_size():
    """No base_ratio: the command's default (2 % of the vertices up to 1,000, at least 1 %): 23 of the
    torus's 1,152; a ratio given is taken as given, and one out of range is refused as the command refuses it."""
    vertices, triangles = torus_mesh()
    default = isoatlas.build(vertices, triangles, chart_size=9, hausdorff=False)
    assert default.report["target_vertices"] == 23
    given = isoatlas.build(vertices, triangles, base_ratio=0.05, chart_size=9, hausdorff=False)
    assert given.report["target_vertices"] == 58
    with pytest.raises(ValueError, match="--base-ratio"):
        isoatlas.build(vertices, triangles, base_ratio=0, chart_size=9, hausdorff=False)
