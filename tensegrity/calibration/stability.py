"""The contact dampers' stability limit (docs/design.md §9, issue 32): the largest ground damper
c_n (C2) and stick damper c_t (C4) that the simulator's semi-implicit Euler step integrates.

A damper c on a strut end of effective mass m_e, stepped explicitly with time step dt, changes
the end's velocity by -c dt / m_e of itself each step: it damps only while c dt / m_e < 2, and
beyond that the velocity flips sign every step and grows until the contact force reaches its cap
(mu f_n for the stick damper, 0 for the normal force): the contact chatters. A force across a
strut at its end moves the end as a mass m_e = m / (1 + (S/2)^2 m / I_t) (I_t = m (S^2/12 +
r^2/4), the strut's transverse inertia: m_e ~ m/4), the smallest of any direction, so

    c* = 2 m_e / dt   (N s/m; 861 N s/m for a 0.172 kg strut at dt = 1e-4 s)          (D1)

Measured (MuJoCo's grounded run, seed 608731, the first of four windows, docs/benchmarks.md): the
shape residual changes smoothly with the stiffness for c_t or c_n <= 860 N s/m, and by 1e-6 to
1e-5 m for any perturbation however small (1e-10) from 900 N s/m on: a chattering contact makes
the run depend on round-off. The forward-difference Jacobian (step 1e-6) is then noise, and a fit
that wandered there (the stick damper fitted to 1080-1362 N s/m, the ground damper to 1013-1342)
stalled where it started. A calibration bounds both dampers to c* (`fit`): above it the simulated
run is not the model's at any time step, only this dt's chatter. A fit that ends at c* says so
(`pinned`): the data ask for more damping than the model integrates at this dt. And every fit
grounded fit names a parameter whose residual is rough at its estimate (`rough`, whatever the
cause).
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from ..physics.dynamics import SimulationError

__all__ = ["DAMPERS", "ROUGH", "limit", "upper", "pinned", "rough", "told"]

DAMPERS = ("ground_damping", "friction_damping")  # (C2) c_n and (C4) c_t, N s/m
AT = 1e-6  # relative: an estimate this close below c* is at the bound (trf stays 1e-10 inside)
TINY = 1e-9  # scaled: the step of the roughness check, 1e-3 of the Jacobian's
ROUGH = 2.0  # the difference quotient at TINY over the one at the Jacobian's step: rough above


def limit(strut_mass: float, strut_length: float, strut_radius: float, dt: float) -> float:
    """(D1): the largest contact damper c* (N s/m) the explicit step dt (s) integrates for a strut
    of mass kg, length and radius m."""
    It = strut_mass * (strut_length**2 / 12 + strut_radius**2 / 4)
    m_e = strut_mass / (1 + (strut_length / 2) ** 2 * strut_mass / It)
    return 2 * m_e / dt


def upper(prob: object, bound: float) -> np.ndarray:
    """The upper bounds (n,) of the fitted parameters of `prob` (`model.Problem`) in scaled units
    (multiples of their start): `bound`, or for a damper of DAMPERS c* / start if smaller (a start
    beyond c* is moved to c*: the fit starts where the model is smooth). Without a damper among
    them, `bound` for all (nothing else of `prob` read). ValueError naming a damper that starts
    `bound` times c* or more (no room left below)."""
    fit, n = tuple(prob.fit), prob.n_params
    if not any(k in DAMPERS for k in fit):
        return np.full(n, float(bound))
    p = prob.params
    c = limit(*(float(np.asarray(getattr(p, k))) for k in ("strut_mass", "strut_length", "strut_radius")), prob.dt)
    out = np.array([min(bound, c / s) if k in DAMPERS else bound for k, s in zip(fit, prob.units[:n], strict=True)])
    if np.any(out <= 1 / bound):
        k = fit[int(np.argmax(out <= 1 / bound))]
        raise ValueError(f"fit: {k} starts {bound:g} times or more above its stability limit (D1) {c:.4g} N s/m")
    return out


def pinned(fit: tuple[str, ...], estimate: np.ndarray, start: np.ndarray, hi: np.ndarray, bound: float) -> list[str]:
    """What to say of each damper whose estimate (n,) lies at its upper bound start * hi (n,) set
    by (D1) (below `bound`, the fit's range): its value is the limit, not what the data determine."""
    out = []
    for k, e, s, h in zip(fit, estimate, start, hi, strict=True):
        if k in DAMPERS and h < bound and e >= s * h * (1 - AT):
            out.append(
                f"{k} at its upper bound {s * h:.4g} N s/m, the stability limit (D1) of the time step: the data ask "
                "for more damping than the model integrates; its value is the limit, not an estimate"
            )
    return out


def rough(prob: object, x: np.ndarray, step: float) -> np.ndarray:
    """The roughness (n,) of the residual of `prob` (`model.Problem`) at the unknowns x (p,)
    scaled, per fitted parameter j: |r(x - TINY e_j) - r(x)| / TINY over |r(x - step e_j) - r(x)| /
    step (one batched simulation). A smooth residual gives 1 to ~1e-3 (the quotients differ by
    the curvature); a run that chatters or switches a contact moves by a jump at any step,
    however small, and gives ~ step / TINY. NaN if a simulation fails."""
    n = prob.n_params
    E = np.eye(len(x))[:n]
    try:
        R = prob.residuals(np.concatenate([x[None], x - TINY * E, x - step * E]))
    except (SimulationError, ValueError):
        return np.full(n, np.nan)
    d = np.linalg.norm(R[1:] - R[0], axis=1)
    with np.errstate(divide="ignore", invalid="ignore"):
        return (d[:n] / TINY) / (d[n:] / step)


def told(c: object, hi: np.ndarray, bound: float, step: float) -> object:
    """Calibration c (`fit.Calibration`) with `pinned`'s sentences, for its upper bounds hi (n,)
    scaled, and in the grounded mode a sentence for each parameter whose residual is rough
    (`rough` > ROUGH at its estimate; `step` the Jacobian's), added to its `undetermined`. (Not in a
    run in volts, whose gears' stick (T5) the intervals' own checks handle, nor in the free mode,
    smooth with the muscles.)"""
    said = pinned(c.names, c.estimate, c.start, hi, bound)
    grounded = c.problem.mode == "grounded" and c.problem.motors is None
    ratio = rough(c.problem, c.x, step) if grounded else np.zeros(len(c.names))
    said += [
        f"{k}: the residual is rough at the estimate (a step of {TINY:g} moves it {q:.3g} times as fast as the "
        f"Jacobian's step {step:g}: a contact that chatters or switches), so the fit's Jacobian there is noise and "
        "it may have stopped short of its optimum; its interval is not to be trusted"
        for k, q in zip(c.names, ratio, strict=True)
        if q > ROUGH
    ]
    return replace(c, unc=replace(c.unc, undetermined=c.unc.undetermined + tuple(said))) if said else c
