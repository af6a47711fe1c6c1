"""Closed-loop simulation of a batch of robots, one controller each (docs/design.md §6).

`lockstep` advances every robot of a `State` by one check interval at a time with the pressures
its controller asked for (with `RollSettings.motors`, motor voltages: `applied`), observes them
all (`observe`: one terrain query for the batch), and sends each controller its `Obs`.
Controllers are generators (see `control`): they yield the pair pressures (12,) MPa for the next
interval and receive the observation after it; their return value is their result. A robot that
finishes leaves the batch; the others go on. Samples of every robot are kept in a `Record` (the
levels applied).
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
from ..physics.terrain import Terrain
from .settings import RollSettings

__all__ = ["Record", "Obs", "observe", "lockstep"]

Controller = Generator[np.ndarray, "Obs", Any]


@dataclass(frozen=True)
class Record:
    """Samples, one per check interval: t (T,) s, nodes (T, 12, 3) m world, pressure (T, 12)
    MPa per pair ((T, 24) per cable if the robot made a per-cable action), face (T,) contact
    face (0: none)."""

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
    cog: np.ndarray | None = field(default=None, repr=False)  # (3,) m: the mean of the nodes (equal
    # strut masses; None: computed here)

    def __post_init__(self):
        if self.cog is None:
            object.__setattr__(self, "cog", self.nodes.mean(axis=0))


def observe(
    params: Params,
    terrain: Terrain,
    state: d.State,
    s: RollSettings,
    before: list[Obs] | None = None,
    pressure: np.ndarray | None = None,
    states: bool = True,
) -> list[Obs]:
    """Observations of every robot of the batch (one terrain query for all of them), with the
    pressures (B, 12) MPa applied over the last interval (default zero; or B rows, each (12,) per
    pair or (24,) per cable, `own`); each with its robot's `state` unless `states` is False."""
    P = d.nodes(state.x, state.q, params.strut_length)
    B = state.batch
    gaps = ct.clearance(P, terrain, float(params.strut_radius)) if B else np.zeros((0, 12))
    faces = ct.resting_face(gaps, s.contact_tolerance).tolist()  # 0: on no face
    cog = P.mean(axis=1)  # (B, 3) m, each row equal to its Obs.cog
    pressure = np.zeros((B, topo.N_PAIRS)) if pressure is None else [np.array(p, float) for p in pressure]
    speed = [float("nan")] * B  # m/s, the CoG's since `before` (np.linalg.norm's numbers: vecdot)
    if before is not None and B:
        t0 = np.array([o.t for o in before])
        step = cog - np.stack([o.cog for o in before])
        with np.errstate(divide="ignore", invalid="ignore"):
            speed = np.where(state.t > t0, np.sqrt(np.vecdot(step, step)) / (state.t - t0), np.nan).tolist()
    out = []
    for b in range(B):
        st = state.take(slice(b, b + 1)) if states else None
        out.append(Obs(state.t, P[b], gaps[b], faces[b] or None, speed[b], pressure[b], st, cog[b]))  # views:
        # none is written in place
    return out


# The strands' rest (docs/design.md §6, "Locomotion in volts"): 0 V leaves them twisted (the gear
# friction holds them), so a pair commanded 0 V is driven back to zero twist.
UNWIND_GAIN = 2.0  # V/rad: the twist closes at about 9/s (a motor turns G/D = 4.4 rad/s per V,
# design.md §10), slower than the motor's own 16/s (J/D = 62 ms) and the 50/s of the checks
UNWIND_TOLERANCE = 1.0  # rad: the twist left, a contraction (theta r)^2 / 2 L0 < 1e-6 m; the 2 V
# that drives it is above the 1.3 V (TC/G) under which the motor does not move


def widths(x: np.ndarray, like: np.ndarray) -> np.ndarray:
    """Levels `x` (..., 12) per pair lifted to their cables (..., 24) where `like` is per cable (a
    robot that has made a per-cable action commands its cables from then on), else as given."""
    return topo.cable_levels(x) if like.shape[-1] == topo.N_CABLES and x.shape[-1] == topo.N_PAIRS else x


def put(pres: np.ndarray, wide: list[bool], b: int, cmd: np.ndarray) -> np.ndarray:
    """Robot b's command `cmd` (12,) or (24,) stored in the batch's commands `pres` (B, 12) or
    (B, 24), widened to per cable (`topology.cable_levels`: the pair levels on both cables, the
    same simulation to the bit) where needed; wide[b] records that robot b commands its cables.
    Returns `pres` (a new array if widened)."""
    cmd = np.asarray(cmd, float)
    wide[b] = wide[b] or cmd.size == topo.N_CABLES
    if cmd.size > pres.shape[1]:
        pres = topo.cable_levels(pres)
    pres[b] = widths(cmd, pres)
    return pres


def own(row: np.ndarray, wide: bool) -> np.ndarray:
    """A robot's command as it gave it: `row` of the batch's commands, per pair (12,) unless the
    robot commands its cables (`wide`; a pair robot's row in a per-cable batch holds each pair's
    level on both its cables)."""
    return row if wide or row.size == topo.N_PAIRS else row[topo.PAIR_CABLES[:, 0]]


def _twist(angle: np.ndarray, like: np.ndarray) -> np.ndarray:
    """The twist (..., 12) rad of each pair, the mean of its two motors' angles (..., 24), lifted
    to its cables (`widths`) where `like` is per cable."""
    return widths(angle[..., topo.PAIR_CABLES].mean(axis=-1), like)


def applied(s: RollSettings, levels: np.ndarray, state: d.State) -> np.ndarray:
    """The levels (B, 12) (or (B, 24) per cable) the actuators get for the commanded `levels` of the robots of `state`:
    the pressures as commanded (MPa); with `s.motors`, the voltages (V) as commanded, but a pair
    commanded 0 V whose strands are twisted by more than UNWIND_TOLERANCE (the mean of its two
    motors) is driven back, -UNWIND_GAIN theta V, at most the rated voltage: a muscle at 0 MPa
    returns to its rest length, a twisted string at 0 V would not."""
    if s.motors is None or state.motor_angle is None:
        return levels
    twist = _twist(state.motor_angle, levels)
    rated = float(np.min(s.motors.rated_voltage))
    back = -np.clip(UNWIND_GAIN * twist, -rated, rated)
    return np.where((levels == 0) & (np.abs(twist) > UNWIND_TOLERANCE), back, levels)


def rested(s: RollSettings, obs: Obs, levels: np.ndarray) -> bool:
    """Whether every pair commanded 0 (`levels` (12,)) is at rest: always for the muscles; for
    the twisted strings, its strands unwound to within UNWIND_TOLERANCE (`lockstep.applied`)."""
    if s.motors is None or obs.state is None or obs.state.motor_angle is None:
        return True
    twist = _twist(obs.state.motor_angle[0], levels)
    return bool(np.all(np.abs(twist[levels == 0]) <= UNWIND_TOLERANCE))


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


def advance(
    params: Params, terrain: Terrain, s: RollSettings, batch: d.State, levels: np.ndarray, live: list[int], every: int
) -> tuple[d.State, dict, np.ndarray]:
    """One check interval (`every` steps) of the live robots' batch under their commanded levels
    (B, 12). A robot whose simulation fails stays where it was; returns (batch, {robot: error}, the levels
    (B, 12) the actuators got)."""
    failed = {}
    cmd = applied(s, levels, batch)  # what the actuators get (the pressures as asked)
    try:
        batch, _ = d.simulate(params, batch, s.schedule(cmd), terrain, s.dt, every, s.motors)
    except d.SimulationError:  # find the robot(s) that failed and advance the rest
        parts = []
        for i, b in enumerate(live):
            try:
                parts.append(d.simulate(params, batch.take([i]), s.schedule(cmd[i]), terrain, s.dt, every, s.motors)[0])
            except d.SimulationError as e:
                failed[b] = e
                parts.append(batch.take([i]))
        batch = d.State.concat(parts, t=batch.t + s.interval)
    return batch, failed, cmd


def first_commands(
    gens: list, state: d.State, wide: list[bool], width: int = topo.N_PAIRS
) -> tuple[np.ndarray, list[int], list, d.State]:
    """Each controller's first command: pres (B, width), widened by `put` (wide: per robot), the
    robots still live, out (B,) holding (result, State) of the controllers that ended at once,
    and the live robots' batch."""
    pres = np.zeros((state.batch, width))
    out: list = [None] * state.batch
    live = []
    for b, gen in enumerate(gens):
        try:
            pres = put(pres, wide, b, next(gen))
            live.append(b)
        except StopIteration as stop:
            out[b] = (stop.value, state.take([b]))
    return pres, live, out, state.take(live)


def lockstep(
    params: Params,
    terrain: Terrain,
    state: d.State,
    make: Callable[[int, Obs], Controller],
    s: RollSettings,
    progress: Callable[[float], None] | None = None,
    record: bool = True,
) -> list[tuple[Any, d.State, Record | None]]:
    """Drive one controller per robot of `state` (B robots) through the simulator together, one
    check interval (s.interval s, time step s.dt s) at a time, the struts damped as every roll
    is (`RollSettings.rolling`); make(b, obs) returns robot b's controller. A robot whose
    simulation fails gets the SimulationError thrown into its controller; the others go on.
    progress(seconds), if given, receives the simulated time of each interval. Returns per
    robot (result, final State, Record); without `record`, no Record (None) and no Obs.state
    (the controllers read it only to unwind the twisted strings: kept with s.motors)."""
    state.check()
    params = s.rolling(params)
    every = int(round(s.interval / s.dt))
    B = state.batch
    states = record or s.motors is not None
    first = observe(params, terrain, state, s, states=states)
    last = list(first)
    gens = [make(b, first[b]) for b in range(B)]
    recs: list[tuple[list, list, list, list]] = [([], [], [], []) for _ in range(B)]
    wide = [False] * B  # robots that command their cables (`put`)
    pres, live, out, batch = first_commands(gens, state, wide)
    with _threads(len(live)):
        while live:
            batch, failed, cmd = advance(params, terrain, s, batch, pres[live], live, every)
            if progress is not None:
                progress(s.interval)
            ob = observe(
                params, terrain, batch, s, [last[b] for b in live], [own(pres[b], wide[b]) for b in live], states
            )
            keep = []
            for i, b in enumerate(live):
                try:
                    if b in failed:
                        gens[b].throw(failed[b])
                        raise RuntimeError("a controller ignored a SimulationError")
                    if record:
                        for lst, v in zip(
                            recs[b], (ob[i].t, ob[i].nodes, own(cmd[i], wide[b]).copy(), ob[i].face or 0)
                        ):
                            lst.append(v)
                    last[b] = ob[i]
                    pres = put(pres, wide, b, gens[b].send(ob[i]))
                    keep.append(i)
                except StopIteration as stop:
                    out[b] = (stop.value, batch.take([i]))
            if len(keep) < len(live):
                live = [live[i] for i in keep]
                batch = batch.take(keep)
    if not record:
        return [(out[b][0], out[b][1], None) for b in range(B)]
    result = []
    for b in range(B):
        t, nodes, p, f = recs[b]
        n = topo.N_CABLES if wide[b] else topo.N_PAIRS  # a robot that commanded its cables: per cable
        rec = Record(
            np.array(t, float),
            np.array(nodes, float).reshape(-1, 12, 3),
            np.array([topo.cable_levels(r) if wide[b] else r for r in p], float).reshape(-1, n),
            np.array(f, np.int64),
        )
        result.append((out[b][0], out[b][1], rec))
    return result
