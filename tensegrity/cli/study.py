"""`tensegrity study`: a design study without Snakemake, with a progress bar."""

from __future__ import annotations

import os
import sys
from pathlib import Path


def run(cfg: dict, name: str, out_dir: str | os.PathLike | None = None, limit: int = 0) -> int:
    """Load and check the study `name` (before any work), run it (`stages.study.run_study`) with
    a progress bar in designs on a terminal (tqdm; quiet otherwise), print where the files are.
    `cfg`: the resolved configuration. Returns 0."""
    from tqdm import tqdm

    from ..io import settings, study_config
    from ..stages.config import stage_config
    from ..stages.study import CHUNK_FILE, run_study
    from ..studies import spec

    study = study_config.load(name, base=settings.params(cfg), dt=cfg["sim"]["dt"])
    out = Path(out_dir or Path("results", "studies", study["name"]))
    n = spec.n_designs(study) if not limit else min(limit, spec.n_designs(study))
    w = study["workspace"]
    per_design_s = len(w["levels"]) * w["hold"]
    with tqdm(
        total=n,
        desc=f"study {study['name']}",
        unit="design",
        disable=None,
        file=sys.stderr,
        bar_format="{desc}: {percentage:3.0f}%|{bar}| {n:.1f}/{total} designs [{elapsed}<{remaining}]",
    ) as bar:
        done = sum(
            len(spec.chunk_rows(study, c, limit))
            for c in range(spec.n_chunks(study, limit))
            if (out / CHUNK_FILE.format(chunk=c)).is_file()
        )
        bar.update(done)

        def progress(seconds: float) -> None:  # a level of one chunk: its designs' share
            bar.update(min(study["chunk_size"], n) * seconds / per_design_s)

        files = run_study(stage_config(cfg, "study_chunk"), study, out, limit, progress)
        bar.n = n
        bar.refresh()
    for f in files:
        print(f)
    return 0
