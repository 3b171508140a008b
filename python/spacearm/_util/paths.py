"""Where a file named by a model may be read from: one rule for the URDF loader and the viewer
(mesh files confined to the model's folder and the declared package folders)."""

from __future__ import annotations

import os
from typing import Sequence

__all__ = ["inside"]


def inside(path: str, roots: Sequence[str]) -> bool:
    """Whether ``path`` (symbolic links and ``..`` resolved) lies in one of the folders ``roots``."""
    real = os.path.realpath(path)
    for root in roots:
        r = os.path.realpath(root)
        try:
            if os.path.commonpath([real, r]) == r:
                return True
        except ValueError:  # another drive
            continue
    return False
