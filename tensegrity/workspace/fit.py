"""Curve fits of the nominal CoG against pressure: cog_axis(pressure) per pair and axis.

A curve is chosen by cross-validation (`cv_select`, also the choice of the two-pair surfaces)
among least-squares polynomials of degree 1..D (numpy.polynomial) and cubic least-squares splines
with uniform knots (scipy.interpolate B-splines), and exported as plain numbers: a piecewise
polynomial with `breaks` (m+1,) in MPa and `coefs` (m, deg+1) in the local variable
u = p - breaks[i], **highest power first** (the numpy.polyval / scipy PPoly order). Outside
[pmin, pmax] the end pieces are continued (cubic/polynomial extrapolation); callers should stay
inside the valid range. Evaluation needs numpy only (no scipy, no pickle).
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

# scipy is imported where splines are fitted, so that evaluating an exported curve (evaluate,
# from_dict, arrays_to_curves) needs numpy only.

TIE_RTOL = 0.05  # a more complex model must lower the CV RMSE by more than 5 % to win
TIE_ATOL = 1e-9  # ... and by more than this fraction of max|values| (roundoff on exact data)
# netCDF dimensions of the arrays made by curves_to_arrays
ARRAY_DIMS = {
    "breaks": ("pair", "axis", "break"),
    "coefs": ("pair", "axis", "piece", "power"),
    "degree": ("pair", "axis"),
    "pmin": ("pair", "axis"),
    "pmax": ("pair", "axis"),
    "cv_rmse": ("pair", "axis"),
    "max_residual": ("pair", "axis"),
    "kind": ("pair", "axis"),
    "model": ("pair", "axis"),
}


@dataclass(frozen=True, eq=False)
class Curve:
    """Piecewise polynomial value(p): breaks (m+1,) MPa increasing, coefs (m, deg+1) in units of
    value/MPa^k, highest power first in u = p - breaks[i]; pmin, pmax (MPa) the data range;
    cv_rmse the cross-validated RMSE (value units, NaN if too few points to validate);
    max_residual the largest |value(p) - data| over the points fitted (value units; NaN: not
    known, a curve read from a file made before issue 34)."""

    kind: str
    breaks: np.ndarray
    coefs: np.ndarray
    pmin: float
    pmax: float
    cv_rmse: float
    model: str
    max_residual: float = float("nan")

    def __post_init__(self):
        b = np.asarray(self.breaks, dtype=float).reshape(-1)
        c = np.atleast_2d(np.asarray(self.coefs, dtype=float))
        if b.size < 2 or np.any(np.diff(b) <= 0) or not np.all(np.isfinite(b)):
            raise ValueError(f"curve breaks must be >= 2 finite increasing MPa, got {b.tolist()}")
        if c.shape[0] != b.size - 1 or not np.all(np.isfinite(c)):
            raise ValueError(f"curve coefs must be finite with {b.size - 1} rows, got {c.shape}")
        if self.kind not in ("polynomial", "spline"):
            raise ValueError(f"curve kind must be 'polynomial' or 'spline', got {self.kind!r}")
        for name, v in (("breaks", b), ("coefs", c)):
            object.__setattr__(self, name, v)
        for name in ("pmin", "pmax", "cv_rmse", "max_residual"):
            object.__setattr__(self, name, float(getattr(self, name)))

    def __call__(self, pressure) -> np.ndarray:
        return evaluate(self, pressure)


def evaluate(curve: Curve | Mapping, pressure: ArrayLike) -> np.ndarray:
    """Value at `pressure` (any shape, MPa), same shape; `curve` is a Curve or a mapping with
    `breaks` and `coefs` (e.g. from JSON; trailing NaN padding is ignored)."""
    b = np.asarray(curve.breaks if isinstance(curve, Curve) else curve["breaks"], float).ravel()
    c = np.asarray(curve.coefs if isinstance(curve, Curve) else curve["coefs"], float)
    b = b[np.isfinite(b)]
    c = np.atleast_2d(c)[: b.size - 1]
    p = np.asarray(pressure, dtype=float)
    i = np.clip(np.searchsorted(b, p, side="right") - 1, 0, b.size - 2)
    u, ci = p - b[i], c[i]
    y = ci[..., 0]
    for k in range(1, c.shape[1]):  # Horner, highest power first
        y = y * u + ci[..., k]
    return y


def _check(pressure, values) -> tuple[np.ndarray, np.ndarray]:
    p, v = np.asarray(pressure, dtype=float), np.asarray(values, dtype=float)
    if p.ndim != 1 or v.ndim != 1:
        raise ValueError(f"pressure and values must be 1-D, got shapes {p.shape} and {v.shape}")
    if p.size != v.size:
        raise ValueError(f"pressure and values have different lengths: {p.size} != {v.size}")
    if p.size < 2:
        raise ValueError(f"fitting a curve needs at least 2 points, got {p.size}")
    for name, a in (("pressure", p), ("values", v)):
        if not np.all(np.isfinite(a)):
            raise ValueError(f"{name} contain NaN or inf at index {np.flatnonzero(~np.isfinite(a))}")
    if np.ptp(p) <= 0:
        raise ValueError("pressure must contain at least 2 distinct levels")
    o = np.argsort(p, kind="stable")
    return p[o], v[o]


def cv_select(
    sizes: Sequence[int],
    predict: Callable[[int, np.ndarray], np.ndarray],
    values: np.ndarray,
    folds: int,
    tie_rtol: float = TIE_RTOL,
) -> tuple[int, float]:
    """Cross-validated choice among candidate models 0..len(sizes)-1, simplest first (sizes:
    their numbers of parameters), of `values` (n,) at points sorted by their coordinates.

    Point i goes to fold i mod folds (interleaved, deterministic; leave-one-out when n < folds).
    A candidate with more parameters than the smallest training fold has points is skipped.
    predict(c, train) returns candidate c fitted on the points where `train` (n,) is True,
    evaluated at the others. The score is the RMSE of the pooled held-out predictions; the
    simplest candidate within tie_rtol * best + TIE_ATOL * max|values| of the best wins.
    Returns (candidate, CV RMSE), or (0, NaN) if no candidate can be validated."""
    v = np.asarray(values, float)
    nf = min(int(folds), v.size)
    if nf < 2:
        raise ValueError(f"folds must be >= 2, got {folds}")
    fold = np.arange(v.size) % nf
    n_train = v.size - int(np.ceil(v.size / nf))
    scores = []
    for c, size in enumerate(sizes):
        if size > n_train:
            continue
        pred = np.empty_like(v)
        for k in range(nf):
            test = fold == k
            pred[test] = predict(c, ~test)
        scores.append((c, float(np.sqrt(np.mean((pred - v) ** 2)))))
    if not scores:
        return 0, float("nan")
    best = min(s for _, s in scores)
    tol = tie_rtol * best + TIE_ATOL * float(np.max(np.abs(v)))
    return next(x for x in scores if x[1] <= best + tol)


def _candidates(max_degree: int, spline_knots: Iterable[int]) -> list[tuple[str, int]]:
    """(name, number of parameters) of the candidate curves, simplest first: polynomials
    "polyD" and cubic splines "spline k=K" (K uniform knots: K + 2 B-splines)."""
    c = [(f"poly{d}", d + 1) for d in range(1, max_degree + 1)]
    c += [(f"spline k={k}", k + 2) for k in spline_knots]
    return sorted(c, key=lambda t: t[1])  # stable: polynomials before splines of equal size


def _least_squares(name: str, p: np.ndarray, v: np.ndarray) -> tuple[str, np.ndarray, np.ndarray]:
    """Candidate `name` fitted by least squares to values v (n,) at sorted pressures p (n,) MPa,
    as (kind, breaks, coefs highest power first): a polynomial in u = p - p[0] over
    [p[0], p[-1]] (numpy.polynomial), or a cubic spline whose K knots divide [p[0], p[-1]]
    evenly, continued by three more at the same spacing on each side, so that the end pieces
    extend as cubics (one piece between knots): scipy.interpolate's B-splines with coefficients
    by numpy's least squares, the least-norm ones where the points leave some undetermined
    (scipy's make_lsq_spline returns NaN there)."""
    if name.startswith("poly"):
        low = np.polynomial.polynomial.polyfit(p - p[0], v, int(name[4:]))
        return "polynomial", np.array([p[0], p[-1]]), low[::-1][None, :]
    from scipy.interpolate import BSpline, PPoly

    base = np.linspace(p[0], p[-1], int(name.split("=")[1]))
    h = base[1] - base[0]
    t = np.r_[base[0] - h * np.arange(3, 0, -1), base, base[-1] + h * np.arange(1, 4)]
    c = np.linalg.lstsq(BSpline.design_matrix(p, t, 3).toarray(), v, rcond=None)[0]
    pp = PPoly.from_spline(BSpline(t, c, 3))
    return "spline", base, pp.c[:, 3 : 3 + base.size - 1].T.copy()


def fit_curve(
    pressure: ArrayLike,
    values: ArrayLike,
    max_degree: int = 3,
    spline_knots: Iterable[int] = (3, 4),
    folds: int = 5,
    tie_rtol: float = TIE_RTOL,
) -> Curve:
    """Fit value(pressure): pressure (n,) MPa, values (n,) (e.g. CoG in m) -> Curve.

    `cv_select` chooses among the candidates (`_candidates`), each fitted and evaluated in its
    exported form (`_least_squares`, `evaluate`). The winner is refit on all points; if
    no candidate can be validated (n = 2) a line is fitted with cv_rmse = NaN. The curve
    states its largest residual against the points (`Curve.max_residual`)."""
    p, v = _check(pressure, values)
    cands = _candidates(int(max_degree), tuple(int(k) for k in spline_knots))
    if not cands:
        raise ValueError("no candidate models: max_degree < 1 and spline_knots empty")

    def predict(c: int, train: np.ndarray) -> np.ndarray:
        _, breaks, coefs = _least_squares(cands[c][0], p[train], v[train])
        return evaluate({"breaks": breaks, "coefs": coefs}, p[~train])

    best, rmse = cv_select([n for _, n in cands], predict, v, folds, tie_rtol)
    name = cands[best][0]
    if np.isnan(rmse) and not name.startswith("poly"):
        raise ValueError(f"{p.size} points are too few for any candidate model")
    kind, breaks, coefs = _least_squares(name, p, v)
    worst = float(np.max(np.abs(evaluate({"breaks": breaks, "coefs": coefs}, p) - v)))
    return Curve(kind, breaks, coefs, p[0], p[-1], rmse, name, worst)


def fit_pairs(pressure: ArrayLike, cog: ArrayLike, **opts: Any) -> list[list[Curve]]:
    """Curves for cog (npair, n, 3) m against pressure (n,) MPa -> curves[pair-1][axis]."""
    cog = np.asarray(cog, dtype=float)
    if cog.ndim != 3 or cog.shape[2] != 3:
        raise ValueError(f"cog must have shape (npair, n, 3), got {cog.shape}")
    out = []
    for i, pair in enumerate(cog):
        row = []
        for a, axis in enumerate("xyz"):
            try:
                row.append(fit_curve(pressure, pair[:, a], **opts))
            except ValueError as e:
                raise ValueError(f"pair {i + 1} axis {axis}: {e}") from e
        out.append(row)
    return out


def to_dict(curve: Curve) -> dict:
    """JSON-ready plain numbers (cv_rmse, max_residual NaN -> None)."""
    return {
        "kind": curve.kind,
        "model": curve.model,
        "breaks": curve.breaks.tolist(),
        "coefs": curve.coefs.tolist(),
        "pmin": curve.pmin,
        "pmax": curve.pmax,
        "cv_rmse": None if np.isnan(curve.cv_rmse) else curve.cv_rmse,
        "max_residual": None if np.isnan(curve.max_residual) else curve.max_residual,
        "coef_order": "highest power first in p - breaks[i]",
        "pressure_units": "MPa",
    }


def from_dict(d: Mapping) -> Curve:
    """Inverse of to_dict."""
    cv, worst = (np.nan if d.get(k) is None else d[k] for k in ("cv_rmse", "max_residual"))
    return Curve(d["kind"], d["breaks"], d["coefs"], d["pmin"], d["pmax"], cv, d["model"], worst)


def curves_to_arrays(curves: Sequence[Sequence[Curve]]) -> dict[str, np.ndarray]:
    """curves[pair][axis] -> arrays with dims ARRAY_DIMS; breaks/coefs padded with NaN to the
    most pieces, coefs left-padded with zeros (highest powers) to the highest degree."""
    flat = [c for row in curves for c in row]
    shape = (len(curves), len(curves[0]))
    if any(len(row) != shape[1] for row in curves):
        raise ValueError("curves must be a rectangular list of lists [pair][axis]")
    m = max(c.coefs.shape[0] for c in flat)
    nc = max(c.coefs.shape[1] for c in flat)
    breaks = np.full((len(flat), m + 1), np.nan)
    coefs = np.full((len(flat), m, nc), np.nan)
    for j, c in enumerate(flat):
        breaks[j, : c.breaks.size] = c.breaks
        coefs[j, : c.coefs.shape[0]] = 0.0
        coefs[j, : c.coefs.shape[0], nc - c.coefs.shape[1] :] = c.coefs
    out = {"breaks": breaks, "coefs": coefs}
    out |= {k: np.array([getattr(c, k) for c in flat]) for k in ("pmin", "pmax", "cv_rmse", "max_residual")}
    out |= {k: np.array([getattr(c, k) for c in flat], dtype=str) for k in ("kind", "model")}
    out["degree"] = np.array([c.coefs.shape[1] - 1 for c in flat])
    return {k: a.reshape(shape + a.shape[1:]) for k, a in out.items()}


def arrays_to_curves(arrays: Mapping) -> list[list[Curve]]:
    """Inverse of curves_to_arrays (exact)."""
    npair, naxis = np.shape(arrays["pmin"])
    out = []
    for i in range(npair):
        row = []
        for a in range(naxis):
            b = np.asarray(arrays["breaks"][i, a], float)
            b = b[np.isfinite(b)]
            deg = int(arrays["degree"][i, a])
            c = np.asarray(arrays["coefs"][i, a], float)[: b.size - 1, -(deg + 1) :]
            row.append(
                Curve(
                    str(arrays["kind"][i, a]),
                    b,
                    c,
                    arrays["pmin"][i, a],
                    arrays["pmax"][i, a],
                    arrays["cv_rmse"][i, a],
                    str(arrays["model"][i, a]),
                    arrays["max_residual"][i, a] if "max_residual" in arrays else np.nan,
                )
            )
        out.append(row)
    return out
