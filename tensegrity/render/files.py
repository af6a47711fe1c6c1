"""Atomic figure files: every PNG and GIF is written to a temporary file in its folder and
renamed (`tensegrity.atomic.replacing`), so that a process killed while writing leaves no partial
file at the path."""

from __future__ import annotations

import os
from pathlib import Path
from typing import TYPE_CHECKING

from ..atomic import replacing as atomic

if TYPE_CHECKING:
    from matplotlib.figure import Figure


def save_figure(fig: Figure, path: str | os.PathLike, dpi: int = 110) -> Path:
    """Write the matplotlib Figure `fig` to the PNG `path` atomically, off-screen (Agg canvas),
    with no version stamp (same bytes each run)."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    FigureCanvasAgg(fig)
    with atomic(path) as tmp:
        fig.savefig(tmp, dpi=dpi, metadata={"Software": None})
    return Path(path)
