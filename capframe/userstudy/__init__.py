"""The user-study kit (the paper's Table 1 user-study columns): a static questionnaire made from a
finished run, and the importer of the participants' answers.

* :func:`make_questionnaire` (``capframe userstudy make``) draws instructions for which every
  chosen method has a render, shows each with a few methods' renders in a random order labelled
  A, B, C (never a method name), asks a 1-5 rating per image and the best image per instruction,
  and writes ``OUT/site/`` (``index.html`` and its images; nothing is fetched from a network) and,
  beside it and never shipped to participants, ``OUT/key.json`` (group -> label -> method).
* :func:`import_answers` (``capframe userstudy import``) validates the participants' CSVs against
  that key and writes one row per method: ``method, rating_mean, rating_n, preference_share``.

The questionnaire's id, in the page and in every answer row, is the hash of its key
(:func:`~capframe.userstudy.key.questionnaire_id`): answers to another questionnaire, or a key
edited after the page was made, are refused.
"""

from .answers import import_answers
from .questionnaire import make_questionnaire

__all__ = ["import_answers", "make_questionnaire"]
