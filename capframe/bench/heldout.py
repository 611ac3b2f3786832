"""Ground benchmark on a suite with hand-written specs (committed instructions: the held-out
sets, issue #15).

``capframe bench ground --suite heldout`` (or ``heldout2`` ... ``heldout20``, development sets, or
``heldout21``, the blind held-out set, or any suite file
naming a ``specs`` folder): every scene of the
suite is generated (when absent) and prepared as the workflow would (COLMAP without poses, gravity
when not aligned), its view cache is warmed, then
every committed instruction text goes through ``capframe ground`` (Retrieve -> Translate ->
Refine, embedded defaults) and the returned camera is judged against the instruction's
hand-written spec with the ground-truth checker (:func:`capframe.evaluate.spec.judge`) and the
clearance verdict (:func:`capframe.evaluate.spec.clearance`).

Printed: full success on the feasible instructions (every row of the spec satisfied; and the same
with a camera in free space), how the infeasible ones were handled (refused, reported by a
failing clause of the method's own report, or claimed satisfied), how many were only partly
understood (result.json ``not_understood``), counts per kind and per failure
reason (refused: unknown subject / parse; error; clause failed: which clause), where the parse
differs from the spec, and a clearance line. Written under the root (by default
``results/bench/<suite name>``): ``ground/<id>/`` (each result folder), ``checks/<id>.json``
(each verdict), ``heldout.csv`` (one row per instruction) and ``heldout.json`` (the figures).
"""

from __future__ import annotations

import contextlib
import csv
import shutil
import sys
import time
import traceback
from collections import Counter
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..constraints import VIEW_SIDES, view_within
from ..errors import InputError
from ..evaluate.check import GroundTruthChecker, read_result_camera
from ..evaluate.spec import InstructionSpec, arc_deviation, clearance, judge
from ..measure import CheckReport
from ..pipeline import GroundOptions, ground
from ..scene import load_scene_dir
from ..scene._io import read_json, write_json
from ..synth.heldout import load_heldout
from .ground import prepare_scene


@dataclass
class Outcome:
    """What happened to one instruction.

    Attributes:
        spec: the instruction.
        status: ``ok`` (every spec row satisfied), ``failed`` (a camera that misses a row),
            ``refused`` (the method raised an input error: it declined the instruction) or
            ``error`` (any other exception: a bug).
        reasons: why it failed (``refused: unknown subject``, ``refused: parse``, ``error: <type>``,
            ``clause failed: <constraint>``); empty when ok.
        message: the refusal or error message.
        own_all_satisfied: the method's own report says every clause holds (None without a camera).
        clearance: why the camera is physically impossible (empty when free or without a camera).
        parse_diffs: fields where the method's parse differs from the spec.
        not_understood: words the method's parse left out that may ask something (result.json
            ``not_understood``): the instruction was only partly understood. This does not make
            it "reported infeasible": the method did not say a clause fails, only that it read
            part of the request.
        seconds: wall time of ``ground``.
        satisfied, applicable: spec rows satisfied / applicable.
    """

    spec: InstructionSpec
    status: str
    reasons: list[str] = field(default_factory=list)
    message: str = ""
    own_all_satisfied: bool | None = None
    clearance: list[str] = field(default_factory=list)
    parse_diffs: list[str] = field(default_factory=list)
    not_understood: list[str] = field(default_factory=list)
    seconds: float = 0.0
    satisfied: int = 0
    applicable: int = 0

    @property
    def success(self) -> bool:
        """Every row of the spec satisfied (the checker's full success)."""
        return self.status == "ok"

    @property
    def free_success(self) -> bool:
        """Full success with a camera in free space."""
        return self.success and not self.clearance

    @property
    def reported_infeasible(self) -> bool:
        """The method declined it or its own report says a clause fails."""
        return self.status == "refused" or self.own_all_satisfied is False


def refusal_reason(message: str) -> str:
    """The failure reason of an input error raised by ``ground``: an unknown subject or any other
    refusal of the parse."""
    text = message.lower()
    if "subject" in text and any(w in text for w in ("not in this scene", "unknown", "closest", "no subject")):
        return "refused: unknown subject"
    return "refused: parse"


def parse_differences(parsed: dict, spec: InstructionSpec) -> list[str]:
    """Fields where the method's parse (``result.json`` ``instruction``) differs from the spec:
    ``subjects`` (other names); per subject ``region``, ``shot`` and ``view`` where the spec asks
    one (a view side is read right when it accepts only azimuths the spec's side accepts: "front-exact"
    for "front"; for an azimuth range: ``view`` unless every azimuth the parsed side aims at lies
    in it: "side", either end, is no reading of "its right-hand end");
    ``elevation`` when the spec asks one and the middle of the parsed range is outside the spec's
    range (or none was parsed); ``roll``."""
    diffs = []
    got = {s["name"]: s for s in parsed.get("subjects", [])}
    if set(got) != set(spec.subject_names):
        diffs.append("subjects")
    for want in spec.constraints.subjects:
        have = got.get(want.name)
        if have is None:
            continue
        diffs += [key for key in ("region", "shot") if getattr(want, key) is not None and have.get(key) != getattr(want, key)]
        if want.view is not None and (have.get("view") not in VIEW_SIDES or not view_within(have["view"], want.view)):
            diffs.append("view")
        if want.name in spec.azimuths:
            sides = VIEW_SIDES.get(have.get("view") or "", ())
            if not sides or not all(arc_deviation(a, *spec.azimuths[want.name]) == 0.0 for a in sides):
                diffs.append("view")
    wanted = spec.elevation_range or spec.constraints.elevation_range()
    if wanted is not None:
        got_range = parsed.get("elevation_range_deg")
        if not got_range or not wanted[0] <= (got_range[0] + got_range[1]) / 2 <= wanted[1]:
            diffs.append("elevation")
    if spec.constraints.roll_deg is not None and parsed.get("roll_deg") != spec.constraints.roll_deg:
        diffs.append("roll")
    return sorted(set(diffs))


def _ground_one(scene_dir: Path, spec: InstructionSpec, out: Path, options: GroundOptions) -> tuple[str, str, float]:
    """Run ``ground`` on one text into ``out``: (status ``done``/``refused``/``error``, message, seconds)."""
    shutil.rmtree(out, ignore_errors=True)
    start = time.perf_counter()
    try:
        with contextlib.redirect_stdout(sys.stderr):
            ground(scene_dir, spec.text, out, options, progress=False)
    except InputError as err:
        return "refused", " ".join(str(err).split()), time.perf_counter() - start
    except Exception as err:  # a bug in the method: counted and reported, the benchmark goes on
        traceback.print_exc(file=sys.stderr)
        return "error", _error_message(err), time.perf_counter() - start
    return "done", "", time.perf_counter() - start


def _error_message(err: Exception) -> str:
    """An exception as one line: its type and its message."""
    return f"{type(err).__name__}: {' '.join(str(err).split())}"


def judge_result(
    out: Path, spec: InstructionSpec, checker: GroundTruthChecker, walls: list[str], seconds: float
) -> tuple[Outcome, CheckReport]:
    """The outcome of a result folder ``out`` written by ``ground``, and the checker's report."""
    result = read_json(out / "result.json")
    camera, _ = read_result_camera(out / "result.json")
    report = judge(checker, camera, spec)
    applicable = [r for r in report.rows if r.satisfied is not None]
    failed = sorted({r.constraint for r in applicable if not r.satisfied})
    return Outcome(
        spec,
        "ok" if report.all_satisfied else "failed",
        [f"clause failed: {c}" for c in failed],
        own_all_satisfied=bool(result["report"]["all_satisfied"]),
        clearance=clearance(checker.ground_truth, walls, camera.center, checker.enclosed),
        parse_diffs=parse_differences(result.get("instruction", {}), spec),
        not_understood=list(result.get("not_understood", [])),
        seconds=seconds,
        satisfied=sum(bool(r.satisfied) for r in applicable),
        applicable=len(applicable),
    ), report


def _scene_checker(ground_dir: Path) -> tuple[GroundTruthChecker, list[str]]:
    """The ground-truth checker of a prepared scene and its room's walls (``room.walls``)."""
    raw = read_json(ground_dir / "ground_truth.json")
    return GroundTruthChecker(ground_dir), list((raw.get("room") or {}).get("walls", []))


def _warm_cache(ground_dir: Path, cache: Path) -> None:
    """The per-scene view measurements, computed once before any instruction is timed."""
    from ..retrieve.views import cached_view_measurements

    cached_view_measurements(load_scene_dir(ground_dir), cache)


def bench_heldout(suite: str | Path, root: str | Path | None = None, blind: bool = False) -> dict:
    """Run ``ground`` on every committed instruction of ``suite`` and judge it (module docstring).
    With ``blind`` the progress lines leave out the instructions' words (:func:`_line`), so a
    held-out set can be measured by someone who must not read it. Returns the figures
    (:func:`summarise`)."""
    from ..synth.generator import generate_scene

    start = time.perf_counter()
    heldout = load_heldout(suite)
    if heldout.parse_only:
        raise InputError(f"suite {heldout.name!r} is a parse-only corpus (its feasibility was not searched); add --parse-only")
    root = Path(root) if root is not None else Path("results/bench") / heldout.name
    outcomes = []
    for scene in heldout.scenes:
        scene_dir = root / "scenes" / scene.id
        if not scene_dir.is_dir():
            generate_scene(scene_dir, **scene.generate_kwargs())
        ground_dir, gravity = prepare_scene(scene_dir, root)
        checker, walls = _scene_checker(ground_dir)
        cache = root / "cache" / ground_dir.name
        _warm_cache(ground_dir, cache)
        options = GroundOptions(cache_dir=cache, gravity=gravity)
        for spec in heldout.specs[scene.id]:
            outcome = _run_one(ground_dir, spec, root, options, checker, walls)
            outcomes.append(outcome)
            print(_line(outcome, blind), file=sys.stderr, flush=True)
    figures = summarise(outcomes)
    figures["suite"] = heldout.name
    figures["wall_s"] = time.perf_counter() - start
    _write_rows(outcomes, root / "heldout.csv")
    write_json(root / "heldout.json", figures)
    return figures


def _run_one(
    ground_dir: Path, spec: InstructionSpec, root: Path, options: GroundOptions, checker: GroundTruthChecker, walls: list[str]
) -> Outcome:
    """Ground one instruction into ``root/ground/<id>`` and judge it (the report to
    ``root/checks/<id>.json``). A bug in the method or in the judge is an ``error`` outcome, so
    the instructions measured before it are kept."""
    out = root / "ground" / spec.id
    status, message, seconds = _ground_one(ground_dir, spec, out, options)
    if status == "refused":
        return Outcome(spec, "refused", [refusal_reason(message)], message, seconds=seconds)
    if status != "done":
        return Outcome(spec, "error", [f"error: {message.split(':')[0]}"], message, seconds=seconds)
    try:
        outcome, report = judge_result(out, spec, checker, walls, seconds)
    except Exception as err:
        traceback.print_exc(file=sys.stderr)
        return Outcome(spec, "error", [f"error: judge {type(err).__name__}"], _error_message(err), seconds=seconds)
    write_json(root / "checks" / f"{spec.id}.json", report.to_dict())
    return outcome


def _line(o: Outcome, blind: bool = False) -> str:
    """One progress line per instruction (stderr): ``ok``/``FAIL`` for a feasible instruction,
    ``INF reported``/``INF NOT reported`` for an infeasible one. ``blind`` keeps the id, the
    verdict and the failure kinds, and drops every word of the instruction (its text, the words
    not understood, the method's message, which may quote a subject)."""
    if o.spec.feasible:
        tag = "ok  " if o.success else "FAIL"
    else:
        tag = "INF reported" if o.reported_infeasible else "INF NOT reported"
    detail = ", ".join(
        o.reasons
        + [f"camera {c}" for c in o.clearance]
        + ([f"parse: {'/'.join(o.parse_diffs)}"] if o.parse_diffs else [])
        + ([f"partly understood: not {o.not_understood}"] if o.not_understood and not blind else [])
        + (["partly understood"] if o.not_understood and blind else [])
    )
    if blind:
        return f"{o.spec.id}: {tag} {o.status} {o.seconds:.1f} s {detail}"
    return f"{o.spec.id}: {tag} {o.status} {o.seconds:.1f} s {detail}  {o.spec.text!r}" + (
        f"  [{o.message}]" if o.message else ""
    )


def summarise(outcomes: list[Outcome]) -> dict:
    """Figures of a run: full success on the feasible instructions (checker, and with a free
    camera), infeasible ones reported, per kind, per failure reason, parse differences, clearance,
    own-report agreement and wall times of ``ground``."""
    feasible = [o for o in outcomes if o.spec.feasible]
    infeasible = [o for o in outcomes if not o.spec.feasible]
    cameras = [o for o in outcomes if o.status in ("ok", "failed")]
    times = np.array([o.seconds for o in outcomes]) if outcomes else np.zeros(1)
    per_kind: dict[str, dict] = {}
    for o in outcomes:
        entry = per_kind.setdefault(o.spec.kind, {"feasible": 0, "ok": 0, "infeasible": 0, "reported": 0})
        if o.spec.feasible:
            entry["feasible"] += 1
            entry["ok"] += o.success
        else:
            entry["infeasible"] += 1
            entry["reported"] += o.reported_infeasible
    clearance_counts = Counter(
        c.split(" (")[0] if not c.startswith("inside") else "inside an object" for o in cameras for c in o.clearance
    )
    return {
        "instructions": len(outcomes),
        "feasible": len(feasible),
        "full_success": sum(o.success for o in feasible),
        "full_success_rate": sum(o.success for o in feasible) / max(1, len(feasible)),
        "full_success_free_camera": sum(o.free_success for o in feasible),
        "constraint_success_rate": sum(o.satisfied for o in feasible) / max(1, sum(o.applicable for o in feasible)),
        "infeasible": len(infeasible),
        "infeasible_reported": sum(o.reported_infeasible for o in infeasible),
        "infeasible_refused": sum(o.status == "refused" for o in infeasible),
        "infeasible_claimed_satisfied": sum(o.own_all_satisfied is True for o in infeasible),
        "partly_understood": sum(bool(o.not_understood) for o in outcomes),
        "partly_understood_feasible": sum(bool(o.not_understood) for o in feasible),
        "per_kind": dict(sorted(per_kind.items())),
        "failure_reasons": dict(Counter(r for o in feasible for r in o.reasons).most_common()),
        "parse_differences": dict(Counter(d for o in feasible for d in o.parse_diffs).most_common()),
        "own_report_claims_success_on_failures": sum(o.own_all_satisfied is True for o in feasible if o.status == "failed"),
        "cameras": len(cameras),
        "cameras_not_free": sum(bool(o.clearance) for o in cameras),
        "clearance": dict(clearance_counts.most_common()),
        "satisfied_but_not_free": sum(o.success and bool(o.clearance) for o in outcomes),
        "median_ground_s": float(np.median(times)),
        "max_ground_s": float(times.max()),
    }


def format_summary(f: dict) -> str:
    """The figures of :func:`summarise` as a short report."""
    pct = lambda n, d: f"{n}/{d} ({100.0 * n / max(1, d):.1f}%)"  # noqa: E731
    lines = [
        f"suite {f.get('suite', '?')}: {f['instructions']} instructions, {f['feasible']} feasible, {f['infeasible']} infeasible",
        f"full success (feasible)        {pct(f['full_success'], f['feasible'])}",
        f"  ... with a free camera       {pct(f['full_success_free_camera'], f['feasible'])}",
        f"constraints satisfied          {100.0 * f['constraint_success_rate']:.1f}%",
        f"infeasible reported            {pct(f['infeasible_reported'], f['infeasible'])}"
        f"  (refused {f['infeasible_refused']}, own report claims success {f['infeasible_claimed_satisfied']})",
        f"partly understood              {f['partly_understood']} instructions ({f['partly_understood_feasible']} feasible): "
        "words that may ask something were not understood",
        "per kind (feasible ok/n; infeasible reported/n):",
    ]
    for kind, e in f["per_kind"].items():
        parts = [f"{e['ok']}/{e['feasible']}"] if e["feasible"] else []
        parts += [f"infeasible reported {e['reported']}/{e['infeasible']}"] if e["infeasible"] else []
        lines.append(f"  {kind:<10} {', '.join(parts)}")
    lines.append("failure reasons on feasible instructions (an instruction counts once per reason):")
    lines += [f"  {reason:<28} {n}" for reason, n in f["failure_reasons"].items()] or ["  none"]
    diffs = ", ".join(f"{k} {n}" for k, n in f["parse_differences"].items()) or "none"
    lines.append(f"parse differs from the spec (feasible): {diffs}")
    lines.append(f"own report says all clauses hold on {f['own_report_claims_success_on_failures']} failed feasible instructions")
    where = ", ".join(f"{k} {n}" for k, n in f["clearance"].items()) or "none"
    lines.append(
        f"clearance: {f['cameras_not_free']}/{f['cameras']} cameras not in free space ({where}); "
        f"{f['satisfied_but_not_free']} of them pass the checker"
    )
    lines.append(
        f"ground time: median {f['median_ground_s']:.1f} s, max {f['max_ground_s']:.1f} s; "
        f"bench wall {f.get('wall_s', 0.0):.0f} s"
    )
    return "\n".join(lines)


def _write_rows(outcomes: list[Outcome], path: Path) -> None:
    """One CSV row per instruction."""
    path.parent.mkdir(parents=True, exist_ok=True)
    keys = ["id", "scene", "kind", "feasible", "reason", "status", "success", "free_success", "reported_infeasible"]
    keys += [
        "failure_reasons",
        "own_all_satisfied",
        "clearance",
        "parse_diffs",
        "not_understood",
        "satisfied",
        "applicable",
        "seconds",
        "message",
        "text",
    ]
    with open(path, "w", newline="") as handle:
        writer = csv.writer(handle)
        writer.writerow(keys)
        for o in outcomes:
            s = o.spec
            writer.writerow(
                [s.id, s.scene, s.kind, s.feasible, s.reason or "", o.status, o.success, o.free_success, o.reported_infeasible]
                + ["; ".join(o.reasons), o.own_all_satisfied, "; ".join(o.clearance), "; ".join(o.parse_diffs)]
                + ["; ".join(o.not_understood)]
                + [o.satisfied, o.applicable, f"{o.seconds:.2f}", o.message, s.text]
            )


__all__ = ["Outcome", "bench_heldout", "format_summary", "parse_differences", "refusal_reason", "summarise"]
