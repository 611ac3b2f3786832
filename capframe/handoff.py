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

Readers refuse, in one line naming the file and field, a file that is not of its kind, any NaN or
infinite number, a world up that is not a direction, an empty list of views; views are stored by
name, and the stages check that the names are the scene's training views and that the subjects
are the scene's objects (:mod:`capframe.pipeline.stages`).

Every file records under ``inputs`` the content hash of the stage files it was made from, and
every reader checks them (:class:`~capframe.scene._io.MadeFrom`): a stage never combines files
that were not made from each other, and a file edited after the files made from it is named.
"""

from __future__ import annotations

import io
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .backends.protocols import Grounding, SubjectMasks
from .errors import InputError, clip
from .scene._io import MadeFrom, as_array, as_direction, atomic_write, digest, parse_json, read_bytes, read_stage_json, write_json
from .translate.instruction import JSON_SCHEMA, ParsedInstruction


def _inputs(made_from: MadeFrom | None) -> dict:
    """A written file's ``inputs``: the stage files its command read (none when made in-process)."""
    return {} if made_from is None else made_from.record()


def _instruction(data: dict, source: str) -> ParsedInstruction:
    """``instruction`` of a stage file, checked against the parser's schema (:data:`JSON_SCHEMA`)."""
    import jsonschema

    value = data["instruction"]
    error = jsonschema.exceptions.best_match(jsonschema.Draft202012Validator(JSON_SCHEMA).iter_errors(value))
    if error is not None:
        where = "".join(f"[{p}]" if isinstance(p, int) else f".{p}" for p in error.absolute_path)
        raise InputError(f"instruction{where}: {clip(error.message)}", source=source)
    try:
        return ParsedInstruction.from_dict(value, source=source)
    except InputError as err:  # a cue the schema allows but the constraints do not (elevation and elevation_deg)
        raise InputError(f"instruction: {err}", source=source) from None


def _views(data: dict, field: str, source: str) -> list[str]:
    """A non-empty list of view names."""
    value = data[field]
    if not isinstance(value, list) or not value or not all(isinstance(v, str) for v in value):
        raise InputError(f"{field} is {clip(repr(value))}; expected a non-empty list of view names", source=source)
    return value


def write_parsed(parsed: ParsedInstruction, path: str | Path) -> None:
    """``parsed.json``: the instruction and ``needs``, the optional stages it needs
    (``orientation``: a subject with a front to be seen from)."""
    needs = {"orientation": any(s.needs_front for s in parsed.subjects)}
    write_json(path, {"format": 1, "instruction": parsed.to_dict(), "needs": needs, "inputs": {}})


def read_parsed(path: str | Path, made_from: MadeFrom | None = None) -> ParsedInstruction:
    """The instruction of a ``parsed.json`` (:func:`write_parsed`)."""
    data = read_stage_json(path, "parsed", "capframe parse", ("instruction", "needs"), made_from)
    return _instruction(data, str(path))


@dataclass
class Coarse:
    """What the coarse stage hands to QE (``coarse.json``).

    Attributes:
        parsed: the parsed instruction.
        coarse: view name -> coarse score, every training view.
        kept: the views QE questions, best coarse score first.
        up: (3,) the world up used.
        source: the file it was read from (None when computed in this process).
    """

    parsed: ParsedInstruction
    coarse: dict[str, float]
    kept: list[str]
    up: np.ndarray
    source: str | None = None

    def write(self, path: str | Path, made_from: MadeFrom | None = None) -> None:
        write_json(
            path,
            {
                "format": 1,
                "instruction": self.parsed.to_dict(),
                "coarse": self.coarse,
                "kept": self.kept,
                "up": self.up.tolist(),
                "inputs": _inputs(made_from),
            },
        )

    @classmethod
    def read(cls, path: str | Path, made_from: MadeFrom | None = None) -> Coarse:
        source = str(path)
        data = read_stage_json(path, "coarse", "capframe coarse", ("instruction", "coarse", "kept", "up"), made_from)
        coarse = data["coarse"]
        if not isinstance(coarse, dict) or not coarse or not all(isinstance(v, (int, float)) for v in coarse.values()):
            raise InputError(f"coarse is {clip(repr(coarse))}; expected view name -> score", source=source)
        kept = _views(data, "kept", source)
        unscored = [v for v in kept if v not in coarse]
        if unscored:
            raise InputError(f"kept names {clip(repr(unscored))}; expected views that coarse scores", source=source)
        up = as_direction(data["up"], "up", source)
        return cls(_instruction(data, source), {k: float(v) for k, v in coarse.items()}, kept, up, source)


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
        source: the file it was read from (None when computed in this process).
    """

    parsed: ParsedInstruction
    retrieval: dict
    top: list[str]
    starts: list[str]
    up: np.ndarray
    source: str | None = None

    def to_dict(self, made_from: MadeFrom | None = None) -> dict:
        return {
            "format": 1,
            "instruction": self.parsed.to_dict(),
            "retrieval": self.retrieval,
            "top": self.top,
            "starts": self.starts,
            "up": self.up.tolist(),
            "inputs": _inputs(made_from),
        }

    @classmethod
    def read(cls, path: str | Path, made_from: MadeFrom | None = None) -> Retrieved:
        source = str(path)
        data = read_stage_json(
            path, "retrieval", "capframe retrieve or capframe qe", ("instruction", "retrieval", "top", "starts", "up"), made_from
        )
        if not isinstance(data["retrieval"], dict):
            raise InputError(f"retrieval is {clip(repr(data['retrieval']))}; expected questions and answers", source=source)
        top, starts = _views(data, "top", source), _views(data, "starts", source)
        up = as_direction(data["up"], "up", source)
        return cls(_instruction(data, source), data["retrieval"], top, starts, up, source)


def write_masks(
    masks: dict[str, SubjectMasks], view_names: list[str], path: str | Path, made_from: MadeFrom | None = None
) -> None:
    """``masks.npz``: ``subjects`` (S,), per subject i ``views_i`` (K,) names and ``masks_i``
    (K, H, W) bool, and ``inputs`` (the JSON of what it was made from)."""
    import json

    arrays = {"subjects": np.array(list(masks), dtype=str), "inputs": np.array(json.dumps(_inputs(made_from)))}
    for i, m in enumerate(masks.values()):
        arrays[f"views_{i}"] = np.array([view_names[v] for v in m.views], dtype=str)
        arrays[f"masks_{i}"] = np.asarray(m.masks, dtype=bool)
    buffer = io.BytesIO()
    np.savez_compressed(buffer, **arrays)
    atomic_write(path, buffer.getvalue())


def read_masks(path: str | Path, view_names: list[str], made_from: MadeFrom | None = None) -> dict[str, SubjectMasks]:
    """Masks written by :func:`write_masks`, their views as indices into ``view_names``."""
    source = str(path)
    content = read_bytes(path, "a masks.npz file")
    index = {name: i for i, name in enumerate(view_names)}
    try:
        with np.load(io.BytesIO(content)) as data:
            inputs = parse_json(str(data["inputs"]).encode(), source) if "inputs" in data else {}
            out = {}
            for i, name in enumerate(data["subjects"].tolist()):
                names, masks = data[f"views_{i}"].tolist(), data[f"masks_{i}"]
                unknown = [n for n in names if n not in index]
                if unknown or masks.ndim != 3 or len(masks) != len(names):
                    raise InputError(
                        f"subject {name!r}: views {unknown} are not training views, or masks of shape "
                        f"{masks.shape} do not match {len(names)} views",
                        source=source,
                    )
                out[name] = SubjectMasks([index[n] for n in names], masks.astype(bool))
    except InputError:
        raise
    except (KeyError, ValueError, OSError) as err:
        raise InputError(f"is not a masks file written by capframe segment ({err})", source=source) from None
    (made_from or MadeFrom()).add("masks", source, digest(content), inputs)
    return out


def write_groundings(groundings: dict[str, Grounding], path: str | Path, made_from: MadeFrom | None = None) -> None:
    """``subjects.json``: per subject its Gaussian indices and centroid."""
    write_json(
        path,
        {
            "format": 1,
            "subjects": {
                name: {"gaussians": g.gaussians.tolist(), "centroid": g.centroid.tolist()} for name, g in groundings.items()
            },
            "inputs": _inputs(made_from),
        },
    )


def read_groundings(path: str | Path, n_gaussians: int, made_from: MadeFrom | None = None) -> dict[str, Grounding]:
    """Groundings written by :func:`write_groundings`, checked against a scene of ``n_gaussians``."""
    source = str(path)
    data = read_stage_json(path, "subjects", "capframe associate", ("subjects",), made_from)
    if not isinstance(data["subjects"], dict):
        raise InputError(f"subjects is {clip(repr(data['subjects']))}; expected subject name -> Gaussians", source=source)
    out = {}
    for name, entry in data["subjects"].items():
        try:
            index = np.asarray(entry["gaussians"], dtype=np.int64)
        except (KeyError, TypeError, ValueError) as err:
            raise InputError(f"subject {name!r}: malformed entry ({err!r})", source=source) from None
        if index.ndim != 1 or index.size == 0 or index.min() < 0 or index.max() >= n_gaussians:
            raise InputError(
                f"subjects.{name}.gaussians: expected a non-empty list of Gaussian indices below {n_gaussians}", source=source
            )
        centroid = as_array(entry.get("centroid"), (3,), f"subjects.{name}.centroid", source)
        out[name] = Grounding(name, index, centroid, None)
    return out


def write_fronts(fronts: dict[str, np.ndarray | None], path: str | Path, made_from: MadeFrom | None = None) -> None:
    """``fronts.json``: subject -> unit front (world) or null when the estimator found none."""
    write_json(
        path,
        {
            "format": 1,
            "fronts": {k: None if f is None else np.asarray(f).tolist() for k, f in fronts.items()},
            "inputs": _inputs(made_from),
        },
    )


def read_fronts(path: str | Path, made_from: MadeFrom | None = None) -> dict[str, np.ndarray | None]:
    data = read_stage_json(path, "fronts", "capframe orient", ("fronts",), made_from)
    if not isinstance(data["fronts"], dict):
        raise InputError(f"fronts is {clip(repr(data['fronts']))}; expected subject name -> front", source=str(path))
    out = {}
    for name, front in data["fronts"].items():
        f = None if front is None else as_array(front, (3,), f"fronts.{name}", str(path))
        if f is not None and abs(np.linalg.norm(f) - 1.0) > 1e-6:
            raise InputError(f"fronts.{name} is {front}; expected a unit 3-vector or null", source=str(path))
        out[name] = f
    return out
