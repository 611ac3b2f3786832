"""The files the method's stages hand to each other, one per (instruction, stage).

Each stage is a ``capframe`` verb and a workflow rule (DESIGN §7); these are their formats:

============  ===================  ===================================================
stage         file                 holds
============  ===================  ===================================================
parse         ``parsed.json``      the parsed instruction and the stages it needs
                                   (the workflow reads ``needs`` to leave stages out)
coarse        ``coarse.json``      the parsed instruction, every view's coarse score,
                                   the views kept for QE, the world up
qe            ``retrieval.json``   questions, answers, the retrieved views and the
                                   views Refine starts from (:class:`Retrieved`)
segment       ``masks.npz``        per subject, 2D masks in the retrieved views
associate     ``subjects.json``    per subject, its Gaussians and centroid
orient        ``fronts.json``      per subject asked for, its front (or null)
translate     ``labels.json``      the pseudo labels (:mod:`capframe.translate.labels`)
============  ===================  ===================================================

Views are stored by name; readers check that the names are the scene's training views.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .backends.protocols import Grounding, SubjectMasks
from .errors import InputError
from .scene._io import atomic_write, read_json, write_json
from .translate.instruction import ParsedInstruction


def _read_format(path: str | Path, kind: str, writer: str, keys: tuple[str, ...]) -> dict:
    data = read_json(path)
    if not isinstance(data, dict) or data.get("format") != 1 or any(k not in data for k in keys):
        raise InputError(f"is not a {kind} file (format 1 with {', '.join(keys)}; written by {writer})", source=str(path))
    return data


def write_parsed(parsed: ParsedInstruction, path: str | Path) -> None:
    """``parsed.json``: the instruction and ``needs``, the optional stages it needs
    (``orientation``: a subject with a front to be seen from)."""
    needs = {"orientation": any(s.needs_front for s in parsed.subjects)}
    write_json(path, {"format": 1, "instruction": parsed.to_dict(), "needs": needs})


def read_parsed(path: str | Path) -> ParsedInstruction:
    """The instruction of a ``parsed.json`` (:func:`write_parsed`)."""
    data = _read_format(path, "parsed-instruction", "capframe parse", ("instruction", "needs"))
    return ParsedInstruction.from_dict(data["instruction"], source=str(path))


@dataclass
class Coarse:
    """What the coarse stage hands to QE (``coarse.json``).

    Attributes:
        parsed: the parsed instruction.
        coarse: view name -> coarse score, every training view.
        kept: the views QE questions, best coarse score first.
        up: (3,) the world up used.
    """

    parsed: ParsedInstruction
    coarse: dict[str, float]
    kept: list[str]
    up: np.ndarray

    def write(self, path: str | Path) -> None:
        write_json(
            path,
            {"format": 1, "instruction": self.parsed.to_dict(), "coarse": self.coarse, "kept": self.kept, "up": self.up.tolist()},
        )

    @classmethod
    def read(cls, path: str | Path) -> Coarse:
        data = _read_format(path, "coarse-retrieval", "capframe coarse", ("instruction", "coarse", "kept", "up"))
        return cls(
            ParsedInstruction.from_dict(data["instruction"], source=str(path)),
            {k: float(v) for k, v in data["coarse"].items()},
            list(data["kept"]),
            np.asarray(data["up"], dtype=np.float64),
        )


@dataclass
class Retrieved:
    """What Retrieve hands to Translate and Refine (``retrieval.json``).

    Attributes:
        parsed: the parsed instruction.
        retrieval: questions, per-view answers and scores (:meth:`Retrieval.to_dict`).
        top: names of the retrieved views (the top K), best first.
        starts: names of the views Refine tries, in order: a seeded pick among the top K, then
            the other kept views by QE score.
        up: (3,) the world up used.
    """

    parsed: ParsedInstruction
    retrieval: dict
    top: list[str]
    starts: list[str]
    up: np.ndarray

    def to_dict(self) -> dict:
        return {
            "format": 1,
            "instruction": self.parsed.to_dict(),
            "retrieval": self.retrieval,
            "top": self.top,
            "starts": self.starts,
            "up": self.up.tolist(),
        }

    @classmethod
    def read(cls, path: str | Path) -> Retrieved:
        data = _read_format(
            path, "retrieval", "capframe retrieve or capframe qe", ("instruction", "retrieval", "top", "starts", "up")
        )
        return cls(
            ParsedInstruction.from_dict(data["instruction"], source=str(path)),
            data["retrieval"],
            data["top"],
            data["starts"],
            np.asarray(data["up"], dtype=np.float64),
        )


def write_masks(masks: dict[str, SubjectMasks], view_names: list[str], path: str | Path) -> None:
    """``masks.npz``: ``subjects`` (S,), and per subject i ``views_i`` (K,) names and ``masks_i``
    (K, H, W) bool."""
    import io

    arrays = {"subjects": np.array(list(masks), dtype=str)}
    for i, m in enumerate(masks.values()):
        arrays[f"views_{i}"] = np.array([view_names[v] for v in m.views], dtype=str)
        arrays[f"masks_{i}"] = np.asarray(m.masks, dtype=bool)
    buffer = io.BytesIO()
    np.savez_compressed(buffer, **arrays)
    atomic_write(path, buffer.getvalue())


def read_masks(path: str | Path, view_names: list[str]) -> dict[str, SubjectMasks]:
    """Masks written by :func:`write_masks`, their views as indices into ``view_names``."""
    index = {name: i for i, name in enumerate(view_names)}
    try:
        with np.load(path) as data:
            out = {}
            for i, name in enumerate(data["subjects"].tolist()):
                names, masks = data[f"views_{i}"].tolist(), data[f"masks_{i}"]
                unknown = [n for n in names if n not in index]
                if unknown or masks.ndim != 3 or len(masks) != len(names):
                    raise InputError(
                        f"subject {name!r}: views {unknown} are not training views, or masks of shape "
                        f"{masks.shape} do not match {len(names)} views",
                        source=str(path),
                    )
                out[name] = SubjectMasks([index[n] for n in names], masks.astype(bool))
            return out
    except FileNotFoundError:
        raise InputError("masks file not found", source=str(path)) from None
    except (KeyError, ValueError, OSError) as err:
        raise InputError(f"is not a masks file written by capframe segment ({err})", source=str(path)) from None


def write_groundings(groundings: dict[str, Grounding], path: str | Path) -> None:
    """``subjects.json``: per subject its Gaussian indices and centroid."""
    write_json(
        path,
        {
            "format": 1,
            "subjects": {
                name: {"gaussians": g.gaussians.tolist(), "centroid": g.centroid.tolist()} for name, g in groundings.items()
            },
        },
    )


def read_groundings(path: str | Path, n_gaussians: int) -> dict[str, Grounding]:
    """Groundings written by :func:`write_groundings`, checked against a scene of ``n_gaussians``."""
    data = _read_format(path, "subjects", "capframe associate", ("subjects",))
    out = {}
    for name, entry in data["subjects"].items():
        try:
            index = np.asarray(entry["gaussians"], dtype=np.int64)
            centroid = np.asarray(entry["centroid"], dtype=np.float64)
        except (KeyError, TypeError, ValueError) as err:
            raise InputError(f"subject {name!r}: malformed entry ({err!r})", source=str(path)) from None
        if index.ndim != 1 or index.size == 0 or index.min() < 0 or index.max() >= n_gaussians or centroid.shape != (3,):
            raise InputError(
                f"subject {name!r}: expected a non-empty list of Gaussian indices below {n_gaussians} and a 3-vector centroid",
                source=str(path),
            )
        out[name] = Grounding(name, index, centroid, None)
    return out


def write_fronts(fronts: dict[str, np.ndarray | None], path: str | Path) -> None:
    """``fronts.json``: subject -> unit front (world) or null when the estimator found none."""
    write_json(path, {"format": 1, "fronts": {k: None if f is None else np.asarray(f).tolist() for k, f in fronts.items()}})


def read_fronts(path: str | Path) -> dict[str, np.ndarray | None]:
    data = _read_format(path, "fronts", "capframe orient", ("fronts",))
    out = {}
    for name, front in data["fronts"].items():
        f = None if front is None else np.asarray(front, dtype=np.float64)
        if f is not None and (f.shape != (3,) or not np.isfinite(f).all() or abs(np.linalg.norm(f) - 1.0) > 1e-6):
            raise InputError(f"subject {name!r}: front {front} is not a finite unit 3-vector", source=str(path))
        out[name] = f
    return out
