"""``capframe userstudy import``: the participants' answer files -> the user-study columns of Table 1.

An answer file is the CSV the questionnaire's page saves (:data:`~capframe.userstudy.key.ANSWER_COLUMNS`,
one row per participant, group and image). Every row is checked against the key; the first fault
raises :class:`~capframe.errors.InputError` naming the file, the line and the field, and nothing is
written. A file may leave groups out (they do not count), but a group it answers is answered whole:
every image rated, exactly one picked best.

The table (:data:`TABLE_COLUMNS`), one row per method of the key, in its order:

* ``rating_mean``: the mean 1-5 rating of the method's images over all participants and groups;
* ``rating_n``: how many ratings that mean is of;
* ``preference_share``: of the answered groups (participant x group) that showed the method, the
  share in which its image was picked best.

A method no answered group showed has ``rating_n`` 0 and empty mean and share.
"""

from __future__ import annotations

import csv
import io
import math
from collections import defaultdict
from dataclasses import dataclass
from pathlib import Path

import pandas as pd

from ..errors import InputError
from ..scene._io import atomic_write, read_bytes
from .key import ANSWER_COLUMNS, RATINGS, Key, read_key

TABLE_COLUMNS = ("method", "rating_mean", "rating_n", "preference_share")


@dataclass(frozen=True)
class Answer:
    """One row of an answer file: a participant's rating of one image, and whether it was the
    group's best pick."""

    participant: str
    group: int
    image: str
    rating: int
    best: bool


def import_answers(key_path: str | Path, answer_paths: list[str | Path], output: str | Path) -> pd.DataFrame:
    """Read the key and every answer file, check them, and write the table (:data:`TABLE_COLUMNS`)
    as CSV at ``output``. Returns the table."""
    key = read_key(key_path)
    seen: dict[tuple[str, int, str], str] = {}
    answers = [a for path in answer_paths for a in read_answers(path, key, str(key_path), seen)]
    table = userstudy_table(key, answers)
    atomic_write(output, table.to_csv(index=False))
    return table


def read_answers(path: str | Path, key: Key, key_source: str, seen: dict[tuple[str, int, str], str]) -> list[Answer]:
    """The rows of the answer file at ``path``, each checked against ``key`` (read from
    ``key_source``). ``seen`` maps (participant, group, image) to where it was answered, across
    files: an answer given twice is refused."""
    source = str(path)
    try:
        text = read_bytes(path, "a CSV of answers").decode("utf-8-sig")
    except UnicodeDecodeError as err:
        raise InputError(f"is not UTF-8 text ({err}); expected the CSV the questionnaire saves", source=source) from None
    reader = csv.reader(io.StringIO(text))
    header = next(reader, None)
    if header != list(ANSWER_COLUMNS):
        raise InputError(f"line 1: header is {header}; expected {','.join(ANSWER_COLUMNS)}", source=source)
    answers: list[Answer] = []
    groups: dict[tuple[str, int], tuple[int, list[Answer]]] = {}  # (participant, group) -> (first line, rows)
    for row in reader:
        if not row:
            continue
        line = reader.line_num
        if len(row) != len(ANSWER_COLUMNS):
            expected = f"{len(ANSWER_COLUMNS)} ({','.join(ANSWER_COLUMNS)})"
            raise InputError(f"line {line}: has {len(row)} fields; expected {expected}", source=source)
        answer = _answer(dict(zip(ANSWER_COLUMNS, row)), key, key_source, f"line {line}", source)
        where = (answer.participant, answer.group, answer.image)
        if where in seen:
            raise InputError(
                f"line {line}: image: duplicated answer: participant {answer.participant!r}, group {answer.group}, image "
                f"{answer.image} was already answered ({seen[where]})",
                source=source,
            )
        seen[where] = f"{source} line {line}"
        groups.setdefault((answer.participant, answer.group), (line, []))[1].append(answer)
        answers.append(answer)
    if not answers:
        raise InputError("holds no answers (a header only); expected the CSV the questionnaire saves", source=source)
    for (participant, number), (line, rows) in groups.items():
        labels = list(key.group(number).methods)
        rated = sorted(a.image for a in rows)
        if rated != labels:
            raise InputError(
                f"line {line}: image: participant {participant!r} answered images {rated} of group {number}; expected all of "
                f"{labels}",
                source=source,
            )
        picks = [a.image for a in rows if a.best]
        if len(picks) != 1:
            raise InputError(
                f"line {line}: best: participant {participant!r} picked {len(picks)} images {picks} as group {number}'s best; "
                "expected exactly one",
                source=source,
            )
    return answers


def _answer(fields: dict[str, str], key: Key, key_source: str, where: str, source: str) -> Answer:
    """One row's fields checked against the key; ``where`` is ``line N`` for messages."""
    if fields["questionnaire"] != key.questionnaire:
        raise InputError(
            f"{where}: questionnaire is {fields['questionnaire']!r}, but {key_source} is questionnaire {key.questionnaire!r}: "
            "answers to another questionnaire",
            source=source,
        )
    participant = fields["participant"].strip()
    if not participant:
        raise InputError(f"{where}: participant is empty; expected the participant's id", source=source)
    numbers = [g.number for g in key.groups]
    group = key.group(int(fields["group"])) if fields["group"].strip().isdigit() else None
    if group is None:
        raise InputError(
            f"{where}: group is {fields['group']!r}: unknown group; {key_source} has groups {min(numbers)}-{max(numbers)}",
            source=source,
        )
    if fields["image"] not in group.methods:
        raise InputError(
            f"{where}: image is {fields['image']!r}; group {group.number} shows images {', '.join(group.methods)}", source=source
        )
    if fields["rating"].strip() not in {str(r) for r in RATINGS}:
        expected = f"a whole number from {RATINGS[0]} to {RATINGS[-1]}"
        raise InputError(f"{where}: rating is {fields['rating']!r}; expected {expected}", source=source)
    if fields["best"].strip() not in ("0", "1"):
        raise InputError(f"{where}: best is {fields['best']!r}; expected 1 (picked as the group's best) or 0", source=source)
    return Answer(participant, group.number, fields["image"], int(fields["rating"]), fields["best"].strip() == "1")


def userstudy_table(key: Key, answers: list[Answer]) -> pd.DataFrame:
    """Per method of ``key``: mean rating, number of ratings and preference share (module
    docstring) of ``answers`` (checked rows: every answered group whole, one best)."""
    ratings: dict[str, list[int]] = defaultdict(list)
    shown: dict[str, int] = defaultdict(int)
    picked: dict[str, int] = defaultdict(int)
    for answer in answers:
        method = key.group(answer.group).methods[answer.image]
        ratings[method].append(answer.rating)
        # Each answered group has exactly one best row, and it shows every method of the group:
        # one count per (participant, group) for each method shown.
        if answer.best:
            for other in key.group(answer.group).methods.values():
                shown[other] += 1
            picked[method] += 1
    rows = [
        {
            "method": method,
            "rating_mean": sum(ratings[method]) / len(ratings[method]) if ratings[method] else math.nan,
            "rating_n": len(ratings[method]),
            "preference_share": picked[method] / shown[method] if shown[method] else math.nan,
        }
        for method in key.methods
    ]
    return pd.DataFrame(rows, columns=list(TABLE_COLUMNS))
