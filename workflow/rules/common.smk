"""Shared helpers: the suite's scenes and the instruction ids behind the instructions checkpoint."""

import json
import shlex

from snakemake.utils import validate

from capframe.synth.suite import load_suite

validate(config, "../schemas/config.schema.yaml")

SUITE_NAME, SUITE_SCENES = load_suite(config["suite"])
SCENES = {scene.id: scene for scene in SUITE_SCENES}


def synth_args(wildcards):
    return " ".join(shlex.quote(arg) for arg in SCENES[wildcards.scene].synth_args())


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
METHOD_STAGES = ("retrieve", "translate", "refine")


def stage_key(variant, stage):
    """Whose outputs ``variant`` uses for ``stage``: its own when it overrides this stage or an
    earlier one, else the default method's. Output paths carry only what changes them, so a
    variant of the refine weights reuses retrieval and translation."""
    overridden = VARIANTS[variant]
    upto = METHOD_STAGES[: METHOD_STAGES.index(stage) + 1]
    return variant if any(s in overridden for s in upto) else "capframe"


def stage_setting(variant, stage, key, default):
    return VARIANTS[variant].get(stage, {}).get(key, default)


def stage_file(stage, pattern):
    """Input function: ``pattern`` (with {key}, {scene}, {instruction}) for the stage's key."""
    return lambda wc: pattern.format(key=stage_key(wc.variant, stage), scene=wc.scene, instruction=wc.instruction)


# Where each method's per-instruction result folder lives.
METHOD_RESULTS = {v: f"results/refine/{v}/{{scene}}/{{instruction}}" for v in VARIANTS}
METHOD_RESULTS["oracle"] = "results/refine/oracle/{scene}/{instruction}"
# The paper's baselines (IVS, SVS, a SplaTraj-style optimiser), scored with the embedded tier.
BASELINES = ("ivs", "svs", "splatraj")
METHOD_RESULTS |= {b: f"results/baselines/{b}/{{scene}}/{{instruction}}" for b in BASELINES}

# Methods shown side by side in the report's image grid.
REPORT_METHODS = ["capframe", *BASELINES, "oracle"]
