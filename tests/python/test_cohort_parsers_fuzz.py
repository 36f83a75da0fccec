"""The cohort's manifest and config parsers, fuzzed: seeded mutations of valid files (bytes flipped,
inserted and deleted, lines dropped and doubled, cells and settings swapped for hostile values). Each
must read, or raise InputError naming the file; any other exception is a crash the command would
print as a traceback. A read manifest's subjects must hold what the command's stages rely on.

ISOATLAS_FUZZ_SECONDS gives each parser that many seconds (scripts/run-fuzz); the default is a fixed
number of mutations, the same on every run."""
import importlib.util
import json
import math
import os
import random
import time

import pytest

_SOURCE = os.path.join(os.path.dirname(__file__), "..", "..", "python", "isoatlas", "cohort", "manifest.py")
_spec = importlib.util.spec_from_file_location("cohort_manifest", _SOURCE)  # the parsers alone: no native module needed
manifest = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(manifest)

GOOD_MANIFEST = (
    "id,volume,seeds,target,width,alpha,edits,backend,series,volume_index\n"
    "ch2,ch2.nii.gz,\"64,115,101,4;70,110,100,3\",112,14,0.8,\"subtract sphere:18,0,0,8\",cpu,,\n"
    "bet,bet/ch2.nii.gz,\"1.5,-2,3e1,2\",,,,\"union box:0,0,0,4,4,4\",auto,1.2.840.1,\n"
    "dicom,series,\"0,0,0,4.5\",100,30,,,gpu,,\n"
    "fmri,bold.nii.gz,\"0,0,0,4.5\",100,30,,,cpu,,12\n")
GOOD_CONFIG = {"target": 100, "width": 30, "alpha": 0.7, "backend": "cpu", "iterations": 500, "topology": "preserve",
               "edits": "subtract sphere:1,2,3,4", "base_ratio": 0.05, "chart_size": 9, "samples": 20000,
               "thumbnail": [64, 64], "allowed_failures": 1, "threads_per_worker": 0}

HOSTILE_CELLS = ["", " ", "nan", "inf", "-inf", "-1", "0", "1e400", "1e-400", "0,0", "1,2,3", "1,2,3,4,5", ";;", ";", "sphere:",
                 "subtract", "subtract sphere:1,2,3", "union blob:1,2,3,4", "x" * 5000, "\x00", "\"", "..", "../..", "/", "é",
                 "1,2,3,nan", "1,2,3,-4", "gpu", "quantum", "a b", "-", "_"]
HOSTILE_VALUES = [None, True, False, 0, -1, 1, 3, 9, 2**64, -(2**64), 1e308, -1e308, float("nan"), float("inf"), 0.5, "", "x",
                  "free", "preserve", "cpu", [], [1], [64, 64], [64, 64, 64], [16.5, 64], {}, {"a": 1}, "subtract sphere:1,2,3,4",
                  "union", 10**400]


def budget():
    """(seconds, or None for a fixed count; the count)."""
    seconds = os.environ.get("ISOATLAS_FUZZ_SECONDS")
    return (float(seconds), None) if seconds else (None, 1500)


def mutate_bytes(rng, data):
    data = bytearray(data)
    for _ in range(rng.randint(1, 4)):
        kind = rng.randrange(6)
        at = rng.randrange(len(data) + 1)
        if kind == 0 and data:
            data[min(at, len(data) - 1)] ^= 1 << rng.randrange(8)
        elif kind == 1:
            data[at:at] = bytes([rng.choice(b",;:\"\n\r\x00\xff0123456789.-e ")])
        elif kind == 2 and data:
            del data[at:at + rng.randint(1, 8)]
        elif kind == 3:
            lines = bytes(data).split(b"\n")
            i = rng.randrange(len(lines))
            lines.insert(i, lines[rng.randrange(len(lines))]) if rng.random() < 0.5 else lines.pop(i)
            data = bytearray(b"\n".join(lines))
        elif kind == 4:
            data[at:at] = bytes(rng.randrange(256) for _ in range(rng.randint(1, 6)))
        else:
            data = data[:at]
    return bytes(data)


def mutate_cells(rng, text):
    lines = text.splitlines()
    for _ in range(rng.randint(1, 3)):
        i = rng.randrange(len(lines))
        cells = lines[i].split(",")
        cells[rng.randrange(len(cells))] = rng.choice(HOSTILE_CELLS)
        lines[i] = ",".join(cells)
    return ("\n".join(lines) + "\n").encode("utf-8", "surrogatepass")


def mutate_config(rng):
    config = dict(GOOD_CONFIG)
    for _ in range(rng.randint(1, 3)):
        kind = rng.randrange(4)
        key = rng.choice(list(manifest.DEFAULTS))
        if kind == 0:
            config[key] = rng.choice(HOSTILE_VALUES)
        elif kind == 1:
            config.pop(key, None)
        elif kind == 2:
            config[rng.choice(["thumbnail", "chart_size", "edits"])] = rng.choice(HOSTILE_VALUES)
        else:
            config["unknown_" + str(rng.randrange(3))] = 1
    text = json.dumps(config, allow_nan=True) if rng.random() < 0.9 else rng.choice(["[]", "1", "null", "\"x\"", "{", ""])
    return mutate_bytes(rng, text.encode()) if rng.random() < 0.2 else text.encode()


def check_subjects(subjects):
    """What the stages rely on: a folder name, seeds of four finite numbers with r > 0, numbers for
    the settings given, a known backend."""
    for s in subjects:
        assert manifest._ID.match(s.id)
        assert s.seeds and all(len(seed) == 4 and all(math.isfinite(v) for v in seed) and seed[3] > 0 for seed in s.seeds), s
        for value in (s.target, s.width, s.alpha):
            assert value is None or (isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value)), s
        assert s.backend in ("gpu", "cpu", "auto")
        assert isinstance(s.volume, str) and isinstance(s.series, str)
        assert s.volume_index is None or (type(s.volume_index) is int and s.volume_index >= 0), s


def run(make_input, parse, path, seed, named=()):
    """Runs `parse` on mutations written to `path` until the budget is spent; returns how many ran. A
    refusal must name `path` or one of the files in `named` (the other file the parse reads)."""
    seconds, count = budget()
    rng = random.Random(seed)
    deadline = time.monotonic() + seconds if seconds else None
    n = 0
    while (deadline and time.monotonic() < deadline) or (count and n < count):
        data = make_input(rng)
        with open(path, "wb") as f:
            f.write(data)
        try:
            parse(path)
        except manifest.InputError as e:
            assert str(e).startswith((str(path), *named)), f"the message names the file: {e}"
            assert "\n" not in str(e).strip(), f"one line: {e!r}"
        except Exception as e:  # noqa: BLE001 - what the fuzzing looks for
            pytest.fail(f"input {data!r}: {type(e).__name__}: {e}")
        n += 1
    return n


def test_the_good_inputs_read(tmp_path):
    (tmp_path / "c.json").write_text(json.dumps(GOOD_CONFIG))
    config = manifest.read_config(str(tmp_path / "c.json"))
    (tmp_path / "m.csv").write_text(GOOD_MANIFEST)
    subjects = manifest.read_manifest(str(tmp_path / "m.csv"), config)
    assert [s.id for s in subjects] == ["ch2", "bet", "dicom", "fmri"]
    assert [s.volume_index for s in subjects] == [None, None, None, 12]
    check_subjects(subjects)


def test_the_manifest_parser_reads_or_refuses_every_mutation(tmp_path):
    config = manifest.read_config(None)
    path = str(tmp_path / "m.csv")

    def parse(p):
        check_subjects(manifest.read_manifest(p, config))
    inputs = lambda rng: mutate_bytes(rng, GOOD_MANIFEST.encode()) if rng.random() < 0.5 else mutate_cells(rng, GOOD_MANIFEST)
    assert run(inputs, parse, path, seed=1) > 0


def test_the_config_parser_reads_or_refuses_every_mutation(tmp_path):
    path, rows = str(tmp_path / "c.json"), str(tmp_path / "m.csv")
    (tmp_path / "m.csv").write_text(GOOD_MANIFEST.replace("112,14,0.8", ",,"))

    def parse(p):
        # The config's values are the rows' defaults: a row that leaves its cells empty takes them.
        check_subjects(manifest.read_manifest(rows, manifest.read_config(p)))
    assert run(mutate_config, parse, path, seed=2, named=(rows,)) > 0


def test_the_stage_list_parser_reads_or_refuses_every_mutation():
    rng = random.Random(3)
    for _ in range(budget()[1] or 2000):
        text = mutate_bytes(rng, b"segment,extract,build,eval,render").decode("utf-8", "replace")
        try:
            stages = manifest.parse_stages(text)
            assert stages and all(s in manifest.STAGES for s in stages)
        except manifest.InputError:
            pass
