"""A suite whose instructions are committed, not generated: hand-written specs (the held-out
sets ``heldout``, ``heldout2`` ... ``heldout20``, development sets now, issue #15, and the blind held-out
set ``heldout21``, written blind to the method on 2026-11-28 (sixth session) and read by its writer only; and the
parse-only corpora ``phrasing1`` ... ``phrasing4`` and ``phrasing9`` (development corpora)
and the development phrase banks ``phrasing5`` (view clauses), ``phrasing6`` (elevation, shot size,
frame region and roll), ``phrasing7`` (how subjects are named and told apart) and ``phrasing8``
(whole requests of several clauses), written blind to the method, and the blind
``phrasing10``, written blind to the method on 2026-11-28 (fourth session), a development corpus since
that day's sixth, and ``phrasing11``, blind, written blind to the method on 2026-11-28 (fifth session) and read by its
writer only, whose scenes are never generated: ``capframe bench ground --suite phrasing11 --parse-only``).

The suite file is a :mod:`capframe.synth.suite` file with one more top-level key, ``specs``: a
folder (relative to the suite file) holding one ``<scene id>.yaml`` per scene (and, for a
parse-only corpus, ``parse_only: true``, which ``bench ground`` refuses without ``--parse-only``)::

    scene: <scene id>
    instructions:
      - {id: ..., text: ..., kind: ..., feasible: ..., subjects: [...], ...}   (capframe.evaluate.spec)

Every scene names its ``objects``; every subject of a spec is the catalog name of one of them
(the suite's objects are the scene's, so the set is checked without generating a scene), a view
side or azimuth range is asked only of an object with a front, a name the instruction uses that
the scene lacks (``absent``) is indeed not one of them, and the scene's ``instructions`` count
equals the number in its file. Ids are unique across the set.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import yaml

from ..errors import InputError
from ..evaluate.spec import InstructionSpec, parse_spec
from .objects import CATALOG
from .suite import SuiteScene, load_suite


@dataclass
class HeldoutSuite:
    """A suite with committed instructions: its name, scenes, and each scene's specs (by id);
    ``parse_only`` for a corpus checked by the parser alone (its feasibility was not searched)."""

    name: str
    scenes: list[SuiteScene]
    specs: dict[str, list[InstructionSpec]]
    parse_only: bool = False

    def cases(self) -> list[tuple[SuiteScene, InstructionSpec]]:
        """Every (scene, instruction), scenes in suite order."""
        return [(scene, spec) for scene in self.scenes for spec in self.specs[scene.id]]


def has_committed_instructions(path: str | Path) -> bool:
    """Whether a suite file names a ``specs`` folder (committed instructions)."""
    try:
        data = yaml.safe_load(Path(path).read_text(encoding="utf-8"))
    except (OSError, yaml.YAMLError):
        return False
    return isinstance(data, dict) and "specs" in data


def _read_yaml(path: Path):
    try:
        return yaml.safe_load(path.read_text(encoding="utf-8"))
    except FileNotFoundError:
        raise InputError("spec file not found", source=str(path)) from None
    except yaml.YAMLError as err:
        raise InputError(f"not valid YAML ({' '.join(str(err).split())})", source=str(path)) from None


def _check_subjects(spec: InstructionSpec, scene: SuiteScene, source: str) -> None:
    """Subjects are catalog names of the scene's objects; views only of objects with a front;
    ``absent`` names are not the scene's objects (nor their aliases)."""
    where = f"instruction {spec.id!r}"
    objects = set(scene.objects)
    for s in spec.constraints.subjects:
        if s.name not in objects:
            raise InputError(
                f"{where}: subject {s.name!r} is not an object of scene {scene.id!r} {sorted(objects)}", source=source
            )
        if (s.view is not None or s.name in spec.azimuths) and CATALOG[s.name].symmetric:
            raise InputError(f"{where}: subject {s.name!r} is symmetric; it has no view side or azimuth", source=source)
    known = objects | {a for o in objects for a in CATALOG[o].aliases}
    for name in spec.absent:
        if name.lower() in known:
            raise InputError(f"{where}: 'absent' name {name!r} is an object of scene {scene.id!r}", source=source)


def load_scene_specs(path: Path, scene: SuiteScene) -> list[InstructionSpec]:
    """Read and validate one scene's spec file."""
    source = str(path)
    data = _read_yaml(path)
    if not isinstance(data, dict) or set(data) != {"scene", "instructions"} or not isinstance(data["instructions"], list):
        raise InputError("expected a mapping with exactly 'scene' and a list 'instructions'", source=source)
    if data["scene"] != scene.id:
        raise InputError(f"'scene' is {data['scene']!r}; expected {scene.id!r} (the file's name)", source=source)
    specs = [parse_spec(entry, scene.id, source, i) for i, entry in enumerate(data["instructions"])]
    for spec in specs:
        _check_subjects(spec, scene, source)
    if len(specs) != scene.instructions:
        raise InputError(f"holds {len(specs)} instructions; the suite's 'instructions' says {scene.instructions}", source=source)
    return specs


def load_heldout(path: str | Path) -> HeldoutSuite:
    """Read and validate a suite with committed instructions (module docstring)."""
    source = str(path)
    name, scenes = load_suite(path)
    data = _read_yaml(Path(path))
    folder = data.get("specs")
    if not isinstance(folder, str) or not folder.strip():
        raise InputError(f"'specs' is {folder!r}; expected the folder of the scenes' spec files", source=source)
    parse_only = data.get("parse_only", False)
    if not isinstance(parse_only, bool):
        raise InputError(f"'parse_only' is {parse_only!r}; expected true or false", source=source)
    root = Path(path).parent / folder
    specs, seen = {}, {}
    for scene in scenes:
        if scene.objects is None:
            raise InputError(f"scene {scene.id!r}: 'objects' is required when the instructions are committed", source=source)
        specs[scene.id] = load_scene_specs(root / f"{scene.id}.yaml", scene)
        for spec in specs[scene.id]:
            if spec.id in seen:
                raise InputError(f"instruction id {spec.id!r} is used twice ({seen[spec.id]} and {scene.id})", source=source)
            seen[spec.id] = scene.id
    return HeldoutSuite(name, scenes, specs, parse_only)


__all__ = ["HeldoutSuite", "has_committed_instructions", "load_heldout", "load_scene_specs"]
