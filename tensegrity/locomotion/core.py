"""Rolling locomotion from the kinematic workspace (paper III.C-D, IV; design.md section 6).

Three layers, each usable on its own:

- `Workspace`: the 20-face workspace (results/workspace.nc, design.md section 5), with the
  unactuated robot prepended at 0 MPa. `predict` places a face's curves in the frame of the
  robot's *current* contact triangle and projects them along gravity (slopes, paper Fig. 10).
- `plan`: the paper's steps 1-3 (III.C): on the current face, rank every pair (and, when no
  single pair makes progress, every two-pair combination, predicted by superposing the
  single-pair curves) by how well the outward direction of the edge its CoG projection crosses
  matches the target, then by the least pressure. Returns a `Plan` with its reasons.
- `roll` / `roll_to` / `roll_many` / `roll_over`: step 4 in the dynamic simulator (gravity,
  ground, friction): ramp the pressure slowly (quasi-static, as the paper's rolling is), hold
  it once a support node lifts, release it once the unactuated robot would fall over the pivot
  edge anyway (`contact.past_edge`), catch the robot on the next face, let it settle; repeat
  toward a goal (or over given edges, as in the paper's experiment). A plan the simulation does
  not follow is escalated along the ramp to the workspace's highest level, then the next
  candidate is tried, then the run ends "stuck"; a step limit bounds every run, and every run
  ends with one of OUTCOMES and a message. Runs of a batch are simulated together
  (`_lockstep` drives one controller generator per robot).
- `locomotion_io` holds the rest: runs as datasets (results/locomotion/*.nc), the workflow's
  demonstration runs, and the `tensegrity plan` / `tensegrity roll` commands.

Numbers people see (faces, pairs, nodes) start at 1. Pressures in MPa, lengths in m, times in s.
"""
from __future__ import annotations

import itertools
import math
import time as _time
from dataclasses import dataclass, field, fields, replace

import numpy as np

from ..physics import contact as ct
from ..physics import dynamics as d
from ..physics import frames, topology as topo
from ..physics.actuation import MAX_PRESSURE, Schedule
from ..physics.params import Params
from ..physics.terrain import Terrain

__all__ = ["Workspace", "Prediction", "Candidate", "Plan", "Settings", "RollResult", "Record",
           "Step", "Run", "predict", "plan", "settle", "roll", "roll_to", "roll_many", "roll_over",
           "OUTCOMES"]

OUTCOMES = ("arrived", "step_limit", "stuck", "no_contact", "off_terrain", "sim_error")


# ------------------------------------------------------------------------------- workspace

@dataclass(frozen=True)
class Workspace:
    """levels (P,) MPa; cog (20, 12, P, 3) m and support (20, 12, P, 3, 3) m in each face's
    support frame (NaN where a pair was not swept); rest_cog (20, 3) m and rest_support
    (20, 3, 3) m: the unactuated symmetric robot in the same frames (the 0 MPa point)."""
    levels: np.ndarray
    cog: np.ndarray
    support: np.ndarray
    rest_cog: np.ndarray
    rest_support: np.ndarray

    def __post_init__(self):
        lv = np.asarray(self.levels, float)
        if lv.ndim != 1 or lv.size < 1 or np.any(np.diff(lv) <= 0) or lv[0] <= 0:
            raise ValueError("workspace levels must be positive, strictly increasing MPa")
        P = lv.size
        shapes = {"cog": (20, 12, P, 3), "support": (20, 12, P, 3, 3), "rest_cog": (20, 3),
                  "rest_support": (20, 3, 3)}
        for name, shape in shapes.items():
            if np.shape(getattr(self, name)) != shape:
                raise ValueError(f"workspace {name} must have shape {shape}, "
                                 f"got {np.shape(getattr(self, name))}")
        object.__setattr__(self, "levels", lv)

    @classmethod
    def from_arrays(cls, levels, cog, support, strut_length: float = 0.5) -> "Workspace":
        """From cog (20, 12, P, 3) and support (20, 12, P, 3, 3) m at `levels` (P,) MPa; the
        0 MPa point is the symmetric robot of strut length `strut_length` m."""
        rest = [frames.rest_frame(f, strut_length) for f in range(1, topo.N_FACES + 1)]
        return cls(np.asarray(levels, float), np.asarray(cog, float), np.asarray(support, float),
                   np.stack([r[0] for r in rest]), np.stack([r[1] for r in rest]))

    @classmethod
    def from_dataset(cls, ds) -> "Workspace":
        """From an xarray Dataset with the contract of results/workspace.nc."""
        from ..io.datasets import strut_length
        strut = strut_length(ds)
        order = {"face": np.arange(1, 21), "pair": np.arange(1, 13), "axis": ["x", "y", "z"]}
        sel = {k: v for k, v in order.items() if k in ds.dims}
        cog = ds["cog"].sel(sel).transpose("face", "pair", "pressure", "axis").values
        sup = ds["support"].sel(sel).transpose("face", "pair", "pressure", "corner", "axis").values
        return cls.from_arrays(ds["pressure"].values, cog, sup, strut)

    @classmethod
    def load(cls, path) -> "Workspace":
        """Read results/workspace.nc (or a file of the same contract)."""
        from ..io.datasets import read
        return cls.from_dataset(read(path))

    @property
    def max_pressure(self) -> float:
        """The highest swept level, MPa: where escalation stops."""
        return float(self.levels[-1])

    @property
    def pressures(self) -> np.ndarray:
        """(P + 1,) MPa: 0 followed by the levels."""
        return np.concatenate([[0.0], self.levels])

    def pairs(self, face: int) -> np.ndarray:
        """1-based pairs with a complete curve on 1-based `face`."""
        ok = np.all(np.isfinite(self.cog[face - 1]), axis=(1, 2))
        return np.flatnonzero(ok) + 1

    def curve(self, face: int, actions) -> tuple[np.ndarray, np.ndarray]:
        """CoG (A, P+1, 3) m and support triangle (A, P+1, 3, 3) m in the face's support frame
        for each action, a tuple of 1-based pairs driven at the same pressure, with the rest
        state first. Two or more pairs are superposed: rest + sum of the single displacements
        (an estimate; statics shows it is conservative for the combinations that matter)."""
        f = face - 1
        rc, rs = self.rest_cog[f], self.rest_support[f]
        c = np.concatenate([np.broadcast_to(rc, (12, 1, 3)), self.cog[f]], axis=1)
        s = np.concatenate([np.broadcast_to(rs, (12, 1, 3, 3)), self.support[f]], axis=1)
        outc, outs = [], []
        for act in actions:
            idx = np.asarray(act, int) - 1
            outc.append(rc + np.sum(c[idx] - rc, axis=0))
            outs.append(rs + np.sum(s[idx] - rs, axis=0))
        return np.stack(outc), np.stack(outs)


@dataclass(frozen=True)
class Prediction:
    """Workspace curves of A actions placed on the current contact triangle. pressure (n,) MPa;
    cog (A, n, 3) m and projection (A, n, 3) m (CoG moved along gravity onto the support plane),
    world frame; local (A, n, 2) m projection and triangle (A, n, 3, 2) m in the face's support
    frame; margin (A, n) m (positive inside); edge_dist (A, n, 3) m signed distances to the edge
    lines (edge k joins corners k, k+1)."""
    pressure: np.ndarray
    cog: np.ndarray
    projection: np.ndarray
    local: np.ndarray
    triangle: np.ndarray
    margin: np.ndarray
    edge_dist: np.ndarray


def predict(workspace: Workspace, face, nodes, actions) -> Prediction:
    """Where the workspace puts the CoG projection for `actions` (tuples of 1-based pairs) on
    `face` (1..20 or three node numbers), in the frame of the current triangle of `nodes`
    (12, 3) m, projected along gravity (paper Fig. 10)."""
    f = topo.face_number(face)
    p = ct.check_nodes(nodes)
    origin, rot = frames.face_frame(p, f)
    gl = rot @ ct.GRAVITY_DIR  # gravity in the support frame
    if gl[2] > -1e-6:
        raise ValueError(f"face {topo.face_label(f)} is not below the robot: gravity does not "
                         "press it onto its support")
    cog, sup = workspace.curve(f, actions)
    proj = cog - (cog[..., 2:3] / gl[2]) * gl
    margin = frames.margin_2d(proj[..., :2], sup[..., :2])
    dist = frames.edge_distances(proj[..., :2], sup[..., :2])
    return Prediction(workspace.pressures, origin + cog @ rot, origin + proj @ rot, proj[..., :2],
                      sup[..., :2], margin, dist)


# ------------------------------------------------------------------------------------ plan

@dataclass(frozen=True)
class Candidate:
    """One way to roll: `pairs` (1-based) driven at the same pressure. edge: the edge (1-based
    nodes) the predicted CoG projection crosses first, or approaches most if it never does;
    next_face: the face across it; pressure: predicted least pressure that rolls the robot
    (linear interpolation of the margin between levels), MPa, NaN if none within the workspace;
    reach: predicted margin at the highest level, m (negative: outside); alignment: cosine
    between the edge's outward direction (horizontal) and the target direction."""
    pairs: tuple[int, ...]
    edge: tuple[int, int]
    next_face: int
    pressure: float
    reach: float
    alignment: float

    @property
    def predicted(self) -> bool:
        return bool(np.isfinite(self.pressure))

    def label(self) -> str:
        return "+".join(f"#{p}" for p in self.pairs)


@dataclass(frozen=True)
class Plan:
    """The chosen actuation on `face` (1-based) and why. pairs: 1-based pairs driven together
    (usually one); pressure: predicted least rolling pressure, MPa (NaN if the workspace predicts
    no roll: then the roll escalates to the highest level); edge, next_face, reach (m) and
    alignment as in `Candidate`; margin: the current CoG projection's margin, m; direction (3,):
    horizontal unit target direction, world; candidates: every option in the order to try (the
    first is the choice); reasons: sentences a person can check."""
    face: int
    pairs: tuple[int, ...]
    pressure: float
    edge: tuple[int, int]
    next_face: int
    reach: float
    alignment: float
    margin: float
    direction: np.ndarray
    candidates: tuple[Candidate, ...]
    reasons: tuple[str, ...]

    @property
    def pair(self) -> int:
        return self.pairs[0]

    @property
    def predicted(self) -> bool:
        return bool(np.isfinite(self.pressure))

    def __str__(self) -> str:
        return "\n".join(self.reasons)


def _direction(nodes: np.ndarray, direction, goal) -> np.ndarray:
    if (direction is None) == (goal is None):
        raise ValueError("give exactly one of direction (a world vector) or goal (a world point)")
    if goal is not None:
        gpt = np.asarray(goal, float).ravel()
        if gpt.size not in (2, 3) or not np.all(np.isfinite(gpt)):
            raise ValueError(f"goal must be a finite world point (x, y) or (x, y, z) m, got {goal!r}")
        v = gpt[:2] - nodes.mean(axis=0)[:2]
    else:
        v = np.asarray(direction, float).ravel()
        if v.size not in (2, 3) or not np.all(np.isfinite(v)):
            raise ValueError(f"direction must be a finite 2- or 3-vector, got {direction!r}")
        v = v[:2]
    n = float(np.linalg.norm(v))
    if n < 1e-6:
        raise ValueError("the target direction is zero: the goal is right above the robot's CoG"
                         if goal is not None else "direction has no horizontal component")
    return np.array([v[0] / n, v[1] / n, 0.0])


def _candidates(workspace, f, nodes, actions, u) -> list[Candidate]:
    pred = predict(workspace, f, nodes, actions)
    out_world = ct.edge_outward(nodes[topo.FACES[f - 1]])
    horiz = out_world[:, :2] / np.maximum(np.linalg.norm(out_world[:, :2], axis=1, keepdims=True), 1e-12)
    align = horiz @ u[:2]
    res = []
    for a, act in enumerate(actions):
        p, k = frames.first_crossing(pred.pressure, pred.margin[a])
        e = int(np.argmin(pred.edge_dist[a, k if k >= 0 else -1]))
        edge = topo.edge_nodes(f, e)
        res.append(Candidate(tuple(int(x) for x in act), edge, topo.neighbour(f, edge), p,
                             float(pred.margin[a, -1]), float(align[e])))
    return res


def plan(workspace: Workspace, face, nodes, *, direction=None, goal=None,
         terrain: Terrain | None = None, avoid=(), combine: bool = True,
         min_alignment: float = 0.0) -> Plan:
    """Choose the actuation that rolls the robot standing on `face` (1..20 or three node
    numbers) with node positions `nodes` (12, 3) m toward a target `direction` (world vector)
    or `goal` (world point, m), from the workspace (paper III.C steps 2-3).

    Ranking: candidates predicted to roll come first, by the alignment of the crossed edge's
    outward direction with the target (best first), then single pairs before combinations,
    then the least pressure. A roll onto a face in `avoid` (faces, e.g. the last few visited)
    is ranked after the others, so that the robot does not rock back and forth or go round in
    a circle. Two-pair combinations are added when no single pair is predicted to roll onto a
    face not avoided over an edge with alignment > min_alignment (e.g. uphill on a slope); if
    `combine` is False they never are. Candidates not predicted to roll follow, closest to
    rolling first. `terrain`, if given, is checked to be under every node."""
    f = topo.face_number(face)
    p = ct.check_nodes(nodes)
    if terrain is not None:
        ct.clearance(p, terrain, 0.0)  # raises if nothing is under a node
    singles = [(int(q),) for q in workspace.pairs(f)]
    if not singles:
        raise ValueError(f"the workspace has no curve for face {topo.face_label(f)}")
    u = _direction(p, direction, goal)
    avoid = {topo.face_number(a) for a in avoid}
    cands = _candidates(workspace, f, p, singles, u)
    good = [c for c in cands if c.predicted and c.next_face not in avoid
            and c.alignment > min_alignment]
    combined = False
    if not good and combine and len(singles) > 1:
        cands += _candidates(workspace, f, p, list(itertools.combinations(
            [s[0] for s in singles], 2)), u)
        combined = True

    def rank(c: Candidate):
        back = c.next_face in avoid
        if c.predicted:
            return (0, back, -round(c.alignment, 9), len(c.pairs), c.pressure, c.pairs)
        return (1, back, c.alignment <= min_alignment, round(c.reach, 9), len(c.pairs), c.pairs)

    cands.sort(key=rank)
    best = cands[0]
    here = ct.judge(p, f)
    reasons = [f"standing on face {topo.face_label(f)} ({topo.FACE_TYPES[f - 1]}); the CoG projection "
               f"is {here.margin * 1e3:.1f} mm inside the support triangle",
               f"target direction {math.degrees(math.atan2(u[1], u[0])):.1f} deg from +x"]
    if combined:
        reasons.append("no single pair is predicted to roll the robot toward the target: "
                       "two-pair combinations (superposed workspace curves) considered")
    if best.predicted:
        reasons.append(
            f"chosen {best.label()} at {best.pressure:.2f} MPa: the CoG projection leaves the "
            f"triangle over edge {best.edge[0]}-{best.edge[1]} (alignment {best.alignment:+.2f}) "
            f"and reaches {-best.reach * 1e3:.1f} mm outside at {workspace.max_pressure:g} MPa; "
            f"next face {topo.face_label(best.next_face)}")
        if best.next_face in avoid:
            reasons.append(f"face {topo.face_label(best.next_face)} was visited recently: rolling "
                           "back onto it only because nothing else is predicted to roll")
    else:
        reasons.append(
            f"the workspace predicts no roll: the best option, {best.label()} toward edge "
            f"{best.edge[0]}-{best.edge[1]}, keeps the CoG projection {best.reach * 1e3:.1f} mm "
            f"inside at {workspace.max_pressure:g} MPa; the simulation will escalate to that level")
    others = [c for c in cands[1:] if c.predicted][:4] or cands[1:4]
    if others:
        reasons.append("next options: " + "; ".join(
            f"{c.label()} over {c.edge[0]}-{c.edge[1]} "
            + (f"at {c.pressure:.2f} MPa" if c.predicted else "(no roll predicted)")
            + f", alignment {c.alignment:+.2f}" for c in others))
    return Plan(f, best.pairs, best.pressure, best.edge, best.next_face, best.reach,
                best.alignment, here.margin, u, tuple(cands), tuple(reasons))


# -------------------------------------------------------------------------------- control

@dataclass(frozen=True)
class Settings:
    """How rolls are driven and judged (the keys of config section `locomotion`, which also
    documents them): ramp_rate MPa/s; interval s (pressure step and check period);
    lift_tolerance m; hold_time s; release_margin m; release_time s; catch_time s;
    settle_speed m/s; settle_time s; contact_tolerance m; combine; min_alignment;
    max_attempts; max_rolls; arrive_tolerance m; dt s (the simulator's time step).

    A roll (see `roll`) ramps the pressure at ramp_rate; a support node lifted by more than
    lift_tolerance holds it (at most hold_time s); once the unactuated robot would fall over the
    pivot edge by release_margin (`contact.past_edge`) the pressure ramps down over
    release_time, and once it has landed on the next face over catch_time (held while it tips
    back); it has settled when its CoG moves slower than settle_speed on a face (contact_
    tolerance) for three checks, or after settle_time."""
    ramp_rate: float = 1.0
    interval: float = 0.02
    lift_tolerance: float = 0.001
    hold_time: float = 1.0
    release_margin: float = 0.005
    release_time: float = 0.4
    catch_time: float = 1.5
    settle_speed: float = 0.03
    settle_time: float = 6.0
    contact_tolerance: float = 0.01
    combine: bool = True
    min_alignment: float = 0.0
    max_attempts: int = 3
    max_rolls: int = 80
    arrive_tolerance: float = 0.3
    dt: float = 1e-4

    def __post_init__(self):
        for f in fields(self):
            v = getattr(self, f.name)
            if f.name in ("combine", "min_alignment"):
                continue
            if isinstance(v, bool) or not (np.isfinite(v) and v > 0):
                raise ValueError(f"locomotion setting {f.name} must be a positive number, got {v!r}")
        for name in ("max_attempts", "max_rolls"):
            v = getattr(self, name)
            if float(v) != int(v):
                raise ValueError(f"locomotion setting {name} must be a whole number, got {v!r}")
            object.__setattr__(self, name, int(v))
        if not (np.isfinite(self.min_alignment) and -1.0 <= self.min_alignment < 1.0):
            raise ValueError(f"locomotion setting min_alignment must be in [-1, 1), got {self.min_alignment!r}")
        if abs(self.interval / self.dt - round(self.interval / self.dt)) > 1e-6:
            raise ValueError(f"locomotion interval {self.interval} s is not a whole number of "
                             f"time steps of {self.dt} s")

    @classmethod
    def from_config(cls, section: dict, dt: float | None = None) -> "Settings":
        """From the `locomotion` config section (keys that are not settings are ignored) and
        the time step `dt` s (config sim.dt)."""
        names = {f.name for f in fields(cls)}
        kw = {k: v for k, v in section.items() if k in names}
        if dt is not None:
            kw["dt"] = dt
        return cls(**kw)


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
class RollResult:
    """One roll attempt. rolled: the robot ended on another face; face_before/face_after
    (1-based; face_after None if it settled on no face); tip_pressure: the pressure held when a
    support node lifted, if the robot then rolled (MPa, NaN if not); peak_pressure MPa;
    t_start, t_end s; cog_before, cog_after (3,) m world. From `roll` also the final `state`
    and the `record`."""
    pairs: tuple[int, ...]
    rolled: bool
    face_before: int
    face_after: int | None
    tip_pressure: float
    peak_pressure: float
    t_start: float
    t_end: float
    cog_before: np.ndarray
    cog_after: np.ndarray
    state: d.State | None = field(default=None, repr=False)
    record: Record | None = field(default=None, repr=False)


@dataclass(frozen=True)
class _Obs:
    """What a controller sees after each check interval."""
    t: float
    nodes: np.ndarray  # (12, 3) m
    gap: np.ndarray    # (12,) m clearance of each node's contact sphere
    face: int | None   # contact face
    speed: float       # CoG speed over the last interval, m/s (NaN: unknown)


def _observe(params: Params, terrain: Terrain, state: d.State, s: Settings,
             before: list[_Obs] | None = None) -> list[_Obs]:
    """Observations of every robot of the batch (one terrain query for all of them)."""
    P = d.nodes(state.x, state.q, params.strut_length)
    B = state.batch
    gaps = ct.clearance(P, terrain, float(params.strut_radius)) if B else np.zeros((0, 12))
    out = []
    for b in range(B):
        try:
            face = ct.face_from_gaps(gaps[b], s.contact_tolerance)
        except ct.ContactError:
            face = None
        speed = float("nan")
        if before is not None and state.t > before[b].t:
            speed = float(np.linalg.norm(P[b].mean(axis=0) - before[b].nodes.mean(axis=0))
                          / (state.t - before[b].t))
        out.append(_Obs(state.t, P[b], gaps[b], face, speed))
    return out


# Controllers are generators: they yield the pair pressures (12,) MPa for the next check
# interval and receive an _Obs of the robot after it; `yield from` composes them, and their
# return value is their result. `_lockstep` drives any number of them as one simulated batch.

_CALM = 3  # checks in a row that count as settled
_TABU = 4  # a run avoids rolling back onto the faces of its last four steps


def _settle_gen(s: Settings, obs: _Obs):
    """Zero pressure until settled (see Settings). Returns (face or None, last observation)."""
    zero, calm, waited = np.zeros(topo.N_PAIRS), 0, 0.0
    while waited < s.settle_time - 1e-9:
        obs = yield zero
        waited += s.interval
        calm = calm + 1 if (obs.face is not None and obs.speed < s.settle_speed) else 0
        if calm >= _CALM:
            break
    return obs.face, obs


def _roll_gen(params: Params, s: Settings, obs: _Obs, pairs, max_pressure: float):
    """See `roll`. Returns (RollResult, last observation)."""
    if obs.face is None:
        raise ct.ContactError("a roll must start from a robot resting on a face")
    face0, t0, cog0 = obs.face, obs.t, obs.nodes.mean(axis=0)
    support = topo.FACES[face0 - 1]
    base = obs.gap[support]
    S = float(params.strut_length)
    idx = np.asarray(pairs) - 1
    level, tip, peak, phase, t_phase = 0.0, float("nan"), 0.0, "ramp", 0.0
    landed, apex = None, -1
    while phase != "settle":
        if phase == "ramp":
            level = min(level + s.ramp_rate * s.interval, max_pressure)
        elif phase == "release":
            level = max(0.0, level - peak * s.interval / s.release_time)
        elif phase == "land":
            # catch the robot on the new face: let go slowly, hold while it tips back over the
            # edge it came across, let go fast if it tips on over another edge
            up = obs.gap[topo.FACES[landed - 1]] > s.lift_tolerance
            if up[apex] and up.sum() == 1 and t_phase < 2 * s.catch_time:
                pass
            else:
                level = max(0.0, level - peak * s.interval / (s.release_time if up.any() else s.catch_time))
        pres = np.zeros(topo.N_PAIRS)
        pres[idx] = level
        peak = max(peak, level)
        obs = yield pres
        t_phase += s.interval
        if phase in ("release", "land"):
            if landed is None and obs.face is not None and obs.face != face0:
                back = topo.common_edge(face0, obs.face)
                if back is not None:
                    landed, phase, t_phase = obs.face, "land", 0.0
                    apex = int(np.flatnonzero(~np.isin(topo.FACES[landed - 1] + 1, back))[0])
            if level <= 0.0:
                phase = "settle"
            continue
        lifted = obs.gap[support] - base > s.lift_tolerance
        over = False
        if lifted.sum() == 1:
            pivot = tuple(int(n) + 1 for n in support[~lifted])
            over = ct.past_edge(obs.nodes, face0, pivot, S) > s.release_margin
        if over or (obs.face is not None and obs.face != face0):
            if not np.isfinite(tip):
                tip = level
            phase, t_phase = "release", 0.0
        elif phase == "ramp" and lifted.any():
            tip, phase, t_phase = level, "hold", 0.0
        elif phase == "ramp" and level >= max_pressure:
            phase, t_phase = "top", 0.0
        elif phase == "hold" and t_phase >= s.hold_time - 1e-9:
            if level < max_pressure:
                phase, tip = "ramp", float("nan")  # rocking without rolling: keep raising
            else:
                phase, t_phase = "release", 0.0  # escalated to the limit: give up
        elif phase == "top" and t_phase >= s.hold_time - 1e-9:
            phase, t_phase = "release", 0.0
        elif obs.t - t0 > max_pressure / s.ramp_rate + 10 * s.hold_time:
            phase, t_phase = "release", 0.0  # a safety net: no attempt runs on forever
    after, obs = yield from _settle_gen(s, obs)
    rolled = after is not None and after != face0
    return RollResult(tuple(int(q) for q in pairs), rolled, face0, after,
                      tip if rolled else float("nan"), peak, t0, obs.t, cog0,
                      obs.nodes.mean(axis=0)), obs


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


def _lockstep(params: Params, terrain: Terrain, state: d.State, make, s: Settings):
    """Drive one controller per robot of `state` through the simulator together; make(b, obs)
    returns robot b's controller. A robot whose simulation fails gets the SimulationError
    thrown into its controller; the others go on. Returns per robot (result, State, Record)."""
    state.check()
    every = int(round(s.interval / s.dt))
    B = state.batch
    first = _observe(params, terrain, state, s)
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
                batch, _ = d.simulate(params, batch, Schedule.constant(pres[live], s.interval),
                                      terrain, s.dt, every)
            except d.SimulationError:  # find the robot(s) that failed and advance the rest
                parts = []
                for i, b in enumerate(live):
                    try:
                        parts.append(d.simulate(params, batch.take([i]), Schedule.constant(
                            pres[b], s.interval), terrain, s.dt, every)[0])
                    except d.SimulationError as e:
                        failed[b] = e
                        parts.append(batch.take([i]))
                batch = d.State(*(np.concatenate([getattr(p, k) for p in parts]) for k in
                                  ("x", "v", "q", "w", "anchor", "stuck")), t=batch.t + s.interval)
            ob = _observe(params, terrain, batch, s, [last[b] for b in live])
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
        rec = Record(np.array(t, float), np.array(nodes, float).reshape(-1, 12, 3),
                     np.array(p, float).reshape(-1, 12), np.array(f, np.int64))
        result.append((out[b][0], out[b][1], rec))
    return result


def settle(params: Params, state: d.State, terrain: Terrain,
           settings: Settings | None = None) -> tuple[d.State, int | None]:
    """Let one robot settle at zero pressure (see Settings). Returns the state and its contact
    face (None if it rests on no face)."""
    s = settings or Settings()
    if state.batch != 1:
        raise ValueError(f"settle drives one robot; the state holds {state.batch}")
    (face, _), st, _ = _lockstep(params, terrain, state, lambda b, o: _settle_gen(s, o), s)[0]
    return st, face


def roll(params: Params, state: d.State, terrain: Terrain, pairs, max_pressure: float,
         settings: Settings | None = None) -> RollResult:
    """One roll in the dynamic simulator (paper III.C step 4) of one robot resting on a face:
    drive 1-based `pairs` together from 0 toward `max_pressure` MPa at ramp_rate. When a support
    node lifts the pressure is held (at most hold_time s, then the ramp resumes: escalation);
    once the unactuated robot would fall over the pivot edge (`contact.past_edge`), or it has
    landed on another face, the pressure is released, slowly once it has landed (held while it
    tips back); then it settles. If nothing lifts by max_pressure (held hold_time s), it is
    released too. Returns the RollResult with the final state and the record.
    Raises SimulationError if the simulation blows up or leaves the terrain, ContactError if
    the robot does not rest on a face."""
    s = settings or Settings()
    pairs = tuple(topo.check_pair(q) for q in np.atleast_1d(pairs))
    if not (np.isfinite(max_pressure) and 0 < max_pressure <= MAX_PRESSURE):
        raise ValueError(f"max_pressure {max_pressure!r} MPa must be in (0, {MAX_PRESSURE}]")
    if state.batch != 1:
        raise ValueError(f"roll drives one robot; the state holds {state.batch}")
    (res, _), st, rec = _lockstep(params, terrain, state, lambda b, o: _roll_gen(
        params, s, o, pairs, max_pressure), s)[0]
    return replace(res, state=st, record=rec)


# ------------------------------------------------------------------------------------- runs

@dataclass(frozen=True)
class Step:
    """One step of a run: the plan made on `face`, the attempts in order, and the face the
    robot ended on (None if on no face)."""
    face: int
    plan: Plan
    attempts: tuple[RollResult, ...]
    face_after: int | None

    @property
    def rolled(self) -> bool:
        return bool(self.attempts) and self.attempts[-1].rolled

    @property
    def used(self) -> RollResult:
        """The attempt that rolled the robot (or the last one)."""
        return self.attempts[-1]


@dataclass(frozen=True)
class Run:
    """A run. outcome: one of OUTCOMES; message: why it ended; goal (3,) m (NaN for a run over
    a list of edges); start (3,) m: the CoG at the start; steps; record: the samples; wall:
    wall-clock time, s (shared by the runs of a batch); state: the final state."""
    outcome: str
    message: str
    goal: np.ndarray
    start: np.ndarray
    steps: tuple[Step, ...]
    record: Record
    wall: float
    state: d.State = field(repr=False)

    @property
    def final(self) -> np.ndarray:
        """Final CoG (3,) m."""
        return self.record.cog[-1] if len(self.record.t) else self.start

    @property
    def distance_to_goal(self) -> float:
        """Horizontal distance of the final CoG to the goal, m (NaN without a goal)."""
        return float(np.linalg.norm(self.final[:2] - self.goal[:2]))

    @property
    def travelled(self) -> float:
        """Horizontal distance from the start to the final CoG, m."""
        return float(np.linalg.norm(self.final[:2] - self.start[:2]))

    @property
    def rolls(self) -> int:
        return sum(1 for st in self.steps if st.rolled)

    @property
    def faces(self) -> list[int]:
        """The contact faces visited, in order (start, then after each roll)."""
        return [st.face for st in self.steps[:1]] + [st.face_after for st in self.steps if st.rolled]


def _drive(workspace: Workspace, params: Params, s: Settings, obs: _Obs, goal=None,
           edges=None, direction=None):
    """The run controller (paper III.C, repeated): toward `goal` (3,) m, or over each edge of
    `edges` in turn. Returns (outcome, message, steps)."""
    steps: list[Step] = []
    visited: list[int] = []
    outcome, message = "step_limit", f"step limit of {s.max_rolls} rolls reached"
    try:
        face, obs = yield from _settle_gen(s, obs)
        for k in range(s.max_rolls + 1):
            if face is None:
                outcome, message = "no_contact", (
                    f"the robot did not come to rest on a face within {s.settle_time} s (it is "
                    "tumbling, e.g. down a slope too steep, or its nodes on the terrain are not "
                    "one of the 20 faces)")
                break
            if edges is not None and k == len(edges):
                outcome, message = "arrived", (f"rolled over {len(edges)} edge(s) onto "
                                               f"{topo.face_label(face)}")
                break
            if edges is None and np.linalg.norm(obs.nodes.mean(axis=0)[:2] - goal[:2]) <= s.arrive_tolerance:
                outcome, message = "arrived", f"within {s.arrive_tolerance} m of the goal"
                break
            if k == s.max_rolls:
                break
            target = dict(goal=goal) if direction is None else dict(direction=direction)
            if edges is not None:
                e = tuple(sorted(int(n) for n in edges[k]))
                corners = [topo.edge_nodes(face, j) for j in range(3)]
                if e not in corners:
                    outcome, message = "stuck", (f"edge {e[0]}-{e[1]} is not an edge of face "
                                                 f"{topo.face_label(face)}")
                    break
                target = dict(direction=ct.edge_outward(obs.nodes[topo.FACES[face - 1]])[corners.index(e)])
            visited = (visited + [face])[-_TABU - 1:]
            pl = plan(workspace, face, obs.nodes, avoid=visited[:-1], combine=s.combine,
                      min_alignment=s.min_alignment, **target)
            tries = []
            for cand in pl.candidates[:s.max_attempts]:
                res, obs = yield from _roll_gen(params, s, obs, cand.pairs, workspace.max_pressure)
                tries.append(res)
                if res.face_after is None or res.rolled:
                    break
            after = tries[-1].face_after
            steps.append(Step(face, pl, tuple(tries), after))
            if after is not None and not tries[-1].rolled:
                outcome = "stuck"
                message = (f"no candidate rolled the robot off face {topo.face_label(face)}: tried "
                           + ", ".join(f"{'+'.join(f'#{q}' for q in r.pairs)} up to "
                                       f"{r.peak_pressure:.2f} MPa" for r in tries)
                           + ("" if pl.predicted else "; the workspace predicted no roll here "
                              "(e.g. a slope too steep for it)"))
                break
            face = after
    except d.SimulationError as e:
        outcome = "off_terrain" if "no terrain" in str(e) else "sim_error"
        message = str(e)
    return outcome, message, steps


def _start(params, terrain, state, face, batch, position, yaw_deg):
    if terrain.kind == "none":
        raise ValueError("rolling needs a terrain: the free mode has no ground")
    if state is None:
        state = d.stand_on(params, face, terrain, batch=batch, position=position, yaw_deg=yaw_deg)
    elif state.batch != batch:
        raise ValueError(f"the state holds {state.batch} robots for {batch} runs")
    state.check()
    P = d.nodes(state.x, state.q, params.strut_length)
    for b in range(batch):
        ct.clearance(P[b], terrain, 0.0)  # nothing under the robot -> ValueError
    return state, P.mean(axis=1)


def _check_goal(goal, terrain: Terrain, start: np.ndarray, size: float) -> np.ndarray:
    gl = np.asarray(goal, float).ravel()
    if gl.size not in (2, 3) or not np.all(np.isfinite(gl)):
        raise ValueError(f"goal must be a finite world point (x, y) m, got {goal!r}")
    h = float(terrain.height(gl[0], gl[1]))
    if np.isnan(h):
        raise ValueError(f"terrain has nothing under the goal ({gl[0]:.3f}, {gl[1]:.3f}) m")
    dist = float(np.linalg.norm(gl[:2] - start[:2]))
    if dist < size:
        raise ValueError(f"goal ({gl[0]:.3f}, {gl[1]:.3f}) m is {dist:.3f} m from the robot, "
                         f"closer than its size ({size} m, the strut length)")
    return np.array([gl[0], gl[1], h])


def roll_many(workspace: Workspace, goals, params: Params | None = None,
              terrain: Terrain | None = None, state: d.State | None = None, face=(9, 10, 12),
              settings: Settings | None = None, position=(0.0, 0.0), yaw_deg: float = 0.0,
              direction=None) -> list[Run]:
    """`roll_to` for several goals (G, 2) m at once, one robot each, simulated as one batch
    (same parameters and terrain); each run equals its single run."""
    params = params or Params()
    terrain = terrain or Terrain.flat()
    s = settings or Settings()
    goals = np.asarray(goals, float)
    if goals.ndim != 2 or goals.shape[1] not in (2, 3) or not len(goals):
        raise ValueError(f"goals must have shape (G, 2) m, got {goals.shape}")
    state, start = _start(params, terrain, state, face, len(goals), position, yaw_deg)
    S = float(np.max(params.strut_length))
    checked = [_check_goal(gl, terrain, start[b], S) for b, gl in enumerate(goals)]
    t0 = _time.perf_counter()
    out = _lockstep(params, terrain, state, lambda b, o: _drive(
        workspace, params, s, o, goal=checked[b], direction=direction), s)
    wall = _time.perf_counter() - t0
    return [Run(res[0], res[1], checked[b], start[b], tuple(res[2]), rec, wall, st)
            for b, (res, st, rec) in enumerate(out)]


def roll_to(workspace: Workspace, goal, params: Params | None = None,
            terrain: Terrain | None = None, state: d.State | None = None, face=(9, 10, 12),
            settings: Settings | None = None, position=(0.0, 0.0), yaw_deg: float = 0.0,
            direction=None) -> Run:
    """Roll toward the world point `goal` (x, y) m: settle, then plan, roll, repeat (paper
    III.C) until the CoG is within arrive_tolerance of the goal ("arrived"), after max_rolls
    rolls ("step_limit"), when no candidate rolls the robot ("stuck"), it rests on no face
    ("no_contact"), leaves the terrain ("off_terrain") or the simulation fails ("sim_error").
    Starts from `state` (one robot), or stands the robot on `face` at `position` turned by
    yaw_deg. `direction` (a world vector) replaces the goal's direction for planning.

    Raises ValueError for bad input: a goal closer than the robot's size (the strut length),
    a non-finite goal or state, a terrain with nothing under the robot or the goal."""
    gl = np.asarray(goal, dtype=float).ravel()
    if gl.size not in (2, 3):
        raise ValueError(f"goal must be a finite world point (x, y) m, got {goal!r}")
    return roll_many(workspace, gl[None, :2], params, terrain, state, face, settings, position,
                     yaw_deg, direction)[0]


def roll_over(workspace: Workspace, edges, params: Params | None = None,
              terrain: Terrain | None = None, state: d.State | None = None, face=(9, 10, 12),
              settings: Settings | None = None, position=(0.0, 0.0), yaw_deg: float = 0.0) -> Run:
    """Roll over each edge of `edges` (pairs of 1-based node numbers) in turn, planning each
    roll toward that edge's outward direction, e.g. the paper's experiment (IV.B):
    roll_over(ws, [(10, 12), (10, 11)]) from (9,10,12) by #10 onto (10,11,12), then by #11
    onto (6,10,11). Outcome "arrived" once every edge is crossed (the plan may choose any
    pair), "stuck" if an edge is not on the current face or nothing rolls the robot."""
    params = params or Params()
    terrain = terrain or Terrain.flat()
    s = settings or Settings()
    edges = [tuple(int(n) for n in e) for e in edges]
    if not edges or any(len(e) != 2 for e in edges):
        raise ValueError(f"edges must be pairs of node numbers, got {edges!r}")
    state, start = _start(params, terrain, state, face, 1, position, yaw_deg)
    t0 = _time.perf_counter()
    (res, st, rec), = _lockstep(params, terrain, state, lambda b, o: _drive(
        workspace, params, s, o, edges=edges), s)
    return Run(res[0], res[1], np.full(3, np.nan), start[0], tuple(res[2]), rec,
               _time.perf_counter() - t0, st)
