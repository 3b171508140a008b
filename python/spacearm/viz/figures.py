"""The one home of figure creation and saving: a matplotlib ``Figure`` on its own Agg canvas
(no pyplot global state) and its atomic write in the format the file name asks for.

Every figure of the package goes through ``save_figure``: ``run.pdf`` is a PDF, ``x.svg`` an
SVG, ``run.png`` a PNG (a name without a suffix gets PNG); a suffix matplotlib cannot write is an
[`ArgumentError`][spacearm.ArgumentError] naming the formats it can, raised before anything is drawn
or written. Files are written atomically (no partial file).
"""

from __future__ import annotations

import os

from .._util.atomic import atomic_path
from .._util.optional import require
from ..errors import ArgumentError

__all__ = ["new_figure", "figure_format", "save_figure", "plot_to"]


def new_figure(*args, **kwargs):
    """A matplotlib ``Figure`` on an Agg canvas; ``layout`` defaults to ``"constrained"`` (labels,
    colour bars and legends outside the axes never overlap a neighbouring panel)."""
    FigureCanvasAgg = require("matplotlib.backends.backend_agg", "figures").FigureCanvasAgg
    Figure = require("matplotlib.figure", "figures").Figure
    kwargs.setdefault("layout", "constrained")
    fig = Figure(*args, **kwargs)
    FigureCanvasAgg(fig)
    return fig


def figure_format(path) -> str:
    """The format ``path``'s suffix names (``"png"`` without one), checked against what
    matplotlib can write."""
    ext = os.path.splitext(os.fspath(path))[1].lower().lstrip(".")
    if not ext:
        return "png"
    FigureCanvasAgg = require("matplotlib.backends.backend_agg", "figures").FigureCanvasAgg
    supported = FigureCanvasAgg.get_supported_filetypes()
    if ext not in supported:
        raise ArgumentError(f"cannot write a figure as '.{ext}' ({os.fspath(path)!r}): the formats are "
                            f"{', '.join('.' + k for k in sorted(supported))}")
    return ext


def save_figure(fig, path, *, dpi: int = 130, **savefig) -> str:
    """Write ``fig`` to ``path`` in the format its suffix names (``figure_format``),
    atomically; returns the path. A PNG is deflated at zlib level 1 (Pillow's default 6 took
    about twice the time for a file some 10 % smaller; benchmarks/README.md)."""
    fmt = figure_format(path)
    if fmt == "png":
        savefig.setdefault("pil_kwargs", {"compress_level": 1})
    path = os.fspath(path)
    with atomic_path(path, suffix="." + fmt) as tmp:
        fig.savefig(tmp, format=fmt, dpi=dpi, **savefig)
    return path


def plot_to(path, draw, *, dpi: int = 130, **savefig) -> str:
    """Check ``path``'s format, then draw (``draw()`` returns the figure) and write it: what
    every result's ``.plot(path)`` does, so that an unwritable format fails before the work of
    drawing."""
    figure_format(path)
    return save_figure(draw(), path, dpi=dpi, **savefig)
