"""Atomic files: every file the toolkit writes (netCDF, JSON, Markdown, HTML, PNG, GIF) goes to a
hidden temporary beside its path, `.STEM.PID.HEX.tmpSUFFIX` (the suffix kept, so that writers
that choose the format by it still do), and is renamed into place when complete. A process killed
while writing leaves no partial file under the final name; the next write of the same file
removes the temporaries that killed writers left behind (`remove_stale`).

A leaf module (the standard library only): `io` and `render` both write through it.
"""

from __future__ import annotations

import contextlib
import os
import re
import secrets
import time
from collections.abc import Iterator
from pathlib import Path

__all__ = ["replacing", "write_text", "remove_stale", "temporary"]

STALE_S = 60.0  # s: a temporary of the same target older than this is left by a killed writer


def temporary(path: str | os.PathLike) -> Path:
    """A fresh temporary name for `path`: .STEM.PID.HEX.tmpSUFFIX in the same folder (the same
    file system, so that the rename is atomic; hidden, so that no output pattern matches it)."""
    path = Path(path)
    return path.with_name(f".{path.stem}.{os.getpid()}.{secrets.token_hex(4)}.tmp{path.suffix}")


def _pattern(path: Path) -> re.Pattern:
    return re.compile(rf"^\.{re.escape(path.stem)}\.(\d+)\.[0-9a-f]{{8}}\.tmp{re.escape(path.suffix)}$")


def _pid_alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except OSError:  # PermissionError: another user's live process
        return True
    return True


def remove_stale(path: str | os.PathLike, min_age_s: float = STALE_S) -> list[Path]:
    """Remove the temporaries of `path` left by killed writers; returns those removed. A
    temporary is stale when its writer's process no longer exists on this host, or when it was
    last modified more than `min_age_s` s ago (another host of a shared file system, or a
    recycled PID). A live writer's temporary younger than that is left alone: the two writers'
    renames are atomic, the last one wins."""
    path = Path(path)
    pattern, now, removed = _pattern(path), time.time(), []
    if not path.parent.is_dir():
        return removed
    for p in path.parent.iterdir():
        m = pattern.match(p.name)
        if not m:
            continue
        try:
            age = now - p.stat().st_mtime
            if age > min_age_s or not _pid_alive(int(m.group(1))):
                p.unlink()
                removed.append(p)
        except FileNotFoundError:
            continue
    return removed


@contextlib.contextmanager
def replacing(path: str | os.PathLike) -> Iterator[Path]:
    """Yield a temporary path beside `path` (its folder made, stale temporaries removed) to write
    to; on success it is renamed to `path`, on failure removed, and an existing `path` is left
    untouched."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    remove_stale(path)
    tmp = temporary(path)
    try:
        yield tmp
        os.replace(tmp, path)
    finally:
        tmp.unlink(missing_ok=True)


def write_text(path: str | os.PathLike, text: str) -> Path:
    """Write the text file `path` atomically (`replacing`); returns the path."""
    with replacing(path) as tmp:
        tmp.write_text(text)
    return Path(path)
