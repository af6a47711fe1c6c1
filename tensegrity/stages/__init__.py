"""The application seam: the workflow's stages as functions from files to files (docs/design.md
§5, §8), one module per rule file `workflow/rules/<rule>.smk`.

Each stage takes `cfg`, the configuration keys it reads (`config.stage_config`), reads its input
files through `io`, turns `cfg` into typed settings once (`io.settings`), calls the domain
(physics, workspace, locomotion, validation, studies, render) and writes its outputs through
`io`, with `provenance` as each file's configuration. The Snakemake scripts call them, and
`tensegrity stage NAME` runs any of them (`config.STAGES` names each one's function and rule).

This module stays light (the standard library only): the Snakefile imports `stages.config`.
"""

from __future__ import annotations

import contextlib
import importlib
import os
from collections.abc import Callable, Iterator, Mapping
from pathlib import Path

from .config import STAGES, stage_config

__all__ = ["STAGES", "stage_config", "function", "provenance", "logging_to", "job"]


def function(stage: str) -> Callable:
    """The function of `stage` (`config.STAGES`), e.g. function("sweep") is `stages.sweep.sweep`."""
    if stage not in STAGES:
        raise ValueError(f"unknown stage {stage!r}: use one of {sorted(STAGES)}")
    module, name = STAGES[stage].function.split(":")
    return getattr(importlib.import_module(f".{module}", __name__), name)


def provenance(cfg: Mapping, *inputs: str | os.PathLike) -> dict:
    """The configuration of a stage's outputs: the configurations of its input files merged key
    by key (`io.config.merge`), then the stage's own keys `cfg` over them."""
    from ..io import config, datasets

    out: dict = {}
    for path in inputs:
        out = config.merge(out, datasets.provenance_config(path))
    return config.merge(out, cfg)


@contextlib.contextmanager
def logging_to(path: str | os.PathLike, threads: int | None = None) -> Iterator[None]:
    """Send stdout and stderr (and a traceback on failure) to the log file `path`; use
    `threads` compute threads."""
    Path(path).parent.mkdir(parents=True, exist_ok=True)
    if threads:
        import numba

        numba.set_num_threads(max(1, min(int(threads), numba.config.NUMBA_NUM_THREADS)))
    with open(path, "w") as log, contextlib.redirect_stdout(log), contextlib.redirect_stderr(log):
        try:
            yield
        except BaseException:
            import traceback

            traceback.print_exc(file=log)
            raise


@contextlib.contextmanager
def job(path: str | os.PathLike, threads: int | None = None) -> Iterator[None]:
    """The body of a workflow script: `logging_to` the log file `path` with `threads` compute
    threads; on success the process then ends at once, without the interpreter's teardown
    (freeing numba's compiled code and the renderer took 0.3-0.45 s of CPU in every job, a
    tenth of the pipeline's). Every output is written and closed by then; the streams are
    flushed first. A failure raises as usual (traceback in the log, exit status 1)."""
    import logging
    import sys

    with logging_to(path, threads):
        yield
    logging.shutdown()
    sys.stdout.flush()
    sys.stderr.flush()
    os._exit(0)
