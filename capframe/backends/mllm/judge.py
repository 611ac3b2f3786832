"""MLLM judges and paraphrases for the benchmark (the paper's Table 1 and sensitivity study).

A judge rates one picture against an instruction (1-5, the alignment score) and picks the best of
several pictures (the win rate). It is blind: the pictures are shown as "Image 1" to "Image N" in
an order drawn from a seed and the instruction, which is recorded; method names never reach the
model. Paraphrases of an instruction feed the sensitivity study's text variation.
"""

from __future__ import annotations

import random
from dataclasses import dataclass

import numpy as np

from ...errors import InputError, ModelError, clip
from .chat import ChatModel
from .prompts import load


@dataclass
class Rating:
    """A judge's alignment score of one picture.

    Attributes:
        score: 1 (very poor match) to 5 (excellent).
        reason: the judge's short reason.
        model: the judge's identity.
        prompt: the prompt version.
    """

    score: int
    reason: str
    model: str
    prompt: str


@dataclass
class Pick:
    """A judge's choice of the best picture among several.

    Attributes:
        best: the name (a method) of the picture chosen.
        order: the names in the order the pictures were shown (Image 1 first).
        seed: the seed the order was drawn with (together with the instruction).
        reason: the judge's short reason.
        model: the judge's identity.
        prompt: the prompt version.
    """

    best: str
    order: list[str]
    seed: int
    reason: str
    model: str
    prompt: str


def blind_order(names: list[str], text: str, seed: int) -> list[str]:
    """``names`` shuffled by a generator seeded with ``seed`` and the instruction ``text``: the
    order differs from instruction to instruction and is the same on every rerun."""
    order = sorted(names)
    random.Random(f"{seed}\n{text}").shuffle(order)
    return order


class MLLMJudge:
    """:class:`~capframe.backends.Judge` through a chat model.

    Args:
        chat: the judge's model.
    """

    def __init__(self, chat: ChatModel):
        self.chat = chat
        self.prompts = {name: load(name) for name in ("judge-rate", "judge-pick")}

    def rate(self, image: np.ndarray, text: str) -> float:
        """The 1-5 alignment score of ``image`` (H, W, 3) uint8 with ``text``."""
        return float(self.assess(image, text).score)

    def _fail(self, prompt: str, message: str) -> ModelError:
        return ModelError(f"{self.chat.identity}: the {prompt} answer ({self.prompts[prompt].version}) is invalid: {message}")

    def assess(self, image: np.ndarray, text: str) -> Rating:
        """:meth:`rate` with the reason, the model and the prompt version."""
        return self.assess_many([image], text)[0]

    def assess_many(self, images: list[np.ndarray], text: str) -> list[Rating]:
        """:meth:`assess` of each of ``images`` (one request per picture, as :meth:`assess` asks
        it), sent together: a local model batches them, an endpoint answers them concurrently."""
        prompt = self.prompts["judge-rate"]
        requests = [prompt.request({"instruction": text.strip()}, images=(image,)) for image in images]
        ratings = []
        for reply in self.chat.complete_many(requests):
            if not 1 <= reply.data["score"] <= 5:
                raise self._fail("judge-rate", f"score {reply.data['score']!r} is not 1 to 5")
            ratings.append(Rating(int(reply.data["score"]), reply.data["reason"], self.chat.identity, prompt.version))
        return ratings

    def pick(self, images: dict[str, np.ndarray], text: str, seed: int) -> Pick:
        """The best of ``images`` (name -> (H, W, 3) uint8) for ``text``, shown blind in
        :func:`blind_order`."""
        if len(images) < 2:
            raise InputError(f"a pick needs at least two pictures; got {sorted(images)}")
        prompt = self.prompts["judge-pick"]
        order = blind_order(list(images), text, seed)
        schema = prompt.narrowed(("properties", "best"), maximum=len(order))
        request = prompt.request(
            {"instruction": text.strip(), "count": len(order)}, images=tuple(images[n] for n in order), schema=schema
        )
        data = self.chat.complete(request).data
        if not 1 <= data["best"] <= len(order):
            raise self._fail("judge-pick", f"best {data['best']!r} is not 1 to {len(order)}")
        return Pick(order[data["best"] - 1], order, seed, data["reason"], self.chat.identity, prompt.version)


class MLLMParaphraser:
    """Paraphrases of an instruction through a chat model (the sensitivity study).

    Args:
        chat: the model.
    """

    def __init__(self, chat: ChatModel):
        self.chat = chat
        self.prompt = load("paraphrase")

    def paraphrase(self, text: str, n: int) -> list[str]:
        """``n`` distinct paraphrases of ``text``, none equal to it (case and spaces aside)."""
        if n < 1:
            raise InputError(f"paraphrases: n is {n}; expected at least 1")
        schema = self.prompt.narrowed(("properties", "paraphrases"), minItems=n, maxItems=n)
        data = self.chat.complete(self.prompt.request({"instruction": text.strip(), "count": n}, schema=schema)).data
        out = [p.strip() for p in data["paraphrases"]]
        norm = [" ".join(p.lower().split()) for p in out]
        if len(out) != n or len(set(norm)) != n or " ".join(text.lower().split()) in norm or not all(out):
            raise ModelError(
                f"{self.chat.identity}: the paraphrase answer ({self.prompt.version}) is invalid: "
                f"expected {n} distinct, non-empty paraphrases unlike the instruction, got {clip(repr(out))}"
            )
        return out
