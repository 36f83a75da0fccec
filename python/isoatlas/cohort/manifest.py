"""The cohort's inputs: the manifest (one row per subject) and the config (defaults for every row).

A manifest is a CSV file with a header. Columns:

    id       a name for the subject's folder (letters, digits, '.', '-', '_')
    volume   the scan (.nii, .nii.gz, .nrrd, .nhdr, .inr, .inr.gz, or a folder of one DICOM series), relative to the manifest's folder
    seeds    seed balls in world mm, ``x,y,z,r;x,y,z,r``
    target, width, alpha   the segmentation's T, eps and alpha (optional; T and eps are otherwise
             probed in the first seed's ball, as ``isoatlas probe`` suggests them)
    edits    boolean edits after the segmentation (optional), ``subtract sphere:x,y,z,r; union box:...``
             with the shapes ``isoatlas edit`` takes
    backend  gpu, cpu or auto (optional)
    series   a DICOM folder's SeriesInstanceUID, where it holds several (optional, as ``--series``)
    volume_index   which volume of a 4D file, from 0 (optional, as ``--volume``; a 4D file needs it)

An empty cell takes the config's value. Errors name the file, the row and the column, and are raised
as ``InputError``: the command prints its one line and exits 2 before any subject runs.
"""
import csv
import json
import math
import os
import re
from dataclasses import dataclass, field

STAGES = ("segment", "extract", "build", "eval", "render")

# The config's keys and their defaults (README and docs/cohort.md list them).
DEFAULTS = {
    "target": None,        # T; None: probed at the first seed
    "width": None,         # eps; None: probed at the first seed
    "alpha": 0.5,          # the segment command's default
    "backend": "auto",
    "iterations": 1000,    # the solver's cap: a subject still moving after this many fails
    "half_resolution_start": False,  # segment --half-resolution-start: faster, its surface a little different
    "topology": "free",    # segment --topology: "preserve" keeps the seeds' topology (one sphere per seed)
    "edits": "",
    "base_ratio": None,    # build --base-ratio; None: build's default
    "chart_size": 33,      # build --chart
    "samples": 200000,     # eval --samples
    "thumbnail": [256, 256],
    "allowed_failures": 2,  # worker deaths one subject may cause before it is given up
    "threads_per_worker": 1,  # the library's threads in each worker (0: every core)
}

COLUMNS = ("id", "volume", "seeds", "target", "width", "alpha", "edits", "backend", "series", "volume_index")
_ID = re.compile(r"^[A-Za-z0-9][A-Za-z0-9._-]*$")


class InputError(ValueError):
    """A bad manifest, config or option: one line naming the file or option."""


@dataclass
class Subject:
    id: str
    volume: str                      # absolute path
    seeds: list                      # [(x, y, z, r)] in world mm
    target: float | None
    width: float | None
    alpha: float
    edits: list = field(default_factory=list)  # [("union" | "subtract", SHAPE)]
    backend: str = "auto"
    series: str = ""                 # a DICOM folder's SeriesInstanceUID; "": its one series
    volume_index: int | None = None  # which volume of a 4D file; None: a 3D file

    def parameters(self):
        """Everything of the row that decides its outputs (the volume's bytes are hashed apart). The
        series and the volume index only where given, so that the hashes of rows from before those
        columns stay."""
        p = {"volume": self.volume, "seeds": self.seeds, "target": self.target, "width": self.width,
             "alpha": self.alpha, "edits": self.edits, "backend": self.backend}
        if self.series:
            p["series"] = self.series
        if self.volume_index is not None:
            p["volume_index"] = self.volume_index
        return p


def read_config(path):
    """The config's values over DEFAULTS; None gives the defaults."""
    config = dict(DEFAULTS)
    if path is None:
        return config
    try:
        with open(path, encoding="utf-8") as f:
            given = json.load(f)
    except FileNotFoundError:
        raise InputError(f"{path}: no such file (--config)") from None
    except (OSError, ValueError) as e:
        raise InputError(f"{path}: not a JSON config ({e})") from None
    if not isinstance(given, dict):
        raise InputError(f"{path}: the config is a JSON object of settings")
    for key, value in given.items():
        if key not in DEFAULTS:
            raise InputError(f"{path}: unknown setting '{_shown(key)}' (known: {', '.join(DEFAULTS)})")
        config[key] = value
    _check_config(config, path)
    return config


def _shown(text, most=60):
    """A user's text as a message quotes it: on one line (control characters escaped), cut short."""
    text = "".join(ch if ch.isprintable() else ascii(ch)[1:-1] for ch in str(text))
    return text if len(text) <= most else text[:most] + "..."


def _is_number(value):
    if not isinstance(value, (int, float)) or isinstance(value, bool):
        return False
    try:
        return math.isfinite(float(value))
    except OverflowError:  # an integer past the largest float
        return False


def _check_config(c, where):
    for key in ("target", "width"):
        if c[key] is not None and not _is_number(c[key]):
            raise InputError(f"{where}: '{key}' must be a number, or null (probed at the first seed)")
    if not _is_number(c["alpha"]):
        raise InputError(f"{where}: 'alpha' must be a number")
    if not isinstance(c["edits"], str):
        raise InputError(f"{where}: 'edits' must be a text of edits, such as \"subtract sphere:x,y,z,r\"")
    parse_edits(c["edits"], f"{where}, edits")

    def positive(key, kind=(int, float)):
        if not isinstance(c[key], kind) or isinstance(c[key], bool) or not 0 < c[key] < 2**31:
            raise InputError(f"{where}: '{key}' must be a positive number below 2^31")
    for key in ("iterations", "chart_size", "samples"):
        positive(key, int)
    ratio = c["base_ratio"]
    if ratio is not None and (not isinstance(ratio, (int, float)) or isinstance(ratio, bool) or not 0 < ratio <= 1):
        raise InputError(f"{where}: 'base_ratio' must be null (build's default) or in (0, 1]")
    for key in ("allowed_failures", "threads_per_worker"):
        if not isinstance(c[key], int) or isinstance(c[key], bool) or not 0 <= c[key] < 2**31:
            raise InputError(f"{where}: '{key}' must be a whole number >= 0 and below 2^31")
    if c["chart_size"] < 3 or (c["chart_size"] - 1) & (c["chart_size"] - 2):
        raise InputError(f"{where}: 'chart_size' must be 2^k + 1 (5, 9, 17, 33, ...)")
    thumbnail = c["thumbnail"]
    if not (isinstance(thumbnail, list) and len(thumbnail) == 2 and all(isinstance(x, int) and 16 <= x <= 2048 for x in thumbnail)):
        raise InputError(f"{where}: 'thumbnail' must be [width, height] in pixels, 16 to 2048")
    if c["backend"] not in ("gpu", "cpu", "auto"):
        raise InputError(f"{where}: 'backend' must be gpu, cpu or auto, not {_shown(repr(c['backend']))}")
    if not isinstance(c["half_resolution_start"], bool):
        raise InputError(f"{where}: 'half_resolution_start' must be true or false")
    if c["topology"] not in ("free", "preserve"):
        raise InputError(f"{where}: 'topology' must be free or preserve, not {_shown(repr(c['topology']))}")


def parse_stages(text):
    """--stages: a comma list of STAGES, each with the stages it needs before it."""
    stages = [s.strip() for s in text.split(",") if s.strip()]
    for s in stages:
        if s not in STAGES:
            raise InputError(f"--stages: unknown stage '{_shown(s)}' (stages: {','.join(STAGES)})")
    needs = {"extract": "segment", "build": "extract", "eval": "build", "render": "build"}
    for s in stages:
        if s in needs and needs[s] not in stages:
            raise InputError(f"--stages: {s} needs {needs[s]}")
    if not stages:
        raise InputError("--stages: name at least one stage")
    return [s for s in STAGES if s in stages]


def parse_seeds(text, where):
    seeds = []
    for part in text.split(";"):
        if not part.strip():
            continue
        try:
            values = [float(x) for x in part.split(",")]
        except ValueError:
            values = []
        if len(values) != 4 or values[3] <= 0 or any(v != v or abs(v) == float("inf") for v in values):
            raise InputError(f"{where}: each seed is x,y,z,r in world mm with r > 0, not '{_shown(part.strip())}'")
        seeds.append(tuple(values))
    if not seeds:
        raise InputError(f"{where}: give at least one seed x,y,z,r (world mm)")
    return seeds


def parse_edits(text, where):
    edits = []
    for part in text.split(";"):
        words = part.split(None, 1)
        if not words:
            continue
        if len(words) != 2 or words[0] not in ("union", "subtract"):
            raise InputError(f"{where}: each edit is 'union SHAPE' or 'subtract SHAPE', not '{_shown(part.strip())}'")
        edits.append((words[0], words[1].strip()))
    return edits


def _number(text, where):
    try:
        value = float(text)
    except ValueError:
        raise InputError(f"{where}: not a number: '{_shown(text)}'") from None
    if value != value or abs(value) == float("inf"):
        raise InputError(f"{where}: not a finite number: '{_shown(text)}'")
    return value


def _volume_index(text, where):
    if not re.fullmatch(r"[0-9]{1,9}", text):
        raise InputError(f"{where}: which volume of a 4D file, from 0 (as --volume), not '{_shown(text)}'")
    return int(text)


def read_manifest(path, config):
    """The subjects of the manifest at `path`, each row's empty cells filled from `config`."""
    try:
        with open(path, newline="", encoding="utf-8") as f:
            reader = csv.DictReader(f)
            rows = list(reader)
            header = list(reader.fieldnames or [])
    except FileNotFoundError:
        raise InputError(f"{path}: no such file (the manifest)") from None
    except (OSError, UnicodeDecodeError, csv.Error) as e:
        raise InputError(f"{path}: not a CSV manifest ({e})") from None
    if not rows:
        raise InputError(f"{path}: the manifest has no subjects (a header, then one row per subject)")
    for name in header:
        if name not in COLUMNS:
            raise InputError(f"{path}: unknown column '{_shown(name)}' (columns: {', '.join(COLUMNS)})")
    for name in ("id", "volume", "seeds"):
        if name not in header:
            raise InputError(f"{path}: the manifest needs a column '{name}'")
    folder = os.path.dirname(os.path.abspath(path))
    subjects, seen = [], set()
    for line, row in enumerate(rows, start=2):
        where = f"{path}, line {line}"
        if None in row or any(v is None for v in row.values()):
            raise InputError(f"{where}: the row has {'more' if None in row else 'fewer'} cells than the header")
        cell = {k: (v or "").strip() for k, v in row.items()}
        subject_id = cell["id"]
        if not _ID.match(subject_id):
            raise InputError(f"{where}, id: '{_shown(subject_id)}' is not a folder name (letters, digits, '.', '-', '_')")
        if subject_id in seen:
            raise InputError(f"{where}, id: '{_shown(subject_id)}' is given twice")
        seen.add(subject_id)
        if not cell["volume"]:
            raise InputError(f"{where}, volume: give the scan's path")

        def setting(name, parse=lambda text, where: _number(text, where)):
            return parse(cell[name], f"{where}, {name}") if cell.get(name) else config[name]

        backend = cell.get("backend") or config["backend"]
        if backend not in ("gpu", "cpu", "auto"):
            raise InputError(f"{where}, backend: gpu, cpu or auto, not '{_shown(backend)}'")
        edits_text = cell.get("edits") or config["edits"]
        subjects.append(Subject(
            id=subject_id, volume=os.path.normpath(os.path.join(folder, cell["volume"])),
            seeds=parse_seeds(cell["seeds"], f"{where}, seeds"), target=setting("target"), width=setting("width"),
            alpha=setting("alpha"), edits=parse_edits(edits_text, f"{where}, edits"), backend=backend,
            series=cell.get("series", ""),
            volume_index=_volume_index(cell["volume_index"], f"{where}, volume_index") if cell.get("volume_index") else None))
    return subjects
