"""Analysis of a study's designs: global sensitivity indices with confidence intervals (SALib),
the best designs for the objective, the robustness figures' numbers. Arrays in, arrays out.

Which indices: a Saltelli design gives Sobol indices (first-order S1 and total ST, SALib
`analyze.sobol`); a Morris design gives elementary effects (mu* and sigma, `analyze.morris`);
any other design (grid, lhs, sobol) gives the moment-independent delta and S1 of
`analyze.delta`, which accepts any sample. Confidence intervals are SALib's 95 % bootstrap.
A design whose output is undefined (a pair that never tips: NaN) is censored at `censor`
(the highest swept level), said in the dataset.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from .spec import problem

# index name -> (its confidence interval's name) per method
INDICES = {
    "saltelli": (("S1", "S1_conf"), ("ST", "ST_conf")),
    "morris": (("mu_star", "mu_star_conf"), ("sigma", None)),
    "delta": (("delta", "delta_conf"), ("S1", "S1_conf")),
}


class _Names(np.ndarray):
    """SALib 1.5.1 passes the group names to pandas.unique, which pandas 3 refuses for a list:
    give them as an array that is also truthy when non-empty (SALib tests `not groups`)."""

    def __bool__(self) -> bool:
        return self.size > 0


def _problem(study: Mapping) -> dict:
    pr = problem(study)
    return {**pr, "groups": np.array(pr["names"], dtype=object).view(_Names)}


def method_of(study: Mapping) -> str:
    """'saltelli', 'morris' or 'delta' (any other design)."""
    m = study["design"]["method"]
    return m if m in ("saltelli", "morris") else "delta"


def sensitivity(
    study: Mapping, X: np.ndarray, y: np.ndarray, censor: float | None = None, seed: int = 1, resamples: int = 100
) -> dict[str, np.ndarray]:
    """Indices of one output y (N,) over the designs X (N, k) (all rows of the design matrix, in
    order): {index: (k,), index_conf: (k,)} as named in INDICES[method_of(study)]. NaN outputs
    are censored at `censor` (ValueError if there is none to use). A constant output has
    all indices 0. `resamples`: bootstrap resamples of the intervals."""
    y = np.asarray(y, float)
    if np.isnan(y).any():
        if censor is None:
            raise ValueError("the output is undefined (NaN) for some designs and no censoring value was given")
        y = np.where(np.isnan(y), censor, y)
    pr, method = _problem(study), method_of(study)
    k = pr["num_vars"]
    if np.ptp(y) == 0:
        return {name: np.zeros(k) for pair in INDICES[method] for name in pair if name}
    from threadpoolctl import threadpool_limits

    with threadpool_limits(1):  # SALib's small BLAS calls (KDEs): threads only wait on each other
        r = _analyze(study, pr, method, X, y, seed, resamples)
    return {name: np.asarray(r[name], float) for pair in INDICES[method] for name in pair if name}


def _analyze(study, pr, method, X, y, seed, resamples):
    """SALib's analysis of `method` (`sensitivity`)."""
    if method == "saltelli":
        from SALib.analyze import sobol

        return sobol.analyze(pr, y, calc_second_order=False, seed=seed, print_to_console=False, num_resamples=resamples)
    if method == "morris":
        from SALib.analyze import morris

        return morris.analyze(
            pr,
            X,
            y,
            num_levels=study["design"]["morris_levels"],
            seed=seed,
            print_to_console=False,
            num_resamples=resamples,
        )
    from SALib.analyze import delta

    return delta.analyze(pr, X, y, seed=seed, print_to_console=False, num_resamples=resamples)


def best_designs(objective: np.ndarray, n: int) -> np.ndarray:
    """Indices (m,) m <= n of the designs with the lowest finite objective, best first (ties:
    lower index first)."""
    obj = np.asarray(objective, float)
    ok = np.flatnonzero(np.isfinite(obj))
    return ok[np.argsort(obj[ok], kind="stable")][:n]


def success_rate(success: np.ndarray) -> tuple[float, float, float]:
    """Success rate of n Bernoulli trials (success (n,) 0/1) and its 95 % Wilson score interval
    (low, high); NaN for n = 0."""
    s = np.asarray(success, float)
    n = s.size
    if n == 0:
        return float("nan"), float("nan"), float("nan")
    p, z = s.mean(), 1.96
    centre = (p + z * z / (2 * n)) / (1 + z * z / n)
    half = z * np.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / (1 + z * z / n)
    return float(p), float(max(0.0, centre - half)), float(min(1.0, centre + half))


def censor_values(study: Mapping) -> dict[str, float]:
    """Where an undefined output is censored (MPa): a pair that never tips, at the highest
    swept level ('workspace'); a roll that never happens, at the roll's highest pressure ('roll')."""
    return {"workspace": float(study["workspace"]["levels"][-1]), "roll": float(study["roll"]["max_pressure"])}


def all_indices(
    study: Mapping, X: np.ndarray, outputs: Mapping[str, np.ndarray], complete: bool
) -> tuple[dict[str, dict[str, np.ndarray]], list[str]]:
    """The indices (`sensitivity`) of every output (name -> y (N,)) over the designs X (N, k):
    output -> {index: (k,)}, NaN where the study was not run in full (`complete` False) or
    SALib could not compute them; and the messages of those it could not compute. Outputs
    named roll_* are censored at the roll's highest pressure, the others at the highest level."""
    censor = censor_values(study)
    method = method_of(study)
    out, failed = {}, []
    for o, y in outputs.items():
        nan = {n: np.full(X.shape[1], np.nan) for p in INDICES[method] for n in p if n}
        try:
            out[o] = (
                sensitivity(study, X, y, censor["roll" if o.startswith("roll_") else "workspace"]) if complete else nan
            )
        except (np.linalg.LinAlgError, ValueError) as e:  # e.g. delta's density of a 0/1 output
            out[o] = nan
            failed.append(f"{o}: {type(e).__name__}: {str(e).splitlines()[0]}")
            print(f"sensitivity of {o} not computed: {e}")
    return out, failed
