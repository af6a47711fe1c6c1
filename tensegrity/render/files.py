"""Atomic figure files: every PNG and GIF is written to a temporary file in its folder and
renamed, so that a process killed while writing leaves no partial file at the path."""
from __future__ import annotations

import contextlib
import os
import secrets
from collections.abc import Iterator
from pathlib import Path
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from matplotlib.figure import Figure


@contextlib.contextmanager
def atomic(path: str | os.PathLike) -> Iterator[Path]:
    """Yield a temporary path beside `path` (folders made) to write to; on success it is renamed
    to `path`, on failure removed."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name(f".{path.stem}.{os.getpid()}-{secrets.token_hex(3)}.tmp{path.suffix}")
    try:
        yield tmp
        os.replace(tmp, path)
    finally:
        tmp.unlink(missing_ok=True)


def save_figure(fig: "Figure", path: str | os.PathLike, dpi: int = 110) -> Path:
    """Write the matplotlib Figure `fig` to the PNG `path` atomically, off-screen (Agg canvas),
    with no version stamp (same bytes each run)."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    FigureCanvasAgg(fig)
    with atomic(path) as tmp:
        fig.savefig(tmp, dpi=dpi, metadata={"Software": None})
    return Path(path)
