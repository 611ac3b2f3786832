"""Parse-only check of a suite: ``capframe bench ground --suite S --parse-only``.

Every instruction of the suite goes through the rule parser alone (no scene is generated, no
camera is placed) and its parse is compared with what the instruction means
(:func:`capframe.bench.heldout.parse_differences`). It prints, in seconds, one line per
instruction whose parse differs, was refused or is only partly understood, then the counts, the
median parse time, and how many fully read instructions keep their reading with one unknown
word put inside them (:func:`interruption_kept`). It is the guard that a parser change keeps
every correct parse correct.

* A suite with committed instructions (the held-out sets): the vocabulary of a scene is built
  from the suite file's ``objects`` and their catalog names and aliases (the generator also adds
  an alias "<colour> <name>" whose colour is drawn at generation time; colour words are therefore
  not checked here). An infeasible instruction for an unknown subject is expected to be refused.
* A suite whose instructions are generated (default, captured, full): they are read from the
  sheets under ``root/instructions`` (``results/bench/suite`` by default, as ``bench ground``
  writes them); scenes and sheets are generated once when absent (the generator needs the
  scene's ground truth), the vocabulary is the scene's semantic sidecar.
"""

from __future__ import annotations

import contextlib
import random
import statistics
import sys
import time
from collections import Counter
from dataclasses import dataclass, field
from pathlib import Path

from ..constraints import Constraints
from ..errors import InputError
from ..evaluate.spec import InstructionSpec
from ..scene._io import read_json
from ..translate.parse import RuleParser
from ..translate.vocabulary import DETERMINERS, PUNCTUATION, Vocabulary, words
from .heldout import parse_differences


@dataclass
class ParseOutcome:
    """One instruction's parse: ``refused`` (the parser's one-line error), ``diffs`` (fields
    differing from the spec), ``partly`` (constraint-like words not understood), ``ms`` and the
    ``constraints`` read (None when refused)."""

    spec: InstructionSpec
    refused: str = ""
    diffs: list[str] = field(default_factory=list)
    partly: list[str] = field(default_factory=list)
    ms: float = 0.0
    constraints: Constraints | None = None

    @property
    def expected_refusal(self) -> bool:
        """An infeasible instruction whose subject the scene lacks: refusing it is right."""
        return not self.spec.feasible and self.spec.reason == "unknown subject"

    @property
    def wrong(self) -> bool:
        """The parse misreads the spec: differences, or a refusal that was not expected."""
        return bool(self.diffs) or (self.spec.feasible and bool(self.refused))


def _catalog_vocabulary(objects: list[str]) -> Vocabulary:
    """A scene's vocabulary from the suite file's object names (catalog names and aliases)."""
    from ..synth.objects import lookup

    entries = []
    for name in objects:
        spec = lookup(name)  # a catalog entry has the name, aliases and symmetry the vocabulary reads
        if spec is None:
            raise InputError(f"object {name!r} is not in the catalog")
        entries.append(spec)
    return Vocabulary.from_semantics(entries)


def committed_cases(path: Path) -> list[tuple[Vocabulary, InstructionSpec]]:
    """(vocabulary, spec) of every instruction of a suite with committed instructions."""
    from ..synth.heldout import load_heldout

    heldout = load_heldout(path)
    return [(_catalog_vocabulary(scene.objects), spec) for scene, spec in heldout.cases()]


def generated_cases(path: Path, root: Path) -> list[tuple[Vocabulary, InstructionSpec]]:
    """(vocabulary, spec) of every generated instruction of a suite; the spec holds the
    generator's constraints (every generated instruction is feasible)."""
    from ..scene import load_scene_dir
    from .refine import suite_cases

    with contextlib.redirect_stdout(sys.stderr):  # generation's progress lines; stdout carries the figures
        cases = suite_cases(path, root)
    vocabularies: dict[Path, Vocabulary] = {}
    out = []
    for scene_dir, key, constraints in cases:
        if scene_dir not in vocabularies:
            semantics = load_scene_dir(scene_dir, load_gaussians=False).semantics or []
            vocabularies[scene_dir] = Vocabulary.from_semantics(semantics)
        text = read_json(root / "instructions" / scene_dir.name / "constraints.json")[key]["text"]
        spec = InstructionSpec(key, scene_dir.name, text, "generated", True, None, constraints)
        out.append((vocabularies[scene_dir], spec))
    return out


def parse_case(parser: RuleParser, vocabulary: Vocabulary, spec: InstructionSpec) -> ParseOutcome:
    """Parse one instruction, timed, and compare it with its spec."""
    start = time.perf_counter()
    try:
        parsed = parser.parse(spec.text, vocabulary)
    except InputError as err:
        return ParseOutcome(spec, refused=" ".join(str(err).split()), ms=1e3 * (time.perf_counter() - start))
    ms = 1e3 * (time.perf_counter() - start)
    diffs = parse_differences(parsed.to_dict(), spec)
    return ParseOutcome(spec, diffs=diffs, partly=parsed.not_understood(), ms=ms, constraints=parsed.constraints())


def bench_parse_only(suite: str | Path, root: str | Path = "results/bench/suite") -> dict:
    """Parse every instruction of ``suite`` (module docstring); returns the figures."""
    from ..synth.heldout import has_committed_instructions

    path = Path(suite)
    cases = committed_cases(path) if has_committed_instructions(path) else generated_cases(path, Path(root))
    parser = RuleParser()
    outcomes = [parse_case(parser, vocabulary, spec) for vocabulary, spec in cases]
    for o in outcomes:
        if o.wrong or o.refused or o.partly:
            print(_line(o), file=sys.stderr)
    feasible = [o for o in outcomes if o.spec.feasible]
    rng = random.Random(INTERRUPTION_SEED)
    kept = [interruption_kept(parser, vocabulary, o, rng) for (vocabulary, _), o in zip(cases, outcomes, strict=True)]
    return {
        "suite": path.stem,
        "instructions": len(outcomes),
        "feasible": len(feasible),
        "parse_differs_feasible": sum(o.wrong for o in feasible),
        "parse_differences": dict(Counter(d for o in feasible for d in o.diffs).most_common()),
        "refused_feasible": sum(bool(o.refused) for o in feasible),
        "unknown_subject_refused": sum(bool(o.refused) for o in outcomes if o.expected_refusal),
        "unknown_subject": sum(o.expected_refusal for o in outcomes),
        "partly_understood": sum(bool(o.partly) for o in outcomes),
        "median_parse_ms": statistics.median(o.ms for o in outcomes) if outcomes else 0.0,
        "max_parse_ms": max((o.ms for o in outcomes), default=0.0),
        "interrupted": sum(k is not None for k in kept),
        "interrupted_kept": sum(bool(k) for k in kept),
    }


# One word no table knows, put inside every fully read instruction at a place drawn with this seed.
INTERRUPTION_WORD = "glorp"
INTERRUPTION_SEED = 7


def interruption_kept(parser: RuleParser, vocabulary: Vocabulary, outcome: ParseOutcome, rng: random.Random) -> bool | None:
    """Whether ``outcome``'s instruction, fully read, keeps its constraints with
    :data:`INTERRUPTION_WORD` put between two of its words (a place drawn from ``rng``, never
    beside a name, a punctuation mark or after a determiner, where a new word would name a
    thing): robustness to a word the tables do not know. None when it was not fully read or has
    no such place."""
    if outcome.refused or outcome.partly:
        return None
    said = words(outcome.spec.text)
    names = vocabulary.name_words() | PUNCTUATION
    places = [k for k in range(1, len(said)) if not {said[k - 1], said[k]} & names and said[k - 1] not in DETERMINERS]
    if not places:
        return None
    k = rng.choice(places)
    try:
        interrupted = parser.parse(" ".join([*said[:k], INTERRUPTION_WORD, *said[k:]]), vocabulary)
    except InputError:
        return False
    return interrupted.constraints() == outcome.constraints


def _line(o: ParseOutcome) -> str:
    """One line per instruction worth a look: what differs, the refusal, the words not understood."""
    parts = []
    if o.diffs:
        parts.append("differs: " + "/".join(o.diffs))
    if o.refused:
        parts.append(("refused (expected)" if o.expected_refusal else "REFUSED") + f": {o.refused}")
    if o.partly:
        parts.append(f"partly understood: {o.partly}")
    tag = "DIFF" if o.wrong else "ok  "
    return f"{o.spec.id}: {tag} {'; '.join(parts)}  {o.spec.text!r}"


def format_parse_summary(f: dict) -> str:
    """The figures of :func:`bench_parse_only` as a few lines."""
    diffs = ", ".join(f"{k} {n}" for k, n in f["parse_differences"].items()) or "none"
    return "\n".join(
        [
            f"suite {f['suite']}: {f['instructions']} instructions parsed, {f['feasible']} feasible",
            f"feasible parsed differently from the spec: {f['parse_differs_feasible']} ({diffs}); "
            f"refused {f['refused_feasible']}",
            f"unknown subjects refused: {f['unknown_subject_refused']}/{f['unknown_subject']}",
            f"partly understood: {f['partly_understood']}",
            f"parse time: median {f['median_parse_ms']:.3f} ms, max {f['max_parse_ms']:.3f} ms",
            f"one unknown word put inside a fully read instruction: reading kept {f['interrupted_kept']}/{f['interrupted']}",
        ]
    )


__all__ = ["ParseOutcome", "bench_parse_only", "format_parse_summary", "interruption_kept", "parse_case"]
