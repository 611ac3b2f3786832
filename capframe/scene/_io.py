"""Helpers shared by the readers and writers (not part of the public API): atomic writes, the
JSON reader and the one JSON writer, the stage-file reader and its record of what a file was
made from, the output-path check, field parsers."""

from __future__ import annotations

import hashlib
import json
import math
import os
import shutil
import tempfile
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import InputError
from .model import Camera

# mkstemp/mkdtemp create private (0600/0700) entries; results get the modes open()/mkdir() would give.
_UMASK = os.umask(0)
os.umask(_UMASK)

# Suffixes tried, in this order, when a camera names its image without an extension.
IMAGE_SUFFIXES = (".png", ".jpg", ".jpeg", ".PNG", ".JPG", ".JPEG", ".webp", ".tif", ".tiff", ".exr")


def atomic_write(path: str | Path, *parts: str | bytes | np.ndarray) -> None:
    """Write ``parts`` one after the other (text as UTF-8, arrays as their C-order bytes, not
    copied) to ``path`` through a temporary file in the same folder and a rename, so a crash
    never leaves a half-written file that looks valid (DESIGN §7). Creates parent folders."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    try:
        with os.fdopen(fd, "wb") as f:
            for part in parts:
                if isinstance(part, str):
                    part = part.encode("utf-8")
                elif isinstance(part, np.ndarray):
                    part = memoryview(np.ascontiguousarray(part)).cast("B")
                f.write(part)
        os.chmod(tmp, 0o666 & ~_UMASK)
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise


def write_npz(path: str | Path, meta: dict, **arrays: np.ndarray) -> None:
    """``arrays`` and the JSON ``meta`` (stored as the string array ``meta``) as one compressed
    ``.npz`` at ``path``, written atomically (:func:`atomic_write`)."""
    import io

    buffer = io.BytesIO()
    np.savez_compressed(buffer, meta=np.array(json.dumps(meta)), **arrays)
    atomic_write(path, buffer.getvalue())


@contextmanager
def atomic_directory(path: str | Path) -> Iterator[Path]:
    """Yield a temporary folder beside ``path``; on success it is renamed to ``path``, on error
    removed, so a folder is either complete or absent (DESIGN §7). ``path`` must not exist or be
    an empty folder: existing results are never overwritten."""
    path = Path(path)
    FOLDER.check(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = Path(tempfile.mkdtemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent))
    try:
        yield tmp
        tmp.chmod(0o777 & ~_UMASK)
        os.replace(tmp, path)  # also replaces an empty folder
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
        raise


def non_finite(value: Any, where: str = "") -> tuple[str, float] | None:
    """The key path (``loss_terms.view``, ``up[0]``) and value of the first NaN or infinite number
    in a JSON-like ``value`` (dicts, lists, tuples, numbers), or None when every number is finite."""
    if isinstance(value, float):
        return None if math.isfinite(value) else (where or "the value", value)
    if isinstance(value, dict):
        items = ((f"{where}.{k}" if where else str(k), v) for k, v in value.items())
    elif isinstance(value, (list, tuple)):
        items = ((f"{where}[{i}]", v) for i, v in enumerate(value))
    else:
        return None
    for key, item in items:
        found = non_finite(item, key)
        if found is not None:
            return found
    return None


def finite_or_null(value: Any) -> Any:
    """``value`` (JSON-like: dicts, lists, tuples, numbers) with every NaN or infinite number
    replaced by None: for figures where a number may be undefined (not measured), which JSON
    writes as null rather than as a literal it has no word for."""
    if isinstance(value, float):
        return value if math.isfinite(value) else None
    if isinstance(value, dict):
        return {k: finite_or_null(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [finite_or_null(v) for v in value]
    return value


def json_text(value: Any, source: str, indent: int | None = 2) -> str:
    """``value`` as JSON text (floats keep all their digits). JSON has no NaN or Infinity (Python
    would write them anyway): a non-finite number raises :class:`InputError` naming its key path,
    so no file or line we write carries one."""
    found = non_finite(value)
    if found is not None:
        raise InputError(f"{found[0]} is {found[1]}; refusing to write a non-finite number", source=source)
    return json.dumps(value, indent=indent, allow_nan=False)


def write_json(path: str | Path, value: Any) -> None:
    """Write ``value`` as indented JSON (:func:`json_text`), atomically."""
    atomic_write(path, json_text(value, str(path)) + "\n")


def read_bytes(path: str | Path, expected: str = "a JSON file") -> bytes:
    """The content of the file at ``path``; a missing, unreadable or folder path raises
    :class:`InputError` naming it (``expected`` says what it should have been)."""
    try:
        return Path(path).read_bytes()
    except FileNotFoundError:
        raise InputError("file not found", source=str(path)) from None
    except IsADirectoryError:
        raise InputError(f"is a folder; expected {expected}", source=str(path)) from None
    except OSError as err:
        raise InputError(f"cannot be read ({err.strerror}); expected {expected}", source=str(path)) from None


def parse_json(content: bytes, source: str) -> Any:
    """Parse JSON text; malformed text raises :class:`InputError` naming ``source``."""
    try:
        return json.loads(content.decode("utf-8"))
    except (json.JSONDecodeError, UnicodeDecodeError) as err:
        raise InputError(f"not valid JSON ({err})", source=source) from None


def read_json(path: str | Path) -> Any:
    """Parse a JSON file; a missing, unreadable or malformed file raises :class:`InputError`
    naming it."""
    return parse_json(read_bytes(path), str(path))


def digest(content: bytes) -> str:
    """The SHA-256 of ``content``, in hex: a stage file's identity (:class:`MadeFrom`)."""
    return hashlib.sha256(content).hexdigest()


class MadeFrom:
    """The stage files one command read, so that what it writes records what it was made from,
    and so that it never combines files that were not made from each other.

    A stage file records under ``inputs`` each stage file it was made from: kind (``retrieval``,
    ``subjects``, ...) -> ``{"path", "sha256"}``. When a command reads a stage file, every input
    that file records must still have the recorded content: the file of that kind the command
    itself read, else the file at the recorded path if it is still there (files moved elsewhere
    are not looked for). A mismatch means a file changed after the files made from it, which the
    workflow never does (Snakemake rebuilds whatever is newer than its inputs): it is refused,
    naming the stale file to rebuild.
    """

    def __init__(self) -> None:
        self.files: dict[str, tuple[str, str]] = {}  # kind -> (path, sha256) of what was read
        self.claims: list[tuple[str, str, str]] = []  # (reader file, kind, sha256 it records)

    def add(self, kind: str, path: str | Path, sha256: str, recorded: Any) -> None:
        """Register the stage file of ``kind`` at ``path`` (content ``sha256``) whose ``inputs``
        are ``recorded``, after checking both against every file read so far."""
        source = str(path)
        if not isinstance(recorded, dict):
            raise InputError(f"inputs is {recorded!r}; expected kind -> {{path, sha256}}", source=source)
        for input_kind, entry in recorded.items():
            if not (isinstance(entry, dict) and isinstance(entry.get("path"), str) and isinstance(entry.get("sha256"), str)):
                raise InputError(f"inputs.{input_kind} is {entry!r}; expected {{path, sha256}}", source=source)
            if input_kind in self.files:
                current = self.files[input_kind]
            elif Path(entry["path"]).is_file():
                current = (entry["path"], digest(read_bytes(entry["path"])))
            else:
                current = None
            if current is not None and current[1] != entry["sha256"]:
                raise _stale(source, input_kind, current[0], entry["sha256"], current[1])
            self.claims.append((source, input_kind, entry["sha256"]))
        for reader, input_kind, recorded_sha in self.claims:
            if input_kind == kind and recorded_sha != sha256:
                raise _stale(reader, kind, source, recorded_sha, sha256)
        self.files[kind] = (source, sha256)

    def record(self) -> dict:
        """``inputs`` of a file made from everything read: kind -> ``{"path", "sha256"}``."""
        return {kind: {"path": path, "sha256": sha} for kind, (path, sha) in self.files.items()}


def read_stage_json(path: str | Path, kind: str, writer: str, keys: tuple[str, ...], made_from: MadeFrom | None) -> dict:
    """A stage file of ``kind`` (:mod:`capframe.handoff`) written by ``writer``: format 1 with
    ``keys``, only finite numbers, and made from the files ``made_from`` has read (it is
    registered there; without one, against the files at the paths it records)."""
    source = str(path)
    content = read_bytes(path)
    data = parse_json(content, source)
    if not isinstance(data, dict) or data.get("format") != 1 or any(k not in data for k in keys):
        raise InputError(f"is not a {kind} file (format 1 with {', '.join(keys)}; written by {writer})", source=source)
    found = non_finite(data)
    if found is not None:
        raise InputError(f"{found[0]} is {found[1]}; expected a finite number", source=source)
    (made_from or MadeFrom()).add(kind, source, digest(content), data.get("inputs", {}))
    return data


def _stale(reader: str, kind: str, path: str, recorded: str, actual: str) -> InputError:
    return InputError(
        f"inputs.{kind} is sha256 {recorded[:12]}, but {path} is now {actual[:12]}: made from a {kind} file that has "
        f"changed since; rebuild {reader}",
        source=reader,
    )


@dataclass(frozen=True)
class Output:
    """What a command writes at an output path, checked by :meth:`check` before any work.

    Attributes:
        kind: ``file`` (written atomically beside itself), ``folder`` (a new folder, written
            whole: it must not exist or be empty) or ``into`` (a folder that files are written
            into; it may exist).
        suffixes: for a file, the accepted suffixes (lower case), or empty for any.
    """

    kind: str
    suffixes: tuple[str, ...] = ()

    def check(self, path: str | Path) -> None:
        """:class:`InputError` naming ``path`` when it cannot be written as this kind of output:
        a folder where a file goes, a file where a folder goes, an existing result, a wrong
        suffix, a path through a file or into a folder this process cannot write."""
        path = Path(path)
        source = str(path)
        if self.kind == "file" and path.is_dir():
            raise InputError("is a folder; expected a file to write", source=source)
        if self.suffixes and path.suffix.lower() not in self.suffixes:
            raise InputError(f"has suffix {path.suffix!r}; expected one of {', '.join(self.suffixes)}", source=source)
        if self.kind == "folder" and path.exists() and (not path.is_dir() or any(path.iterdir())):
            raise InputError("already exists and is not an empty folder; remove it or choose another", source=source)
        if self.kind == "into" and path.exists() and not path.is_dir():
            raise InputError("is a file; expected a folder to write into", source=source)
        # Files are written into an existing "into" folder; everything else is created beside its
        # path (a temporary and a rename), after the missing parent folders.
        base = path if self.kind == "into" and path.is_dir() else path.parent
        existing = next(p for p in (base, *base.parents) if p.exists())
        if not existing.is_dir():
            raise InputError(f"{existing} is a file, not a folder; cannot write below it", source=source)
        try:
            # A real file rather than os.access: that answers yes to root on a read-only mount.
            with tempfile.TemporaryFile(dir=existing):
                pass
        except OSError as err:
            raise InputError(f"cannot write in {existing} ({err.strerror})", source=source) from None


FOLDER = Output("folder")
# The outputs commands declare, by name: an image is written as PNG or JPEG by its suffix.
OUTPUTS = {
    "file": Output("file"),
    "folder": FOLDER,
    "into": Output("into"),
    "image": Output("file", (".png", ".jpg", ".jpeg")),
    "png": Output("file", (".png",)),
}


def require_keys(entry: dict, keys: tuple[str, ...], what: str, source: str) -> None:
    """Raise :class:`InputError` listing every key of ``keys`` missing from ``entry``."""
    if not isinstance(entry, dict):
        raise InputError(f"{what} is {type(entry).__name__}, expected a JSON object", source=source)
    missing = [k for k in keys if k not in entry]
    if missing:
        raise InputError(f"{what} lacks {', '.join(repr(k) for k in missing)}", source=source)


def as_float(value: Any, what: str, source: str) -> float:
    """A JSON number as float (NaN/Inf pass through; pose validation reports them)."""
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise InputError(f"{what} is {value!r}, expected a number", source=source)
    return float(value)


def as_size(value: Any, what: str, source: str) -> int:
    """A JSON image dimension: a positive whole number (``640`` or ``640.0``)."""
    number = as_float(value, what, source)
    if not math.isfinite(number) or number != int(number) or number <= 0:
        raise InputError(f"{what} is {value!r}, expected a positive whole number of pixels", source=source)
    return int(number)


def resolve_image(images_dir: str | Path | None, name: str) -> str | None:
    """Path of the image called ``name`` in ``images_dir``: the exact file if it exists, else
    ``name`` plus the first of :data:`IMAGE_SUFFIXES` that exists; ``None`` if there is none."""
    if images_dir is None:
        return None
    exact = Path(images_dir) / name
    if exact.is_file():
        return str(exact)
    for suffix in IMAGE_SUFFIXES:
        candidate = Path(images_dir) / f"{name}{suffix}"
        if candidate.is_file():
            return str(candidate)
    return None


def check_unique_names(names: list[str], source: str) -> None:
    """Cameras are matched by name (DESIGN §3), so a name may occur only once."""
    seen: set[str] = set()
    duplicates = sorted({n for n in names if n in seen or seen.add(n)})
    if duplicates:
        raise InputError(f"duplicate camera names {duplicates[:5]}; expected unique names", source=source)


def as_array(value: Any, shape: tuple[int, ...], what: str, source: str) -> np.ndarray:
    """A nested JSON list as a finite float64 array of ``shape``, else :class:`InputError`."""
    try:
        array = np.array(value, dtype=np.float64)
    except (TypeError, ValueError):
        array = None
    if array is None or array.shape != shape:
        raise InputError(f"{what} is {value!r}; expected {'x'.join(map(str, shape))} numbers", source=source)
    if not np.isfinite(array).all():
        raise InputError(f"{what} has non-finite values {array.tolist()}; expected finite numbers", source=source)
    return array


def as_direction(value: Any, what: str, source: str) -> np.ndarray:
    """A JSON 3-vector as a finite unit (3,) float64 direction (normalised), else
    :class:`InputError`: the zero vector has no direction."""
    v = as_array(value, (3,), what, source)
    norm = np.linalg.norm(v)
    if norm == 0:
        raise InputError(f"{what} is the zero vector; expected a direction", source=source)
    return v / norm


def make_camera(
    T_cw: np.ndarray, K: np.ndarray, width: int, height: int, name: str, image_path: str | None, source: str
) -> Camera:
    """Build a :class:`Camera`, re-raising its validation error with the file's name in front."""
    try:
        return Camera(T_cw=T_cw, K=K, width=width, height=height, name=name, image_path=image_path)
    except InputError as err:
        raise InputError(str(err), source=source) from None


def intrinsics(fx: float, fy: float, cx: float, cy: float) -> np.ndarray:
    """Pinhole matrix K (3, 3) from focal lengths and principal point in pixels."""
    return np.array([[fx, 0.0, cx], [0.0, fy, cy], [0.0, 0.0, 1.0]])
