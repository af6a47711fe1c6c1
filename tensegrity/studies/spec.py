"""A design study: its file (config/studies/<name>.yaml) validated against
tensegrity/io/study.schema.yaml, the design matrix it names and its chunks of designs.

`validate` checks the schema, then what it cannot say; every error is a `ConfigError` naming the
key (``study key parameters.cable_stiffness.low: ...``), raised before any job runs.
"""
from __future__ import annotations

import copy
import difflib
import functools
import itertools
import math
import os
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import jsonschema
import numpy as np

from ..io import config as cfgmod
from ..io.config import ConfigError
from ..physics.params import Params

SCHEMA_PATH = Path(__file__).resolve().parents[1] / "io" / "study.schema.yaml"
STUDY_DIR = Path("config", "studies")
# The unit of each parameter a study may vary (the configuration's `params`, docs/design.md §4).
UNITS = {"strut_length": "m", "strut_radius": "m", "strut_mass": "kg", "cable_stiffness": "N/m",
         "cable_pretension": "N", "cable_damping": "N s/m", "muscle_min_length": "m",
         "muscle_gain": "N/(MPa m)", "ground_stiffness": "N/m", "ground_damping": "N s/m",
         "friction": "1", "friction_stiffness": "N/m", "friction_damping": "N s/m"}
# Parameters that must be one number for the whole batch of a roll (lockstep.observe, contact).
NOT_IN_ROLLS = ("strut_radius", "strut_length")


@functools.lru_cache(maxsize=1)
def _validator():
    s = cfgmod.read_yaml(SCHEMA_PATH)
    cls = jsonschema.validators.validator_for(s)
    cls.check_schema(s)
    return cfgmod._extend_with_default(cls)(s), s


def _study_key(messages: list[str]) -> list[str]:
    return [m.replace("config key ", "study key ", 1).replace("config:", "study:", 1) for m in messages]


def _semantic(st: dict, base: Params, dt: float | None) -> list[str]:
    out = []
    for name, r in st["parameters"].items():
        key = f"study key parameters.{name}"
        if not r["low"] < r["high"]:
            out.append(f"{key}.high: {r['high']} is not greater than low = {r['low']}")
        if r["units"] != UNITS[name]:
            out.append(f"{key}.units: {r['units']!r} is not the unit of {name} ({UNITS[name]!r})")
    ws = st["workspace"]
    lv = ws["levels"]
    if any(b <= a for a, b in zip(lv, lv[1:])):
        out.append(f"study key workspace.levels: {lv} MPa are not strictly increasing")
    if dt is not None and abs(ws["hold"] / (dt * ws["sample_every"]) - round(ws["hold"] / (dt * ws["sample_every"]))) > 1e-6:
        out.append(f"study key workspace.hold: {ws['hold']} s is not a whole number of sampling intervals "
                   f"(workspace.sample_every = {ws['sample_every']} steps of sim.dt = {dt} s)")
    if ws["discard"] >= ws["hold"]:
        out.append(f"study key workspace.discard: {ws['discard']} s is not less than workspace.hold = {ws['hold']} s")
    if ws["enabled"] and not lv[0] <= ws["reference_pressure"] <= lv[-1]:
        out.append(f"study key workspace.reference_pressure: {ws['reference_pressure']} MPa is outside "
                   f"the levels {lv[0]}..{lv[-1]} MPa")
    if not ws["enabled"] and not st["roll"]["enabled"]:
        out.append("study key workspace.enabled: the study computes nothing (workspace and roll both disabled)")
    if st["roll"]["enabled"]:
        bad = [p for p in NOT_IN_ROLLS if p in st["parameters"]]
        if bad:
            out.append(f"study key parameters.{bad[0]}: cannot vary in a study with roll.enabled "
                       "(the batched roll needs one strut length and radius)")
    for o in st["analysis"]["outputs"]:
        part = "roll" if o.startswith("roll_") else "workspace"
        if not st[part]["enabled"]:
            out.append(f"study key analysis.outputs: {o!r} needs {part}.enabled: true")
    for p in st["analysis"]["response"]:
        if p not in st["parameters"]:
            out.append(f"study key analysis.response: {p!r} is not a varied parameter "
                       f"({', '.join(st['parameters'])})")
    if out:
        return out
    names = list(st["parameters"])  # every corner of the box must be a valid robot
    for corner in itertools.product(*[(st["parameters"][n]["low"], st["parameters"][n]["high"]) for n in names]):
        try:
            base.replace(**dict(zip(names, corner)))
        except ValueError as e:
            out.append(f"study key parameters: the corner {dict(zip(names, corner))} is not a valid robot: {e}")
            break
    return out


def validate(study: Mapping | None, base: Params | None = None, dt: float | None = None) -> dict:
    """Validated copy of a study (a mapping, as read from its YAML file) with every default
    filled in; `base` the parameters of the main configuration, `dt` its time step (s). Raises ConfigError listing every
    problem, each naming its key."""
    if not isinstance(study, Mapping):
        raise ConfigError(f"study: expected a mapping of sections, got {type(study).__name__}")
    val, sch = _validator()
    inst = cfgmod._coerce(sch, cfgmod._plain(study))
    errors = []
    for err in sorted(val.iter_errors(inst), key=cfgmod._sort_key):
        if list(err.absolute_path) == ["parameters"] and err.validator == "enum":  # not a key of `params`
            close = difflib.get_close_matches(str(err.instance), list(UNITS), n=1)
            hint = f"did you mean {close[0]!r}?" if close else f"known: {', '.join(UNITS)}"
            errors.append(f"config key parameters.{err.instance}: not a parameter a study can vary ({hint})")
            continue
        errors += cfgmod._schema_message(err)
    errors += cfgmod._nonfinite(inst)
    if errors:
        raise ConfigError(_study_key(errors))
    errors = _semantic(inst, base or Params(), dt)
    if errors:
        raise ConfigError(errors)
    if not inst["analysis"]["response"]:
        inst["analysis"]["response"] = list(inst["parameters"])[:2]
    return inst


def path_of(name: str, root: str | os.PathLike = ".") -> Path:
    """config/studies/<name>.yaml under `root`; ConfigError naming the known studies if absent."""
    p = Path(root) / STUDY_DIR / f"{name}.yaml"
    if not p.is_file():
        known = sorted(q.stem for q in (Path(root) / STUDY_DIR).glob("*.yaml"))
        raise ConfigError(f"config key study: no study file {p} (known studies: {', '.join(known) or 'none'})")
    return p


def load(name_or_path: str | os.PathLike, base: Params | None = None, root: str | os.PathLike = ".",
         dt: float | None = None) -> dict:
    """The validated study from a name (config/studies/<name>.yaml) or a YAML path; the key
    `name` is set to the file's stem."""
    p = Path(name_or_path)
    if p.suffix not in (".yaml", ".yml"):
        p = path_of(str(name_or_path), root)
    try:
        st = validate(cfgmod.read_yaml(p), base, dt)
    except ConfigError as e:
        raise ConfigError([f"{p}: {m}" for m in e.errors]) from None
    return {"name": p.stem, **st}


def problem(study: Mapping) -> dict:
    """The SALib problem: names, bounds (one [low, high] per parameter), num_vars."""
    names = list(study["parameters"])
    return {"num_vars": len(names), "names": names,
            "bounds": [[study["parameters"][n]["low"], study["parameters"][n]["high"]] for n in names]}


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
    return {"grid": d["levels"] ** k, "lhs": d["n"], "sobol": d["n"],
            "saltelli": d["n"] * (k + 2), "morris": d["n"] * (k + 1)}[d["method"]]


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
