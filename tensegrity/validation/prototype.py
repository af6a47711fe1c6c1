"""The paper's experiment (IV.B) in the grounded simulation, with the prototype's twisted-string
actuators (`physics.twisted`, docs/design.md §10): on (9,10,12) pair #10 at 11.1 V rolls the robot
to (10,11,12); then #11 at 6 V rolls it on to (6,10,11); #10 at 6 V does not roll; the lowest
voltage of each roll, by multisection (`voltage_bracket`); and how each depends on the assumed
parameters, +-20 % (`sensitivity`). Numbers only: `benchmarks/bench_prototype.py` prints them;
the stage `validate_prototype` writes them with the two rolls' `Trace` (results/validation/
prototype.nc, by `ExperimentSettings`) for validation check 8 (`prototype_check`) and Fig. 12."""

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


@dataclass(frozen=True)
class ExperimentSettings:
    """The configuration's `prototype` section (config/README.md): each roll's voltage held
    `drive` s, then 0 V for `settle` s (`Protocol`); the lowest rolling voltages searched by
    `rounds` rounds of `points` voltages side by side (`voltage_bracket`; rounds 0: not searched)."""

    drive: float = 30.0
    settle: float = 4.0
    rounds: int = 2
    points: int = 8

    def __post_init__(self) -> None:
        for key, v in (("drive", self.drive), ("settle", self.settle)):
            if not v > 0:
                raise ValueError(f"config key prototype.{key}: must be a positive time in s, got {v!r}")
        for key, v, least in (("rounds", self.rounds, 0), ("points", self.points, 1)):
            if not (isinstance(v, int | np.integer) and v >= least):
                raise ValueError(f"config key prototype.{key}: must be a whole number >= {least}, got {v!r}")

    def protocol(self, dt: float) -> Protocol:
        """The `Protocol` of each roll at time step dt s."""
        return Protocol(drive=float(self.drive), settle=float(self.settle), dt=float(dt))


def _roll(
    params: Params, motors: TwistedString, state: State, pair: int, volts: np.ndarray, protocol: Protocol
) -> tuple[np.ndarray, State, np.ndarray, dynamics.Trajectory, np.ndarray]:
    """`roll`, and its recorded run and resting faces (B, T) (1-based, 0: none)."""
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
    return last, final, landed, run, faces


def roll(
    params: Params, motors: TwistedString, state: State, pair: int, volts: np.ndarray, protocol: Protocol = Protocol()
) -> tuple[np.ndarray, State, np.ndarray]:
    """Drives `pair` (1-based) of every robot of `state` (B robots; `motors` fields may be (B,)
    arrays) at volts (B,) V by `protocol`. Returns the faces (B,) it rests on after the settle
    (1-based, 0: none), the final state, and the time (B,) s from the voltage's start at which
    each robot came to rest on that face for good (0: it never left it)."""
    return _roll(params, motors, state, pair, volts, protocol)[:3]


def voltage_bracket(
    params: Params,
    motors: TwistedString,
    start: State,
    pair: int,
    target: int,
    span: tuple[float, float] = (0.0, 12.0),
    points: int = 8,
    rounds: int = 2,
    protocol: Protocol = Protocol(),
) -> tuple[np.ndarray, np.ndarray]:
    """The bracket (lo, hi] (V) of the lowest voltage in `span` at which `pair` rolls the robot
    of `start` onto face `target`, for each of the M variants of `motors` (fields (M,) arrays,
    or floats: M = 1) and its start (`start` holds 1 robot, or M: one per variant), by
    multisection: `points` voltages per variant per round, side by side, the bracket shrinking
    `points` times a round (width (span[1] - span[0]) / points^rounds). hi rolls, lo does not
    (lo = span[0]: not tried). Returns lo (M,), hi (M,) V; both NaN where nothing in span rolls.
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
    return np.where(found, lo, np.nan), np.where(found, hi, np.nan)


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
    """The lowest voltage (M,) V that rolls: the top of `voltage_bracket` (same arguments); NaN
    where none in span rolls."""
    return voltage_bracket(params, motors, start, pair, target, span, points, rounds, protocol)[1]


@dataclass(frozen=True)
class Experiment:
    """Section IV.B simulated: the faces reached (1-based) by #10 at 11.1 V from (9,10,12)
    (face_1), then #11 at 6 V from there (face_2), #10 at 6 V from (9,10,12) (face_low); each
    roll's lowest voltage (V), the second from the first's landing state, within the bracket
    (lower_1, lowest_1] and (lower_2, lowest_2] (NaN: not searched, or nothing in 0-12 V
    rolls); time_1, time_2: s from the voltage's start to the landing of each roll at the
    paper's voltage; locked_1, locked_2: whether a strand pair ended that roll twisted past its
    lock (the model's limit, `TwistedString.locked`)."""

    face_1: int
    face_2: int
    face_low: int
    lowest_1: float
    lowest_2: float
    time_1: float = float("nan")
    time_2: float = float("nan")
    locked_1: bool = False
    locked_2: bool = False
    lower_1: float = float("nan")
    lower_2: float = float("nan")

    @property
    def locked(self) -> bool:
        return self.locked_1 or self.locked_2

    @property
    def reproduced(self) -> bool:
        (_, _, f1), (_, _, f2) = paper.EXPERIMENT
        return (
            self.face_1 == topo.face_number(f1)
            and self.face_2 == topo.face_number(f2)
            and self.face_low == topo.face_number(paper.START_FACE)
            and not self.locked
        )


@dataclass(frozen=True)
class Trace:
    """The two rolls at the paper's voltages of one robot, one after the other, every
    `Protocol.record` s: t (T,) s from the first voltage's start, volts (T, 2) V on #10 and #11
    (each sample's command), face (T,) the face it rests on (1-based, 0: none), cog (T, 3) m and
    nodes (3, 12, 3) m at the start, at the end of roll 1 and at the end of roll 2, world frame."""

    t: np.ndarray
    volts: np.ndarray
    face: np.ndarray
    cog: np.ndarray
    nodes: np.ndarray


def _trace(params: Params, runs, faces, starts, pairs, protocol: Protocol) -> Trace:
    """One `Trace` of robot 0 of the runs (dynamics.Trajectory) and faces (B, T) of each roll."""
    t, volts, face, cog = [], [], [], []
    offset = 0.0
    for run, fc, pair in zip(runs, faces, pairs):
        tt = run.t - run.t[0] + offset
        v = np.zeros((tt.size, 2))
        v[:, list(paper.VOLTAGE).index(pair)] = np.where(tt - offset < protocol.drive, paper.VOLTAGE[pair], 0.0)
        t.append(tt), volts.append(v), face.append(fc[0]), cog.append(run.cog()[0])
        offset = tt[-1] + protocol.record
    ends = [dynamics.nodes(s.x[:1], s.q[:1], params.strut_length)[0] for s in starts]
    return Trace(np.concatenate(t), np.concatenate(volts), np.concatenate(face), np.concatenate(cog), np.stack(ends))


def experiment_trace(
    params: Params, motors: TwistedString, protocol: Protocol = Protocol(), rounds: int = 2, points: int = 8
) -> tuple[Experiment, Trace]:
    """Runs section IV.B (module docstring) for one robot; `voltage_bracket` by rounds, points
    (rounds 0: no search). Returns the `Experiment` and the `Trace` of its two rolls."""
    (p1, _, f1), (p2, _, f2) = paper.EXPERIMENT
    start = dynamics.stand_on(params, paper.START_FACE, Terrain.flat())
    both = State.concat([start, start])
    faces, landed, t_1, run_1, fc_1 = _roll(params, motors, both, p1, [paper.VOLTAGE[p1], paper.VOLTAGE[p2]], protocol)
    after = replace(landed.take(slice(0, 1)), t=0.0)
    face_2, final, t_2, run_2, fc_2 = _roll(params, motors, after, p2, [paper.VOLTAGE[p2]], protocol)
    locked = bool(motors.locked(after.motor_angle).any()), bool(motors.locked(final.motor_angle).any())
    kw = dict(rounds=rounds, points=points, protocol=protocol)
    lo_1, hi_1 = voltage_bracket(params, motors, start, p1, topo.face_number(f1), **kw)
    lo_2, hi_2 = voltage_bracket(params, motors, after, p2, topo.face_number(f2), **kw)
    e = Experiment(
        int(faces[0]),
        int(face_2[0]),
        int(faces[1]),
        float(hi_1[0]),
        float(hi_2[0]),
        float(t_1[0]),
        float(t_2[0]),
        *locked,
        float(lo_1[0]),
        float(lo_2[0]),
    )
    trace = _trace(params, (run_1, run_2), (fc_1, fc_2), (start, after, final), (p1, p2), protocol)
    return e, trace


def experiment(
    params: Params, motors: TwistedString, protocol: Protocol = Protocol(), rounds: int = 2, points: int = 8
) -> Experiment:
    """Runs section IV.B (module docstring) for one robot; `lowest_voltage` by rounds, points."""
    return experiment_trace(params, motors, protocol, rounds, points)[0]


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
