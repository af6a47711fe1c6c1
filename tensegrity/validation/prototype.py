"""The paper's experiment (IV.B) in the grounded simulation, with the prototype's twisted-string
actuators (`physics.twisted`, docs/design.md §10): on (9,10,12) pair #10 at 11.1 V rolls the robot
to (10,11,12); then #11 at 6 V rolls it on to (6,10,11); #10 at 6 V does not roll; the lowest
voltage of each roll, by multisection (`lowest_voltage`); and how each depends on the assumed
parameters, +-20 % (`sensitivity`). Numbers only; `benchmarks/bench_prototype.py` prints them."""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from .. import paper
from ..physics import contact, dynamics
from ..physics import topology as topo
from ..physics.params import Params
from ..physics.state import State
from ..physics.terrain import Terrain
from ..physics.twisted import TwistedString, Voltages

# The assumed values (config/README.md): the ones the +-20 % table varies.
ASSUMED = (
    "rotor_inertia",
    "string_length",
    "string_radius",
    "spring_stiffness",
    "fibre_stiffness",
    "pretension",
    "damping",
)


@dataclass(frozen=True)
class Protocol:
    """One roll: the pair's voltage held `drive` s (the motors twist at most at their no-load
    speed), then 0 V for `settle` s (the strings stay twisted: the gear friction holds them);
    the face it stands on then, within `tolerance` m of the ground (locomotion.contact_tolerance).
    dt s; `record` s between samples."""

    drive: float = 30.0
    settle: float = 4.0
    tolerance: float = 0.01
    dt: float = 1e-4
    record: float = 0.01


def roll(
    params: Params, motors: TwistedString, state: State, pair: int, volts: np.ndarray, protocol: Protocol = Protocol()
) -> tuple[np.ndarray, State, np.ndarray]:
    """Drives `pair` (1-based) of every robot of `state` (B robots; `motors` fields may be (B,)
    arrays) at volts (B,) V by `protocol`. Returns the faces (B,) it rests on after the settle
    (1-based, 0: none), the final state, and the time (B,) s from the voltage's start at which
    each robot came to rest on that face for good (0: it never left it)."""
    volts = np.asarray(volts, float)
    B = state.batch
    v = np.zeros((B, 2, topo.N_PAIRS))
    v[:, 0, topo.check_pair(pair) - 1] = volts
    every = int(round(protocol.record / protocol.dt))
    sched = Voltages(np.array([protocol.drive, protocol.settle]), v)
    final, run = dynamics.simulate(params, state, sched, Terrain.flat(), protocol.dt, every, motors=motors)
    faces = contact.resting_face(run.nodes(params.strut_length)[..., 2] - params.strut_radius, protocol.tolerance)
    last = faces[:, -1]
    # the last sample on another face (or none): the landing is the next one
    other = faces != last[:, None]
    k = np.where(other.any(1), faces.shape[1] - np.argmax(other[:, ::-1], axis=1), 0)
    landed = np.where(k > 0, run.t[np.minimum(k, faces.shape[1] - 1)] - state.t, 0.0)
    return last, final, landed


def lowest_voltage(
    params: Params,
    motors: TwistedString,
    start: State,
    pair: int,
    target: int,
    span: tuple[float, float] = (0.0, 12.0),
    points: int = 8,
    rounds: int = 2,
    protocol: Protocol = Protocol(),
) -> np.ndarray:
    """The lowest voltage (V) in `span` at which `pair` rolls the robot of `start` onto face
    `target`, for each of the M variants of `motors` (fields (M,) arrays, or floats: M = 1) and
    its start (`start` holds 1 robot, or M: one per variant):
    `points` voltages per variant per round, the bracket shrinking `points + 1` times a round
    (resolution (hi - lo) / (points + 1)^rounds). Returns (M,) V; NaN where none in span rolls.
    Rolling is taken as monotonic in the voltage between the grid points (not checked)."""
    M = max(int(np.size(getattr(motors, f))) for f in motors.__dataclass_fields__)
    lo, hi = np.full(M, span[0]), np.full(M, span[1])
    found = np.zeros(M, bool)
    for _ in range(rounds):
        frac = np.arange(1, points + 1) / points
        grid = lo[:, None] + (hi - lo)[:, None] * frac  # (M, points), the last = hi
        variants = motors.replace(
            **{
                f: np.repeat(np.broadcast_to(np.asarray(getattr(motors, f), float), (M,)), points)
                for f in motors.__dataclass_fields__
            }
        )
        state = start.take(np.repeat(np.arange(M) if start.batch == M else np.zeros(M, int), points))
        faces = roll(params, variants, state, pair, grid.ravel(), protocol)[0]
        ok = faces.reshape(M, points) == target
        first = np.where(ok.any(1), ok.argmax(1), points)
        found |= ok.any(1)
        prev = np.where(first > 0, grid[np.arange(M), np.maximum(first - 1, 0)], lo)
        hi = np.where(ok.any(1), grid[np.arange(M), np.minimum(first, points - 1)], hi)
        lo = np.where(ok.any(1), prev, lo)
    return np.where(found, hi, np.nan)


@dataclass(frozen=True)
class Experiment:
    """Section IV.B simulated: the faces reached (1-based) by #10 at 11.1 V from (9,10,12)
    (face_1), then #11 at 6 V from there (face_2), #10 at 6 V from (9,10,12) (face_low); each
    roll's lowest voltage (V), the second from the first's landing state; time_1, time_2: s from
    the voltage's start to the landing of each roll at the paper's voltage; locked: whether a
    strand pair ended a roll at the paper's voltages twisted past its lock (the model's limit,
    `TwistedString.locked`)."""

    face_1: int
    face_2: int
    face_low: int
    lowest_1: float
    lowest_2: float
    time_1: float = float("nan")
    time_2: float = float("nan")
    locked: bool = False

    @property
    def reproduced(self) -> bool:
        (_, _, f1), (_, _, f2) = paper.EXPERIMENT
        return (
            self.face_1 == topo.face_number(f1)
            and self.face_2 == topo.face_number(f2)
            and self.face_low == topo.face_number(paper.START_FACE)
            and not self.locked
        )


def experiment(
    params: Params, motors: TwistedString, protocol: Protocol = Protocol(), rounds: int = 2, points: int = 8
) -> Experiment:
    """Runs section IV.B (module docstring) for one robot; `lowest_voltage` by rounds, points."""
    (p1, _, f1), (p2, _, f2) = paper.EXPERIMENT
    start = dynamics.stand_on(params, paper.START_FACE, Terrain.flat())
    faces, landed, t_1 = roll(
        params, motors, State.concat([start, start]), p1, [paper.VOLTAGE[p1], paper.VOLTAGE[p2]], protocol
    )
    after = replace(landed.take(slice(0, 1)), t=0.0)
    face_2, final, t_2 = roll(params, motors, after, p2, [paper.VOLTAGE[p2]], protocol)
    locked = bool(motors.locked(landed.motor_angle).any() or motors.locked(final.motor_angle).any())
    kw = dict(rounds=rounds, points=points, protocol=protocol)
    low_1 = lowest_voltage(params, motors, start, p1, topo.face_number(f1), **kw)
    low_2 = lowest_voltage(params, motors, after, p2, topo.face_number(f2), **kw)
    times = float(t_1[0]), float(t_2[0])
    return Experiment(int(faces[0]), int(face_2[0]), int(faces[1]), float(low_1[0]), float(low_2[0]), *times, locked)


def sensitivity(
    params: Params,
    motors: TwistedString,
    names: tuple[str, ...] = ASSUMED,
    change: float = 0.2,
    protocol: Protocol = Protocol(),
    rounds: int = 2,
    points: int = 8,
) -> dict[str, np.ndarray]:
    """The lowest voltage of each roll with each parameter of `names` times (1 - change) and
    (1 + change), the others as given: {name: (2 rolls, 2 signs)} V. The second roll starts, as
    in `experiment`, where the first at the paper's voltage landed (its strands still twisted:
    they help the second roll); NaN where that first roll failed, or nothing in 0-12 V rolls."""
    (p1, _, f1), (p2, _, f2) = paper.EXPERIMENT
    fields = {f: np.asarray(getattr(motors, f), float) for f in motors.__dataclass_fields__}
    variants = {f: np.repeat(v[None], 2 * len(names), 0) for f, v in fields.items()}
    for k, name in enumerate(names):
        variants[name][2 * k : 2 * k + 2] = fields[name] * np.array([1 - change, 1 + change])
    batch = motors.replace(**variants)
    kw = dict(rounds=rounds, points=points, protocol=protocol)
    start = dynamics.stand_on(params, paper.START_FACE, Terrain.flat())
    M = 2 * len(names)
    faces, landed = roll(params, batch, start.take(np.zeros(M, int)), p1, np.full(M, paper.VOLTAGE[p1]), protocol)[:2]
    out = [lowest_voltage(params, batch, start, p1, topo.face_number(f1), **kw)]
    second = lowest_voltage(params, batch, replace(landed, t=0.0), p2, topo.face_number(f2), **kw)
    out.append(np.where(faces == topo.face_number(f1), second, np.nan))
    return {name: np.array([o[2 * k : 2 * k + 2] for o in out]) for k, name in enumerate(names)}
