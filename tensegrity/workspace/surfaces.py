"""Fitted surfaces of the two-pair workspace, as results/curves/two_pair.json stores them
(`io.formats.two_pair`): plain numbers, each surface with its largest residual against its data.

A surface is the least-squares polynomial of the two pairs' pressures whose degree
cross-validation chooses (as a curve's, `workspace.fit`) if it keeps every swept point within
MAX_RESIDUAL; else the tensor-product spline that interpolates the grid (scipy's
RectBivariateSpline, cubic in each pressure, or of degree levels - 1 below 4 levels), exported as
a piecewise bicubic polynomial. Its residual at the swept points is roundoff; between them it is
the interpolation error of a cubic spline, O(h^4) of the level step h for a smooth workspace.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from .fit import cv_select

MAX_RESIDUAL = 1e-4  # m: a polynomial that misses a swept point by more gives way to the spline


def powers(degree: int) -> np.ndarray:
    """Exponents (n, 2) of the monomials p_a^i p_b^j with i + j <= degree, by total degree."""
    return np.array([(i, t - i) for t in range(degree + 1) for i in range(t, -1, -1)])


def _sorted(pa: ArrayLike, pb: ArrayLike, values: ArrayLike) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    pa, pb, v = (np.asarray(x, float).ravel() for x in (pa, pb, values))
    if not (pa.size == pb.size == v.size) or pa.size < 3 or not np.all(np.isfinite(np.r_[pa, pb, v])):
        raise ValueError(f"fit_surface needs >= 3 finite points of equal count, got {pa.size}, {pb.size}, {v.size}")
    o = np.lexsort((pb, pa))
    return pa[o], pb[o], v[o]


def fit_polynomial(pa: ArrayLike, pb: ArrayLike, values: ArrayLike, max_degree: int = 3, folds: int = 5) -> dict:
    """Least-squares polynomial value(p_a, p_b) (MPa) of total degree 1..max_degree chosen by
    cross-validation as a curve is (`workspace.fit.cv_select`, points sorted by (p_a, p_b)),
    refit on all points. Returns plain numbers: kind 'polynomial', powers (n, 2), coefs (n,) in
    value/MPa^(i+j), degree, cv_rmse (value units, NaN if nothing could be validated), max_residual
    (value units, the largest miss of a point), pmin, pmax (MPa)."""
    pa, pb, v = _sorted(pa, pb, values)
    design = lambda a, b, pw: a[:, None] ** pw[:, 0] * b[:, None] ** pw[:, 1]
    degrees = range(1, int(max_degree) + 1)

    def predict(c: int, train: np.ndarray) -> np.ndarray:
        pw = powers(degrees[c])
        coef = np.linalg.lstsq(design(pa[train], pb[train], pw), v[train], rcond=None)[0]
        return design(pa[~train], pb[~train], pw) @ coef

    c, rmse = cv_select([len(powers(d)) for d in degrees], predict, v, folds)
    deg = degrees[c] if degrees else 1
    pw = powers(deg)
    coef = np.linalg.lstsq(design(pa, pb, pw), v, rcond=None)[0]
    return {
        "kind": "polynomial",
        "powers": pw.tolist(),
        "coefs": coef.tolist(),
        "degree": deg,
        "cv_rmse": None if np.isnan(rmse) else rmse,
        "max_residual": float(np.max(np.abs(design(pa, pb, pw) @ coef - v))),
        "pmin": float(min(pa.min(), pb.min())),
        "pmax": float(max(pa.max(), pb.max())),
    }


def _pieces(t: np.ndarray, k: int) -> tuple[np.ndarray, np.ndarray]:
    """Breaks (m+1,) of the pieces of the B-splines of degree k on knots t, and each B-spline's
    polynomial on each piece, (n, k+1, m) highest power first in p - breaks[piece]."""
    from scipy.interpolate import BSpline, PPoly

    n = t.size - k - 1
    per = [PPoly.from_spline(BSpline(t, np.eye(n)[i], k)) for i in range(n)]
    keep = np.flatnonzero((np.diff(t) > 0) & (t[:-1] >= t[k]) & (t[1:] <= t[n]))
    return np.r_[t[keep], t[keep[-1] + 1]], np.stack([pp.c[:, keep] for pp in per])


def fit_spline(pa: ArrayLike, pb: ArrayLike, values: ArrayLike) -> dict:
    """Tensor-product spline interpolating value on the full grid of levels (pa, pb), MPa
    (every combination of the distinct pa and pb present once): scipy's RectBivariateSpline
    (s = 0), cubic or of degree levels - 1. Returns plain numbers: kind 'spline', breaks_a
    (ma+1,) and breaks_b (mb+1,) MPa, coefs (ma, mb, ka+1, kb+1) in value/MPa^(i+j), highest
    powers first in u = pa - breaks_a[i], v = pb - breaks_b[j], degree [ka, kb], max_residual
    (value units), cv_rmse None (an interpolant is not cross-validated), pmin, pmax (MPa)."""
    from scipy.interpolate import RectBivariateSpline

    pa, pb, v = _sorted(pa, pb, values)
    xa, xb = np.unique(pa), np.unique(pb)
    if xa.size * xb.size != v.size or xa.size < 2 or xb.size < 2:
        raise ValueError(f"a spline surface needs a full grid of >= 2 x 2 levels, got {v.size} points")
    grid = v.reshape(xa.size, xb.size)  # sorted by (pa, pb): row-major over the grid
    ka, kb = min(3, xa.size - 1), min(3, xb.size - 1)
    spl = RectBivariateSpline(xa, xb, grid, kx=ka, ky=kb, s=0)
    ta, tb, c = spl.tck  # full knot vectors (end knots k + 1 times) and coefficients
    (ba, qa), (bb, qb) = _pieces(ta, ka), _pieces(tb, kb)
    coefs = np.einsum("iKm,ij,jLn->mnKL", qa, c.reshape(qa.shape[0], qb.shape[0]), qb)
    out = {
        "kind": "spline",
        "breaks_a": ba.tolist(),
        "breaks_b": bb.tolist(),
        "coefs": coefs.tolist(),
        "degree": [ka, kb],
        "cv_rmse": None,
        "pmin": float(min(xa[0], xb[0])),
        "pmax": float(max(xa[-1], xb[-1])),
    }
    return out | {"max_residual": float(np.max(np.abs(evaluate(out, pa, pb) - v)))}


def fit_surface(
    pa: ArrayLike,
    pb: ArrayLike,
    values: ArrayLike,
    max_degree: int = 3,
    folds: int = 5,
    max_residual: float = MAX_RESIDUAL,
) -> dict:
    """The surface of value(pa, pb) (values in m, pressures MPa) as two_pair.json stores it:
    the cross-validated polynomial (`fit_polynomial`) if its largest residual is within
    `max_residual` (value units), else the interpolating spline (`fit_spline`)."""
    poly = fit_polynomial(pa, pb, values, max_degree, folds)
    return poly if poly["max_residual"] <= max_residual else fit_spline(pa, pb, values)


def evaluate(surface: dict, pa: ArrayLike, pb: ArrayLike) -> np.ndarray:
    """A surface (`fit_surface`, or read from two_pair.json) at pressures pa, pb (MPa, broadcast);
    numpy only. A spline continues its end pieces outside its breaks."""
    if surface.get("kind", "polynomial") == "polynomial":
        pw = np.asarray(surface["powers"], float)
        c = np.asarray(surface["coefs"], float)
        a, b = np.asarray(pa, float)[..., None], np.asarray(pb, float)[..., None]
        return np.sum(c * a ** pw[:, 0] * b ** pw[:, 1], axis=-1)
    ba, bb = (np.asarray(surface[k], float) for k in ("breaks_a", "breaks_b"))
    c = np.asarray(surface["coefs"], float)
    a, b = np.broadcast_arrays(np.asarray(pa, float), np.asarray(pb, float))
    i = np.clip(np.searchsorted(ba, a, side="right") - 1, 0, ba.size - 2)
    j = np.clip(np.searchsorted(bb, b, side="right") - 1, 0, bb.size - 2)
    ka, kb = c.shape[2] - 1, c.shape[3] - 1
    u = (a - ba[i])[..., None] ** np.arange(ka, -1, -1)
    w = (b - bb[j])[..., None] ** np.arange(kb, -1, -1)
    return np.einsum("...KL,...K,...L->...", c[i, j], u, w)
