"""Question-Evaluation by an MLLM (the paper's Retrieve, §4.1): the model writes the questions an
instruction decomposes into, then scores every kept training view on all of them at once (one
request per view, 0-100 per question with a short reason); the views are cut adaptively.

Questions come back in our :class:`~capframe.backends.Question` kinds, so the geometric scorers
(the baselines' candidate ranking) answer the same questions: a question keeps its kind when the
parsed instruction asks for that aspect of that subject (its target is then the parsed cue),
otherwise it becomes an ``overall`` question.

The adaptive cut (:func:`adaptive_cut`) follows the authors' code: of the views scoring above a
threshold, keep those before the largest drop in score, at most K, and only among the better half
by coarse score.
"""

from __future__ import annotations

import math

import numpy as np

from ...errors import ModelError, clip
from ...retrieve.views import VIEWS_LONG_SIDE
from ...translate.instruction import ParsedInstruction
from ..protocols import BackendContext, Question
from ..views import view_image
from .chat import ChatModel
from .prompts import load

# A view must score above this mean (0-100) to be kept by the largest-gap rule (authors' value).
SCORE_THRESHOLD = 42.0


def adaptive_cut(scores: np.ndarray, top_k: int, threshold: float = SCORE_THRESHOLD) -> list[int]:
    """The kept views' positions (best first) after the adaptive cut.

    Args:
        scores: (M,) mean QE scores of the kept views, in coarse order (best coarse score first).
        top_k: the most views kept.
        threshold: scores above it take part in the largest-gap rule.

    With m views above ``threshold``: none or one keeps the best view alone; otherwise the cut
    falls at the largest drop between consecutive scores among those m (ties: the first), and at
    most ``top_k`` views are kept. Kept views outside the better half by coarse score are dropped
    (the best one stays when that would drop all). Equal scores keep the coarse order.
    """
    scores = np.asarray(scores, dtype=np.float64)
    order = np.argsort(-scores, kind="stable")
    ranked = scores[order]
    m = int((ranked > threshold).sum())
    if m <= 1:
        return [int(order[0])]
    cut = int(np.argmax(ranked[: m - 1] - ranked[1:m])) + 1
    kept = [int(i) for i in order[: min(cut, top_k)]]
    half = max(1, len(scores) // 2)
    return [i for i in kept if i < half] or kept[:1]


def _image(picture: np.ndarray, long_side: int) -> np.ndarray:
    """(H, W, 3) uint8 ``picture`` downscaled so its long side is at most ``long_side``."""
    from PIL import Image

    h, w = picture.shape[:2]
    scale = long_side / max(h, w)
    if scale >= 1.0:
        return picture
    size = (max(1, round(w * scale)), max(1, round(h * scale)))
    return np.asarray(Image.fromarray(picture).resize(size, Image.BICUBIC))


class MLLMQE:
    """:class:`~capframe.backends.QuestionEvaluator` through a chat model.

    Args:
        chat: the model.
        context: the job's backend context (the training views' images).
        long_side: the views are shown at this long side (the perception resolution of the
            oracle tier's measurements, :data:`~capframe.retrieve.views.VIEWS_LONG_SIDE`).
    """

    def __init__(self, chat: ChatModel, context: BackendContext, long_side: int = VIEWS_LONG_SIDE):
        self.chat = chat
        self.context = context
        self.long_side = long_side
        self.prompts = {name: load(name) for name in ("qe-questions", "qe-answers")}
        self.reasons: list[list[str]] = []

    def _fail(self, prompt: str, message: str) -> ModelError:
        return ModelError(f"{self.chat.identity}: the {prompt} answer ({self.prompts[prompt].version}) is invalid: {message}")

    def questions(self, parsed: ParsedInstruction) -> list[Question]:
        """The model's questions for ``parsed``, in its order, as our kinds (see the module doc)."""
        prompt = self.prompts["qe-questions"]
        names = [s.name for s in parsed.subjects]
        listing = "; ".join(_asked(s) for s in parsed.subjects) + _camera(parsed)
        schema = prompt.narrowed(("properties", "questions", "items", "properties", "subject"), enum=[*names, None])
        data = self.chat.complete(prompt.request({"instruction": parsed.text.strip(), "subjects": listing}, schema=schema)).data
        out = []
        for i, q in enumerate(data["questions"]):
            if q["subject"] is not None and q["subject"] not in names:
                raise self._fail(
                    "qe-questions", f"questions[{i}].subject {clip(repr(q['subject']))} is not a parsed subject; expected {names}"
                )
            out.append(_question(q["kind"], q["subject"], q["text"], parsed))
        return out

    def answer(self, questions: list[Question], view_indices: list[int]) -> np.ndarray:
        """(len(view_indices), len(questions)) scores in [0, 100]; the reasons are kept in
        :attr:`reasons` (rows in ``view_indices`` order) for :meth:`record`."""
        prompt = self.prompts["qe-answers"]
        numbered = "\n".join(f"{k + 1}. {q.text}" for k, q in enumerate(questions))
        numbers = [str(k + 1) for k in range(len(questions))]
        schema = prompt.keyed(("properties", "answers"), numbers, "answer")
        requests = [
            prompt.request({"questions": numbered}, images=(_image(view_image(self.context, v), self.long_side),), schema=schema)
            for v in view_indices
        ]
        replies = self.chat.complete_many(requests)
        scores = np.zeros((len(view_indices), len(questions)))
        self.reasons = []
        for row, (v, reply) in enumerate(zip(view_indices, replies)):
            given = reply.data["answers"]
            if sorted(given) != sorted(numbers):
                raise self._fail(
                    "qe-answers", f"view {self._view_name(v)}: answers {sorted(given)}; expected questions {numbers}"
                )
            for k, number in enumerate(numbers):
                score = given[number]["score"]
                if not (isinstance(score, (int, float)) and math.isfinite(score) and 0 <= score <= 100):
                    raise self._fail(
                        "qe-answers", f"view {self._view_name(v)}: answers.{number}.score {clip(repr(score))} is not in [0, 100]"
                    )
                scores[row, k] = float(score)
            self.reasons.append([given[n]["reason"] for n in numbers])
        return scores

    def cut(self, scores: np.ndarray, top_k: int) -> list[int]:
        """Positions of the retrieved views among the kept ones, best first (:func:`adaptive_cut`)."""
        return adaptive_cut(scores, top_k)

    def record(self) -> dict:
        """What ``retrieval.json`` records of this evaluator: the model, the prompt versions, and
        the last :meth:`answer`'s reasons (rows in its views' order)."""
        return {
            "backend": "mllm",
            "model": self.chat.identity,
            "prompts": [p.version for p in self.prompts.values()],
            "reasons": self.reasons,
        }

    def _view_name(self, v: int) -> str:
        return self.context.scene.cameras[v].name


def _asked(s) -> str:
    """What the instruction asks of one subject, for the question prompt."""
    cues = [f"{field} {value}" for field, value in (("region", s.region), ("shot", s.shot)) if value]
    if s.view and not s.symmetric:
        cues.append(f"seen from its {s.view}")
    return f"{s.name} (said: {s.mention!r}): " + (", ".join(cues) or "nothing beyond being visible")


def _camera(parsed: ParsedInstruction) -> str:
    """The camera cues of ``parsed``, for the question prompt."""
    cues = []
    if parsed.elevation or parsed.elevation_deg is not None:
        cues.append(f"elevation {parsed.elevation or f'{parsed.elevation_deg:+g} degrees'}")
    if parsed.roll_deg is not None:
        cues.append(f"roll {parsed.roll_deg:+g} degrees")
    return f"; camera: {', '.join(cues)}" if cues else ""


def _question(kind: str, subject: str | None, text: str, parsed: ParsedInstruction) -> Question:
    """The model's question in our kinds: its kind with the parsed cue as target when the
    instruction asks that of that subject, else ``overall``."""
    s = next((s for s in parsed.subjects if s.name == subject), None)
    if kind == "visible" and s is not None:
        return Question("visible", text, s.name, {"shot": s.shot})
    if kind == "region" and s is not None and s.region:
        return Question("region", text, s.name, {"region": s.region})
    if kind == "shot" and s is not None and s.shot:
        return Question("shot", text, s.name, {"shot": s.shot})
    if kind == "view" and s is not None and s.view and not s.symmetric:
        return Question("view", text, s.name, {"view": s.view})
    elevation = parsed.constraints().elevation_range()
    if kind == "elevation" and elevation is not None:
        # Measured around the primary subject, as the pseudo labels measure it.
        return Question("elevation", text, parsed.subjects[0].name, {"range_deg": list(elevation)})
    if kind == "roll" and parsed.roll_deg is not None:
        return Question("roll", text, None, {"roll_deg": parsed.roll_deg})
    return Question("overall", text)
