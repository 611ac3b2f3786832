"""Benchmark suites of synthetic scenes (``config/suites/*.yaml``).

A suite file is YAML with a ``suite`` name and a list of ``scenes``; each scene entry names the
arguments of one :func:`capframe.synth.generator.generate_scene` call and how many instructions
to generate for it (format documented at the top of ``config/suites/full.yaml``).
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass
from pathlib import Path

import yaml

from ..errors import InputError
from .generator import CAPTURES, PRESETS, parse_resolution
from .objects import resolve_names

_REQUIRED = (
    "id",
    "group",
    "seed",
    "preset",
    "capture",
    "views",
    "scale",
    "tilt",
    "poses",
    "resolution",
    "density",
    "instructions",
)
_OPTIONAL = ("objects",)
# Scene ids and groups become workflow wildcards, paths under results/ and shell arguments: a
# letter or digit, then letters, digits, '_', '.', '-', and never '..' (the workflow's config
# schema holds the same pattern for variant names).
SAFE_NAME = r"[A-Za-z0-9][A-Za-z0-9_.-]*"


def is_safe_name(name: object) -> bool:
    """Whether ``name`` may become a wildcard, a path component and a shell argument."""
    return isinstance(name, str) and re.fullmatch(SAFE_NAME, name) is not None and ".." not in name


@dataclass(frozen=True)
class SuiteScene:
    """One scene of a suite: the generator arguments and the instruction count."""

    id: str
    group: str
    seed: int
    preset: str
    capture: str
    objects: tuple[str, ...] | None
    views: int
    scale: float
    tilt: float
    poses: bool
    resolution: tuple[int, int]
    density: float
    instructions: int

    def generate_kwargs(self) -> dict:
        """Keyword arguments for :func:`~capframe.synth.generator.generate_scene`."""
        return dict(
            seed=self.seed,
            objects=None if self.objects is None else list(self.objects),
            preset=self.preset,
            capture=self.capture,
            views=self.views,
            scale=self.scale,
            tilt_deg=self.tilt,
            poses=self.poses,
            resolution=self.resolution,
            density=self.density,
        )

    def synth_args(self) -> list[str]:
        """The same as ``capframe synth`` arguments (after the output folder)."""
        args = [
            "--seed",
            str(self.seed),
            "--preset",
            self.preset,
            "--capture",
            self.capture,
            "--views",
            str(self.views),
            "--scale",
            repr(self.scale),
            "--tilt",
            repr(self.tilt),
            "--resolution",
            f"{self.resolution[0]}x{self.resolution[1]}",
            "--density",
            repr(self.density),
        ]
        if self.objects is not None:
            args += ["--objects", ",".join(self.objects)]
        if not self.poses:
            args.append("--no-poses")
        return args


def _number(entry: dict, key: str, kind, source: str, what: str, positive: bool = False):
    value = entry[key]
    if isinstance(value, bool) or not isinstance(value, (int, float)) or (kind is int and not isinstance(value, int)):
        raise InputError(
            f"{what}: '{key}' is {value!r}; expected {'a whole number' if kind is int else 'a number'}", source=source
        )
    if not math.isfinite(value) or (positive and value <= 0):
        raise InputError(f"{what}: '{key}' is {value!r}; expected a positive finite number", source=source)
    return kind(value)


def load_suite(path: str | Path) -> tuple[str, list[SuiteScene]]:
    """Read and validate a suite file; returns its name and scenes. :class:`InputError` names the
    file and the scene for unknown keys, missing keys, bad values and duplicate ids."""
    source = str(path)
    try:
        data = yaml.safe_load(Path(path).read_text(encoding="utf-8"))
    except FileNotFoundError:
        raise InputError("suite file not found", source=source) from None
    except yaml.YAMLError as err:
        raise InputError(f"not valid YAML ({' '.join(str(err).split())})", source=source) from None
    if not isinstance(data, dict) or not isinstance(data.get("scenes"), list):
        raise InputError("expected a mapping with 'suite' and a list 'scenes'", source=source)
    scenes, seen = [], set()
    for i, entry in enumerate(data["scenes"]):
        what = f"scene {i}" + (f" ({entry.get('id')!r})" if isinstance(entry, dict) else "")
        if not isinstance(entry, dict):
            raise InputError(f"{what} is not a mapping", source=source)
        missing = [k for k in _REQUIRED if k not in entry]
        unknown = sorted(set(entry) - set(_REQUIRED) - set(_OPTIONAL))
        if missing or unknown:
            raise InputError(f"{what}: missing keys {missing}, unknown keys {unknown}", source=source)
        for key in ("id", "group"):
            if not is_safe_name(entry[key]):
                raise InputError(
                    f"{what}: '{key}' is {entry[key]!r}; expected a name matching {SAFE_NAME} without '..'", source=source
                )
        if entry["id"] in seen:
            raise InputError(f"{what}: duplicate id", source=source)
        seen.add(entry["id"])
        if entry["preset"] not in PRESETS or entry["capture"] not in CAPTURES:
            raise InputError(
                f"{what}: preset {entry['preset']!r} / capture {entry['capture']!r}; expected one of {PRESETS} / {CAPTURES}",
                source=source,
            )
        if not isinstance(entry["poses"], bool):
            raise InputError(f"{what}: 'poses' is {entry['poses']!r}; expected true or false", source=source)
        objects = entry.get("objects")
        if objects is not None:
            if not isinstance(objects, list) or not objects:
                raise InputError(f"{what}: 'objects' must be a non-empty list of catalog names", source=source)
            try:
                objects = tuple(spec.name for spec in resolve_names([str(o) for o in objects]))
            except InputError as err:
                raise InputError(f"{what}: {err}", source=source) from None
        try:
            resolution = parse_resolution(entry["resolution"])
        except InputError as err:
            raise InputError(f"{what}: {err}", source=source) from None
        scenes.append(
            SuiteScene(
                id=str(entry["id"]),
                group=str(entry["group"]),
                seed=_number(entry, "seed", int, source, what),
                preset=entry["preset"],
                capture=entry["capture"],
                objects=objects,
                views=_number(entry, "views", int, source, what, positive=True),
                scale=_number(entry, "scale", float, source, what, positive=True),
                tilt=_number(entry, "tilt", float, source, what),
                poses=entry["poses"],
                resolution=resolution,
                density=_number(entry, "density", float, source, what, positive=True),
                instructions=_number(entry, "instructions", int, source, what, positive=True),
            )
        )
    return str(data.get("suite", Path(path).stem)), scenes


__all__ = ["SuiteScene", "load_suite"]
