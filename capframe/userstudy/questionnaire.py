"""``capframe userstudy make``: the questionnaire of a finished run (see :mod:`capframe.userstudy`)."""

from __future__ import annotations

import dataclasses
import hashlib
import io
import random
import secrets
from pathlib import Path

from PIL import Image, UnidentifiedImageError

from ..errors import InputError
from ..scene._io import atomic_directory, atomic_write, read_json
from .key import LABELS, Group, Key, questionnaire_id
from .page import render_page


def method_folder(results: Path, method: str) -> Path:
    """Where the workflow writes ``method``'s per-instruction folders (``<scene>/<id>/render.png``):
    ``results/refine/<method>`` (CapFrame, its variants, the oracle), ``results/baselines/<method>``
    (IVS, SVS, SplaTraj, ChatCam) or, for ``retrieve``, ``results/retrieved``."""
    candidates = [results / "refine" / method, results / "baselines" / method]
    if method == "retrieve":
        candidates.append(results / "retrieved")
    for folder in candidates:
        if folder.is_dir():
            return folder
    found = sorted(p.name for kind in ("refine", "baselines") if (results / kind).is_dir() for p in (results / kind).iterdir())
    found += ["retrieve"] if (results / "retrieved").is_dir() else []
    raise InputError(
        f"--methods: no results for {method!r} ({' or '.join(str(c) for c in candidates)}); methods there: {found}",
        source=str(results),
    )


def instructions(results: Path) -> list[tuple[str, str, str]]:
    """``(scene, id, text)`` of every instruction of the run, sorted by scene and id, from
    ``results/instructions/<scene>/constraints.json``."""
    root = results / "instructions"
    files = sorted(root.glob("*/constraints.json"))
    if not files:
        expected = "expected the results folder of a finished run"
        raise InputError(f"has no {root}/<scene>/constraints.json; {expected}", source=str(results))
    found = []
    for path in files:
        entries = read_json(path)
        if not isinstance(entries, dict):
            raise InputError("is not instruction id -> {text, ...}", source=str(path))
        for instruction, entry in sorted(entries.items()):
            if not (isinstance(entry, dict) and isinstance(entry.get("text"), str) and entry["text"].strip()):
                raise InputError(f"{instruction}.text is missing or empty; expected the instruction", source=str(path))
            found.append((path.parent.name, instruction, entry["text"]))
    return found


def make_questionnaire(
    results: str | Path, methods: list[str], output: str | Path, *, groups: int = 12, per_group: int = 3, seed: int = 0
) -> Key:
    """Write the questionnaire of a finished run: ``output/site/`` (``index.html``, ``img/``) for
    the participants and ``output/key.json`` (:class:`~capframe.userstudy.key.Key`), all at once.

    Draws ``groups`` instructions with ``random.Random(seed)`` among those for which every one of
    ``methods`` has a ``render.png`` and whose text names none of them; each group shows
    ``per_group`` methods (all of them when there are as many; else those shown least so far,
    ties drawn) in a drawn order, labelled A, B, ... The renders are re-encoded as PNG (no
    metadata) under hashed names. ``output`` must not exist or be empty (nothing is half-written).
    """
    results = Path(results)
    _check_choice(methods, groups, per_group)
    folders = {m: method_folder(results, m) for m in methods}
    candidates = [
        (scene, instruction, text)
        for scene, instruction, text in instructions(results)
        if not _names_method(text, methods) and all((folders[m] / scene / instruction / "render.png").is_file() for m in methods)
    ]
    if len(candidates) < groups:
        raise InputError(
            f"only {len(candidates)} instructions have a render.png of every method {methods} (and name none of them); "
            f"--groups {groups} asks for more; expected {len(candidates)} or fewer",
            source=str(results),
        )
    rng = random.Random(seed)
    nonce = secrets.token_hex(16)
    shown_count = dict.fromkeys(methods, 0)
    drawn = []
    for number, (scene, instruction, text) in enumerate(rng.sample(candidates, groups), start=1):
        shown = sorted(methods, key=lambda m: (shown_count[m], rng.random()))[:per_group]
        rng.shuffle(shown)
        for m in shown:
            shown_count[m] += 1
        labels = LABELS[:per_group]
        drawn.append(
            Group(
                number=number,
                scene=scene,
                instruction=instruction,
                text=text,
                methods=dict(zip(labels, shown)),
                images={label: f"img/{_image_name(nonce, number, label)}.png" for label in labels},
                sources={label: str(folders[m] / scene / instruction / "render.png") for label, m in zip(labels, shown)},
            )
        )
    draft = Key("", nonce, seed, tuple(methods), tuple(drawn))
    key = dataclasses.replace(draft, questionnaire=questionnaire_id(draft.content()))
    with atomic_directory(output) as tmp:
        for group in key.groups:
            for label, image in group.images.items():
                atomic_write(tmp / "site" / image, _png(group.sources[label]))
        atomic_write(tmp / "site" / "index.html", render_page(key))
        _check_no_method_named(tmp / "site", methods, Path(output) / "site")
        key.write(tmp / "key.json")
    return key


def _check_choice(methods: list[str], groups: int, per_group: int) -> None:
    if len(set(methods)) != len(methods) or not all(methods) or len(methods) < 2:
        raise InputError(f"--methods {','.join(methods)!r}: expected two or more distinct, non-empty method names")
    if not 2 <= per_group <= min(len(methods), len(LABELS)):
        raise InputError(f"--per-group {per_group}: expected 2 to {min(len(methods), len(LABELS))} (the number of --methods)")
    if groups < 1:
        raise InputError(f"--groups {groups}: expected at least 1")


def _names_method(text: str, methods: list[str]) -> bool:
    """Whether an instruction's text holds a method's name (the page would show it)."""
    return any(m.lower() in text.lower() for m in methods)


def _image_name(nonce: str, group: int, label: str) -> str:
    """An image's file name: a hash of the questionnaire's secret nonce, the group and the label,
    so the name tells nothing of the method (nor of the render it was copied from)."""
    return hashlib.sha256(f"{nonce}:{group}:{label}".encode()).hexdigest()[:20]


def _png(path: str) -> bytes:
    """The image at ``path`` re-encoded as PNG: its pixels only (no text chunks or other metadata
    that could name a method), and a render that cannot be read is refused by name."""
    try:
        with Image.open(path) as image:
            image.load()
            buffer = io.BytesIO()
            image.save(buffer, format="PNG")
    except (OSError, UnidentifiedImageError) as err:
        raise InputError(f"cannot be read as an image ({err}); expected a method's render", source=path) from None
    return buffer.getvalue()


def _check_no_method_named(site: Path, methods: list[str], shown_as: Path) -> None:
    """Refuse a site whose file names or page text hold a method's name (case-insensitive): a
    method named like a word of the page ("image", "group") would be revealed."""
    for path in sorted(site.rglob("*")):
        text = path.relative_to(site).as_posix()
        if path.suffix == ".html":
            text += "\n" + path.read_text(encoding="utf-8")
        for method in methods:
            if method.lower() in text.lower():
                raise InputError(
                    f"{shown_as / path.relative_to(site)} would hold the method name {method!r}; participants must not "
                    "see method names: rename that method's results folder"
                )
