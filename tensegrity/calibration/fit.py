"""Calibration from a measured trajectory (docs/design.md §9): least squares of simulated
against measured node positions (`scipy.optimize.least_squares`, trust region reflective, with
bounds), the Jacobian by forward differences as one batched simulation (one robot per unknown;
the base point the one trf has just evaluated), on a growing horizon (from the first change of
the command, an eighth of the samples after it, then a quarter, a half, all: a long trajectory
started 10-20 % off would match oscillations out of phase, a local minimum; each stage starts in
the next one's basin), then what the fit knows (`uncertainty`) and a prediction check (fit on
the first part, predict the rest from the same initial state). The check's part is one of the
stages: the fit of the first 1 - check of the samples, which never sees the rest, is its fit.

When to stop. A stage before the check's or the last one stops at a relative decrease of the cost
of FTOL_STAGE (it only has to start the next one in its basin); in the free mode with the
muscles (`smooth`) every stage stops as soon as the Gauss-Newton step from the accepted point
would move no unknown by more than STOP (5 %) of its standard error (`_Residuals.stop`; the
iterations past it moved the estimates by < 0.01 standard errors at most of the cost; docs/
design.md §9). Without noise the fit runs to the tolerances.

Whether the intervals hold: `misfit` (a model that does not fit the run: grounded, the intervals
of refits on time windows, `discrepancy`), `linearity` (the cost at each interval's ends; where
it fails, the interval of the profile, `profile`).

Forward differences of step STEP in the scaled unknowns (a relative step of 1e-6 for a parameter,
1e-8 m or rad for the initial state) are good to about 1e-5 of a column (truncation ~ STEP
against round-off ~ 1e-16 / STEP); the optimum does not depend on them, the intervals to that
relative error. A trial point whose simulation fails (blows up, invalid parameters) costs as if
every coordinate were FAILED m off, so the step is refused and the trust region shrinks.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import partial

import numpy as np
from scipy.optimize import least_squares
from threadpoolctl import threadpool_limits

from ..physics.dynamics import SimulationError
from ..physics.params import Params
from ..physics.twisted import TwistedString
from . import discrepancy, minima, stability
from . import model as mdl
from .measurement import Measurement
from .uncertainty import Uncertainty, normal_inverse

__all__ = ["Calibration", "calibrate", "solve", "STEP", "PARAM_RANGE"]

STEP = 1e-6  # forward-difference step in scaled unknowns
FAILED = 1.0  # m: the residual of a trial point whose simulation failed
PARAM_RANGE = 100.0  # a parameter is bounded to [start / 100, start * 100]
TILT_BOUND = 50.0  # scaled: 0.5 rad of a strut's or the frame's tilt
HORIZONS = 4  # stages of the fit: the first 1/8 of the samples, 1/4, 1/2, all
FTOL = 1e-12  # the last stage stops when a step lowers the cost by less than this, relatively
FTOL_STAGE = 1e-6  # an earlier stage, which only has to bring the next one into its basin
STOP = 0.05  # or when the Gauss-Newton step is below this many standard errors in every unknown


@dataclass(frozen=True)
class Calibration:
    """The result. names, start, estimate (n,) parameters in their units, with `unc`; x the
    optimum of every unknown (scaled), `problem` the problem; simulated and measured (T, 12, 3)
    m world nodes; rms_mm the RMS of the residual fitted (`model.RESIDUALS`); prediction:
    fit_until s (the fit's last sample), rms_fit_mm and rms_predict_mm of the check (NaN if not
    made) and its estimates (n,);
    nfev, njev, message of the optimiser; base the Params it started from; restarts: what found
    each lower point the fit restarted from (`minima`); costs (1 + starts,) |r|^2 m^2 of each
    start's fit, the configured start first (the lowest kept)."""

    names: tuple[str, ...]
    start: np.ndarray
    estimate: np.ndarray
    unc: Uncertainty
    x: np.ndarray
    problem: mdl.Problem
    simulated: np.ndarray
    measured: np.ndarray
    rms_mm: float
    nfev: int
    njev: int
    message: str
    base: Params
    prediction: dict = field(default_factory=dict)
    restarts: tuple[str, ...] = ()
    costs: np.ndarray = field(default_factory=lambda: np.zeros(0))

    @property
    def params(self) -> Params:
        """The calibrated Params: `base` with the estimates (gravity as configured)."""
        own = {k: float(v) for k, v in zip(self.names, self.estimate, strict=True) if not k.startswith(mdl.ACTUATOR)}
        return self.base.replace(**own)

    @property
    def motors(self) -> TwistedString | None:
        """The calibrated twisted strings of a run in volts (None for the muscles)."""
        if self.problem.motors is None:
            return None
        n = len(mdl.ACTUATOR)
        own = {k[n:]: float(v) for k, v in zip(self.names, self.estimate, strict=True) if k.startswith(mdl.ACTUATOR)}
        return self.problem.motors.replace(**own)


class _Residuals:
    """f(x) and its forward-difference Jacobian for least_squares, the base point cached."""

    def __init__(self, prob: mdl.Problem, lo: np.ndarray, hi: np.ndarray):
        self.prob, self.lo, self.hi, self.last = prob, lo, hi, (None, None)
        self.nsim, self.J = 0, None

    def __call__(self, x: np.ndarray) -> np.ndarray:
        if self.last[0] is not None and np.array_equal(self.last[0], x):
            return self.last[1]
        try:
            self.nsim += 1
            r = self.prob.residuals(x[None])[0]
        except (SimulationError, ValueError):
            r = np.full(int(self.prob.valid.sum()), FAILED)
        self.last = (x.copy(), r)
        return r

    def jac(self, x: np.ndarray) -> np.ndarray:
        step = np.where(x + STEP <= self.hi, STEP, -STEP)
        X = x[None] + np.diag(step)
        # one batched simulation: one robot per unknown, and the base unless trf has just
        # evaluated it (it always has: it asks for the Jacobian of the point it accepted)
        known = self.last[0] is not None and np.array_equal(self.last[0], x)
        R = self.prob.residuals(X if known else np.concatenate([x[None], X]))
        r0, R = (self.last[1], R) if known else (R[0], R[1:])
        self.nsim += 1
        self.last = (x.copy(), r0)
        self.J = ((R - r0) / step[:, None]).T
        return self.J

    def stop(self, intermediate_result: object) -> None:
        """least_squares' callback after each iteration: StopIteration once the Gauss-Newton
        step from the accepted point (J^T J)^-1 J^T r moves no unknown by more than STOP of its
        standard error s sqrt((J^T J)^-1_jj) (`uncertainty`): the rest would not change the
        estimates or their intervals. Without noise s ~ 0 and the tolerances stop the fit."""
        x, r = intermediate_result.x, intermediate_result.fun
        if self.last[0] is None or not np.array_equal(self.last[0], x):
            return
        N, p = self.J.shape
        Hi = normal_inverse(self.J)
        se = np.sqrt(np.maximum(np.diag(Hi), 0.0) * float(r @ r) / max(N - p, 1))
        if np.all(np.abs(Hi @ (self.J.T @ r)) <= STOP * se):
            raise StopIteration


def _bounds(prob: mdl.Problem) -> tuple[np.ndarray, np.ndarray]:
    n = prob.n_params
    lo, hi = np.full(len(prob.names), -np.inf), np.full(len(prob.names), np.inf)
    lo[:n], hi[:n] = 1 / PARAM_RANGE, stability.upper(prob, PARAM_RANGE)
    for j, name in enumerate(prob.names):
        if "tilt" in name:
            lo[j], hi[j] = -TILT_BOUND, TILT_BOUND
    return lo, hi


def smooth(prob: mdl.Problem) -> bool:
    """Whether the fit may stop at STOP standard errors: the free mode with the muscles, whose
    residual is smooth (measured). The ground's stick and slip and the strings' gear friction
    (stick and slip, (T5)) make the finite-difference Jacobian a poor guide to the optimum: a
    run in volts with 0.05 mm of noise stopped 0.75 standard errors from it. They run to FTOL."""
    return prob.mode == "free" and prob.motors is None


def solve(
    prob: mdl.Problem, x0: np.ndarray | None = None, max_nfev: int = 100, ftol: float = FTOL
) -> tuple[np.ndarray, np.ndarray, object]:
    """The least-squares optimum x, its Jacobian (N, p) in scaled unknowns and scipy's result;
    `ftol` the relative decrease of the cost below which it stops (`FTOL`, `FTOL_STAGE`)."""
    lo, hi = _bounds(prob)
    f = _Residuals(prob, lo, hi)
    x0 = np.clip(prob.x0 if x0 is None else x0, lo, hi)  # (a damper's start beyond `stability.limit`)
    f(x0)
    if np.all(f.last[1] == FAILED):
        f.prob.residuals(x0[None])  # raise the simulator's own error: the start itself fails
    # the optimiser's SVDs are small (N x p, p <= ~70): one BLAS thread, which never waits on a
    # busy second core (two spun for seconds per SVD on a loaded machine)
    with threadpool_limits(limits=1, user_api="blas"):
        res = least_squares(
            f,
            x0,
            jac=f.jac,
            bounds=(lo, hi),
            method="trf",
            x_scale=1.0,  # the unknowns are scaled already; "jac" blows up a column the data do not see
            xtol=1e-10,
            ftol=ftol,
            gtol=1e-10,
            max_nfev=max_nfev,
            callback=f.stop if smooth(prob) else None,
        )
    if res.status == -2:
        res.message = f"the Gauss-Newton step is below {STOP:g} standard errors in every unknown"
    return res.x, res.jac, res  # trf's Jacobian at its last accepted point: the optimum's


def horizons(n: int, onset: int = 0, stages: int = HORIZONS, least: int = 20) -> list[int]:
    """The samples fitted at each stage of a fit of n samples whose command first changes at
    sample `onset`: onset + (n - onset) / 2^(stages-1), ..., / 2, then n (at least `least`), each
    stage starting from the last one's optimum. (Samples before the first change of the command
    say little about the actuator: a stage of those alone would let the parameters wander.)"""
    out = [n if i == 0 else max(least, onset + -(-(n - onset) // 2**i)) for i in reversed(range(stages))]
    return sorted({min(k, n) for k in out})


def calibrate(
    m: Measurement,
    params: Params,
    fit: tuple[str, ...],
    mode: str,
    dt: float,
    fit_initial: bool = True,
    fit_frame: bool = True,
    check: float = 0.25,
    motors: TwistedString | None = None,
    residual: str | None = None,
    starts: int = 0,
    spread: float = minima.SPREAD,
    windows: int | None = None,
) -> Calibration:
    """Fit the Params fields `fit` (start: `params`; a run in volts: also the twisted strings'
    keys `model.ACTUATOR_FITTABLE`, start: `motors`) to measurement m in `mode`, simulating with
    time step dt s (`model.problem`), and check the fit on the first 1 - check of the samples
    (a stage of the growing horizon: it never sees the rest) by predicting the rest (check 0:
    none); `residual` of `model.RESIDUALS` (None: the mode's, `model.DEFAULT_RESIDUAL`); `starts`
    more fits from parameters within a factor `spread` of the start, the lowest cost kept, and a
    restart from any lower point the intervals' checks find (`minima`); `windows` time windows
    refitted for the intervals of a misfit (`discrepancy.count`; None: 4 grounded, 0 free)."""
    if not 0 <= check < 1:
        raise ValueError(f"check: the fraction of samples predicted must be in [0, 1), got {check!r}")
    residual = mdl.DEFAULT_RESIDUAL.get(mode, "positions") if residual is None else residual
    prob = mdl.problem(m, params, tuple(fit), mode, dt, fit_initial, fit_frame, motors, residual)
    T, (lo, hi) = m.t.size, _bounds(prob)
    changed = np.flatnonzero(np.any(m.pressure[2:] != m.pressure[1], axis=1))
    onset = int(changed[0]) + 2 if changed.size else 0
    kc = max(3, int(round(T * (1 - check)))) if check > 0 else T  # the prediction check's samples
    args = (prob.fit, mode, dt, fit_initial, fit_frame, motors, residual)
    parts = {k: prob if k == T else mdl.problem(m.head(k), params, *args) for k in set(horizons(T, onset)) | {kc}}
    (x, J, res, nfev, njev, fitted), costs = minima.lowest(
        partial(_staged, parts, kc), minima.draws(prob, starts, lo, hi, spread)
    )
    n, st = prob.n_params, minima.settle(prob, x, J, res, solve, lo, hi)
    prediction = _predict(prob, st.x, **fitted) if fitted else {}
    c = Calibration(
        prob.fit,
        prob.values(prob.x0)[:n],
        prob.values(st.x)[:n],
        st.unc,
        st.x,
        prob,
        st.simulated,
        prob.measured(st.x),
        float(np.sqrt(np.mean(st.r**2)) * 1e3),
        int(nfev + st.nfev),
        int(njev + st.njev),
        str(st.res.message),
        params,
        prediction,
        st.restarts,
        costs,
    )
    k = discrepancy.count(windows, mode, m.t.size)
    c = discrepancy.given(c, calibrate, k, fit_initial, fit_frame, PARAM_RANGE, hi[:n]) if k else c  # misfit only
    return stability.told(c, hi[:n], PARAM_RANGE, STEP)


def _staged(parts: dict, kc: int, x: np.ndarray | None) -> tuple:
    """The fit on the growing horizon from x (None: the problems' x0): each stage k of `parts`
    (its problem, the last one all samples) from the last one's optimum. (x, J, res, nfev,
    njev, the check's stage kc: its optimum and problem, if short of the last)."""
    nfev, njev, fitted, T, start = 0, 0, {}, max(parts), x
    for k in sorted(parts):  # the first part, twice as long, ..., all of it
        ftol = FTOL if k in (kc, T) else FTOL_STAGE
        try:
            x, J, res = solve(parts[k], x, ftol=ftol)
        except (SimulationError, ValueError):  # the last stage's optimum fails on the longer part
            x, J, res = solve(parts[k], start, ftol=ftol)
        nfev, njev = nfev + res.nfev, njev + res.njev
        if k == kc < T:
            fitted = {"x_part": x, "problem": parts[k]}
    return x, J, res, nfev, njev, fitted


def _predict(prob: mdl.Problem, x: np.ndarray, *, x_part: np.ndarray, problem: mdl.Problem) -> dict:
    """The prediction check of the full fit x of `prob`: the optimum x_part of its first k
    samples (`problem`), simulated over all of them: the RMS (mm) of the fitted part and of the
    predicted rest."""
    m, k, xp, part = prob.m, problem.m.t.size, x_part, problem
    sim = prob.simulate(xp[None])[0]
    sq = prob.per_sample(sim[None], xp)[0] ** 2  # in the check's own frame (NaN: not measured)
    (Rc, oc), (R, o) = prob.frame(xp), prob.frame(x)
    rms = [float(np.sqrt(np.nanmean(sq[a:b])) * 1e3) for a, b in ((0, k), (k, m.t.size))]
    return {
        "fit_until": float(m.t[k - 1]),
        "rms_fit_mm": rms[0],
        "rms_predict_mm": rms[1],
        "estimate": part.values(xp)[: prob.n_params],
        "simulated": (sim - oc) @ Rc @ R.T + o,  # in the full fit's frame, as its measured nodes
    }
