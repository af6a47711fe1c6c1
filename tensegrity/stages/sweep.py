"""Rule `sweep` (workflow/rules/sweep.smk): the pressure staircase of every configured pair on a
contact face, results/sweeps/{contact}/pairNN.nc."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from ..io import datasets, formats, settings
from ..io.formats import actuation
from ..physics import topology as topo
from ..workspace.sweep import SweepSetup

LOCKED = (
    "1 if a motor had twisted its strands past their lock (theta r / p = pi / 2, Palli et al. 2013) "
    "by the end of the level: the twisting model (T1) does not hold there (docs/design.md 10)"
)


def sweep(cfg: dict, contact: str, out_dir: str | os.PathLike) -> list[Path]:
    """Stage `sweep`: sweep every pair of sweep.pairs standing on the canonical face of `contact`
    (one batch); write `out_dir`/pairNN.nc. With the twisted-string actuator (an `actuator`
    section in `cfg`) the levels are motor voltages and the files say V (`formats.actuation`)."""
    from ..workspace import sweep as sw  # the simulator (numba) only where it runs

    if contact not in topo.CONTACT_FACES:
        raise ValueError(f"unknown contact {contact!r}: use one of {list(topo.CONTACT_FACES)}")
    setup, params = settings.build(SweepSetup, cfg), settings.params(cfg)
    motors = settings.motors(cfg) if "actuator" in cfg else None
    kind = actuation.PNEUMATIC if motors is None else actuation.TWISTED
    res = sw.run(params, topo.CONTACT_FACES[contact], cfg["sweep"]["pairs"], setup, motors)
    paths = []
    for b, pair in enumerate(res.pairs):
        ds = formats.sweep_dataset(res, b, contact, setup, int(cfg["sweep"]["node_stride"]), float(params.strut_length))
        if res.locked is not None:
            ds["strands_locked"] = datasets.var(("levels",), res.locked[b].astype(np.int8), "1", LOCKED)
        paths.append(
            datasets.write(
                actuation.relabel(ds, kind),
                Path(out_dir) / formats.SWEEP_FILE.format(pair=int(pair)),
                cfg,
                actuation.words(f"Pressure sweep of pair #{pair} standing on {topo.face_label(res.face)}", kind),
                stage="sweep",
            )
        )
    return paths
