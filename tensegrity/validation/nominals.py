"""The nominal CoG the checks compare: the pipeline's nominal CoG of each contact case
(`workspace.nominal.Nominal`, read by `io.formats.read_nominal`), and the checks' own sweeps, run
and averaged as the pipeline does (workspace.sweep, workspace.nominal)."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, replace

import numpy as np

from ..physics import topology as topo
from ..physics.params import Params
from ..physics.twisted import TwistedString
from ..workspace import nominal as nom
from ..workspace import sweep as sw
from ..workspace.mapping import same_levels
from ..workspace.nominal import Nominal
from ..workspace.sweep import SweepSetup


def common_levels(nominals: Mapping[str, Nominal]) -> np.ndarray:
    """The pressure levels (P,) MPa shared by the nominal CoG of the contact cases (contact ->
    `Nominal`); ValueError if none is given or the contact cases were swept at different levels."""
    return same_levels([n.levels for n in nominals.values()])


@dataclass(frozen=True)
class NominalRun:
    """Nominal CoG of a simulated sweep, per pair (n,) and level (P,): pairs (n,) 1-based,
    cog (n, P, 3) m and support (n, P, 3, 3) m in the face's support frame, margin (n, P) m,
    and end_face (n, P), the face the robot rests on at the end of each level
    (`contact.resting_face`; 0: none)."""

    pairs: np.ndarray
    cog: np.ndarray
    support: np.ndarray
    margin: np.ndarray
    end_face: np.ndarray


def simulate_nominal(
    params: Params,
    face: int | Sequence[int],
    pairs: Sequence[int],
    setup: SweepSetup,
    discard: float,
    motors: TwistedString | None = None,
    **override: object,
) -> NominalRun:
    """Run the staircase of `setup` on `pairs` (1-based, batched) standing on `face` (1..20 or
    three node numbers) and average each level after its first `discard` s as the pipeline does
    (workspace.nominal.nominal); `override` replaces fields of the setup (mode, settle s, dt s,
    record_every steps); with `motors` (the twisted-string actuator) the levels are volts."""
    face = topo.face_number(face)
    setup = replace(setup, **override)
    res = sw.run(params, face, pairs, setup, motors)
    P = len(setup.levels)
    out = [
        nom.nominal(res.t, res.level, res.cog[b], res.support[b], P, setup.hold, discard) for b in range(len(res.pairs))
    ]
    last = np.array([np.flatnonzero(res.level == k)[-1] for k in range(P)])
    end_face = res.resting_face[:, last]
    return NominalRun(res.pairs, *(np.stack([o[k] for o in out]) for k in (0, 2, 3)), end_face)
