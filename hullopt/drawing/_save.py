"""The one way hullopt saves a matplotlib figure: rendered in memory (the format from the file's suffix, PNG
when it has none), then written atomically (a temporary file in the same folder, renamed), the figure closed."""

from __future__ import annotations

import io
import os
import sys
from pathlib import Path
from typing import Any, Protocol, runtime_checkable

from ..geometry import atomic_write_bytes


@runtime_checkable
class Figure(Protocol):
    """A matplotlib figure, by what :func:`save_figure` uses of it (matplotlib is imported only to draw)."""

    def savefig(self, fname: Any, **kwargs: Any) -> Any: ...


def save_figure(fig: Figure, path: str | os.PathLike, **savefig_kw) -> Path:
    """Save ``fig`` to ``path`` atomically and close it (also when saving fails); ``savefig_kw`` go to
    ``Figure.savefig`` (``dpi``, ``bbox_inches``…). A reader never sees a half-written file, and a failed save
    leaves no temporary file. ValueError for a format matplotlib cannot write, OSError for a bad folder.

    Parameters
    ----------
    fig : matplotlib.figure.Figure
        The figure; closed afterwards.
    path : str or os.PathLike
        The file; its suffix picks the format (PNG when none).
    **savefig_kw
        Passed to ``Figure.savefig``.

    Returns
    -------
    pathlib.Path
        ``path``.

    Raises
    ------
    ValueError
        For a format matplotlib cannot write.
    OSError
        For a folder that cannot be written.
    """
    path = Path(path)
    try:
        buf = io.BytesIO()
        fig.savefig(buf, format=path.suffix.lstrip(".").lower() or "png", **savefig_kw)
        atomic_write_bytes(path, buf.getvalue())
    finally:
        plt = sys.modules.get("matplotlib.pyplot")  # a figure made without pyplot has nothing to close there
        if plt is not None:
            plt.close(fig)
    return path
