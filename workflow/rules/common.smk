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
