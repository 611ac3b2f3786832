"""Synthetic benchmark material: scenes with ground truth and instructions with checkable constraints."""
