"""Optional dependencies: imported only where they are needed, with one clear error otherwise.

The plain install (``pip install spacearm``) holds the numerical core and the CLI: numpy,
defusedxml and tqdm. Figures need matplotlib (extra ``plot``), closed-form derivation needs
SymPy (extra ``symbolic``), cluster campaigns need Dask (extra ``campaign``), and videos need
imageio-ffmpeg's ffmpeg (extra ``video``, with MuJoCo for its renderer); ``all`` holds
every extra. Each optional package is imported through ``require``, never at module level,
so ``import spacearm`` and every ``spacearm`` command start without them, and a missing one
gives a [`MissingDependencyError`][spacearm.MissingDependencyError] that names the extra to install (the
CLI prints it as one line and exits with status 2).
"""

from __future__ import annotations

import importlib
from types import ModuleType

from ..errors import MissingDependencyError

__all__ = ["require", "EXTRAS"]

#: Which extra provides each optional top-level package (the one table of it; pyproject.toml
#: declares the same extras).
EXTRAS = {
    "matplotlib": "plot",
    "mpl_toolkits": "plot",
    "sympy": "symbolic",
    "distributed": "campaign",
    "dask": "campaign",
    "casadi": "optimal-control",
    "trimesh": "mesh",
    "imageio_ffmpeg": "video",
    "meshcat": "view",
    "gymnasium": "rl",
    "Basilisk": "basilisk",
}

#: The pip distribution of an optional package that is in no extra, where its name differs
#: from the package's (``pip install pin`` gives ``import pinocchio``).
PIP_NAMES = {"pinocchio": "pin"}


def require(module: str, purpose: str) -> ModuleType:
    """Import ``module`` (e.g. ``"matplotlib.figure"``) or raise a MissingDependencyError.

    ``purpose`` completes "<package> is needed for ...", e.g. ``"figures"``.
    """
    try:
        return importlib.import_module(module)
    except ImportError as exc:
        top = module.split(".")[0]
        if exc.name is not None and exc.name.split(".")[0] != top:
            raise  # the package is there but broken: show the real import error
        extra = EXTRAS.get(top)
        hint = f'pip install "spacearm[{extra}]"' if extra else f"pip install {PIP_NAMES.get(top, top)}"
        raise MissingDependencyError(f"{top} is needed for {purpose} but is not installed: {hint}",
                                     package=top, extra=extra) from None
