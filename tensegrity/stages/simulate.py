"""`tensegrity simulate`: one actuation of one robot, ramped to a pressure and held, written as
a netCDF file (docs/datasets.md, "Simulation"). No rule runs it; it is a stage all the same."""

from __future__ import annotations

import os
from collections.abc import Callable, Sequence
from pathlib import Path

import numpy as np

from ..io import datasets, formats, settings
from ..physics import topology as topo
from ..physics.terrain import Terrain

CHUNK = 0.05  # s: the simulation runs in pieces of about this length (the progress bar's steps)


def simulate(
    cfg: dict,
    face: int | Sequence[int],
    pairs: Sequence[int],
    pressure: float,
    duration: float,
    out_path: str | os.PathLike,
    ramp: float = 0.0,
    mode: str = "free",
    terrain: Terrain | None = None,
    progress: Callable[[float], None] | None = None,
) -> Path:
    """Stage `simulate`: stand the robot on `face`, ramp `pairs` to `pressure` MPa over `ramp` s
    (0: a step) and hold it for the rest of `duration` s, in `mode` ('free' or 'grounded', on
    `terrain`, default flat); record every sim.record_every steps of sim.dt s. progress(s)
    receives the simulated seconds. Writes `out_path`.
    With actuator.kind twisted_string the pairs are the prototype's twisted strings and
    `pressure` is their voltage in V: the file holds `voltage_cmd` (V), and its first sample is
    the state at t = 0 (at rest, the motors untwisted), from which `tensegrity calibrate` replays
    a run in volts (the motors' angles are not recorded)."""
    from ..physics import dynamics as d
    from ..physics.schedule import Schedule
    from ..physics.twisted import Voltages
    from ..workspace import sweep

    params, ground = sweep.setup(settings.params(cfg), mode)
    motors = settings.motors(cfg) if "actuator" in cfg else None  # None: the pneumatic muscles
    volts = motors is not None
    kind = Voltages if volts else Schedule
    if terrain is not None:
        if mode == "free":
            raise ValueError("a terrain needs mode grounded (the free mode has no ground)")
        ground = terrain
    face = topo.face_number(face)
    pairs = [topo.check_pair(p) for p in pairs]
    dt, every = float(cfg["sim"]["dt"]), int(cfg["sim"]["record_every"])
    state = d.stand_on(params, face, ground)
    kind.check(np.full(topo.N_PAIRS, pressure), "--voltage" if volts else "--pressure")  # before any work
    chunk = dt * every * max(1, round(CHUNK / (dt * every)))
    n = max(1, round(duration / chunk))
    ramp_n = round(ramp / chunk)
    # a run in volts starts with the state at t = 0, where the motors' state is known (zero)
    xs, qs, ts, ps = ([state.x], [state.q], [[state.t]], [np.zeros((1, topo.N_PAIRS))]) if volts else ([], [], [], [])
    for k in range(n):
        level = pressure * min(1.0, (k + 1) / ramp_n) if ramp_n else pressure
        pres = np.zeros(topo.N_PAIRS)
        pres[np.array(pairs) - 1] = level
        state, tr = d.simulate(params, state, kind.constant(pres, chunk), ground, dt, every, motors=motors)
        xs.append(tr.x[0]), qs.append(tr.q[0]), ts.append(tr.t), ps.append(tr.pressure[0])
        if progress is not None:
            progress(chunk)
    x, q = np.concatenate(xs), np.concatenate(qs)
    ds = formats.simulation_dataset(
        np.concatenate(ts),
        d.nodes(x, q, params.strut_length),
        np.concatenate(ps),
        face,
        {"mode": mode, "pairs": pairs, ("voltage_v" if volts else "pressure_mpa"): pressure, "ramp_s": ramp},
        volts=volts,
    )
    title = f"Simulation of pairs {pairs} at {pressure} {'V' if volts else 'MPa'} on {topo.face_label(face)}"
    return datasets.write(ds, out_path, cfg, title, stage="simulate")
