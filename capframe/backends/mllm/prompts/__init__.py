"""The MLLM roles' prompts: one versioned YAML file per prompt, holding the system text, the user
turn's template and the JSON schema of the answer.

A prompt's :attr:`Prompt.version` (``"<name>-v<version>"``) goes into every request
(:attr:`ChatRequest.prompt_version`, part of the response cache's key) and every output the role
writes: editing a prompt's text or schema means raising its ``version``, so no cached answer
to the old wording is reused. The templates use ``$field`` placeholders (:class:`string.Template`),
so JSON braces in a prompt need no escaping.
"""

from __future__ import annotations

import copy
import functools
from dataclasses import dataclass
from importlib import resources
from string import Template

import numpy as np

from ..chat import ChatRequest

NAMES = ("subjects", "layout", "orientation", "qe-questions", "qe-answers", "judge-rate", "judge-pick", "paraphrase")


@dataclass(frozen=True)
class Prompt:
    """One prompt file.

    Attributes:
        name: the prompt's name (its file is ``<name>.yaml`` with ``_`` for ``-``).
        version: ``"<name>-v<n>"``.
        system: the system text template.
        user: the user turn's template.
        schema: the answer's JSON schema (a role may narrow it per request, e.g. to the scene's names).
        max_tokens: the longest answer the role asks for.
    """

    name: str
    version: str
    system: str
    user: str
    schema: dict
    max_tokens: int

    def request(self, fields: dict, images: tuple[np.ndarray, ...] = (), schema: dict | None = None) -> ChatRequest:
        """The request with ``fields`` filled into both templates; ``schema`` replaces the
        file's (a narrowed copy of :attr:`schema`)."""
        return ChatRequest(
            system=Template(self.system).substitute(fields).strip(),
            user=Template(self.user).substitute(fields).strip(),
            schema=self.schema if schema is None else schema,
            schema_name=self.name.replace("-", "_"),
            prompt_version=self.version,
            images=tuple(images),
            max_tokens=self.max_tokens,
        )

    def keyed(self, path: tuple[str, ...], keys: list[str], entry: str, value: dict | None = None) -> dict:
        """A copy of :attr:`schema` whose sub-schema at ``path`` becomes an object with exactly
        the properties ``keys``, each a copy of ``$defs[entry]`` (or of ``value``, a role's
        rewrite of it): one answer per subject or per question by construction, which
        constrained decoding then guarantees."""
        value = self.schema["$defs"][entry] if value is None else value
        return self.narrowed(
            path,
            type="object",
            properties={k: copy.deepcopy(value) for k in keys},
            required=list(keys),
            additionalProperties=False,
        )

    def narrowed(self, path: tuple[str, ...], **updates) -> dict:
        """A copy of :attr:`schema` with ``updates`` set on the sub-schema at ``path`` (a key path
        through ``properties`` / ``items``), e.g. an ``enum`` of the scene's names."""
        schema = copy.deepcopy(self.schema)
        node = schema
        for key in path:
            node = node[key]
        node.update(updates)
        return schema


@functools.cache
def load(name: str) -> Prompt:
    """The prompt called ``name`` (one of :data:`NAMES`)."""
    import yaml

    if name not in NAMES:
        raise KeyError(f"no prompt {name!r}; prompts: {NAMES}")
    data = yaml.safe_load(resources.files(__package__).joinpath(name.replace("-", "_") + ".yaml").read_text())
    assert data["name"] == name, f"{name}.yaml names itself {data['name']!r}"
    return Prompt(name, f"{name}-v{data['version']}", data["system"], data["user"], data["schema"], int(data["max_tokens"]))
