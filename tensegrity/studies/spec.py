"""A design study (config/studies/<name>.yaml, read and checked by `io.study_config`): the
parameters it may vary and their units, the design matrix it names and its chunks of designs.
"""

from __future__ import annotations

import copy
import itertools
import math
from collections.abc import Mapping
from typing import Any

import numpy as np

from ..physics.params import Params

# The unit of each parameter a study may vary (the configuration's `params`, docs/design.md §4).
UNITS = {
    "strut_length": "m",
    "strut_radius": "m",
    "strut_mass": "kg",
    "cable_stiffness": "N/m",
    "cable_pretension": "N",
    "cable_damping": "N s/m",
    "muscle_min_length": "m",
    "muscle_gain": "N/(MPa m)",
    "ground_stiffness": "N/m",
    "ground_damping": "N s/m",
    "friction": "1",
    "friction_stiffness": "N/m",
    "friction_damping": "N s/m",
}
# Parameters that must be one number for the whole batch of a roll (lockstep.observe, contact).
NOT_IN_ROLLS = ("strut_radius", "strut_length")


def problem(study: Mapping) -> dict:
    """The SALib problem: names, bounds (one [low, high] per parameter), num_vars."""
    names = list(study["parameters"])
    return {
        "num_vars": len(names),
        "names": names,
        "bounds": [[study["parameters"][n]["low"], study["parameters"][n]["high"]] for n in names],
    }


def design_matrix(study: Mapping) -> np.ndarray:
    """The designs (N, k): one row per design, one column per varied parameter (in its units),
    deterministic for a given study."""
    d, pr = study["design"], problem(study)
    lo, hi = np.array(pr["bounds"], float).T
    k, method = pr["num_vars"], d["method"]
    if method == "grid":
        axes = [np.linspace(a, b, d["levels"]) for a, b in zip(lo, hi)]
        return np.array(list(itertools.product(*axes)), float).reshape(-1, k)
    if method in ("lhs", "sobol"):
        from scipy.stats import qmc

        eng = qmc.LatinHypercube(d=k, seed=d["seed"]) if method == "lhs" else qmc.Sobol(d=k, seed=d["seed"])
        return qmc.scale(eng.random(d["n"]), lo, hi)
    if method == "saltelli":
        from SALib.sample import sobol

        return sobol.sample(pr, d["n"], calc_second_order=False, seed=d["seed"])
    from SALib.sample import morris

    return morris.sample(pr, d["n"], num_levels=d["morris_levels"], seed=d["seed"])


def n_designs(study: Mapping) -> int:
    """Number of designs of the study (rows of `design_matrix`) without building it."""
    d, k = study["design"], len(study["parameters"])
    return {
        "grid": d["levels"] ** k,
        "lhs": d["n"],
        "sobol": d["n"],
        "saltelli": d["n"] * (k + 2),
        "morris": d["n"] * (k + 1),
    }[d["method"]]


def n_chunks(study: Mapping, limit: int = 0) -> int:
    """Number of chunk jobs: the designs (the first `limit` if limit > 0) in chunks of chunk_size."""
    n = n_designs(study) if not limit else min(limit, n_designs(study))
    return math.ceil(n / study["chunk_size"])


def chunk_rows(study: Mapping, chunk: int, limit: int = 0) -> np.ndarray:
    """Design indices (0-based rows of `design_matrix`) of chunk number `chunk` (0-based)."""
    n = n_designs(study) if not limit else min(limit, n_designs(study))
    cs = study["chunk_size"]
    if not 0 <= chunk < n_chunks(study, limit):
        raise ValueError(f"chunk {chunk} is outside 0..{n_chunks(study, limit) - 1}")
    return np.arange(chunk * cs, min(n, (chunk + 1) * cs))


def design_params(base: Params, study: Mapping, X: np.ndarray) -> list[Params]:
    """One `Params` per design row of X (n, k): `base` with the varied parameters set."""
    names = list(study["parameters"])
    return [base.replace(**{nm: float(v) for nm, v in zip(names, row)}) for row in np.atleast_2d(X)]


def chunk_study(study: Mapping) -> dict[str, Any]:
    """The parts of a study a chunk's numbers depend on (the chunk job's Snakemake params):
    changing the analysis section or resources re-runs no chunk."""
    return {k: copy.deepcopy(v) for k, v in study.items() if k not in ("analysis", "resources", "description")}
