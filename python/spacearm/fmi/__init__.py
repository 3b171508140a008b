"""FMI co-simulation units of spacearm models (docs/fmi.md): [`export`][spacearm.fmi.export] writes an FMU
(FMI 3 or FMI 2) whose binary is the spacearm C library (docs/c-api.md).

>>> import spacearm, spacearm.fmi
>>> spacearm.fmi.export(spacearm.presets.spatial6(), "spatial6.fmu")   # doctest: +SKIP
"""

from .fmu import binary_folder, export
from .library import path as library_path

__all__ = ["export", "binary_folder", "library_path"]
