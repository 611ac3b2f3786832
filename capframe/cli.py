"""The ``capframe`` command. Each verb is a thin wrapper over one library entry point.

Input errors (:class:`capframe.errors.InputError`) print as one line on stderr and exit with 2;
model failures (:class:`capframe.errors.ModelError`) likewise with 3.
"""

from __future__ import annotations

import argparse
import os
import sys

from ._malloc import keep_freed_memory
from .errors import InputError, ModelError


def _cmd_render(args: argparse.Namespace) -> None:
    from .render.cli import render_command

    render_command(args.scene, args.camera, args.output, backend=args.backend, long_side=args.long_side)


def _cmd_import(args: argparse.Namespace) -> None:
    from .scene.directory import import_scene

    import_scene(args.src, args.dst, copy_images=args.copy_images)


def _cmd_colmap(args: argparse.Namespace) -> None:
    from .scene.sfm import colmap_command

    colmap_command(args.scene, args.output, matcher=args.matcher, camera_model=args.camera_model, num_threads=args.threads)


def _cmd_align_truth(args: argparse.Namespace) -> None:
    from .evaluate.alignment import align_truth_command

    align_truth_command(args.recovered, args.truth, args.output)


def _cmd_gravity(args: argparse.Namespace) -> None:
    from .geometry.gravity import gravity_command

    gravity_command(args.scene, args.output, use_lines=not args.no_lines, as_json=args.json)


def _cmd_synth(args: argparse.Namespace) -> None:
    from .synth.generator import synth_command

    synth_command(args)


def _cmd_instructions(args: argparse.Namespace) -> None:
    from .synth.instructions import write_instructions

    write_instructions(args.scene, args.output, count=args.count, seed=args.seed)


def _cmd_check(args: argparse.Namespace) -> None:
    from .evaluate.check import check_command

    check_command(
        args.scene,
        args.result,
        args.constraints,
        instruction_id=args.id,
        as_json=args.json,
        output=args.output,
        cache_dir=args.cache,
    )


def _cmd_oracle(args: argparse.Namespace) -> None:
    from .evaluate.oracle import oracle_command

    oracle_command(args.scene, args.constraints, args.id, args.output)


def _cmd_aggregate(args: argparse.Namespace) -> None:
    from .evaluate.aggregate import aggregate_command

    aggregate_command(args.method, args.checks, args.results, args.output)


def _cmd_refine(args: argparse.Namespace) -> None:
    from .pipeline import StageClock, stages
    from .pipeline.outputs import write_ground_result, write_refine_result
    from .render import check_render_memory
    from .scene import load_scene_dir
    from .scene._io import MadeFrom
    from .translate.labels import read_pseudo_labels

    options = _ground_options(args)
    options.check()
    clock = StageClock(True)
    made_from = MadeFrom()
    labels = read_pseudo_labels(args.labels, made_from)
    scene = load_scene_dir(args.scene)
    if scene.gaussians is None:
        raise InputError("has no scene.ply to refine against", source=str(args.scene))
    beyond = [s.name for s in labels.subjects if s.gaussians.max() >= len(scene.gaussians)]
    if beyond:
        raise InputError(
            f"subjects {beyond} have Gaussian indices beyond the {len(scene.gaussians)} of {args.scene}; "
            "expected labels made for this scene",
            source=str(args.labels),
        )
    if _is_retrieval_file(args.init):
        from .handoff import Retrieved

        retrieved = Retrieved.read(args.init, made_from)
        if not scene.cameras:
            raise InputError("has no training cameras to refine from retrieved views", source=str(args.scene))
        starts = [scene.cameras[v] for v in stages.view_indices(scene, retrieved.starts, retrieved.source)]
        check_render_memory(starts, device=scene.gaussians.means.device, source=str(args.scene))
        occupancy = _occupancy(args, scene, labels, options, clock)
        refined = stages.refine(scene, labels, starts, options, clock, occupancy)
        write_ground_result(args.output, scene, labels, retrieved, refined, options, clock, occupancy)
    else:
        start = _initial_camera(scene.cameras, args.init)
        check_render_memory(start, device=scene.gaussians.means.device, source=args.init)
        clock.done("load")
        occupancy = _occupancy(args, scene, labels, options, clock)
        refined = stages.refine(scene, labels, [start], options, clock, occupancy, solve=False)
        write_refine_result(args.output, scene, labels, refined, options.refine, clock)


def _occupancy(args: argparse.Namespace, scene, labels, options, clock):
    """The occupancy of ``capframe refine``: its --occupancy file (built from this scene's
    Gaussians), else the cached one (None with --no-free-space)."""
    from .pipeline import stages
    from .scene.occupancy import gaussians_fingerprint, load_occupancy

    if not options.free_space:
        return None
    if args.occupancy is None:
        return stages.free_space(scene, labels.up, options, clock, labels)
    occupancy = load_occupancy(args.occupancy, gaussians=gaussians_fingerprint(scene.gaussians))
    if occupancy is None:
        raise InputError(
            "not found or not an occupancy of this version; rebuild it with capframe occupancy", source=args.occupancy
        )
    return stages.subject_space(occupancy, scene, labels, clock)


def _cmd_warm_server(args: argparse.Namespace) -> None:
    from .warm import serve

    serve(args.socket, main, parent=args.parent)


def _cmd_occupancy(args: argparse.Namespace) -> None:
    from .geometry.gravity import world_up
    from .scene import load_scene_dir
    from .scene.occupancy import build_occupancy, gaussians_fingerprint, occupancy_fingerprint, save_occupancy

    scene = load_scene_dir(args.scene)
    if scene.gaussians is None:
        raise InputError("has no scene.ply to build free space from", source=str(args.scene))
    up = world_up(args.scene, args.gravity)
    grid = build_occupancy(scene.gaussians, up, scene.cameras)
    fingerprint = occupancy_fingerprint(scene.gaussians, up, scene.cameras)
    save_occupancy(grid, args.output, fingerprint, gaussians_fingerprint(scene.gaussians))
    print(f"{args.output}: {grid.occupied.shape} voxels of {grid.voxel:.4g}, {int(grid.free.sum())} free")


def _initial_camera(scene_cameras, init: str):
    """A camera.json path or the name of a training view."""
    import difflib
    from pathlib import Path

    from .scene import read_camera_json

    if Path(init).is_file():
        return read_camera_json(init)
    for camera in scene_cameras:
        if camera.name == init:
            return camera
    close = difflib.get_close_matches(init, [c.name for c in scene_cameras], n=3)
    raise InputError(f"--init {init!r} is neither a camera.json nor a training view; closest views: {close}")


def _is_retrieval_file(init: str) -> bool:
    import json
    from pathlib import Path

    if not init.endswith(".json") or not Path(init).is_file():
        return False
    try:
        return "starts" in json.loads(Path(init).read_text())
    except ValueError:
        return False


def _refine_config(args: argparse.Namespace):
    """The optimiser's settings from ``--iterations``, ``--long-side`` and ``--weights``."""
    import dataclasses
    import math

    from .refine.optimize import RefineConfig

    config = RefineConfig(iterations=args.iterations, long_side=args.long_side)
    if getattr(args, "weights", None):
        weights = dataclasses.asdict(config.weights)
        for item in args.weights.split(","):
            key, _, text = item.partition("=")
            if key not in weights:
                raise InputError(f"--weights: unknown term {key!r}; expected one of {sorted(weights)}")
            try:
                value = float(text)
            except ValueError:
                value = math.nan
            # A weight of 1e400 reads as infinity and would turn every loss into inf or NaN.
            if not math.isfinite(value) or value < 0:
                raise InputError(f"--weights: {key} is {text!r}; expected a finite number >= 0")
            weights[key] = value
        config = dataclasses.replace(config, weights=type(config.weights)(**weights))
    return config


def _cmd_views(args: argparse.Namespace) -> None:
    from .retrieve.views import views_command

    views_command(args.scene, args.output, long_side=args.long_side)


def _cmd_compare(args: argparse.Namespace) -> None:
    from .evaluate.aggregate import compare_command

    compare_command(args.tables, args.output)


def _cmd_sensitivity(args: argparse.Namespace) -> None:
    from .evaluate.tables import sensitivity_command

    sensitivity_command(args.reference, args.variant, args.checks_root, args.scenes_root, args.output, args.metrics)


def _cmd_groups(args: argparse.Namespace) -> None:
    from .evaluate.tables import group_table_command

    group_table_command(args.tables, args.group, args.output, args.metrics)


def _cmd_metrics(args: argparse.Namespace) -> None:
    from .evaluate.metrics import metrics_command

    metrics_command(args.scene, args.constraints, args.method, args.models, args.output)


def _cmd_judge(args: argparse.Namespace) -> None:
    from .evaluate.judging import judge_command

    judge_command(args.scene, args.constraints, args.method, args.models, args.cache, args.output, seed=args.seed)


def _cmd_quantitative(args: argparse.Namespace) -> None:
    from .evaluate.quantitative import quantitative_command

    quantitative_command(args.tables, args.metrics, args.judgements, args.userstudy, args.output)


def _cmd_scene_table(args: argparse.Namespace) -> None:
    from .evaluate.tables import scene_table_command

    scene_table_command(args.scenes_root, args.colmap_root, args.gravity_root, args.output)


def _cmd_runtime(args: argparse.Namespace) -> None:
    from .evaluate.tables import runtime_command

    runtime_command(args.benchmarks, args.output, args.methods_table, args.results_root)


def _ground_options(args: argparse.Namespace):
    """The :class:`~capframe.pipeline.GroundOptions` of a verb's arguments (each verb has some)."""
    from .backends import ROLES
    from .pipeline import GroundOptions

    values = {
        "top_k": getattr(args, "topk", None),
        "seed": getattr(args, "seed", None),
        "candidates": getattr(args, "candidates", None),
        "attempts": getattr(args, "attempts", None),
        "models": getattr(args, "models", None),
        "cache_dir": getattr(args, "cache", None),
        "gravity": getattr(args, "gravity", None),
        "drop": getattr(args, "drop", None),
        "box_noise": getattr(args, "box_noise", None),
        "front_noise_deg": getattr(args, "front_noise", None),
        "noise_seed": getattr(args, "noise_seed", None),
        "solve": getattr(args, "solve", None),
        "free_space": getattr(args, "free_space", None),
    }
    if hasattr(args, "iterations"):
        values["refine"] = _refine_config(args)
    backends = {role: getattr(args, _role_dest(role), None) for role in ROLES}
    return GroundOptions(backends={k: v for k, v in backends.items() if v}, **{k: v for k, v in values.items() if v is not None})


def _role_dest(role: str) -> str:
    return "backend_" + role.replace("-", "_")


def _stage_job(args: argparse.Namespace):
    """The options, clock and job of a per-instruction stage verb."""
    from .pipeline import StageClock, open_job

    options = _ground_options(args)
    args.clock = StageClock(True)  # its timings and model counters go to the stage's sidecar (_stage_verb)
    return options, args.clock, open_job(args.scene, options)


def _cmd_parse(args: argparse.Namespace) -> None:
    from .handoff import write_parsed
    from .pipeline import stages

    _, clock, job = _stage_job(args)
    write_parsed(stages.parse(job, args.instruction, clock), args.output)


def _cmd_coarse(args: argparse.Namespace) -> None:
    from .handoff import read_parsed
    from .pipeline import stages
    from .scene._io import MadeFrom

    if (args.instruction is None) == (args.parsed is None):
        raise InputError("give the instruction or --parsed parsed.json (one of them)")
    made_from = MadeFrom()
    parsed = read_parsed(args.parsed, made_from) if args.parsed else None
    _, clock, job = _stage_job(args)
    coarse = stages.coarse(job, parsed or stages.parse(job, args.instruction, clock), clock, args.parsed)
    coarse.write(args.output, made_from)


def _cmd_qe(args: argparse.Namespace) -> None:
    from .handoff import Coarse
    from .pipeline import stages
    from .scene._io import MadeFrom, write_json

    made_from = MadeFrom()
    coarse = Coarse.read(args.coarse, made_from)
    options, clock, job = _stage_job(args)
    write_json(args.output, stages.qe(job, coarse, options, clock).to_dict(made_from))


def _cmd_retrieve(args: argparse.Namespace) -> None:
    from .pipeline import stages
    from .scene._io import write_json

    options, clock, job = _stage_job(args)
    coarse = stages.coarse(job, stages.parse(job, args.instruction, clock), clock)
    write_json(args.output, stages.qe(job, coarse, options, clock).to_dict())


def _cmd_segment(args: argparse.Namespace) -> None:
    from .handoff import Retrieved, write_masks
    from .pipeline import stages
    from .scene._io import MadeFrom

    made_from = MadeFrom()
    retrieved = Retrieved.read(args.retrieval, made_from)
    _, clock, job = _stage_job(args)
    write_masks(stages.segment(job, retrieved, clock), job.view_names, args.output, made_from)


def _cmd_associate(args: argparse.Namespace) -> None:
    from .handoff import Retrieved, read_masks, write_groundings
    from .pipeline import stages
    from .scene._io import MadeFrom

    made_from = MadeFrom()
    retrieved = Retrieved.read(args.retrieval, made_from)
    _, clock, job = _stage_job(args)
    if args.masks:
        masks = read_masks(args.masks, job.view_names, made_from)
    elif job.backends["associator"].needs_masks:
        masks = stages.segment(job, retrieved, clock)
    else:
        masks = {}
    write_groundings(stages.associate(job, retrieved, masks, clock), args.output, made_from)


def _cmd_orient(args: argparse.Namespace) -> None:
    from .handoff import Retrieved, read_masks, write_fronts
    from .pipeline import stages
    from .scene._io import MadeFrom

    made_from = MadeFrom()
    retrieved = Retrieved.read(args.retrieval, made_from)
    _, clock, job = _stage_job(args)
    masks = read_masks(args.masks, job.view_names, made_from) if args.masks else None
    write_fronts(stages.orient(job, retrieved, clock, masks), args.output, made_from)


def _cmd_translate(args: argparse.Namespace) -> None:
    from .handoff import Retrieved, read_fronts, read_groundings
    from .pipeline import StageClock, stages
    from .scene import load_scene_dir
    from .scene._io import MadeFrom
    from .translate.labels import write_pseudo_labels

    made_from = MadeFrom()
    retrieved = Retrieved.read(args.retrieval, made_from)
    options = _ground_options(args)
    clock = StageClock(True)
    if args.subjects:
        options.check()
        scene = load_scene_dir(args.scene)
        if scene.gaussians is None:
            raise InputError("has no scene.ply; the subjects' Gaussian indices refer to it", source=str(args.scene))
        groundings = read_groundings(args.subjects, len(scene.gaussians), made_from)
        fronts = read_fronts(args.fronts, made_from) if args.fronts else {}
        labels = stages.translate(retrieved, groundings, fronts, options, clock)
    else:
        labels = stages.perceive(stages.open_job(args.scene, options), retrieved, options, clock)
    write_pseudo_labels(labels, args.output, made_from)


def _cmd_retrieved_view(args: argparse.Namespace) -> None:
    from .handoff import Retrieved
    from .pipeline import StageClock
    from .pipeline.outputs import write_retrieved_view
    from .pipeline.stages import view_indices
    from .scene import load_scene_dir

    clock = StageClock(False)
    scene = load_scene_dir(args.scene)
    if scene.gaussians is None or not scene.cameras:
        raise InputError("needs scene.ply and training cameras to render a retrieved view", source=str(args.scene))
    retrieved = Retrieved.read(args.retrieval)
    camera = scene.cameras[view_indices(scene, retrieved.starts[:1], retrieved.source)[0]]
    clock.done("load")
    summary = write_retrieved_view(args.output, scene, retrieved, camera, clock)
    print(f"{args.output}: retrieved view {summary['init_view']}")


def _cmd_grid(args: argparse.Namespace) -> None:
    from .evaluate.grid import grid_command

    grid_command(args.text, args.methods, args.results, args.checks, args.output)


def _cmd_ground(args: argparse.Namespace) -> None:
    from .pipeline import ground
    from .scene._io import json_text

    result = ground(args.scene, args.instruction, args.output, _ground_options(args), progress=not args.json)
    if args.json:
        keys = ("T_cw", "K", "width", "height", "init_view", "timings", "report", "understood", "verdict", "instruction")
        print(json_text({k: result[k] for k in keys}, "the result", indent=None))
    else:
        print(f"{args.output}: camera from {result['init_view']}, {result['timings']['total_s']:.1f} s; {result['verdict']}")


def _cmd_baseline(args: argparse.Namespace) -> None:
    from .baselines.chatcam import ChatCamConfig
    from .baselines.run import BaselineOptions, run_baseline
    from .refine.optimize import RefineConfig
    from .scene._io import json_text

    budget = {"iterations": args.chatcam_iterations, "long_side": args.chatcam_long_side}
    options = BaselineOptions(
        seed=args.seed,
        chatcam=ChatCamConfig(RefineConfig(**{k: v for k, v in budget.items() if v is not None})),
        stages=_ground_options(argparse.Namespace(**{**vars(args), "seed": None})),
    )
    result = run_baseline(args.method, args.scene, args.instruction, args.output, options, progress=not args.json)
    if args.json:
        keys = ("T_cw", "K", "width", "height", "method", "score", "timings")
        print(json_text({k: result[k] for k in keys}, "the result", indent=None))
    else:
        print(f"{args.output}: {args.method} camera, score {result['score']:.1f}, {result['timings']['total_s']:.1f} s")


def _cmd_bench(args: argparse.Namespace) -> None:
    from .bench import run_bench

    if args.what == "segment" and args.models is None:
        raise InputError("capframe bench segment needs --models (the models config of the segmenter)")
    run_bench(
        args.what,
        as_json=args.json,
        suite=args.suite,
        models=args.models,
        segmenter=args.segmenter,
        benchmarks=args.benchmarks,
        photos=args.photos,
        reference=args.reference,
        points=args.points,
        sizes=args.sizes,
        parse_only=args.parse_only,
        blind=args.blind,
    )


def _cmd_models_export(args: argparse.Namespace) -> None:
    from .backends.export import export_command

    export_command(args.backend, args.models, args.output)


def _cmd_models_check(args: argparse.Namespace) -> None:
    from .backends.check import check_models

    faults = check_models(args.models)
    if faults:
        raise ModelError(f"{faults} entries of {args.models} failed the check (lines above)")


def _cmd_userstudy_make(args: argparse.Namespace) -> None:
    from .userstudy import make_questionnaire

    methods = [m.strip() for m in args.methods.split(",")]
    key = make_questionnaire(args.results, methods, args.output, groups=args.groups, per_group=args.per_group, seed=args.seed)
    print(
        f"{args.output}/site/index.html: questionnaire {key.questionnaire}, {len(key.groups)} groups of {args.per_group} images; "
        f"the key {args.output}/key.json stays with you"
    )


def _cmd_userstudy_import(args: argparse.Namespace) -> None:
    from .userstudy import import_answers

    table = import_answers(args.key, args.answers, args.output)
    print(f"{args.output}: {len(args.answers)} answer files, {int(table['rating_n'].sum())} ratings of {len(table)} methods")


def _perception_options(p: argparse.ArgumentParser) -> None:
    """The backend of every perception role (``capframe.backends.ROLES``), the models config,
    the per-scene cache and the gravity file: options shared by the method's stages."""
    from .backends import ROLES, backend_names

    for role, spec in ROLES.items():
        if spec.backends:
            names = ", ".join(backend_names(role))
            p.add_argument(
                spec.option, dest=_role_dest(role), default=None, help=f"{spec.help}: {names} (default {spec.default})"
            )
    p.add_argument("--models", default=None, help="models config (weights, endpoints) of model backends, e.g. config/models.yaml")
    p.add_argument("--cache", default=None, help="per-scene cache folder (default: ~/.cache/capframe/<scene>)")
    p.add_argument("--gravity", default=None, help="gravity.json when scene.json has no up (default: SCENE/gravity.json)")


def _placement_options(p: argparse.ArgumentParser) -> None:
    """Refine's starts and free space (``GroundOptions.solve`` / ``free_space``)."""
    p.add_argument(
        "--solve",
        type=int,
        default=3,
        help="also start from up to this many cameras solved in closed form from the pseudo labels (0: retrieved views only)",
    )
    p.add_argument(
        "--no-free-space",
        dest="free_space",
        action="store_false",
        help="ignore the scene's occupancy: cameras may end inside geometry (needs --solve 0)",
    )


def _stage_verb(verbs, name: str, help_text: str, output: str, func) -> argparse.ArgumentParser:
    """A per-instruction stage of the method: ``capframe NAME SCENE ... -o OUTPUT`` with the
    perception options; the caller adds the stage's own inputs."""
    p = verbs.add_parser(name, help=f"{help_text}: {output}")
    p.add_argument("scene")
    p.add_argument("-o", "--output", required=True, help=f"{output} to write (and its timing sidecar, .timings.json)")
    _perception_options(p)
    p.set_defaults(func=_with_timings(func), outputs={"output": "file"})
    return p


def _with_timings(func):
    """``func`` followed by the stage's timing sidecar (DESIGN §7): ``<output stem>.timings.json``,
    the stage clock's seconds and its models' counters (MLLM calls, cache hits, tokens, seconds),
    which ``capframe runtime`` sums per stage and scene. Written only after the output."""

    def run(args: argparse.Namespace) -> None:
        from pathlib import Path

        from .scene._io import write_json

        func(args)
        clock = getattr(args, "clock", None)
        if clock is not None:
            write_json(Path(args.output).with_suffix(".timings.json"), clock.total())

    return run


class _Parser(argparse.ArgumentParser):
    """Usage errors as one line, like every other input error (exit status 2)."""

    def error(self, message: str):
        self.exit(2, f"{self.prog}: error: {message} (see {self.prog} --help)\n")


def _positive_int(text: str) -> int:
    """An argument that counts pixels or steps: a whole number of at least 1."""
    try:
        value = int(text)
    except ValueError:
        value = 0
    if value < 1:
        raise argparse.ArgumentTypeError(f"{text!r} is not a positive whole number")
    return value


def _add_frames_of_scene(p: argparse.ArgumentParser) -> None:
    """The arguments of the verbs that score every method's final frame of one scene."""
    p.add_argument("--scene", required=True, help="the scene's id (the table's scene column)")
    p.add_argument("--constraints", required=True, help="the scene's constraints.json (instruction ids and texts)")
    p.add_argument("--method", nargs="+", required=True, metavar="NAME=DIR", help="methods' result folders: DIR/<id>/render.png")


def build_parser() -> argparse.ArgumentParser:
    from . import __version__

    parser = _Parser(prog="capframe", description=__doc__.splitlines()[0])
    parser.add_argument("--version", action="version", version=f"capframe {__version__}")
    verbs = parser.add_subparsers(dest="verb", required=True)

    p = verbs.add_parser("render", help="render one view of a scene")
    p.add_argument("scene", help="scene directory (see docs/scene-directory.md) or a 3DGS PLY file")
    p.add_argument("--camera", required=True, help="camera.json (capframe) to render from")
    p.add_argument("-o", "--output", required=True, help="output image: .png, or .jpg/.jpeg for JPEG")
    p.add_argument("--backend", default="auto", choices=["auto", "cpu", "compiled", "torch", "gsplat"])
    p.add_argument("--long-side", type=_positive_int, default=None, help="resize so the longer side has this many pixels")
    p.set_defaults(func=_cmd_render, outputs={"output": "image"})

    p = verbs.add_parser(
        "import",
        help="import an Inria 3DGS output, a COLMAP or nerfstudio dataset, or a 3DGS file (.ply, .compressed.ply, "
        ".splat, .spz) as a scene directory",
    )
    p.add_argument("src", help="a folder, or a single 3DGS file (then the scene has no cameras)")
    p.add_argument("dst")
    p.add_argument("--copy-images", action="store_true", help="copy images instead of symlinking them")
    p.set_defaults(func=_cmd_import, outputs={"dst": "folder"})

    p = verbs.add_parser("colmap", help="recover the poses of a scene without poses (structure from motion)")
    p.add_argument("scene", help="scene directory with images/, or a folder of photos")
    p.add_argument("-o", "--output", required=True, help="output scene directory (must not exist)")
    p.add_argument(
        "--matcher",
        default="auto",
        choices=["auto", "exhaustive", "sequential"],
        help="auto: exhaustive up to 60 images, else sequential in name order",
    )
    p.add_argument(
        "--camera-model",
        default="SIMPLE_PINHOLE",
        choices=["SIMPLE_PINHOLE", "SIMPLE_RADIAL", "OPENCV"],
        help="one camera shared by all images: SIMPLE_PINHOLE for renders; SIMPLE_RADIAL or OPENCV for photos "
        "as shot (they are undistorted into the output)",
    )
    p.add_argument("--threads", type=int, default=1, help="COLMAP threads (1: repeatable)")
    p.set_defaults(func=_cmd_colmap, outputs={"output": "folder"})

    p = verbs.add_parser(
        "align-truth",
        help="evaluation: map capframe colmap's poses into a synthetic scene's ground-truth world and add its Gaussians",
    )
    p.add_argument("recovered", help="output directory of capframe colmap")
    p.add_argument("--truth", required=True, help="the synthetic scene the images came from")
    p.add_argument("-o", "--output", required=True, help="output scene directory (must not exist)")
    p.set_defaults(func=_cmd_align_truth, outputs={"output": "folder"})

    p = verbs.add_parser("gravity", help="estimate the world up of a scene from its cameras and straight edges")
    p.add_argument("scene", help="scene directory with training cameras")
    p.add_argument("-o", "--output", default=None, help="gravity file to write (default: SCENE/gravity.json)")
    p.add_argument("--no-lines", action="store_true", help="use the cameras only, not vanishing points of image lines")
    p.add_argument("--json", action="store_true", help="print the JSON written instead of a one-line summary")
    p.set_defaults(func=_cmd_gravity, outputs={"output": "file"})

    p = verbs.add_parser("synth", help="generate a synthetic 3DGS scene with ground truth")
    p.add_argument("out_dir")
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--objects", default=None, help='comma-separated catalog names, e.g. "teddy bear,armchair,ball"')
    p.add_argument("--preset", default="tabletop", choices=["tabletop", "room", "outdoor"])
    p.add_argument(
        "--capture", default=None, choices=["orbit", "forward", "walkthrough"], help="camera path (default: per preset)"
    )
    p.add_argument("--views", type=int, default=24)
    p.add_argument("--scale", type=float, default=1.0, help="multiply all lengths")
    p.add_argument("--tilt", type=float, default=0.0, help="rotate the world so that up is not an axis (degrees)")
    p.add_argument("--no-poses", action="store_true", help="write images only (the COLMAP stage must recover poses)")
    p.add_argument(
        "--no-images",
        action="store_true",
        help="skip the training images (cameras only; the embedded tier needs them only for COLMAP and gravity)",
    )
    p.add_argument("--resolution", default="320x240", help="training image size WxH")
    p.add_argument("--density", type=float, default=1.0, help="multiply the number of Gaussians")
    p.set_defaults(func=_cmd_synth, outputs={"out_dir": "folder"})

    p = verbs.add_parser("instructions", help="generate instructions with machine-checkable constraints for a synthetic scene")
    p.add_argument("scene")
    p.add_argument("-o", "--output", required=True, help="folder for instructions.tsv and constraints.json")
    p.add_argument("--count", type=int, default=3)
    p.add_argument("--seed", type=int, default=0)
    p.set_defaults(func=_cmd_instructions, outputs={"output": "into"})

    p = verbs.add_parser("check", help="check a result camera against a synthetic scene's ground truth")
    p.add_argument("scene")
    p.add_argument("result", help="result.json or camera.json with T_cw, K, width, height")
    p.add_argument("--constraints", required=True, help="constraints.json")
    p.add_argument("--id", default=None, help="instruction id (default: the result's instruction_id)")
    p.add_argument("--json", action="store_true")
    p.add_argument("-o", "--output", default=None, help="also write the report as JSON to this file")
    p.add_argument("--cache", default=None, help="folder caching the scene's occupancy (clearance verdict); default: none")
    p.set_defaults(func=_cmd_check, outputs={"output": "file"})

    p = verbs.add_parser("oracle", help="oracle pseudo labels and a seeded initial view from a synthetic scene's ground truth")
    p.add_argument("scene")
    p.add_argument("--constraints", required=True, help="constraints.json")
    p.add_argument("--id", required=True, help="instruction id")
    p.add_argument("-o", "--output", required=True, help="folder for labels.json and init.json")
    p.set_defaults(func=_cmd_oracle, outputs={"output": "into"})

    p = verbs.add_parser("aggregate", help="tables from per-instruction check reports and results")
    p.add_argument("--method", required=True)
    p.add_argument("--checks", nargs="+", required=True)
    p.add_argument("--results", nargs="+", required=True)
    p.add_argument("-o", "--output", required=True, help="per-instruction CSV; summaries are written beside it")
    p.set_defaults(func=_cmd_aggregate, outputs={"output": "file"})

    p = verbs.add_parser("refine", help="optimise a camera pose from pseudo labels")
    p.add_argument("scene", help="scene directory")
    p.add_argument("--labels", required=True, help="pseudo labels (labels.json)")
    p.add_argument(
        "--init",
        required=True,
        help="initial camera: a camera.json, a training view name, or a retrieval.json (its views are tried in order)",
    )
    p.add_argument("--attempts", type=int, default=3, help="with a retrieval.json: retry from the next view while a clause fails")
    p.add_argument(
        "--candidates", type=int, default=1, help="with a retrieval.json: refine from this many views and rank the poses"
    )
    p.add_argument("-o", "--output", required=True, help="output folder (must not exist)")
    p.add_argument("--iterations", type=int, default=1500)
    p.add_argument("--long-side", type=_positive_int, default=160, help="optimisation resolution (long side, pixels)")
    p.add_argument("--weights", default=None, help="loss weights to override, e.g. inside=4,upright=1")
    _placement_options(p)
    p.add_argument(
        "--occupancy", default=None, help="the scene's occupancy.npz (capframe occupancy); default: built in the --cache folder"
    )
    p.add_argument("--cache", default=None, help="per-scene cache folder (default: ~/.cache/capframe/<scene>)")
    p.set_defaults(func=_cmd_refine, outputs={"output": "folder"})

    p = verbs.add_parser("occupancy", help="the free space of a scene (where a camera can be), once per scene")
    p.add_argument("scene", help="scene directory with scene.ply")
    p.add_argument("-o", "--output", required=True, help="occupancy.npz to write")
    p.add_argument("--gravity", default=None, help="gravity.json when scene.json has no up (default: SCENE/gravity.json)")
    p.set_defaults(func=_cmd_occupancy, outputs={"output": "file"})

    p = verbs.add_parser("warm-server", help="workflow: serve capframe commands from one process that imported the library once")
    p.add_argument("socket", help="Unix socket to listen on; commands find it in $CAPFRAME_WARM_SOCKET")
    p.add_argument("--parent", type=int, default=None, help="stop when this process is gone (default: the parent)")
    p.set_defaults(func=_cmd_warm_server)

    p = verbs.add_parser("views", help="label renders of the training views, measured once per scene (retrieval cache)")
    p.add_argument("scene", help="scene directory with cameras and a semantic sidecar")
    p.add_argument("-o", "--output", required=True, help="label_views.npz to write")
    p.add_argument("--long-side", type=_positive_int, default=160, help="measurement resolution (long side, pixels)")
    p.set_defaults(func=_cmd_views, outputs={"output": "file"})

    p = verbs.add_parser("compare", help="one table of several methods' summaries")
    p.add_argument("tables", nargs="+", help="per-instruction CSVs written by capframe aggregate")
    p.add_argument("-o", "--output", required=True, help="summary CSV; .md is written beside it")
    p.set_defaults(func=_cmd_compare, outputs={"output": "file"})

    p = verbs.add_parser("groups", help="success per method and dataset group (Retrieve against Refine and the rest)")
    p.add_argument("tables", nargs="+", help="per-instruction CSVs written by capframe aggregate, rows in this order")
    p.add_argument("--group", nargs="+", required=True, metavar="SCENE=GROUP", help="every scene's dataset group")
    p.add_argument("--metrics", nargs="*", default=[], help="capframe metrics CSVs: adds the mean SigLIP 2 and CLIP scores")
    p.add_argument("-o", "--output", required=True, help="CSV; .md is written beside it")
    p.set_defaults(func=_cmd_groups, outputs={"output": "file"})

    p = verbs.add_parser("metrics", help="CLIP and SigLIP 2 scores of every method's final frame against its instruction")
    _add_frames_of_scene(p)
    p.add_argument("--models", required=True, help="models config with metrics-clip and/or metrics-siglip")
    p.add_argument("-o", "--output", required=True, help="CSV to write")
    p.set_defaults(func=_cmd_metrics, outputs={"output": "file"})

    p = verbs.add_parser("judge", help="MLLM judges: 1-5 alignment score of every method's frame and a blind best pick")
    _add_frames_of_scene(p)
    p.add_argument("--models", required=True, help="models config with judge and/or judge-2")
    p.add_argument("--cache", required=True, help="the scene's cache folder (the response cache is <cache>/mllm)")
    p.add_argument("--seed", type=int, default=0, help="seed of the order the pictures are shown in (with the instruction)")
    p.add_argument("-o", "--output", required=True, help="JSON record to write")
    p.set_defaults(func=_cmd_judge, outputs={"output": "file"})

    p = verbs.add_parser("quantitative", help="the paper's Table 1: methods by metrics, judges, user study, ground truth")
    p.add_argument("tables", nargs="+", help="per-instruction CSVs written by capframe aggregate, rows in this order")
    p.add_argument("--metrics", nargs="*", default=[], help="capframe metrics CSVs")
    p.add_argument("--judgements", nargs="*", default=[], help="capframe judge records")
    p.add_argument("--userstudy", default=None, help="userstudy.csv of capframe userstudy import")
    p.add_argument("-o", "--output", required=True, help="CSV; .md is written beside it")
    p.set_defaults(func=_cmd_quantitative, outputs={"output": "file"})

    p = verbs.add_parser("sensitivity", help="pose deviation and success change of method variants against the default method")
    p.add_argument("--reference", required=True, help="the default method's result folders, e.g. results/refine/capframe")
    p.add_argument(
        "--variant",
        nargs="+",
        required=True,
        metavar="NAME=DIR",
        help="variants' result folders, e.g. top3=results/refine/capframe-top3",
    )
    p.add_argument("--checks-root", default="results/check", help="check reports: CHECKS_ROOT/<method>/<scene>/<id>.json")
    p.add_argument("--scenes-root", default="results/scenes", help="scene directories (ground_truth.json scale)")
    p.add_argument("--metrics", nargs="*", default=[], help="capframe metrics CSVs: adds ΔCLIP and ΔSigLIP 2")
    p.add_argument("-o", "--output", required=True, help="CSV; .md is written beside it")
    p.set_defaults(func=_cmd_sensitivity, outputs={"output": "file"})

    p = verbs.add_parser("scene-table", help="per-scene table: views, Gaussians, COLMAP and gravity errors")
    p.add_argument("--scenes-root", default="results/scenes", help="scene directories (ground_truth.json)")
    p.add_argument("--colmap-root", default="results/colmap", help="COLMAP outputs: COLMAP_ROOT/<scene>/colmap.json")
    p.add_argument("--gravity-root", default="results/gravity", help="gravity files: GRAVITY_ROOT/<scene>.json")
    p.add_argument("-o", "--output", required=True, help="CSV; .md is written beside it")
    p.set_defaults(func=_cmd_scene_table, outputs={"output": "file"})

    p = verbs.add_parser("runtime", help="seconds per scene and stage, and per instruction and method, from benchmark TSVs")
    p.add_argument("--benchmarks", default="results/benchmarks", help="Snakemake benchmark: folder")
    p.add_argument(
        "--methods-table",
        default=None,
        help="capframe compare's CSV: adds the error-against-run-time points and plot (<stem>_pareto.csv, .png)",
    )
    p.add_argument(
        "--results-root",
        default=None,
        help="results folder: adds the MLLM counters per scene and stage (stage sidecars, result.json, judges; <stem>_mllm.csv)",
    )
    p.add_argument("-o", "--output", required=True, help="per-scene CSV; <stem>_methods.csv and .md are written beside it")
    p.set_defaults(func=_cmd_runtime, outputs={"output": "file"})

    p = _stage_verb(verbs, "parse", "parse an instruction against the scene's vocabulary", "parsed.json", _cmd_parse)
    p.add_argument("instruction")

    p = _stage_verb(
        verbs, "retrieve", "parse an instruction and rank the training views (Retrieve)", "retrieval.json", _cmd_retrieve
    )
    p.add_argument("instruction")
    p.add_argument("--topk", type=int, default=2)
    p.add_argument("--seed", type=int, default=0)

    p = _stage_verb(verbs, "coarse", "Retrieve, step 1: score every training view for an instruction", "coarse.json", _cmd_coarse)
    p.add_argument("instruction", nargs="?", default=None, help="the instruction (or --parsed)")
    p.add_argument("--parsed", default=None, help="parsed.json written by capframe parse")

    p = _stage_verb(verbs, "qe", "Retrieve, step 2: QE scoring of the views coarse kept", "retrieval.json", _cmd_qe)
    p.add_argument("--coarse", required=True, help="coarse.json written by capframe coarse")
    p.add_argument("--topk", type=int, default=2)
    p.add_argument("--seed", type=int, default=0)

    for verb, help_text, output, func in (
        ("segment", "Translate, step 1: the subjects' 2D masks in the retrieved views", "masks.npz", _cmd_segment),
        ("associate", "Translate, step 2: each subject's Gaussians", "subjects.json", _cmd_associate),
        ("orient", "Translate, step 3: the front of each asymmetric subject with a view cue", "fronts.json", _cmd_orient),
    ):
        p = _stage_verb(verbs, verb, help_text, output, func)
        p.add_argument("--retrieval", required=True, help="retrieval.json written by capframe qe or capframe retrieve")
        if verb in ("associate", "orient"):
            p.add_argument(
                "--masks",
                default=None,
                help="masks.npz of capframe segment (default: segment here when the "
                f"{'associator' if verb == 'associate' else 'orientation estimator'} reads masks)",
            )

    p = _stage_verb(verbs, "translate", "pseudo labels from a retrieval.json (Translate)", "labels.json", _cmd_translate)
    p.add_argument("--retrieval", required=True, help="retrieval.json written by capframe retrieve")
    p.add_argument("--drop", default=None, choices=["layout", "orientation"], help="ablation: leave these pseudo labels out")
    p.add_argument("--box-noise", type=float, default=0.0, help="shift layout boxes by this frame fraction (sensitivity)")
    p.add_argument("--front-noise", type=float, default=0.0, help="turn subject fronts by this many degrees (sensitivity)")
    p.add_argument("--noise-seed", type=int, default=0)
    p.add_argument("--subjects", default=None, help="subjects.json of capframe associate (default: associate here)")
    p.add_argument("--fronts", default=None, help="fronts.json of capframe orient (default: orient here)")

    p = verbs.add_parser("retrieved-view", help="the retrieved view Refine starts from, written as a method's result")
    p.add_argument("scene", help="scene directory with training cameras and scene.ply")
    p.add_argument("--retrieval", required=True, help="retrieval.json written by capframe qe or capframe retrieve")
    p.add_argument("-o", "--output", required=True, help="result folder to write (result.json, camera.json, render.png)")
    p.set_defaults(func=_cmd_retrieved_view, outputs={"output": "folder"})

    p = verbs.add_parser("grid", help="side-by-side renders of one instruction with the checker's verdicts")
    p.add_argument("--text", required=True, help="the instruction")
    p.add_argument("--methods", nargs="+", required=True)
    p.add_argument("--results", nargs="+", required=True, help="result folders (with render.png), one per method")
    p.add_argument("--checks", nargs="+", required=True, help="check reports, one per method")
    p.add_argument("-o", "--output", required=True, help="PNG to write")
    p.set_defaults(func=_cmd_grid, outputs={"output": "png"})

    p = verbs.add_parser("ground", help="find the camera for an instruction: Retrieve, Translate, Refine")
    p.add_argument("scene", help="scene directory with training cameras (and a semantic sidecar for the oracle backends)")
    p.add_argument("instruction", help='e.g. "a close-up of the teddy bear on the right, seen from its left"')
    p.add_argument("-o", "--output", required=True, help="output folder (must not exist)")
    p.add_argument("--topk", type=int, default=2, help="retrieved views kept as initialisations")
    p.add_argument("--seed", type=int, default=0, help="picks the initial view among the top K")
    p.add_argument("--candidates", type=int, default=1, help="refine from this many retrieved views and rank the poses")
    p.add_argument(
        "--attempts", type=int, default=3, help="with one candidate: retry from the next retrieved view while a clause fails"
    )
    _perception_options(p)
    _placement_options(p)
    p.add_argument("--iterations", type=int, default=1500)
    p.add_argument("--long-side", type=_positive_int, default=160, help="optimisation resolution (long side, pixels)")
    p.add_argument("--json", action="store_true", help="print one JSON object (camera, timings, report) instead of progress")
    p.set_defaults(func=_cmd_ground, outputs={"output": "folder"})

    p = verbs.add_parser(
        "baseline", help="find the camera with a baseline pose search: IVS, SVS, SplaTraj-style or ChatCam-style"
    )
    p.add_argument(
        "method",
        help="ivs (interpolate between retrieved views), svs (sample a sphere around the subjects), "
        "splatraj (optimise mask centre, area and uprightness) or chatcam (optimise the --diff-scorer "
        "image-text score of the render from the best-scoring training view)",
    )
    p.add_argument("scene", help="scene directory with training cameras (and a semantic sidecar for the oracle backends)")
    p.add_argument("instruction", help='e.g. "a close-up of the teddy bear on the right, seen from its left"')
    p.add_argument("-o", "--output", required=True, help="output folder (must not exist)")
    _perception_options(p)
    p.add_argument("--seed", type=int, default=0, help="seed of the SVS samples")
    p.add_argument(
        "--iterations", dest="chatcam_iterations", type=_positive_int, default=None, help="chatcam: Adam steps (default Refine's)"
    )
    p.add_argument(
        "--long-side", dest="chatcam_long_side", type=_positive_int, default=None, help="chatcam: render size (default Refine's)"
    )
    p.add_argument("--json", action="store_true", help="print one JSON object (camera, score, timings) instead of progress")
    p.set_defaults(func=_cmd_baseline, outputs={"output": "folder"})

    p = verbs.add_parser("bench", help="print benchmark figures")
    p.add_argument(
        "what", choices=["render", "render-cuda", "refine", "ground", "segment", "models", "mllm", "startup", "colmap", "scale"]
    )
    p.add_argument(
        "--suite",
        default=None,
        help="refine/ground: a suite name in config/suites (captured, default, full, heldout, heldout2 ... heldout21, the "
        "parse-only corpora phrasing1 ... phrasing11) or a suite file; a suite with hand-written specs (the heldout sets) "
        "prints full success and failures per kind",
    )
    p.add_argument("--json", action="store_true", help="print one JSON object instead of a table")
    p.add_argument(
        "--parse-only",
        action="store_true",
        help="ground: parse every instruction of the suite and print where the parse differs from its meaning "
        "(no scene generation for committed instructions; seconds)",
    )
    p.add_argument(
        "--blind",
        action="store_true",
        help="ground on a held-out suite: progress lines carry ids, verdicts and failure kinds, no instruction words "
        "(to measure a blind set without reading it; heldout.csv still holds the texts)",
    )
    p.add_argument("--segmenter", default="detector", help="segment: the model segmenter (knn associator, other roles oracle)")
    p.add_argument(
        "--models", default=None, help="segment: the models config of the segmenter's weights; models: also time its encoders"
    )
    p.add_argument(
        "--benchmarks",
        default=None,
        help="startup: a workflow run's benchmark folder (run without the warm server), for the per-instruction overhead",
    )
    p.add_argument("--photos", default=None, help="colmap: folder of photos (default: the real capture in ../shared/data/real)")
    p.add_argument("--reference", default=None, help="colmap: the photos' published Inria cameras.json")
    p.add_argument("--points", default=None, help="colmap: the published COLMAP points3D.bin (plane up; optional)")
    p.add_argument("--sizes", default=None, help="scale: counts of Gaussians, comma-separated (default 0.3M,1M,3M)")
    p.set_defaults(func=_cmd_bench)

    p = verbs.add_parser("userstudy", help="the user study: a static questionnaire of a run's renders, and its answers' table")
    actions = p.add_subparsers(dest="action", required=True)
    p = actions.add_parser(
        "make", help="a questionnaire (OUT/site/, no method names) of drawn instructions and its key (OUT/key.json)"
    )
    p.add_argument("--results", default="results", help="the results folder of a finished run")
    p.add_argument("--methods", required=True, help="comma-separated methods, e.g. capframe,oracle,svs")
    p.add_argument("-o", "--output", required=True, help="folder to write (must not exist or be empty)")
    p.add_argument("--groups", type=_positive_int, default=12, help="instructions asked")
    p.add_argument("--per-group", type=_positive_int, default=3, help="methods shown per instruction")
    p.add_argument("--seed", type=int, default=0, help="draws the instructions, the methods shown and their order")
    p.set_defaults(func=_cmd_userstudy_make, outputs={"output": "folder"})
    p = actions.add_parser("import", help="the participants' answer CSVs -> method, rating_mean, rating_n, preference_share")
    p.add_argument("answers", nargs="+", help="answer CSVs saved by the questionnaire's page")
    p.add_argument("--key", required=True, help="key.json written by capframe userstudy make")
    p.add_argument("-o", "--output", required=True, help="CSV to write, e.g. results/tables/userstudy.csv")
    p.set_defaults(func=_cmd_userstudy_import, outputs={"output": "file"})

    p = verbs.add_parser("models", help="model backends' files")
    actions = p.add_subparsers(dest="action", required=True)
    p = actions.add_parser("export", help="write a backend's image encoder as ONNX (for onnxruntime on the CPU)")
    p.add_argument("backend", help="clip, siglip, fg-clip, fg-clip2 or orient-anything")
    p.add_argument("--models", required=True, help="models config with the backend's weights")
    p.add_argument("-o", "--output", required=True, help="ONNX file to write; name it as the entry's onnx field")
    p.set_defaults(func=_cmd_models_export, outputs={"output": "file"})
    p = actions.add_parser(
        "check", help="try every entry of a models config: files exist, endpoints answer, MLLMs answer a tiny schema"
    )
    p.add_argument("--models", required=True, help="the models config to check, e.g. config/models.yaml")
    p.set_defaults(func=_cmd_models_check)
    return parser


def _check_outputs(args: argparse.Namespace) -> None:
    """Every output path the verb declared (``outputs``: argument -> a kind of
    :data:`capframe.scene._io.OUTPUTS`), checked before the verb does any work, so a search never
    ends in an unwritable path."""
    from .scene._io import OUTPUTS

    for dest, kind in getattr(args, "outputs", {}).items():
        if getattr(args, dest) is not None:
            OUTPUTS[kind].check(getattr(args, dest))


def passive_openmp() -> bool:
    """Let OpenMP worker threads sleep between parallel regions (``OMP_WAIT_POLICY=PASSIVE``)
    unless the environment says otherwise; returns False when too late (torch already imported:
    the OpenMP runtime reads the variable when it loads).

    By default torch's OpenMP threads spin for a while after each parallel region. On two cores
    that spinning takes the second core from the compiled renderer's kernel threads, which run
    between torch's operations (2 threads gained little over 1), and on a loaded machine it burns
    the CPU that other jobs need: 50k Gaussians at 160x120, 2 threads, under a load of ~12, took
    1.47 s per torch render and backward spinning, 0.094 s passive (compiled: CPU 58 -> 37 ms)."""
    if "torch" in sys.modules:
        return False
    os.environ.setdefault("OMP_WAIT_POLICY", "PASSIVE")
    return True


def main(argv: list[str] | None = None) -> int:
    passive_openmp()
    if argv is None:
        from .warm import run_warm

        # The workflow's warm server runs the command when there is one (capframe.warm).
        status = run_warm(sys.argv[1:])
        if status is not None:
            return status
    args = build_parser().parse_args(argv)
    keep_freed_memory()
    try:
        _check_outputs(args)
        args.func(args)
    except InputError as err:
        print(f"capframe: error: {err}", file=sys.stderr)
        return 2
    except ModelError as err:
        print(f"capframe: model error: {err}", file=sys.stderr)
        return 3
    except Exception as err:
        if not _interrupted(err):
            raise
        return _report_interrupt()
    except KeyboardInterrupt:
        return _report_interrupt()
    return 0


def _interrupted(err: BaseException | None) -> bool:
    """Whether ``err`` comes from a Ctrl-C: compiled code turns a KeyboardInterrupt raised inside
    it (numba's dispatcher while it compiles or loads a kernel) into a SystemError caused by it."""
    seen = set()
    while err is not None and id(err) not in seen:
        if isinstance(err, KeyboardInterrupt):
            return True
        seen.add(id(err))
        err = err.__cause__ or err.__context__
    return False


def _report_interrupt() -> int:
    # Every output is written atomically, so nothing partial is left to mention; the shell's
    # convention for a SIGINT exit is 128 + 2.
    print("capframe: interrupted; nothing was written for this command", file=sys.stderr)
    return 130


if __name__ == "__main__":
    sys.exit(main())
