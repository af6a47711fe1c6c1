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
- `run_dataset`, `run_demo`, `main`: results/locomotion/*.nc, the workflow stage, and the
  command line (`python -m tensegrity.locomotion plan|roll`, or `add_cli` for another parser).

Numbers people see (faces, pairs, nodes) start at 1. Pressures in MPa, lengths in m, times in s.
"""
from __future__ import annotations

import itertools
import math
import sys
import time as _time
from dataclasses import dataclass, field, fields, replace

import numpy as np

from . import contact as ct
from . import dynamics as d
from . import geometry as g
from .actuation import MAX_PRESSURE, Schedule
from .params import Params
from .terrain import Terrain

__all__ = ["Workspace", "Prediction", "Candidate", "Plan", "Settings", "RollResult", "Record",
           "Step", "Run", "predict", "plan", "settle", "roll", "roll_to", "roll_many", "roll_over",
           "run_dataset", "terrain_from_dataset", "run_demo", "describe", "add_cli", "OUTCOMES",
           "DEMOS"]

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
        ref = g.reference_nodes(strut_length)
        rest = [g.in_support_frame(ref, f) for f in range(1, 21)]
        return cls(np.asarray(levels, float), np.asarray(cog, float), np.asarray(support, float),
                   np.stack([r[0] for r in rest]), np.stack([r[1] for r in rest]))

    @classmethod
    def from_dataset(cls, ds) -> "Workspace":
        """From an xarray Dataset with the contract of results/workspace.nc."""
        try:
            from .datasets import provenance_config
            strut = float(provenance_config(ds).get("params", {}).get("strut_length", 0.5))
        except ValueError:
            strut = 0.5
        order = {"face": np.arange(1, 21), "pair": np.arange(1, 13), "axis": ["x", "y", "z"]}
        sel = {k: v for k, v in order.items() if k in ds.dims}
        cog = ds["cog"].sel(sel).transpose("face", "pair", "pressure", "axis").values
        sup = ds["support"].sel(sel).transpose("face", "pair", "pressure", "corner", "axis").values
        return cls.from_arrays(ds["pressure"].values, cog, sup, strut)

    @classmethod
    def load(cls, path) -> "Workspace":
        """Read results/workspace.nc (or a file of the same contract)."""
        from .datasets import read
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


def _frame(face: int, nodes: np.ndarray):
    tri = nodes[g.FACES[face - 1]]
    return g.support_frame(tri, int(g.FACE_REFERENCE[face - 1]), nodes.mean(axis=0))


def predict(workspace: Workspace, face, nodes, actions) -> Prediction:
    """Where the workspace puts the CoG projection for `actions` (tuples of 1-based pairs) on
    `face` (1..20 or three node numbers), in the frame of the current triangle of `nodes`
    (12, 3) m, projected along gravity (paper Fig. 10)."""
    f = g.face_number(face)
    p = ct.check_nodes(nodes)
    origin, rot = _frame(f, p)
    gl = rot @ ct.GRAVITY_DIR  # gravity in the support frame
    if gl[2] > -1e-6:
        raise ValueError(f"face {g.face_label(f)} is not below the robot: gravity does not "
                         "press it onto its support")
    cog, sup = workspace.curve(f, actions)
    proj = cog - (cog[..., 2:3] / gl[2]) * gl
    margin = g.margin_2d(proj[..., :2], sup[..., :2])
    dist = g.edge_distances(proj[..., :2], sup[..., :2])
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


def _tip(pressure: np.ndarray, margin: np.ndarray) -> tuple[float, int]:
    """Least pressure where margin (n,) turns negative, interpolated, and the index of the first
    level outside; (NaN, -1) if it never does."""
    out = np.flatnonzero(margin < 0)
    if out.size == 0:
        return float("nan"), -1
    k = int(out[0])
    if k == 0:
        return 0.0, 0
    m0, m1 = margin[k - 1], margin[k]
    return float(pressure[k - 1] + (pressure[k] - pressure[k - 1]) * m0 / (m0 - m1)), k


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
    out_world = ct.edge_outward(nodes[g.FACES[f - 1]])
    horiz = out_world[:, :2] / np.maximum(np.linalg.norm(out_world[:, :2], axis=1, keepdims=True), 1e-12)
    align = horiz @ u[:2]
    res = []
    for a, act in enumerate(actions):
        p, k = _tip(pred.pressure, pred.margin[a])
        e = int(np.argmin(pred.edge_dist[a, k if k >= 0 else -1]))
        edge = ct.edge_nodes(f, e)
        res.append(Candidate(tuple(int(x) for x in act), edge, ct.neighbour(f, edge), p,
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
    f = g.face_number(face)
    p = ct.check_nodes(nodes)
    if terrain is not None:
        ct.clearance(p, terrain, 0.0)  # raises if nothing is under a node
    singles = [(int(q),) for q in workspace.pairs(f)]
    if not singles:
        raise ValueError(f"the workspace has no curve for face {g.face_label(f)}")
    u = _direction(p, direction, goal)
    avoid = {g.face_number(a) for a in avoid}
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
    reasons = [f"standing on face {g.face_label(f)} ({g.FACE_TYPES[f - 1]}); the CoG projection "
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
            f"next face {g.face_label(best.next_face)}")
        if best.next_face in avoid:
            reasons.append(f"face {g.face_label(best.next_face)} was visited recently: rolling "
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
    zero, calm, waited = np.zeros(g.N_PAIRS), 0, 0.0
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
    support = g.FACES[face0 - 1]
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
            up = obs.gap[g.FACES[landed - 1]] > s.lift_tolerance
            if up[apex] and up.sum() == 1 and t_phase < 2 * s.catch_time:
                pass
            else:
                level = max(0.0, level - peak * s.interval / (s.release_time if up.any() else s.catch_time))
        pres = np.zeros(g.N_PAIRS)
        pres[idx] = level
        peak = max(peak, level)
        obs = yield pres
        t_phase += s.interval
        if phase in ("release", "land"):
            if landed is None and obs.face is not None and obs.face != face0:
                back = ct.common_edge(face0, obs.face)
                if back is not None:
                    landed, phase, t_phase = obs.face, "land", 0.0
                    apex = int(np.flatnonzero(~np.isin(g.FACES[landed - 1] + 1, back))[0])
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
    pres = np.zeros((B, g.N_PAIRS))
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
    pairs = tuple(g.check_pair(q) for q in np.atleast_1d(pairs))
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
                                               f"{g.face_label(face)}")
                break
            if edges is None and np.linalg.norm(obs.nodes.mean(axis=0)[:2] - goal[:2]) <= s.arrive_tolerance:
                outcome, message = "arrived", f"within {s.arrive_tolerance} m of the goal"
                break
            if k == s.max_rolls:
                break
            target = dict(goal=goal) if direction is None else dict(direction=direction)
            if edges is not None:
                e = tuple(sorted(int(n) for n in edges[k]))
                corners = [ct.edge_nodes(face, j) for j in range(3)]
                if e not in corners:
                    outcome, message = "stuck", (f"edge {e[0]}-{e[1]} is not an edge of face "
                                                 f"{g.face_label(face)}")
                    break
                target = dict(direction=ct.edge_outward(obs.nodes[g.FACES[face - 1]])[corners.index(e)])
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
                message = (f"no candidate rolled the robot off face {g.face_label(face)}: tried "
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


# --------------------------------------------------------------------- datasets and stages

DEMOS = ("paper", "flat", "slope_up", "slope_down", "terrain")


def _var(dims, data, units, long_name):
    return (dims, data, {"units": units, "long_name": long_name})


def run_dataset(run: Run, terrain: Terrain, name: str = "") -> "xr.Dataset":
    """A run as an xarray Dataset (design.md section 5, results/locomotion/*.nc): samples
    (time), steps (step, with the chosen pair(s) and pressures), the faces visited (visit) and
    the terrain, with units and long names. Nothing time-dependent (no wall time) is stored."""
    import xarray as xr
    rec, steps = run.record, run.steps
    n = len(steps)
    used = [st.used for st in steps]
    pairs = np.zeros((n, 2), np.int64)
    for i, r in enumerate(used):
        pairs[i, :len(r.pairs)] = r.pairs
    edge = np.array([st.plan.edge for st in steps], np.int64).reshape(n, 2)
    ds = xr.Dataset(
        {"nodes": _var(("time", "node", "axis"), rec.nodes, "m", "node positions, world frame"),
         "cog": _var(("time", "axis"), rec.cog, "m", "centre of gravity, world frame"),
         "pressure": _var(("time", "pair"), rec.pressure, "MPa", "pressure applied to each actuator pair"),
         "contact_face": _var(("time",), rec.face, "1", "face resting on the terrain (0: none)"),
         "face": _var(("step",), np.array([st.face for st in steps], np.int64), "1", "face the step started on"),
         "next_face": _var(("step",), np.array([st.face_after or 0 for st in steps], np.int64), "1",
                           "face the robot settled on after the step (0: none)"),
         "predicted_face": _var(("step",), np.array([st.plan.next_face for st in steps], np.int64), "1",
                                "face the plan predicted (across the planned edge)"),
         "step_pair": _var(("step", "slot"), pairs, "1", "actuator pair(s) driven in the step's rolling attempt (0: none)"),
         "planned_pressure": _var(("step",), np.array([st.plan.pressure for st in steps]), "MPa",
                                  "least rolling pressure predicted by the workspace (NaN: no roll predicted)"),
         "tip_pressure": _var(("step",), np.array([r.tip_pressure for r in used]), "MPa",
                              "pressure held when the robot tipped in the simulation (NaN: it did not roll)"),
         "peak_pressure": _var(("step",), np.array([r.peak_pressure for r in used]), "MPa",
                               "highest pressure applied in the step's last attempt"),
         "edge": _var(("step", "end"), edge, "1", "nodes of the planned edge"),
         "alignment": _var(("step",), np.array([st.plan.alignment for st in steps]), "1",
                           "cosine between the planned edge's outward direction and the target direction"),
         "reach": _var(("step",), np.array([st.plan.reach for st in steps]), "m",
                       "predicted margin at the workspace's highest level (negative: outside)"),
         "attempts": _var(("step",), np.array([len(st.attempts) for st in steps], np.int64), "1",
                          "candidates tried in the step"),
         "t_start": _var(("step",), np.array([st.attempts[0].t_start for st in steps]), "s", "start of the step"),
         "t_end": _var(("step",), np.array([r.t_end for r in used]), "s", "end of the step (settled)"),
         "position": _var(("step", "axis"), np.array([r.cog_after for r in used]).reshape(n, 3), "m",
                          "centre of gravity after the step, world frame"),
         "faces": _var(("visit",), np.array(run.faces, np.int64), "1", "contact faces visited, in order"),
         "goal": _var(("axis",), run.goal, "m", "goal, world frame (NaN: a run over given edges)"),
         "start": _var(("axis",), run.start, "m", "centre of gravity at the start, world frame"),
         "terrain_heights": _var(("tx", "ty"), terrain.heights, "m",
                                 "height field of the terrain (kind heightfield)")},
        coords={"time": ("time", rec.t, {"units": "s", "long_name": "time"}),
                "node": ("node", np.arange(1, 13), {"units": "1", "long_name": "node number"}),
                "pair": ("pair", np.arange(1, 13), {"units": "1", "long_name": "actuator pair number"}),
                "axis": ("axis", ["x", "y", "z"], {"units": "1", "long_name": "world axis"}),
                "step": ("step", np.arange(1, n + 1), {"units": "1", "long_name": "step number"}),
                "slot": ("slot", [1, 2], {"units": "1", "long_name": "pair slot (two pairs when combined)"}),
                "end": ("end", [1, 2], {"units": "1", "long_name": "edge end"}),
                "visit": ("visit", np.arange(1, len(run.faces) + 1), {"units": "1", "long_name": "visit number"})},
        attrs={"run": name, "outcome": run.outcome, "message": run.message, "rolls": run.rolls,
               "terrain_kind": terrain.kind, "terrain_normal": terrain.normal,
               "terrain_offset": float(terrain.offset), "terrain_origin": np.asarray(terrain.origin, float),
               "terrain_spacing": float(terrain.spacing)})
    return ds


def terrain_from_dataset(ds) -> Terrain:
    """The terrain a run dataset was simulated on."""
    return Terrain(kind=str(ds.attrs["terrain_kind"]), normal=np.asarray(ds.attrs["terrain_normal"], float),
                   offset=float(ds.attrs["terrain_offset"]), origin=tuple(np.asarray(ds.attrs["terrain_origin"], float)),
                   spacing=float(ds.attrs["terrain_spacing"]), heights=ds["terrain_heights"].values)


def demo_setup(cfg: dict, name: str) -> dict:
    """Terrain, goal or edges, and start of the demonstration run `name` (one of DEMOS) from
    the resolved configuration's `locomotion` section."""
    if name not in DEMOS:
        raise ValueError(f"unknown locomotion run {name!r}: use one of {DEMOS}")
    c = cfg["locomotion"]
    dist, head = float(c["goal_distance"]), math.radians(float(c["goal_heading"]))
    toward = dist * np.array([math.cos(head), math.sin(head)])
    if name == "paper":
        return {"terrain": Terrain.flat(), "edges": [(10, 12), (10, 11)]}
    if name == "flat":
        return {"terrain": Terrain.flat(), "goal": toward}
    if name in ("slope_up", "slope_down"):  # the slope rises toward +x
        sign = 1.0 if name == "slope_up" else -1.0
        return {"terrain": Terrain.slope(float(c["slope_angle"])), "goal": np.array([sign * dist, 0.0])}
    return {"terrain": Terrain.random(int(c["terrain_seed"]), size=2 * dist + 4.0,
                                      spacing=float(c["terrain_spacing"]),
                                      amplitude=float(c["terrain_amplitude"])), "goal": toward}


def locomotion_params(cfg: dict) -> Params:
    """Parameters of the rolling simulations: config `params` with locomotion.strut_damping."""
    from .config import params_from_config
    return params_from_config(cfg).replace(strut_damping=float(cfg["locomotion"]["strut_damping"]))


def run_demo(cfg: dict, name: str, workspace_path, out_path):
    """Stage: the demonstration run `name` (one of DEMOS) from the workspace file; writes the
    run dataset to `out_path` and returns the path. Prints the steps and the outcome."""
    from . import datasets
    ws = Workspace.load(workspace_path)
    setup = demo_setup(cfg, name)
    params = locomotion_params(cfg)
    s = Settings.from_config(cfg["locomotion"], cfg["sim"]["dt"])
    if "edges" in setup:
        run = roll_over(ws, setup["edges"], params, setup["terrain"], settings=s)
    else:
        run = roll_to(ws, setup["goal"], params, setup["terrain"], settings=s)
    print(describe(run, name))
    cfg_prov = dict(datasets.provenance_config(workspace_path))
    cfg_prov.update(cfg)
    return datasets.write(run_dataset(run, setup["terrain"], name), out_path, cfg_prov,
                          f"Rolling locomotion run '{name}': {run.outcome}",
                          stage="locomotion", allow_nan=["planned_pressure", "tip_pressure", "goal"])


def describe(run: Run, name: str = "") -> str:
    """A few lines a person can read: the outcome and every step."""
    lines = [f"run {name}: {run.outcome} ({run.message}); {run.rolls} rolls, "
             f"{run.travelled:.2f} m travelled" + ("" if np.isnan(run.goal[0]) else
                                                   f", {run.distance_to_goal:.2f} m from the goal")]
    for k, st in enumerate(run.steps, 1):
        r = st.used
        lines.append(f"  step {k}: {g.face_label(st.face)} -> "
                     f"{g.face_label(st.face_after) if st.face_after else 'no face'}: planned "
                     f"{st.plan.pairs} at {st.plan.pressure:.2f} MPa over {st.plan.edge}; rolled by "
                     f"{r.pairs} at {r.tip_pressure:.2f} MPa (peak {r.peak_pressure:.2f}), "
                     f"{len(st.attempts)} attempt(s)")
    return "\n".join(lines)


# -------------------------------------------------------------------------- command line

def _floats(text: str, n: tuple[int, ...], what: str) -> np.ndarray:
    try:
        v = np.array([float(x) for x in str(text).replace(" ", "").split(",")])
    except ValueError:
        raise ValueError(f"{what} must be comma-separated numbers, got {text!r}") from None
    if not np.all(np.isfinite(v)):
        raise ValueError(f"{what} must be finite, got {text!r}")
    if v.size not in n:
        raise ValueError(f"{what} needs {' or '.join(map(str, n))} numbers, got {text!r}")
    return v


def _terrain_arg(text: str) -> Terrain:
    """flat | slope:ANGLE[:AZIMUTH] | random:SEED[:AMPLITUDE]"""
    kind, _, rest = text.partition(":")
    args = list(_floats(rest.replace(":", ","), (0, 1, 2), "terrain")) if rest else []
    if kind == "flat" and not args:
        return Terrain.flat()
    if kind == "slope" and 1 <= len(args) <= 2:
        return Terrain.slope(*args)
    if kind == "random" and 1 <= len(args) <= 2:
        return Terrain.random(int(args[0]), size=12.0, **({"amplitude": args[1]} if len(args) > 1 else {}))
    raise ValueError(f"terrain must be flat, slope:ANGLE[:AZIMUTH] or random:SEED[:AMPLITUDE], "
                     f"got {text!r}")


def add_cli(sub, parents=()) -> None:
    """Add the `plan` and `roll` subcommands to an argparse subparsers object. `parents`:
    parsers whose arguments they share; without one that defines --config, they get their own
    --config (and read --set overrides if a parent defines them)."""
    own_config = not any("--config" in p._option_string_actions for p in parents)
    for name, helptext in (("plan", "choose the pair and pressure that roll the robot toward a target"),
                           ("roll", "roll the robot toward a goal in the dynamic simulator")):
        p = sub.add_parser(name, help=helptext, description=helptext, parents=list(parents))
        p.add_argument("--workspace", default="results/workspace.nc", help="workspace file (results/workspace.nc)")
        if own_config:
            p.add_argument("--config", default=None, help="configuration file (default config/config.yaml)")
        p.add_argument("--face", default="9,10,12", help="contact face at the start: three node numbers or 1..20")
        p.add_argument("--terrain", default="flat", help="flat | slope:ANGLE[:AZIMUTH] | random:SEED[:AMPLITUDE]")
        p.add_argument("--yaw", type=float, default=0.0, help="turn of the robot about the terrain normal, deg")
        if name == "plan":
            tgt = p.add_mutually_exclusive_group(required=True)
            tgt.add_argument("--direction", help="target heading in deg from +x, or a vector x,y")
            tgt.add_argument("--goal", help="goal point x,y in m")
        else:
            p.add_argument("--goal", required=True, help="goal point x,y in m")
            p.add_argument("--out", help="write the run to this netCDF file")
        p.set_defaults(func=_cli_plan if name == "plan" else _cli_roll)


def _cli_common(a):
    from . import config
    cfg = config.load(a.config, overrides=getattr(a, "set", None) or None)
    face = _floats(a.face, (1, 3), "--face").astype(int)
    face = g.face_number(int(face[0]) if face.size == 1 else tuple(face))
    terrain = _terrain_arg(a.terrain)
    params = locomotion_params(cfg)
    return cfg, face, terrain, params, Workspace.load(a.workspace)


def _cli_plan(a) -> int:
    cfg, face, terrain, params, ws = _cli_common(a)
    s = Settings.from_config(cfg["locomotion"], cfg["sim"]["dt"])
    state, _ = settle(params, d.stand_on(params, face, terrain, yaw_deg=a.yaw), terrain, s)
    nodes = d.nodes(state.x, state.q, params.strut_length)[0]
    here = ct.face_from_gaps(ct.clearance(nodes, terrain, float(params.strut_radius)), s.contact_tolerance)
    if a.goal is not None:
        pl = plan(ws, here, nodes, goal=_floats(a.goal, (2,), "--goal"), terrain=terrain,
                  combine=s.combine, min_alignment=s.min_alignment)
    else:
        v = _floats(a.direction, (1, 2), "--direction")
        v = np.array([math.cos(math.radians(v[0])), math.sin(math.radians(v[0]))]) if v.size == 1 else v
        pl = plan(ws, here, nodes, direction=v, terrain=terrain, combine=s.combine,
                  min_alignment=s.min_alignment)
    print(pl)
    return 0


def _cli_roll(a) -> int:
    from . import datasets
    cfg, face, terrain, params, ws = _cli_common(a)
    s = Settings.from_config(cfg["locomotion"], cfg["sim"]["dt"])
    run = roll_to(ws, _floats(a.goal, (2,), "--goal"), params, terrain, face=face, settings=s,
                  yaw_deg=a.yaw)
    print(describe(run))
    if a.out:
        datasets.write(run_dataset(run, terrain, "cli"), a.out, cfg, f"Rolling locomotion run: {run.outcome}",
                       stage="locomotion", allow_nan=["planned_pressure", "tip_pressure", "goal"])
    return 0 if run.outcome == "arrived" else 1


def main(argv=None) -> int:
    """python -m tensegrity.locomotion plan|roll ..."""
    import argparse
    ap = argparse.ArgumentParser(prog="python -m tensegrity.locomotion", description=__doc__.split("\n")[0])
    add_cli(ap.add_subparsers(dest="command", required=True))
    a = ap.parse_args(argv)
    try:
        return a.func(a)
    except (ValueError, FileNotFoundError) as e:
        print(f"error: {e}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
