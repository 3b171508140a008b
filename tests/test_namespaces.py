"""spacearm.rotations and spacearm.control export their API only: every public module-level
name is in __all__, and every name of __all__ is there (issue 26, item 8)."""

from __future__ import annotations

import importlib

import pytest


@pytest.mark.parametrize("name", ["spacearm.rotations", "spacearm.control"])
def test_the_public_names_are_the_api(name):
    mod = importlib.import_module(name)
    public = {n for n in vars(mod) if not n.startswith("_")}
    assert public == set(mod.__all__), f"stray: {sorted(public - set(mod.__all__))}, missing: {sorted(set(mod.__all__) - public)}"
