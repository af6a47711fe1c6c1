"""Closed-loop simulation of a batch of robots, one controller each (docs/design.md §6).

`lockstep` advances every robot of a `State` by one check interval at a time with the pressures
its controller asked for, observes them all (`observe`: one terrain query for the batch), and
sends each controller its `Obs`. Controllers are generators (see `control`): they yield the pair
pressures (12,) MPa for the next interval and receive the observation after it; their return
value is their result. A robot that finishes leaves the batch; the others go on. Samples of every
robot are kept in a `Record`.
"""

from __future__ import annotations

from collections.abc import Callable, Generator
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..physics import contact as ct
from ..physics import dynamics as d
from ..physics import topology as topo
from ..physics.params import Params
from ..physics.schedule import Schedule
from ..physics.terrain import Terrain
from .settings import RollSettings

__all__ = ["Record", "Obs", "observe", "lockstep"]

Controller = Generator[np.ndarray, "Obs", Any]


@dataclass(frozen=True)
class Record:
    """Samples, one per check interval: t (T,) s, nodes (T, 12, 3) m world, pressure (T, 12)
    MPa per pair, face (T,) contact face (0: none)."""

    t: np.ndarray
    nodes: np.ndarray
    pressure: np.ndarray
    face: np.ndarray

    @property
    def cog(self) -> np.ndarray:
        """(T, 3) m, world (equal strut masses: the mean of the nodes)."""
        return self.nodes.mean(axis=1)


@dataclass(frozen=True)
class Obs:
    """What a controller sees after each check interval."""

    t: float
    nodes: np.ndarray  # (12, 3) m
    gap: np.ndarray  # (12,) m clearance of each node's contact sphere
    face: int | None  # contact face
    speed: float  # CoG speed over the last interval, m/s (NaN: unknown)
    pressure: np.ndarray = field(default_factory=lambda: np.zeros(topo.N_PAIRS))  # (12,) MPa
    # applied over the last interval: the next controller goes on from them (brake_rate)
    state: d.State | None = field(default=None, repr=False)  # the robot's whole state (batch 1)


def observe(
    params: Params,
    terrain: Terrain,
    state: d.State,
    s: RollSettings,
    before: list[Obs] | None = None,
    pressure: np.ndarray | None = None,
) -> list[Obs]:
    """Observations of every robot of the batch (one terrain query for all of them), with the
    pair pressures (B, 12) MPa applied over the last interval (default zero)."""
    P = d.nodes(state.x, state.q, params.strut_length)
    B = state.batch
    gaps = ct.clearance(P, terrain, float(params.strut_radius)) if B else np.zeros((0, 12))
    faces = ct.resting_face(gaps, s.contact_tolerance)  # 0: on no face
    out = []
    for b in range(B):
        speed = float("nan")
        if before is not None and state.t > before[b].t:
            speed = float(np.linalg.norm(P[b].mean(axis=0) - before[b].nodes.mean(axis=0)) / (state.t - before[b].t))
        out.append(
            Obs(
                state.t,
                P[b],
                gaps[b],
                int(faces[b]) or None,
                speed,
                np.zeros(topo.N_PAIRS) if pressure is None else pressure[b].copy(),
                state.take(slice(b, b + 1)),
            )
        )  # views: no state is written in place
    return out


class _threads:
    """Run the compiled kernel on one thread for a batch of one robot: it gains nothing from
    more, and on a busy machine the hand-off costs more than a check interval's 200 steps."""

    def __init__(self, batch: int):
        self.batch = batch

    def __enter__(self):
        import numba

        self.saved = numba.get_num_threads()
        if self.batch == 1:
            numba.set_num_threads(1)

    def __exit__(self, *exc):
        import numba

        numba.set_num_threads(self.saved)


def lockstep(
    params: Params,
    terrain: Terrain,
    state: d.State,
    make: Callable[[int, Obs], Controller],
    s: RollSettings,
    progress: Callable[[float], None] | None = None,
) -> list[tuple[Any, d.State, Record]]:
    """Drive one controller per robot of `state` (B robots) through the simulator together, one
    check interval (s.interval s, time step s.dt s) at a time, the struts damped as every roll
    is (`RollSettings.rolling`); make(b, obs) returns robot b's controller. A robot whose
    simulation fails gets the SimulationError thrown into its controller; the others go on.
    progress(seconds), if given, receives the simulated time of each interval. Returns per
    robot (result, final State, Record)."""
    state.check()
    params = s.rolling(params)
    every = int(round(s.interval / s.dt))
    B = state.batch
    first = observe(params, terrain, state, s)
    last = list(first)
    gens = [make(b, first[b]) for b in range(B)]
    recs: list[tuple[list, list, list, list]] = [([], [], [], []) for _ in range(B)]
    out: list = [None] * B
    pres = np.zeros((B, topo.N_PAIRS))
    live = []
    for b in range(B):
        try:
            pres[b] = next(gens[b])
            live.append(b)
        except StopIteration as stop:
            out[b] = (stop.value, state.take([b]))
    batch = state.take(live)
    with _threads(len(live)):
        while live:
            failed = {}
            try:
                batch, _ = d.simulate(params, batch, Schedule.constant(pres[live], s.interval), terrain, s.dt, every)
            except d.SimulationError:  # find the robot(s) that failed and advance the rest
                parts = []
                for i, b in enumerate(live):
                    try:
                        parts.append(
                            d.simulate(
                                params, batch.take([i]), Schedule.constant(pres[b], s.interval), terrain, s.dt, every
                            )[0]
                        )
                    except d.SimulationError as e:
                        failed[b] = e
                        parts.append(batch.take([i]))
                batch = d.State.concat(parts, t=batch.t + s.interval)
            if progress is not None:
                progress(s.interval)
            ob = observe(params, terrain, batch, s, [last[b] for b in live], pres[live])
            keep = []
            for i, b in enumerate(live):
                try:
                    if b in failed:
                        gens[b].throw(failed[b])
                        raise RuntimeError("a controller ignored a SimulationError")
                    for lst, v in zip(recs[b], (ob[i].t, ob[i].nodes, pres[b].copy(), ob[i].face or 0)):
                        lst.append(v)
                    last[b] = ob[i]
                    pres[b] = gens[b].send(ob[i])
                    keep.append(i)
                except StopIteration as stop:
                    out[b] = (stop.value, batch.take([i]))
            if len(keep) < len(live):
                live = [live[i] for i in keep]
                batch = batch.take(keep)
    result = []
    for b in range(B):
        t, nodes, p, f = recs[b]
        rec = Record(
            np.array(t, float),
            np.array(nodes, float).reshape(-1, 12, 3),
            np.array(p, float).reshape(-1, 12),
            np.array(f, np.int64),
        )
        result.append((out[b][0], out[b][1], rec))
    return result
