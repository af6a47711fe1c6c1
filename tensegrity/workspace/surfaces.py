"""Fitted surfaces of the two-pair workspace: a least-squares polynomial of the two pairs'
pressures, its degree chosen by cross-validation as a curve's is (`workspace.fit`); plain
numbers, as results/curves/two_pair.json stores them (`io.formats.two_pair`)."""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from .fit import cv_select


def powers(degree: int) -> np.ndarray:
    """Exponents (n, 2) of the monomials p_a^i p_b^j with i + j <= degree, by total degree."""
    return np.array([(i, t - i) for t in range(degree + 1) for i in range(t, -1, -1)])


def fit_surface(pa: ArrayLike, pb: ArrayLike, values: ArrayLike, max_degree: int = 3, folds: int = 5) -> dict:
    """Least-squares polynomial value(p_a, p_b) (MPa) of total degree 1..max_degree chosen by
    cross-validation as a curve is (`workspace.fit.cv_select`, points sorted by (p_a, p_b)),
    refit on all points. Returns plain numbers: powers (n, 2), coefs (n,) in value/MPa^(i+j), degree,
    cv_rmse (value units, NaN if nothing could be validated), pmin, pmax (MPa)."""
    pa, pb, v = (np.asarray(x, float).ravel() for x in (pa, pb, values))
    if not (pa.size == pb.size == v.size) or pa.size < 3 or not np.all(np.isfinite(np.r_[pa, pb, v])):
        raise ValueError(f"fit_surface needs >= 3 finite points of equal count, got {pa.size}, {pb.size}, {v.size}")
    o = np.lexsort((pb, pa))
    pa, pb, v = pa[o], pb[o], v[o]
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
    lo, hi = float(min(pa.min(), pb.min())), float(max(pa.max(), pb.max()))
    return {
        "powers": pw.tolist(),
        "coefs": coef.tolist(),
        "degree": deg,
        "cv_rmse": None if np.isnan(rmse) else rmse,
        "pmin": lo,
        "pmax": hi,
    }
