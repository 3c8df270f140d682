"""Helpers of the teaching notebooks, imported there as ``_helpers`` (tested in ``tests/``)."""
