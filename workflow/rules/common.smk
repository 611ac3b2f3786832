"""Shared helpers: the suite's scenes and the instruction ids behind the instructions checkpoint."""

import json
import shlex

from snakemake.utils import validate

from capframe.synth.suite import load_suite

validate(config, "../schemas/config.schema.yaml")

SUITE_NAME, SUITE_SCENES = load_suite(config["suite"])
SCENES = {scene.id: scene for scene in SUITE_SCENES}


def synth_args(wildcards):
    scene = wildcards.scene
    images = [] if needs_images(scene) else ["--no-images"]
    return " ".join(shlex.quote(arg) for arg in SCENES[scene].synth_args() + images)


def needs_images(scene):
    """Only COLMAP (no poses) and gravity (not aligned) read the training images in the embedded
    tier; the other stages render label maps. Other scenes are generated without photos."""
    return not aligned(scene)


def instruction_ids(scene):
    """Ids in the scene's constraints.json (known once the instructions checkpoint has run)."""
    path = checkpoints.instructions.get(scene=scene).output.constraints
    with open(path) as f:
        return sorted(json.load(f))


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
    """The ``--gravity`` option of a rule with a ``gravity`` input (empty when the scene is aligned)."""
    return f"--gravity {input.gravity}" if input.gravity else ""


def instruction_text(wildcards):
    """The instruction's text, or its first paraphrase for a variant that asks for it (a param,
    so editing one text reruns only that instruction)."""
    path = checkpoints.instructions.get(scene=wildcards.scene).output.constraints
    with open(path) as f:
        entry = json.load(f)[wildcards.instruction]
    variant = wildcards.get("variant", "capframe")
    if VARIANTS[variant].get("retrieve", {}).get("paraphrase") and entry.get("paraphrases"):
        return entry["paraphrases"][0]
    return entry["text"]


# The method and its variants (ablations, sensitivity): name -> per-stage overrides.
VARIANTS = {"capframe": {}} | {f"capframe-{name}": v for name, v in config.get("variants", {}).items()}
# The method's per-instruction stages in pipeline order, each with the variant settings
# (config section, key) it reads.
METHOD_STAGES = {
    "coarse": [("retrieve", "paraphrase")],
    "qe": [("retrieve", "topk")],
    "segment": [("translate", "perception")],
    "associate": [("translate", "perception")],
    "orient": [],
    "translate": [("translate", key) for key in ("drop", "box_noise", "front_noise", "noise_seed")],
    "refine": [("refine", key) for key in ("weights", "iterations", "long_side")],
}


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


PERCEPTION_MASKS = ("label-masks",)  # perceptions that segment before associating


def perception(variant):
    return stage_setting(variant, "translate", "perception", "labels")


def masks_input(wildcards):
    """The segmentation stage's masks, for a perception that has one (labels associate by id)."""
    if perception(wildcards.variant) not in PERCEPTION_MASKS:
        return []
    return stage_file("segment", "results/segment/{key}/{scene}/{instruction}.npz")(wildcards)


def parsed_instruction(wildcards):
    """The instruction as the rule parser reads it (exactly what the coarse stage parses), or
    None when it does not parse: the coarse job then fails with the parser's message. Parsed here,
    at DAG time, to leave out the orientation stage; a checkpoint per instruction would have to
    be resolved inside the instructions checkpoint, which Snakemake does not do in one pass."""
    from types import SimpleNamespace

    from capframe.errors import InputError
    from capframe.translate.parse import RuleParser
    from capframe.translate.vocabulary import Vocabulary

    try:  # the sidecar's names read directly: capframe.scene's reader would import torch into every DAG build
        with open(f"results/scenes/{wildcards.scene}/semantics.json") as f:
            objects = [
                SimpleNamespace(name=o["name"], aliases=o.get("aliases", []), symmetric=o.get("symmetric", False))
                for o in json.load(f)["objects"]
            ]
        return RuleParser().parse(instruction_text(wildcards), Vocabulary.from_semantics(objects))
    except (OSError, KeyError, InputError):
        return None


def fronts_input(wildcards):
    """The orientation stage's fronts, only for an instruction with an asymmetric subject and a
    view cue and a variant that keeps orientation."""
    if stage_setting(wildcards.variant, "translate", "drop", None) == "orientation":
        return []
    parsed = parsed_instruction(wildcards)
    if parsed is None or not any(s.needs_front for s in parsed.subjects):
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
# The paper's baselines (IVS, SVS, a SplaTraj-style optimiser), scored with the embedded tier.
BASELINES = ("ivs", "svs", "splatraj")
METHOD_RESULTS |= {b: f"results/baselines/{b}/{{scene}}/{{instruction}}" for b in BASELINES}

# Methods shown side by side in the report's image grid.
REPORT_METHODS = ["retrieve", "capframe", *BASELINES, "oracle"]
# Methods of the per-group table, Retrieve and Refine (CapFrame) first.
GROUP_METHODS = ["retrieve", "capframe", "oracle", *BASELINES]
