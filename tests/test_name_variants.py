"""Longer everyday names of the catalog's objects (:data:`~capframe.translate.vocabulary.NAME_VARIANTS`):
each answers to its object, none carries a colour, and none is offered as the closest name to a
word the scene lacks."""

from __future__ import annotations

import pytest

from capframe.errors import InputError
from capframe.scene import SemanticObject
from capframe.translate.parse import parse_instruction
from capframe.translate.vocabulary import COLORS, NAME_KINDS, NAME_SYNONYMS, NAME_VARIANTS, Vocabulary, key


def scene(*names: str) -> Vocabulary:
    return Vocabulary.from_semantics([SemanticObject(i, name, [], False) for i, name in enumerate(names)])


VARIANTS = [(group[0], variant) for group in NAME_VARIANTS for variant in group[1:]]


@pytest.mark.parametrize("name, variant", [pytest.param(n, v, id=v) for n, v in VARIANTS])
def test_a_variant_names_its_object_beside_another(name, variant):
    other = "mug" if name != "mug" else "bench"
    assert scene(name, other).match(variant) == name
    assert parse_instruction(f"a photo of the {variant} from the front", scene(name, other)).subjects[0].name == name


def test_no_variant_carries_a_colour():
    """A colour in a name excludes the object from a mention of another colour ("the blue pot
    plant" would no longer be the potted plant if "green plant" were one of its names)."""
    assert not [v for _, v in VARIANTS if set(key(v)) & COLORS]


def test_a_word_the_scene_lacks_is_not_offered_a_variant_as_closest():
    vocabulary = scene("ball", "bench", "teddy bear", "tree")
    with pytest.raises(InputError) as error:
        vocabulary.match("sundial")
    assert "closest" not in str(error.value) and "known" in str(error.value)


def test_the_variants_repeat_no_synonym_or_kind():
    """The tables stay disjoint: a name in two of them is kept in one place."""
    others = {key(w) for group in (*NAME_SYNONYMS, *NAME_KINDS) for w in group[1:]}
    assert not [v for _, v in VARIANTS if key(v) in others]
