"""Shared helpers: the suite's scenes and the instruction ids behind the instructions checkpoint."""

import json
import os
import re
import shutil
import subprocess
import tempfile

from snakemake.utils import validate

from capframe.backends.registry import MASK_ASSOCIATORS, ROLES, resolve_choices
from capframe.backends.registry import MASK_ORIENTERS
from capframe.backends.models import read_models_config
from capframe.evaluate.judging import JUDGE_HINT, configured_judges
from capframe.evaluate.metrics import METRIC_HINT, METRIC_NAMES, configured_metrics
from capframe.synth.suite import SAFE_NAME, is_safe_name, load_suite
from capframe.warm import SOCKET_ENV, server_environment

validate(config, "../schemas/config.schema.yaml")

SUITE_NAME, SUITE_SCENES = load_suite(config["suite"])
SCENES = {scene.id: scene for scene in SUITE_SCENES}


def synth_args(wildcards):
    scene = wildcards.scene
    return SCENES[scene].synth_args() + ([] if needs_images(scene) else ["--no-images"])


def needs_images(scene):
    """Only COLMAP (no poses) and gravity (not aligned) read the training images in the embedded
    tier; the other stages render label maps. Other scenes are generated without photos."""
    return not aligned(scene)


def checkpoint_output(deciding, path, **wildcards):
    """``path``, the output of the checkpoint ``deciding`` for ``wildcards``, for an input
    function to read.

    A file that exists is read directly; only a missing one defers the decision to the
    checkpoint. Snakemake 9 leaves every checkpoint undecided in the first DAG it builds
    (Checkpoint.get() raises until a checkpoint job is registered, even with its output
    complete), so the jobs reached through one join the DAG only afterwards, while incomplete
    markers are looked up in that first DAG only: jobs interrupted by SIGINT after a checkpoint
    kept their markers and were never rerun, even with --rerun-incomplete. Read directly, they
    are in the first DAG. A checkpoint job that reruns still updates the jobs that list its
    output as an input, so the rules whose inputs are expanded over its file list it.
    """
    if not os.path.exists(path):
        deciding.get(**wildcards)
    return path


def constraints_file(scene):
    """The instructions checkpoint's file of ``scene`` (:func:`checkpoint_output`)."""
    return checkpoint_output(checkpoints.instructions, f"results/instructions/{scene}/constraints.json", scene=scene)


def instruction_ids(scene):
    """Ids in the scene's constraints.json (known once the instructions checkpoint has run); each
    becomes a wildcard and a path, so it must be a safe name (SAFE_NAME)."""
    path = constraints_file(scene)
    with open(path) as f:
        ids = sorted(json.load(f))
    unsafe = [i for i in ids if not is_safe_name(i)]
    if unsafe:
        raise ValueError(f"{path}: instruction ids {unsafe} are not safe names ({SAFE_NAME}, no '..')")
    return ids


# Inputs of the rules that expand patterns over instruction ids (per_instruction): so that a rerun
# of the instructions checkpoint updates their jobs (checkpoint_output).
CONSTRAINTS = [f"results/instructions/{scene}/constraints.json" for scene in SCENES]


def per_instruction(pattern):
    """Input function: ``pattern`` expanded over every scene and its instruction ids."""

    def expand_all(wildcards):
        return [pattern.format(scene=s, instruction=i) for s in SCENES for i in instruction_ids(s)]

    return expand_all


def aligned(scene):
    """Whether the scene's world is gravity-aligned (scene.json carries an up): generated with
    poses and without tilt."""
    return SCENES[scene].poses and SCENES[scene].tilt == 0


def posed_scene(wildcards):
    """The scene directory with training cameras: COLMAP's output for a scene without poses."""
    return f"results/scenes/{wildcards.scene}" if SCENES[wildcards.scene].poses else f"results/colmap/{wildcards.scene}"


def gravity_input(wildcards):
    """The gravity file, for a scene that is not aligned only."""
    return [] if aligned(wildcards.scene) else f"results/gravity/{wildcards.scene}.json"


def gravity_option(wildcards, input):
    """The ``--gravity`` option of a rule with a ``gravity`` input (none when the scene is aligned),
    as arguments for ``{params.gravity:q}``."""
    return ["--gravity", input.gravity] if input.gravity else []


def instruction_text(wildcards):
    """The instruction's text, or its first paraphrase for a variant that asks for it (a param,
    so editing one text reruns only that instruction)."""
    with open(constraints_file(wildcards.scene)) as f:
        entry = json.load(f)[wildcards.instruction]
    variant = wildcards.get("variant", "capframe")
    if VARIANTS[variant].get("retrieve", {}).get("paraphrase") and entry.get("paraphrases"):
        return entry["paraphrases"][0]
    return entry["text"]


# The method and its variants (ablations, sensitivity): name -> per-stage overrides.
VARIANTS = {"capframe": {}} | {f"capframe-{name}": v for name, v in config.get("variants", {}).items()}
# The method's per-instruction stages in pipeline order, each with the variant settings
# (config section, key) it reads; a backend choice is ("backends", role).
METHOD_STAGES = {
    "parse": [("retrieve", "paraphrase"), ("backends", "parser")],
    "coarse": [("backends", "coarse")],
    "qe": [("retrieve", "topk"), ("backends", "qe")],
    "segment": [("backends", "segmenter")],
    "associate": [("backends", "associator")],
    "orient": [("backends", "orient")],
    "translate": [("translate", key) for key in ("drop", "box_noise", "front_noise", "noise_seed")],
    "refine": [("refine", key) for key in ("weights", "iterations", "long_side")],
}
# The roles whose backend each stage runs (their options are passed to its verb).
STAGE_ROLES = {"parse": ["parser"], "coarse": ["coarse"], "qe": ["qe"], "segment": ["segmenter"], "associate": ["associator"]}
# An orientation estimator that reads masks gets them from the segment stage (masks_input).
STAGE_ROLES["orient"] = ["orient"]
# The baselines run the shared stages and score candidates in one job.
BASELINE_ROLES = [*ROLES]


def stage_key(variant, stage):
    """Whose outputs ``variant`` uses for ``stage``: its own when it overrides a setting of this
    stage or of an earlier one, else the default method's. A variant of the refine weights thus
    reuses retrieval and translation, one of top-K reuses the coarse scores."""
    overridden = VARIANTS[variant]
    upto = list(METHOD_STAGES)[: list(METHOD_STAGES).index(stage) + 1]
    reads = {setting for s in upto for setting in METHOD_STAGES[s]}
    return variant if any((section, key) in reads for section, keys in overridden.items() for key in keys) else "capframe"


def stage_setting(variant, stage, key, default):
    return VARIANTS[variant].get(stage, {}).get(key, default)


def stage_file(stage, pattern):
    """Input function: ``pattern`` (with {key}, {scene}, {instruction}) for the stage's key."""
    return lambda wc: pattern.format(key=stage_key(wc.variant, stage), scene=wc.scene, instruction=wc.instruction)


def backends(variant):
    """Role -> backend name of ``variant``: the registry's defaults, the config's ``backends`` and
    the variant's own ``backends``, each checked against the registry."""
    return resolve_choices(config.get("backends", {}) | VARIANTS[variant].get("backends", {}))


def backend_options(variant, roles):
    """The ``--<role> <backend>`` options of ``roles`` for ``variant`` (and ``--models`` when a
    models config is set), as arguments for ``{params.backends:q}``."""
    chosen = backends(variant)
    options = [arg for role in roles if role in chosen for arg in (ROLES[role].option, chosen[role])]
    if config.get("models"):
        options += ["--models", config["models"]]
    return options


def masks_input(role="associator"):
    """Input function: the segmentation stage's masks, for an associator or an orientation
    estimator that reads masks (the oracles read labels and annotated fronts)."""
    readers = {"associator": MASK_ASSOCIATORS, "orient": MASK_ORIENTERS}[role]

    def masks(wildcards):
        if backends(wildcards.variant)[role] not in readers:
            return []
        return stage_file("segment", "results/segment/{key}/{scene}/{instruction}.npz")(wildcards)

    return masks


def parse_output(wildcards):
    """The parse checkpoint's file for this instruction and variant (it decides which of the later
    stages run; :func:`checkpoint_output`)."""
    key = stage_key(wildcards.variant, "parse")
    path = f"results/parse/{key}/{wildcards.scene}/{wildcards.instruction}.json"
    return checkpoint_output(checkpoints.parse, path, variant=key, scene=wildcards.scene, instruction=wildcards.instruction)


def parse_outputs(method):
    """Input function: the parse checkpoint's file of every instruction that ``method`` parses
    (none for a baseline or the oracle). Listed as inputs of the method's table so the checkpoints
    are in the DAG before fronts_input() asks them: a checkpoint reached only through an input
    function stays undecided in a dry run."""
    if method not in VARIANTS:
        return lambda wildcards: []
    return per_instruction(f"results/parse/{stage_key(method, 'parse')}/{{scene}}/{{instruction}}.json")


def fronts_input(wildcards):
    """The orientation stage's fronts, only for an instruction whose parse needs one (an
    asymmetric subject with a view cue) and a variant that keeps orientation."""
    if stage_setting(wildcards.variant, "translate", "drop", None) == "orientation":
        return []
    with open(parse_output(wildcards)) as f:
        if not json.load(f)["needs"]["orientation"]:
            return []
    return stage_file("orient", "results/orient/{key}/{scene}/{instruction}.json")(wildcards)


# The method's chain of per-instruction jobs is scheduled before the baselines' single long jobs,
# so its longest refinements start early instead of finishing last on one core.
METHOD_PRIORITY = 10
# Checks and image grids run as soon as their inputs exist: they are cheap, an interrupted run
# keeps every finished result checked, and each job selection (which stats the inputs of every
# ready job) has fewer jobs to look at.
EVALUATE_PRIORITY = 20

# Where each method's per-instruction result folder lives.
METHOD_RESULTS = {v: f"results/refine/{v}/{{scene}}/{{instruction}}" for v in VARIANTS}
METHOD_RESULTS["oracle"] = "results/refine/oracle/{scene}/{instruction}"
# The retrieved view Refine starts from, unrefined: the "Retrieve" row against CapFrame's "Refine".
METHOD_RESULTS["retrieve"] = "results/retrieved/{scene}/{instruction}"
# The paper's baselines (IVS, SVS, a SplaTraj-style optimiser), scored with the embedded tier,
# and the ChatCam-style optimiser only when a differentiable image-text model is configured
# (`backends: {diff-scorer: ...}` and `models`): the embedded tier has none.
BASELINES = ("ivs", "svs", "splatraj")
if config.get("backends", {}).get("diff-scorer") and config.get("models"):
    BASELINES += ("chatcam",)
METHOD_RESULTS |= {b: f"results/baselines/{b}/{{scene}}/{{instruction}}" for b in BASELINES}

# The paper's learned-model evaluation (workflow/rules/paper.smk): image-text metrics and MLLM
# judges, each only when its models-config entries exist.
MODELS = read_models_config(config.get("models"))
METRIC_COLUMNS = configured_metrics(MODELS)
JUDGES = configured_judges(MODELS)
# Metrics score every method and variant (Table 2 compares Retrieve with Refine, Table 3 the
# variants); the judges compare the methods a user can run (the paper's Table 1 rows).
METRIC_METHODS = list(METHOD_RESULTS)
JUDGED_METHODS = ["capframe", *BASELINES]
# Table 1's rows: the methods, then Retrieve alone and Refine from oracle labels for reference.
TABLE1_METHODS = [*JUDGED_METHODS, "retrieve", "oracle"]
METRIC_FILES = [f"results/metrics/{scene}.csv" for scene in SCENES] if METRIC_COLUMNS else []
JUDGE_FILES = [f"results/judges/{scene}.json" for scene in SCENES] if JUDGES else []
# What each absent column needs (the tables' captions).
MISSING_COLUMNS = [f"{METRIC_NAMES[c]}: {METRIC_HINT[c]}" for c in METRIC_HINT if c not in METRIC_COLUMNS]
MISSING_COLUMNS += [] if JUDGES else [f"judge AS and WR: {JUDGE_HINT}"]
# The user study's table, written by `capframe userstudy import` (another tool; optional input).
USERSTUDY = "results/tables/userstudy.csv"
USERSTUDY_NOTE = "user-study rating and preference: run `capframe userstudy import` to add them"


def scene_results(methods):
    """Input function: the result folder of each of ``methods`` for every instruction of the scene."""

    def folders(wildcards):
        ids = instruction_ids(wildcards.scene)
        return [METHOD_RESULTS[m].format(scene=wildcards.scene, instruction=i) for m in methods for i in ids]

    return folders


def method_specs(methods):
    """Params function: ``NAME=DIR`` per method, DIR holding the scene's ``<id>/render.png`` folders."""
    return lambda wc: [f"{m}={os.path.dirname(METHOD_RESULTS[m].format(scene=wc.scene, instruction='x'))}" for m in methods]


def userstudy_input(wildcards):
    """The user study's table when `capframe userstudy import` has written it: optional, so the
    workflow never asks for it (and reruns Table 1 once it appears)."""
    return [USERSTUDY] if os.path.exists(USERSTUDY) else []


# Methods shown side by side in the report's image grid.
REPORT_METHODS = ["retrieve", "capframe", *BASELINES, "oracle"]
# Methods of the per-group table, Retrieve and Refine (CapFrame) first.
GROUP_METHODS = ["retrieve", "capframe", "oracle", *BASELINES]


# The warm server of this run (capframe.warm): started by onstart, stopped by onsuccess/onerror,
# and gone on its own within a second when Snakemake exits any other way.
WARM_SERVER = {}


def start_warm_server():
    """Start `capframe warm-server` for this run and point the jobs at it (capframe.warm.SOCKET_ENV).
    A job that finds no server yet (it imports for a few seconds) runs its command itself."""
    executable = shutil.which("capframe")
    if not config.get("warm_start", False) or executable is None:
        return
    path = os.path.join(tempfile.gettempdir(), f"capframe-warm-{os.getpid()}.sock")
    os.makedirs("results/logs", exist_ok=True)
    with open("results/logs/warm-server.log", "w") as log:
        WARM_SERVER["process"] = subprocess.Popen(
            [executable, "warm-server", path, "--parent", str(os.getpid())],
            env=server_environment(os.environ),
            stdin=subprocess.DEVNULL,
            stdout=log,
            stderr=subprocess.STDOUT,
            start_new_session=True,
        )
    os.environ[SOCKET_ENV] = path


def stop_warm_server():
    process = WARM_SERVER.pop("process", None)
    if process is not None:
        process.terminate()
        process.wait()
    os.environ.pop(SOCKET_ENV, None)
