"""Translate: from language to geometric pseudo labels (subjects, layout boxes, view targets)."""

from .labels import PseudoLabels, SubjectLabel, ViewTarget, layout_boxes, read_pseudo_labels, write_pseudo_labels

__all__ = ["PseudoLabels", "SubjectLabel", "ViewTarget", "layout_boxes", "read_pseudo_labels", "write_pseudo_labels"]
