"""Gravity-aware workspace (issue 10, item 2): the single-pair workspace measured with gravity,
the ground and friction, on flat ground and on slopes, with the pressure raised slowly (a ramp
at a few MPa/s, quasi-static, not the staircase) until the robot rolls.

Every robot of a contact case (pairs x slopes x headings) runs in one batch on the slope ground
of `workspace.slopes` (one planar strip per slope; the robot turned to set the heading, the
uphill direction in the contact face's support frame). The CoG is projected along gravity onto
the plane of the deformed contact face (paper Fig. 10); the robot tips where that projection
leaves the triangle (`frames.first_crossing` of the margin).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from ..physics import contact as ct
from ..physics import dynamics as d
from ..physics import frames
from ..physics import topology as topo
from ..physics.params import Params
from ..physics.schedule import MAX_PRESSURE, Schedule, hold_step, whole_steps
from ..physics.terrain import Terrain
from ..physics.twisted import MAX_VOLTAGE, TwistedString, Voltages
from .slopes import gravity_frame, place, slope_field

FALLING = 0.01  # m: a CoG projection this far past an edge means the robot is rolling over it
HOLD = 1.0  # s the top of the ramp is held
MAX_HOLD = 5.0  # s, longest total time a ramp is held where a support node lifts


@dataclass(frozen=True)
class GravitySweep:
    """One contact case. face 1..20; pairs (N,); slopes (S,) deg; headings (H,) deg; pressure
    (P,) MPa, the grid along the ramp. stood (S, H): the unactuated robot stays on the face;
    rolled (S, H, N); tip_pressure (S, H, N) MPa (NaN: no roll); tip_edge (S, H, N, 2) the
    crossed edge's nodes (0: none); cog (S, H, N, P, 3) m and support (S, H, N, P, 3, 3) m in
    the deformed face's support frame, projection (S, H, N, P, 2) m the CoG moved along gravity
    onto the face plane, margin (S, H, N, P) m (positive inside); NaN once the robot rolled."""

    face: int
    pairs: np.ndarray
    slopes: np.ndarray
    headings: np.ndarray
    pressure: np.ndarray
    stood: np.ndarray
    rolled: np.ndarray
    tip_pressure: np.ndarray
    tip_edge: np.ndarray
    cog: np.ndarray
    support: np.ndarray
    projection: np.ndarray
    margin: np.ndarray


@dataclass(frozen=True)
class GravitySetup:
    """The ramp of the gravity-aware workspace, as the controller ramps a roll: `settle` s at
    rest, then ramp_rate MPa/s in steps held `interval` s up to max_pressure MPa, held for
    hold_time s once a support node lifts by lift_tolerance m; the struts damped by
    strut_damping 1/s (the rolling simulations' robot); grid_step MPa, the pressure grid of the
    results; dt s, the time step (V/s and V with the twisted-string actuator). Config `locomotion`
    (ramp, hold, damping), `gravity` and `sim`; the defaults are the schema's (pinned by
    tests/io/test_settings.py)."""

    ramp_rate: float = 1.0
    interval: float = 0.02
    lift_tolerance: float = 0.001
    hold_time: float = HOLD
    strut_damping: float = 1.0
    max_pressure: float = 5.0
    settle: float = 0.5
    grid_step: float = 0.2
    dt: float = 1e-4

    def __post_init__(self):
        for name in ("ramp_rate", "max_pressure", "grid_step", "interval", "lift_tolerance", "dt"):
            if not (np.isfinite(getattr(self, name)) and getattr(self, name) > 0):
                raise ValueError(f"gravity setting {name} must be a positive number, got {getattr(self, name)!r}")
        for name in ("settle", "strut_damping", "hold_time"):  # 0: none
            if not (np.isfinite(getattr(self, name)) and getattr(self, name) >= 0):
                raise ValueError(f"gravity setting {name} must be >= 0, got {getattr(self, name)!r}")
        step = self.ramp_rate * self.interval
        if not whole_steps(self.grid_step, step):
            raise ValueError(
                f"gravity.grid_step {self.grid_step} is not a whole number of ramp "
                f"increments ({step:g} = ramp_rate x interval; MPa, or V with the twisted-string actuator)"
            )
        if not whole_steps(self.interval, self.dt):
            raise ValueError(f"gravity interval {self.interval} s is not a whole number of time steps of {self.dt} s")

    def rolling(self, params: Params) -> Params:
        """`params` with the struts damped as in the rolling simulations (strut_damping 1/s)."""
        return params.replace(strut_damping=float(self.strut_damping))

    def levels(self, hold: float = HOLD) -> tuple[np.ndarray, int]:
        """`ramp_levels` of this ramp."""
        return ramp_levels(self.ramp_rate, self.max_pressure, self.settle, self.interval, hold)


def run(
    params: Params,
    face: int | Sequence[int],
    pairs: ArrayLike,
    slopes: ArrayLike,
    headings: ArrayLike,
    setup: GravitySetup,
    flat_once: bool = True,
    motors: TwistedString | None = None,
) -> GravitySweep:
    """The gravity-aware workspace of `face`: each pair of `pairs` on each slope (deg) and
    heading (deg), `settle` s at rest, then the pressure ramped from 0 at ramp_rate MPa/s in
    steps held `interval` s, up to max_pressure MPa (held HOLD s) or until the robot rolls (its
    CoG projection FALLING m past an edge, or another face resting on the ground), holding it
    as the controller does once a support node lifts (`ramp`); all of `setup`. All robots in one
    batch; with `flat_once` a zero slope runs one heading and copies it to the others (on flat
    ground the heading is a turn of the whole scene). With `motors` (docs/design.md §10): volts."""
    face = topo.face_number(face)
    pairs = np.array([topo.check_pair(p) for p in np.atleast_1d(pairs)])
    slopes, headings = np.atleast_1d(np.asarray(slopes, float)), np.atleast_1d(np.asarray(headings, float))
    params = setup.rolling(params)
    terrain, centres = slope_field(slopes)
    cases = [
        (i, j) for i in range(slopes.size) for j in range(headings.size) if not (flat_once and slopes[i] == 0 and j > 0)
    ]
    N = pairs.size
    state = d.State.concat([place(params, face, terrain, centres[i], headings[j], N) for i, j in cases])
    level, n_settle = setup.levels()
    rec, gone = ramp(params, terrain, face, state, np.tile(pairs, len(cases)), level, n_settle, setup, N, motors)
    return _collect(face, pairs, slopes, headings, cases, setup.max_pressure, n_settle, setup.grid_step, rec, gone)


def ramp_levels(
    ramp_rate: float, max_pressure: float, settle: float, interval: float, hold: float = HOLD
) -> tuple[np.ndarray, int]:
    """Pressure (T,) MPa held over each interval: `settle` s at zero, then the ramp at
    ramp_rate MPa/s up to max_pressure, held `hold` s (a robot just past an edge there
    falls slowly); and the number of settling intervals."""
    n_settle = int(np.ceil(settle / interval - 1e-9))
    n_ramp = int(np.ceil(max_pressure / (ramp_rate * interval) - 1e-9))
    ramp_ = np.minimum(ramp_rate * interval * np.arange(1, n_ramp + 1), max_pressure)
    top = np.full(int(np.ceil(hold / interval - 1e-9)), max_pressure)
    return np.concatenate([np.zeros(n_settle), ramp_, top]), n_settle


def ramp(
    params: Params,
    terrain: Terrain,
    face: int,
    state: d.State,
    pair_of: np.ndarray,
    level: np.ndarray,
    n_settle: int,
    setup: GravitySetup,
    copies: int = 1,
    motors: TwistedString | None = None,
) -> tuple[dict, np.ndarray]:
    """Drive robot b of `state` (resting on `face`) with pair pair_of[b] (or, pair_of (R, 12) or
    (R, 24), the pressures level pair_of[b] per pair, `locomotion.control.action_weights`, or per
    cable, `cable_actions`) through the pressures `level` (L,) MPa, one per setup.interval s
    (the first n_settle at zero), time step setup.dt s, `params` as given (`GravitySetup.rolling`
    is the caller's). By the controller's rule
    (`schedule.hold_step`, as in `locomotion.control.roll`), when a support node has lifted by
    lift_tolerance m (from its clearance at the end of the settling) the pressure is held for
    hold_time s before the ramp goes on: near the tipping point the robot creeps over the edge
    at a constant pressure, which a steady ramp would overshoot. As in a braked roll, a node
    still up holds it again; at most MAX_HOLD s of holds per robot. A robot is
    dropped once it rolls (see `run`) or, at the end of the settling, does not stand. Returns
    records (pressure (R, T) MPa, cog (R, T, 3), support (R, T, 3, 3), proj (R, T, 2), margin
    (R, T); `gravity_frame`, NaN once dropped) and the sample each robot was dropped at (R,)
    (T: never, also when it reached the end of `level` or of its holds).
    `copies`: the robots come in runs of `copies` equal ones (the same state; `run` drives each
    of a case's pairs from one placement): the settling, at zero pressure, is simulated for the
    first robot of each run only and then copied to the others, with its records. The same
    numbers as simulating every copy (a robot's results do not depend on its batch); the
    gravity-aware workspace settles a twelfth of its robots. With `motors`: volts (`Voltages`)."""
    interval, dt, lift_tolerance = setup.interval, setup.dt, setup.lift_tolerance
    (Schedule if motors is None else Voltages).check(level, "gravity.max_pressure")  # MPa or V: before any work
    R, L = state.batch, level.size
    copies = int(copies) if n_settle > 0 else 1
    if copies > 1 and (R % copies or np.any(level[:n_settle] != 0)):
        raise ValueError(f"copies = {copies} needs runs of that many robots ({R}) settling at zero pressure")
    T = L + int(np.ceil(MAX_HOLD / interval - 1e-9))
    every = int(round(interval / dt))
    shapes = {"pressure": (), "cog": (3,), "support": (3, 3), "proj": (2,), "margin": ()}
    rec = {name: np.full((R, T, *shape), np.nan) for name, shape in shapes.items()}
    gone = np.full(R, T)
    active = np.arange(R)
    k = np.zeros(R, np.int64)  # level index of each robot
    holding, held, total = np.zeros(R, bool), np.zeros(R), np.zeros(R)  # in a hold; its time, all holds', s
    base = np.zeros((R, 3))  # clearance of the support nodes at the end of the settling, m
    support = topo.FACES[face - 1]
    r = float(np.max(params.strut_radius))
    if copies > 1:  # the first of each run until the end of the settling
        active = np.arange(0, R, copies)
        state = state.take(active)
    for t in range(T):
        ka = k[active]
        if pair_of.ndim == 2:  # weight vectors (R, 12 or 24), largest entry 1: pressures level w
            pres = np.minimum(level[ka, None] * pair_of[active], MAX_PRESSURE if motors is None else MAX_VOLTAGE)
        else:
            pres = np.zeros((active.size, topo.N_PAIRS))
            pres[np.arange(active.size), pair_of[active] - 1] = level[ka]
        sched = (Schedule if motors is None else Voltages)(np.array([interval]), pres[:, None])
        state, tr = d.simulate(params, state, sched, terrain, dt, every, motors=motors)
        nodes = tr.nodes(params.strut_length)[:, -1]
        cog, sup, proj, margin = gravity_frame(nodes, face)
        for name, v in (("pressure", level[ka]), ("cog", cog), ("support", sup), ("proj", proj), ("margin", margin)):
            rec[name][active, t] = v
        gap = ct.clearance(nodes, terrain, r)
        resting = ct.resting_face(gap, r)
        off = (margin < -FALLING) | ((resting != face) & (resting != 0))
        if t + 1 == n_settle:  # end of the settling: who stands?
            off |= (resting != face) | (margin <= 0)
            base[active] = gap[:, support]
        lifted = (ka >= n_settle) & np.any(gap[:, support] - base[active] > lift_tolerance, axis=1)
        holding[active], held[active], _, total[active] = hold_step(
            holding[active],
            held[active],
            True,
            lifted,
            interval,
            setup.hold_time,
            rearm=True,
            spent=total[active],
            budget=MAX_HOLD,
        )
        k[active[~holding[active]]] += 1
        off |= k[active] >= L  # through the whole ramp without rolling
        if off.any():
            gone[active[off]] = np.where(k[active[off]] >= L, T, t + 1)
            active, state = active[~off], state.take(~off)
        if copies > 1 and (t + 1 == n_settle or not active.size):  # the settling done: copy the runs
            first = np.arange(0, R, copies)
            for name in rec:
                rec[name][:, : t + 1] = np.repeat(rec[name][first, : t + 1], copies, axis=0)
            gone[:], base[:], k[:] = (np.repeat(a[first], copies, axis=0) for a in (gone, base, k))
            state = state.take(np.repeat(np.arange(active.size), copies))
            active = (active[:, None] + np.arange(copies)).ravel()
            copies = 1
        if not active.size:
            break
    return rec, gone


def tip(rec: dict, row: int, face: int, n_settle: int, gone: int) -> tuple[float, int, tuple[int, int] | None]:
    """`frames.crossing` of robot `row` of the records `rec` (`ramp`) on `face` between the end
    of the settling (sample n_settle) and its drop (sample `gone`; none if never dropped): the
    tipping pressure MPa, the record's first sample outside and the edge, or (NaN, -1, None)."""
    w = slice(n_settle, gone) if n_settle < gone < rec["pressure"].shape[1] else slice(0, 0)
    path = (rec[name][row, w] for name in ("pressure", "margin", "proj", "support"))
    p, k, edge = frames.crossing(*path, face)
    return p, (w.start + k if k >= 0 else -1), edge


def _collect(face, pairs, slopes, headings, cases, max_pressure, n_settle, grid_step, rec, gone) -> GravitySweep:
    """Per-robot records (R, T, ...) -> the arrays of a GravitySweep."""
    S, H, N = slopes.size, headings.size, pairs.size
    grid = grid_step * np.arange(1, int(round(max_pressure / grid_step)) + 1)
    P, T = grid.size, rec["pressure"].shape[1]
    out = {
        "stood": np.zeros((S, H), bool),
        "rolled": np.zeros((S, H, N), bool),
        "tip_pressure": np.full((S, H, N), np.nan),
        "tip_edge": np.zeros((S, H, N, 2), np.int64),
        "cog": np.full((S, H, N, P, 3), np.nan),
        "support": np.full((S, H, N, P, 3, 3), np.nan),
        "projection": np.full((S, H, N, P, 2), np.nan),
        "margin": np.full((S, H, N, P), np.nan),
    }
    for c, (i, j) in enumerate(cases):
        js = range(H) if (slopes[i] == 0 and len([1 for a, _ in cases if a == i]) == 1) else [j]
        rows = np.arange(c * N, (c + 1) * N)
        stood = bool(np.all(gone[rows] > n_settle))
        out["stood"][i, list(js)] = stood
        if not stood:
            continue
        for n, row in enumerate(rows):
            pr = rec["pressure"][row]  # to its last record (gone = T after the whole ramp: NaN past it)
            end = min(gone[row], int(np.flatnonzero(np.isfinite(pr))[-1]) + 1)
            p_tip, _, edge = tip(rec, row, face, n_settle, gone[row])
            rolled = edge is not None
            # a grid value is the mean over the samples within half a step of it (the nominal
            # averaging of paper III.A along the ramp: the robot rocks on the ground by a few mm),
            # valid if the robot was not dropped before the end of the window
            window = (np.abs(pr[None, :] - grid[:, None]) <= grid_step / 2 + 1e-9) & (np.arange(T) >= n_settle)
            valid = (gone[row] >= T) | (pr[:end].max() > grid + grid_step / 2 + 1e-9)
            w = window[:, :end] / np.maximum(window[:, :end].sum(1, keepdims=True), 1)
            means = {k: np.einsum("pt,t...->p...", w, v[row, :end]) for k, v in rec.items() if k != "pressure"}
            for jj in js:
                out["rolled"][i, jj, n] = rolled
                if rolled:  # tip_edge (0, 0): none (docs/datasets.md)
                    out["tip_pressure"][i, jj, n], out["tip_edge"][i, jj, n] = p_tip, edge
                for name, key in (("cog", "cog"), ("support", "support"), ("projection", "proj"), ("margin", "margin")):
                    out[name][i, jj, n, valid] = means[key][valid]
    return GravitySweep(face, pairs, slopes, headings, grid, **out)
