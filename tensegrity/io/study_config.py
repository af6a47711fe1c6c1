"""Design-study files (config/studies/<name>.yaml) read and validated against
tensegrity/io/study.schema.yaml: `load`, `validate`, `path_of`.

`validate` checks the schema, then what it cannot say; every error is a `ConfigError` naming the
key (``study key parameters.cable_stiffness.low: ...``), raised before any job runs. Among them
the sample sizes the designs need: `sobol` and `saltelli` draw scipy's Sobol' sequence (of the
base sample, for saltelli), whose balance properties need n a power of 2 (scipy warns otherwise);
`morris` needs an even number of levels (SALib warns that the sample is biased otherwise) and at
least two trajectories (the spread sigma of one is undefined); and a chunk job within the limits
of `io.job_costs`.
"""

from __future__ import annotations

import difflib
import functools
import itertools
import os
from collections.abc import Mapping
from pathlib import Path

from ..physics.params import Params
from ..physics.schedule import whole_steps
from ..studies.spec import NOT_IN_ROLLS, UNITS
from . import config as cfgmod
from . import job_costs
from .config import ConfigError
from .schema_checks import check_against, filling_validator

SCHEMA_PATH = Path(__file__).with_name("study.schema.yaml")
STUDY_DIR = Path("config", "studies")


@functools.lru_cache(maxsize=1)
def _validator():
    s = cfgmod.read_yaml(SCHEMA_PATH)
    return filling_validator(s), s


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
    if dt is not None and not whole_steps(ws["hold"], dt * ws["sample_every"]):
        out.append(
            f"study key workspace.hold: {ws['hold']} s is not a whole number of sampling intervals "
            f"(workspace.sample_every = {ws['sample_every']} steps of sim.dt = {dt} s)"
        )
    if ws["discard"] >= ws["hold"]:
        out.append(f"study key workspace.discard: {ws['discard']} s is not less than workspace.hold = {ws['hold']} s")
    if ws["enabled"] and not lv[0] <= ws["reference_pressure"] <= lv[-1]:
        out.append(
            f"study key workspace.reference_pressure: {ws['reference_pressure']} MPa is outside "
            f"the levels {lv[0]}..{lv[-1]} MPa"
        )
    if ws["enabled"] and ws["method"] == "statics" and float(base.cable_exponent) != 1.0:
        out.append(
            f"study key workspace.method: statics needs linear cables (params.cable_exponent = 1), "
            f"got {float(base.cable_exponent)}"
        )
    if not ws["enabled"] and not st["roll"]["enabled"]:
        out.append("study key workspace.enabled: the study computes nothing (workspace and roll both disabled)")
    if st["roll"]["enabled"]:
        bad = [p for p in NOT_IN_ROLLS if p in st["parameters"]]
        if bad:
            out.append(
                f"study key parameters.{bad[0]}: cannot vary in a study with roll.enabled "
                "(the batched roll needs one strut length and radius)"
            )
    for o in st["analysis"]["outputs"]:
        part = "roll" if o.startswith("roll_") else "workspace"
        if not st[part]["enabled"]:
            out.append(f"study key analysis.outputs: {o!r} needs {part}.enabled: true")
    for p in st["analysis"]["response"]:
        if p not in st["parameters"]:
            out.append(f"study key analysis.response: {p!r} is not a varied parameter ({', '.join(st['parameters'])})")
    out += _sample_size(st["design"])
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


def _sample_size(d: Mapping) -> list[str]:
    """What scipy and SALib need of the sample size of design `d` (see the module's doc)."""
    n, method, out = d["n"], d["method"], []
    if method in ("sobol", "saltelli") and n & (n - 1):
        low = 1 << (n.bit_length() - 1)
        what = "the base sample of a saltelli design is" if method == "saltelli" else "a sobol design is"
        out.append(
            f"study key design.n: {n} is not a power of 2: {what} a scrambled Sobol' sequence, "
            f"balanced only for 2^m points (scipy.stats.qmc.Sobol); use {low} or {2 * low}"
        )
    if method == "morris":
        if n < 2:
            out.append(f"study key design.n: {n} Morris trajectory leaves the spread sigma undefined; use 2 or more")
        if d["morris_levels"] % 2:
            out.append(
                f"study key design.morris_levels: {d['morris_levels']} is odd; SALib's Morris sample is "
                "biased unless the number of levels is even"
            )
    return out


# the keys a chunk job's cost grows with, the first named when several would lower it as much
CHUNK_KEYS = (
    "chunk_size",
    "workspace.hold",
    "workspace.levels",
    "workspace.pairs",
    "workspace.contacts",
    "workspace.sample_every",
)


def _chunk_cost(st: dict, dt: float | None) -> list[str]:
    """A chunk job over a limit of `io.job_costs` (time step `dt`, default the schema's)."""
    dt = cfgmod.defaults()["sim"]["dt"] if dt is None else float(dt)
    val, sch = _validator()
    defaults = check_against(val, sch, {k: st[k] for k in ("parameters", "design")})[0]
    return job_costs.over_limit(lambda s: job_costs.study_chunk(s, dt), st, defaults, CHUNK_KEYS, "study key")


def validate(study: Mapping | None, base: Params | None = None, dt: float | None = None) -> dict:
    """Validated copy of a study (a mapping, as read from its YAML file) with every default
    filled in; `base` the parameters of the main configuration, `dt` its time step (s). Raises ConfigError listing every
    problem, each naming its key."""
    if not isinstance(study, Mapping):
        raise ConfigError(f"study: expected a mapping of sections, got {type(study).__name__}")
    val, sch = _validator()

    def unknown_parameter(err) -> list[str] | None:
        if list(err.absolute_path) == ["parameters"] and err.validator == "enum":  # not a key of `params`
            close = difflib.get_close_matches(str(err.instance), list(UNITS), n=1)
            hint = f"did you mean {close[0]!r}?" if close else f"known: {', '.join(UNITS)}"
            return [f"config key parameters.{err.instance}: not a parameter a study can vary ({hint})"]
        return None

    inst, errors = check_against(val, sch, study, unknown_parameter)
    if errors:
        raise ConfigError(_study_key(errors))
    errors = _semantic(inst, base or Params(), dt) or _chunk_cost(inst, dt)
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


def load(
    name_or_path: str | os.PathLike, base: Params | None = None, root: str | os.PathLike = ".", dt: float | None = None
) -> dict:
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
