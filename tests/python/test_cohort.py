"""isoatlas-cohort on a local Dask cluster of 2 worker processes over 6 small phantoms: failures become
rows with the command's messages, good subjects equal the command's results, a re-run does no work,
a changed row redoes only itself, a killed worker's subject is run elsewhere, Ctrl-C then resume."""
import csv
import json
import os
import re
import signal
import subprocess
import sys
import threading
import time

import nibabel as nib
import numpy as np
import psutil
import pytest

from isoatlas.cohort import main as cohort_main

EXE = os.environ["ISOATLAS_EXE"]
SPACING = 1.5
ORIGIN = np.array([-30.0, -30.0, -30.0])
CONFIG = {"target": 100, "width": 30, "chart_size": 9, "samples": 20000, "thumbnail": [64, 64], "backend": "cpu"}
GOOD = ["ball", "big-ball", "torus", "carved"]


def write_phantom(path, shape, inside):
    """A bright shape (100) on a dark ground (20) with noise, 1.5 mm voxels from ORIGIN."""
    x, y, z = np.meshgrid(*[ORIGIN[a] + SPACING * np.arange(shape[a]) for a in range(3)], indexing="ij")
    rng = np.random.default_rng(len(path))
    data = np.where(inside(x, y, z), 100, 20) + rng.normal(0, 3, shape)
    affine = np.diag([SPACING, SPACING, SPACING, 1.0])
    affine[:3, 3] = ORIGIN
    nib.save(nib.Nifti1Image(data.astype(np.int16), affine), path)


def make_study(folder, size=40):
    """Six subjects: four good (two balls, a torus, a ball with a bite carved out), a damaged file, a
    seed outside its volume. Returns the manifest's path."""
    os.makedirs(folder, exist_ok=True)
    shape = (size, size, size)
    write_phantom(os.path.join(folder, "ball.nii.gz"), shape, lambda x, y, z: x**2 + y**2 + z**2 < 12**2)
    write_phantom(os.path.join(folder, "big-ball.nii.gz"), shape, lambda x, y, z: x**2 + y**2 + z**2 < 18**2)
    write_phantom(os.path.join(folder, "torus.nii.gz"), shape,
                  lambda x, y, z: (np.sqrt(x**2 + y**2) - 15) ** 2 + z**2 < 6**2)
    with open(os.path.join(folder, "damaged.nii.gz"), "wb") as f:
        f.write(b"\x1f\x8b\x08\x00 not a volume")
    rows = [("ball", "ball.nii.gz", "0,0,0,4.5", ""),
            ("big-ball", "big-ball.nii.gz", "0,0,0,4.5;6,0,0,3", ""),
            ("torus", "torus.nii.gz", "15,0,0,3", ""),
            ("carved", "big-ball.nii.gz", "0,0,0,4.5", "subtract sphere:18,0,0,8"),
            ("damaged", "damaged.nii.gz", "0,0,0,4.5", ""),
            ("outside", "ball.nii.gz", "500,0,0,4.5", "")]
    manifest = os.path.join(folder, "manifest.csv")
    with open(manifest, "w", newline="") as f:
        writer = csv.writer(f)
        writer.writerow(["id", "volume", "seeds", "edits"])
        writer.writerows(rows)
    with open(os.path.join(folder, "cohort.json"), "w") as f:
        json.dump(CONFIG, f)
    return manifest


class Cohort:
    """isoatlas-cohort as a process, its stderr lines collected as they come."""

    def __init__(self, manifest, out, *extra):
        folder = os.path.dirname(manifest)
        self.process = subprocess.Popen(
            [sys.executable, "-m", "isoatlas.cohort", manifest, "--out", out, "--workers", "2", "--config",
             os.path.join(folder, "cohort.json"), *extra], stderr=subprocess.PIPE, text=True, start_new_session=True)
        self.lines = []
        self.reader = threading.Thread(target=lambda: self.lines.extend(self.process.stderr), daemon=True)
        self.reader.start()

    def wait_for(self, text, timeout=120):
        deadline = time.monotonic() + timeout
        while not any(text in line for line in self.lines):
            assert self.process.poll() is None, "".join(self.lines)
            assert time.monotonic() < deadline, "".join(self.lines)
            time.sleep(0.02)

    def finish(self, timeout=300):
        code = self.process.wait(timeout=timeout)
        self.reader.join(timeout=10)
        return code, "".join(self.lines)


def table(out):
    with open(os.path.join(out, "cohort.csv")) as f:
        return {row["id"]: row for row in csv.DictReader(f)}


def files_of(out):
    """Every file under `out` with its bytes' hash and modification time."""
    found = {}
    for root, _, names in os.walk(out):
        for name in names:
            path = os.path.join(root, name)
            with open(path, "rb") as f:
                found[os.path.relpath(path, out)] = (hash(f.read()), os.stat(path).st_mtime_ns)
    return found


@pytest.fixture(scope="module")
def study(tmp_path_factory):
    """The study run once: (manifest, out, exit code, stderr)."""
    folder = str(tmp_path_factory.mktemp("study"))
    manifest = make_study(folder)
    out = os.path.join(folder, "out")
    code, log = Cohort(manifest, out).finish()
    return manifest, out, code, log


def test_failures_are_rows_with_the_commands_messages_and_the_rest_go_on(study):
    manifest, out, code, log = study
    rows = table(out)
    assert code == 2, log  # two subjects failed
    assert list(rows) == GOOD + ["damaged", "outside"]
    assert rows["damaged"]["status"] == "failed" and "not a readable NIfTI" in rows["damaged"]["error"]
    assert rows["outside"]["status"] == "failed" and "outside the volume" in rows["outside"]["error"]
    assert "500" in rows["outside"]["error"]  # names the seed in world mm
    for name in GOOD:
        r = rows[name]
        assert r["status"] == "done" and r["error"] == "", r
        assert r["converged"] == "True" and int(r["iterations"]) > 0
        assert int(r["components"]) == 1
        assert int(r["genus"]) == (1 if name == "torus" else 0), r
        assert float(r["psnr_top_db"]) > float(r["psnr_level0_db"]) > 10
        assert int(r["model_bytes"]) == os.path.getsize(os.path.join(out, name, "model.isoatlas"))
        assert r["worker"].startswith("tcp://")
        for product in ("mask.nii.gz", "surface.ply", "model.isoatlas", "thumbnail.png", "report.json"):
            assert os.path.isfile(os.path.join(out, name, product)), (name, product)
        assert float(r["seconds_total"]) >= float(r["seconds_segment"]) > 0
    # Volumes against the analytic shapes (the voxel count times 1.5^3 mm^3), areas against the spheres'.
    assert float(rows["ball"]["volume_mm3"]) == pytest.approx(4 / 3 * np.pi * 12**3, rel=0.1)
    assert float(rows["big-ball"]["volume_mm3"]) == pytest.approx(4 / 3 * np.pi * 18**3, rel=0.1)
    assert float(rows["ball"]["area_mm2"]) == pytest.approx(4 * np.pi * 12**2, rel=0.15)
    assert float(rows["carved"]["volume_mm3"]) < float(rows["big-ball"]["volume_mm3"]) * 0.97
    assert os.path.isfile(os.path.join(out, "carved", "mask_edited.nii.gz"))
    page = open(os.path.join(out, "index.html")).read()
    assert all(f"{name}/thumbnail.png" in page for name in GOOD) and "2 failed" in page
    assert os.path.isfile(os.path.join(out, "volumes.png"))
    assert not [f for f in files_of(out) if ".partial." in f]
    for name in GOOD:  # one log line per stage per subject
        for stage in ("segment", "extract", "build", "eval", "render"):
            assert f"cohort: {name}: {stage} " in log, (name, stage)


def test_a_subjects_mask_equals_the_commands_voxel_for_voxel(study, tmp_path):
    manifest, out, _, _ = study
    volume = os.path.join(os.path.dirname(manifest), "big-ball.nii.gz")
    mask = str(tmp_path / "mask.nii.gz")
    # The manifest's world seeds (0,0,0,4.5) and (6,0,0,3) in voxel indices: (30 - 0) / 1.5 = 20, radius 3 and 2.
    subprocess.run([EXE, "segment", volume, "--seed", "20,20,20,3", "--seed", "24,20,20,2", "-T", "100", "-e", "30", "-a", "0.5",
                    "-n", "1000", "--converge", "--backend", "cpu", "-o", mask, "-q"], check=True)
    ours = np.asanyarray(nib.load(os.path.join(out, "big-ball", "mask.nii.gz")).dataobj)
    theirs = np.asanyarray(nib.load(mask).dataobj)
    assert ours.shape == theirs.shape and ours.sum() > 1000
    assert np.array_equal(ours, theirs)


def test_a_rerun_does_no_work_and_touches_nothing(study):
    manifest, out, _, _ = study
    before = files_of(out)
    code, log = Cohort(manifest, out).finish()
    assert code == 2, log
    assert "6 of 6 subjects already settled" in log
    assert "segment" not in log.replace("segment,", "")
    assert files_of(out) == before


def test_a_changed_row_redoes_only_that_subject(study):
    manifest, out, _, _ = study
    before = files_of(out)
    text = open(manifest).read()
    with open(manifest, "w") as f:
        f.write(text.replace("torus.nii.gz,\"15,0,0,3\"", "torus.nii.gz,\"15,0,0,4\""))
    try:
        code, log = Cohort(manifest, out).finish()
    finally:
        with open(manifest, "w") as f:
            f.write(text)
    assert code == 2, log
    assert "5 of 6 subjects already settled" in log and "cohort: torus: segment" in log
    after = files_of(out)
    changed = {path for path in after if after[path] != before.get(path)}
    assert changed and all(path.startswith("torus/") or path in ("cohort.csv", "index.html") for path in changed), changed
    assert table(out)["torus"]["status"] == "done"


def worker_pids(process):
    """The Dask worker processes the command started (its children spawned by multiprocessing)."""
    return [p.pid for p in psutil.Process(process.pid).children(recursive=True)
            if any("spawn_main" in part for part in p.cmdline())]


def unfinished_subjects(lines):
    """Subjects whose start the log shows and not their end (the last stage's line, or a failure):
    {id: (worker address, pid)}."""
    running = {}
    for line in list(lines):
        if m := re.match(r"^cohort: ([\w.-]+): started on (\S+) \(pid (\d+)\)$", line.strip()):
            running[m.group(1)] = (m.group(2), int(m.group(3)))
        elif m := re.match(r"^cohort: ([\w.-]+): (eval \d|failed: )", line):
            running.pop(m.group(1), None)
    return running


def test_a_killed_worker_s_subject_is_run_elsewhere(tmp_path):
    manifest = make_study(str(tmp_path / "study"), size=56)
    out = str(tmp_path / "out")
    run = Cohort(manifest, out, "--stages", "segment,extract,build,eval")
    run.wait_for(": started on ")
    # A subject that has started and not ended, and its worker: frozen first (SIGSTOP), so that the
    # subject cannot end between the look and the kill; killed once its lines say it is still running.
    for _ in range(200):
        running = unfinished_subjects(run.lines)
        candidates = sorted((s, w) for s, w in running.items() if w[1] in worker_pids(run.process))
        if candidates:
            lost, (address, pid) = candidates[0]
            os.kill(pid, signal.SIGSTOP)
            time.sleep(0.5)  # what it sent before it stopped arrives
            if lost in unfinished_subjects(run.lines):
                os.kill(pid, signal.SIGKILL)
                break
            os.kill(pid, signal.SIGCONT)
        time.sleep(0.02)
    else:
        pytest.fail("no subject was caught running: " + "".join(run.lines))
    code, log = run.finish()
    rows = table(out)
    assert code == 2, log
    assert all(rows[name]["status"] == "done" for name in GOOD), rows
    again = re.search(rf"^cohort: {re.escape(lost)}: started again on (\S+) \(pid (\d+)\): the worker that ran it, "
                      rf"{re.escape(address)} \(pid {pid}\), was lost$", log, re.MULTILINE)
    assert again, log  # the subject the killed worker held was run again, elsewhere, and its report says where
    assert int(again.group(2)) != pid
    with open(os.path.join(out, lost, "report.json")) as f:
        assert json.load(f)["worker"] == again.group(1)
    assert not [f for f in files_of(out) if ".partial." in f]


def test_lines_said_from_two_threads_never_share_a_line(monkeypatch):
    """The progress line and Dask's event handler (another thread) write stderr at once: each line
    must go out whole, or a log line lands behind a progress line and the log cannot be read."""
    from isoatlas.cohort.runner import _Progress

    class Recorder:
        def __init__(self):
            self.writes = []

        def write(self, text):
            self.writes.append(text)
            time.sleep(0)  # lets the other thread in between writes, as a busy machine does

        def flush(self):
            pass

        def isatty(self):
            return False

    recorder = Recorder()
    monkeypatch.setattr(sys, "stderr", recorder)
    progress = _Progress(6, quiet=False)
    threads = [threading.Thread(target=lambda: [progress.show(i, 0, 2) for i in range(200)]),
               threading.Thread(target=lambda: [progress.say(f"cohort: ball: started on here {i}") for i in range(200)])]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    lines = "".join(recorder.writes).split("\n")
    assert lines[-1] == "" and len(lines) == 401
    assert all(re.fullmatch(r"cohort: (\d+/6 subjects: .*|ball: started on here \d+)", line) for line in lines[:-1])
    assert all(w.endswith("\n") and w.count("\n") == 1 for w in recorder.writes)


def test_ctrl_c_stops_cleanly_and_the_next_run_goes_on(tmp_path):
    manifest = make_study(str(tmp_path / "study"))
    out = str(tmp_path / "out")
    run = Cohort(manifest, out)
    run.wait_for(": render ")  # one subject done
    os.killpg(run.process.pid, signal.SIGINT)  # as a terminal's Ctrl-C: the whole process group
    code, log = run.finish(timeout=60)
    assert code == 130, log
    assert "run the same command again" in log
    rows = table(out)
    finished = [name for name, r in rows.items() if r["status"] == "done"]
    assert finished and any(r["status"] == "not run" for r in rows.values()), rows
    before = files_of(out)
    code, log = Cohort(manifest, out).finish()
    assert code == 2, log
    rows = table(out)
    assert all(rows[name]["status"] == "done" for name in GOOD)
    for name in finished:  # what was done before is kept as it was
        assert f"cohort: {name}: segment" not in log
        assert files_of(out)[f"{name}/report.json"] == before[f"{name}/report.json"]


@pytest.mark.parametrize("manifest_text, config, extra, message", [
    ("id,volume\na,x.nii.gz\n", CONFIG, [], "needs a column 'seeds'"),
    ("id,volume,seeds,colour\na,x.nii.gz,\"0,0,0,1\",red\n", CONFIG, [], "unknown column 'colour'"),
    ("id,volume,seeds\na,x.nii.gz,\"0,0,0,1\"\na,y.nii.gz,\"0,0,0,1\"\n", CONFIG, [], "'a' is given twice"),
    ("id,volume,seeds\na/b,x.nii.gz,\"0,0,0,1\"\n", CONFIG, [], "is not a folder name"),
    ("id,volume,seeds\na,x.nii.gz,\"0,0,0\"\n", CONFIG, [], "line 2, seeds: each seed is x,y,z,r"),
    ("id,volume,seeds\na,x.nii.gz,\"0,0,0,-1\"\n", CONFIG, [], "with r > 0"),
    ("id,volume,seeds,target\na,x.nii.gz,\"0,0,0,1\",bright\n", CONFIG, [], "line 2, target: not a number"),
    ("id,volume,seeds,edits\na,x.nii.gz,\"0,0,0,1\",\"carve sphere:0,0,0,1\"\n", CONFIG, [], "'union SHAPE' or 'subtract SHAPE'"),
    ("id,volume,seeds,backend\na,x.nii.gz,\"0,0,0,1\",tpu\n", CONFIG, [], "backend: gpu, cpu or auto"),
    ("id,volume,seeds\n", CONFIG, [], "has no subjects"),
    ("id,volume,seeds\na,x.nii.gz,\"0,0,0,1\"\n", {"colour": 1}, [], "unknown setting 'colour'"),
    ("id,volume,seeds\na,x.nii.gz,\"0,0,0,1\"\n", {"chart_size": 10}, [], "'chart_size' must be 2^k + 1"),
    ("id,volume,seeds\na,x.nii.gz,\"0,0,0,1\"\n", {"iterations": 0}, [], "'iterations' must be a positive number"),
    ("id,volume,seeds\na,x.nii.gz,\"0,0,0,1\"\n", {"base_ratio": 2}, [], "'base_ratio' must be null (build's default) or in (0, 1]"),
    ("id,volume,seeds\na,x.nii.gz,\"0,0,0,1\"\n", {"half_resolution_start": "yes"}, [], "'half_resolution_start' must be true or false"),
    ("id,volume,seeds\na,x.nii.gz,\"0,0,0,1\"\n", {"topology": "keep"}, [], "'topology' must be free or preserve"),
    ("id,volume,seeds\na,x.nii.gz,\"0,0,0,1\"\n", CONFIG, ["--stages", "build"], "--stages: build needs extract"),
    ("id,volume,seeds\na,x.nii.gz,\"0,0,0,1\"\n", CONFIG, ["--stages", "segment,mesh"], "unknown stage 'mesh'"),
    ("id,volume,seeds\na,x.nii.gz,\"0,0,0,1\"\n", CONFIG, ["--workers", "0"], "--workers must be >= 1"),
])
def test_bad_input_exits_2_with_one_line_and_writes_nothing(tmp_path, capsys, manifest_text, config, extra, message):
    manifest, settings, out = tmp_path / "m.csv", tmp_path / "c.json", tmp_path / "out"
    manifest.write_text(manifest_text)
    settings.write_text(json.dumps(config))
    assert cohort_main([str(manifest), "--out", str(out), "--config", str(settings), *extra]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith("isoatlas-cohort: error: ") and message in err, err
    assert not out.exists()


def test_missing_manifest_and_config_are_named(tmp_path, capsys):
    assert cohort_main([str(tmp_path / "none.csv"), "--out", str(tmp_path / "out")]) == 2
    assert "none.csv: no such file (the manifest)" in capsys.readouterr().err
    (tmp_path / "m.csv").write_text("id,volume,seeds\na,x.nii.gz,\"0,0,0,1\"\n")
    assert cohort_main([str(tmp_path / "m.csv"), "--out", str(tmp_path / "out"), "--config", str(tmp_path / "none.json")]) == 2
    assert "none.json: no such file (--config)" in capsys.readouterr().err


def test_the_console_script_module_answers_help():
    result = subprocess.run([sys.executable, "-m", "isoatlas.cohort", "--help"], capture_output=True, text=True)
    assert result.returncode == 0 and "--scheduler" in result.stdout


def test_an_existing_scheduler_runs_the_cohort(tmp_path):
    """dask-scheduler and dask-worker started as docs/cohort.md starts them, then --scheduler."""
    manifest = make_study(str(tmp_path / "study"))
    info = str(tmp_path / "scheduler.json")
    started = [subprocess.Popen(["dask-scheduler", "--port", "0", "--no-dashboard", "--scheduler-file", info],
                                stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)]
    try:
        deadline = time.monotonic() + 60
        while not os.path.isfile(info):
            assert time.monotonic() < deadline and started[0].poll() is None
            time.sleep(0.1)
        time.sleep(0.2)  # written whole
        with open(info) as f:
            address = json.load(f)["address"]
        started.append(subprocess.Popen(["dask-worker", address, "--nworkers", "2", "--nthreads", "1", "--no-dashboard"],
                                        stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL))
        out = str(tmp_path / "out")
        run = subprocess.run([sys.executable, "-m", "isoatlas.cohort", manifest, "--out", out, "--scheduler", address, "--config",
                              os.path.join(os.path.dirname(manifest), "cohort.json"), "--stages", "segment,extract"],
                             capture_output=True, text=True, timeout=300)
        rows = table(out)
        assert run.returncode == 2, run.stderr
        assert all(rows[name]["status"] == "done" for name in GOOD) and rows["damaged"]["status"] == "failed"
        assert os.path.isfile(os.path.join(out, "torus", "surface.ply"))
        assert not os.path.exists(os.path.join(out, "torus", "model.isoatlas"))  # only the stages asked for
    finally:
        for process in reversed(started):
            process.terminate()
            process.wait(timeout=30)


def test_no_scheduler_at_the_address_is_one_line(tmp_path, capsys):
    manifest = make_study(str(tmp_path / "study"))
    assert cohort_main([manifest, "--out", str(tmp_path / "out"), "--scheduler", "tcp://127.0.0.1:9"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "--scheduler tcp://127.0.0.1:9: no Dask scheduler answers there" in err, err
    assert not (tmp_path / "out").exists()


def test_a_segmentation_still_moving_at_its_cap_fails_its_subject(tmp_path):
    """Run in this process (no cluster): a cap of 5 iterations leaves the ball growing."""
    from isoatlas.cohort import manifest as manifests, subject

    path = make_study(str(tmp_path / "study"))
    config = dict(manifests.DEFAULTS, **CONFIG, iterations=5)
    ball = manifests.read_manifest(path, config)[0]
    report = subject.run_subject(ball, config, ["segment", "extract"], str(tmp_path / "out"), "hash")
    assert report["status"] == "failed" and not report["bad_input"], report
    assert "still moved after 5 iterations" in report["error"] and report["figures"]["iterations"] == 5
    assert not os.path.exists(tmp_path / "out" / "ball" / "mask.nii.gz")  # nothing of a failed stage
    with open(tmp_path / "out" / "ball" / "report.json") as f:
        assert json.load(f)["status"] == "failed"


def test_the_half_resolution_start_gives_the_commands_mask(tmp_path):
    """Run in this process (no cluster): with the config's half_resolution_start, the subject's mask is
    `isoatlas segment --converge --half-resolution-start`'s, voxel for voxel."""
    from isoatlas.cohort import manifest as manifests, subject

    path = make_study(str(tmp_path / "study"))
    config = dict(manifests.DEFAULTS, **CONFIG, half_resolution_start=True)
    ball = next(s for s in manifests.read_manifest(path, config) if s.id == "big-ball")
    report = subject.run_subject(ball, config, ["segment"], str(tmp_path / "out"), "hash")
    assert report["status"] == "done", report
    assert report["figures"]["half_resolution_iterations"] > 0
    mask = str(tmp_path / "mask.nii.gz")
    subprocess.run([EXE, "segment", ball.volume, "--seed", "20,20,20,3", "--seed", "24,20,20,2", "-T", "100", "-e", "30", "-a", "0.5",
                    "-n", "1000", "--converge", "--half-resolution-start", "--backend", "cpu", "-o", mask, "-q"], check=True)
    ours = np.asanyarray(nib.load(str(tmp_path / "out" / "big-ball" / "mask.nii.gz")).dataobj)
    assert ours.sum() > 1000 and np.array_equal(ours, np.asanyarray(nib.load(mask).dataobj))


def test_a_preserved_topology_gives_the_commands_mask_and_a_sphere(tmp_path):
    """Run in this process: with the config's topology preserve, the torus subject's mask is
    `isoatlas segment --converge --topology preserve`'s, and its surface a sphere (the free one's a torus)."""
    from isoatlas.cohort import manifest as manifests, subject

    path = make_study(str(tmp_path / "study"))
    for topology, genus in (("preserve", 0), ("free", 1)):
        config = dict(manifests.DEFAULTS, **CONFIG, topology=topology)
        torus = next(s for s in manifests.read_manifest(path, config) if s.id == "torus")
        report = subject.run_subject(torus, config, ["segment", "extract"], str(tmp_path / topology), "hash")
        assert report["status"] == "done", report
        assert report["figures"]["genus"] == genus and report["figures"]["components"] == 1, report["figures"]
    mask = str(tmp_path / "mask.nii.gz")
    subprocess.run([EXE, "segment", torus.volume, "--seed", "30,20,20,2", "-T", "100", "-e", "30", "-a", "0.5", "-n", "1000",
                    "--converge", "--topology", "preserve", "--backend", "cpu", "-o", mask, "-q"], check=True)
    ours = np.asanyarray(nib.load(str(tmp_path / "preserve" / "torus" / "mask.nii.gz")).dataobj)
    assert ours.sum() > 1000 and np.array_equal(ours, np.asanyarray(nib.load(mask).dataobj))


def test_a_volume_of_a_4d_file_is_picked_by_its_index(tmp_path):
    """Run in this process: a 4D file of two phantoms (a ball, then a torus); the row's volume_index
    picks one, and its mask is `isoatlas segment --volume N`'s; without the index the row fails with
    the file's count; a bad index is refused naming the row and column."""
    from isoatlas.cohort import manifest as manifests, subject

    folder = tmp_path / "study"
    make_study(str(folder))
    ball, torus = (nib.load(str(folder / f"{name}.nii.gz")) for name in ("ball", "torus"))
    series = np.stack([np.asanyarray(ball.dataobj), np.asanyarray(torus.dataobj)], axis=-1)
    nib.save(nib.Nifti1Image(series, ball.affine), str(folder / "series.nii.gz"))
    path = folder / "series.csv"
    path.write_text("id,volume,seeds,volume_index\ntorus,series.nii.gz,\"15,0,0,3\",1\nwhole,series.nii.gz,\"15,0,0,3\",\n")
    config = dict(manifests.DEFAULTS, **CONFIG)
    rows = {s.id: s for s in manifests.read_manifest(str(path), config)}
    assert rows["torus"].volume_index == 1 and rows["whole"].volume_index is None
    report = subject.run_subject(rows["torus"], config, ["segment"], str(tmp_path / "out"), "hash")
    assert report["status"] == "done", report
    mask = str(tmp_path / "mask.nii.gz")
    subprocess.run([EXE, "segment", rows["torus"].volume, "--volume", "1", "--seed", "30,20,20,2", "-T", "100", "-e", "30", "-a", "0.5",
                    "-n", "1000", "--converge", "--backend", "cpu", "-o", mask, "-q"], check=True)
    ours = np.asanyarray(nib.load(str(tmp_path / "out" / "torus" / "mask.nii.gz")).dataobj)
    assert ours.sum() > 1000 and np.array_equal(ours, np.asanyarray(nib.load(mask).dataobj))
    failed = subject.run_subject(rows["whole"], config, ["segment"], str(tmp_path / "out"), "hash")
    assert failed["status"] == "failed" and "holds 2 volumes" in failed["error"], failed
    path.write_text("id,volume,seeds,volume_index\ntorus,series.nii.gz,\"15,0,0,3\",-1\n")
    with pytest.raises(manifests.InputError, match=r"line 2, volume_index: which volume of a 4D file"):
        manifests.read_manifest(str(path), config)


def test_the_docs_example_reads_and_its_seeds_lie_in_every_brain():
    """docs/cohort.md's manifest and config as written: three subjects whose world seeds fall inside
    each brain's grid (its affine read by nibabel) and on white matter (T1 near the config's target)."""
    from isoatlas.cohort import manifest as manifests

    here = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "docs", "cohort")
    config = manifests.read_config(os.path.join(here, "mni.json"))
    subjects = manifests.read_manifest(os.path.join(here, "mni.csv"), config)
    assert [s.id for s in subjects] == ["ch2", "ch2bet", "ch2better"]
    for s in subjects:
        image = nib.load(s.volume)  # data/volumes, from scripts/fetch-data
        for x, y, z, r in s.seeds:
            i, j, k = np.rint(np.linalg.solve(image.affine, [x, y, z, 1])[:3]).astype(int)
            assert all(0 <= a < n for a, n in zip((i, j, k), image.shape)), (s.id, (x, y, z))
            assert abs(float(image.dataobj[i, j, k]) - config["target"]) <= config["width"], (s.id, (x, y, z))


def test_only_this_hosts_partials_of_gone_writers_are_removed(tmp_path):
    """A subject's folder on a shared filesystem: another host's partial may be live, and so may a
    partial of a process of this host that still runs; one whose writer is gone goes."""
    import socket
    from isoatlas.cohort.files import remove_partials, write_atomically
    child = subprocess.Popen([sys.executable, "-c", "pass"])
    child.wait()  # reaped: its pid names no process now
    host = socket.gethostname()
    gone = f".{child.pid}-0@{host}.partial.mask.nii.gz"
    live = f".{os.getpid()}-0@{host}.partial.mask.nii.gz"
    elsewhere = f".{child.pid}-0@another-host.partial.mask.nii.gz"
    for name in (gone, live, elsewhere):
        (tmp_path / name).write_bytes(b"half")
    remove_partials(str(tmp_path))
    assert sorted(os.listdir(tmp_path)) == sorted([live, elsewhere])
    write_atomically(str(tmp_path / "report.json"), "{}")
    assert sorted(os.listdir(tmp_path)) == sorted([live, elsewhere, "report.json"]), "no partial of its own left"
