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
    """The instruction's text (a param, so editing one text reruns only that instruction)."""
    path = checkpoints.instructions.get(scene=wildcards.scene).output.constraints
    with open(path) as f:
        return json.load(f)[wildcards.instruction]["text"]


# Where each method's per-instruction result folder lives.
METHOD_RESULTS = {
    "capframe": "results/ground/{scene}/{instruction}",
    "oracle": "results/refine/oracle/{scene}/{instruction}",
}
