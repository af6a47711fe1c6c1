"""The configuration checks a JSON schema cannot express: relations between keys (levels that
increase, a hold longer than its discard, intervals that are whole numbers of time steps, a robot
that can be built, runs whose plans the sweeps cover, goals no closer than the robot's size) and
what a job would cost (the sweep, two-pair and gravity jobs within the limits of `io.job_costs`).
`io.config.validate` runs them on every configuration before any work; the stages call
`section_errors` on the sections they are given. Each returns one message per problem, naming
the key.
"""

from __future__ import annotations

from collections.abc import Mapping

from ..physics.params import Params, rest_length
from ..physics.schedule import MAX_PRESSURE, whole_steps
from ..physics.twisted import MAX_VOLTAGE
from . import job_costs
from .formats import actuation

# the keys each job's cost grows with, the first named when several would lower it as much
JOBS = {
    "sweep": (
        job_costs.sweep,
        ("sweep.hold", "sweep.settle", "sweep.levels", "sweep.pairs", "sweep.contacts", "sim.record_every", "sim.dt"),
    ),
    "two_pair": (
        job_costs.two_pair,
        ("two_pair.hold", "two_pair.levels", "two_pair.pairs", "two_pair.record_every", "sim.dt", "sweep.contacts"),
    ),
    "gravity": (
        job_costs.gravity,
        (
            "locomotion.ramp_rate",
            "locomotion.interval",
            "gravity.settle",
            "gravity.max_pressure",
            "gravity.slopes",
            "gravity.headings",
            "gravity.pairs",
            "sim.dt",
        ),
    ),
}


def semantic_errors(cfg: dict, defaults: Mapping | None = None) -> list[str]:
    """Checks the schema cannot express; `cfg` has passed the schema. `defaults`, the schema's
    complete default configuration, lets a job over a cost limit name the key that costs most
    (without it the job's first key is named)."""
    out = level_errors(cfg, "sweep")
    levels = cfg["sweep"]["levels"]
    for i in range(1, len(levels)):
        if levels[i] <= levels[i - 1]:
            out.append(
                f"config key sweep.levels[{i}]: {levels[i]} is not greater than the "
                f"previous level {levels[i - 1]} (levels must be strictly increasing, {_unit(cfg)})"
            )
            break
    discard, hold = cfg["nominal"]["discard"], cfg["sweep"]["hold"]
    if discard >= hold:
        out.append(f"config key nominal.discard: {discard} s is not less than sweep.hold = {hold} s")
    p = cfg["params"]
    rest = rest_length(p["strut_length"], p["cable_pretension"], p["cable_stiffness"])
    if rest <= 0:
        out.append(
            f"config key params.cable_pretension: {p['cable_pretension']} N gives a cable "
            f"rest length L = l0 - T0/K = {rest:.4g} m, which must be positive"
        )
    elif p["muscle_min_length"] >= rest:
        out.append(
            f"config key params.muscle_min_length: {p['muscle_min_length']} m is not below "
            f"the cable rest length L = l0 - T0/K = {rest:.4g} m"
        )
    dt, interval = cfg["sim"]["dt"], cfg["locomotion"]["interval"]
    if not whole_steps(interval, dt):
        steps = interval / dt
        out.append(
            f"config key locomotion.interval: {interval:g} s is not a whole number of time steps "
            f"sim.dt = {dt:g} s ({steps:.4g} steps; e.g. {max(1, round(steps)) * dt:g} s)"
        )
    runs, contacts = cfg["locomotion"]["runs"], cfg["sweep"]["contacts"]
    missing = [c for c in ("equilateral", "isosceles") if c not in contacts]
    if runs and missing:
        # every demonstration run rolls onto faces of both kinds: its plans need both workspaces
        out.append(
            f"config key locomotion.runs: the demonstration runs {', '.join(runs)} roll over faces "
            f"of both kinds, but sweep.contacts = [{', '.join(contacts)}] leaves out "
            f"{' and '.join(missing)}, so the workspace has no curves to plan them with; add "
            f"{' and '.join(missing)} to sweep.contacts, or leave out the runs with "
            f"locomotion='{{runs: []}}'"
        )
    loc, strut = cfg["locomotion"], p["strut_length"]
    goal_runs = [r for r in loc["runs"] if r != "paper"]  # `paper` rolls over given edges
    if goal_runs and loc["goal_distance"] < strut:
        out.append(
            f"config key locomotion.goal_distance: {loc['goal_distance']} m is less than the strut length "
            f"params.strut_length = {strut} m: the runs {', '.join(goal_runs)} refuse a goal closer than "
            "the robot's size"
        )
    out += statics_errors(cfg)
    out += section_errors(cfg, "two_pair") + section_errors(cfg, "gravity")
    for estimate, keys in JOBS.values():
        out += job_costs.over_limit(estimate, cfg, defaults or cfg, keys)
    if not out:
        try:
            Params(**p)
        except ValueError as e:
            out.append(f"config key params: {e}")
    return out


def _unit(cfg: Mapping) -> str:
    """The unit of the actuation levels: MPa, or V with actuator.kind twisted_string."""
    return actuation.units(cfg.get("actuator", {}).get("kind", actuation.PNEUMATIC))


def level_errors(cfg: Mapping, section: str) -> list[str]:
    """The levels of `section` (sweep or two_pair) within the actuator's bound: a pressure at most
    schedule.MAX_PRESSURE MPa, a motor voltage at most twisted.MAX_VOLTAGE V (the schema allows
    the larger of the two); the levels are read in the unit of actuator.kind."""
    volts = _unit(cfg) == "V"
    top, what = (MAX_VOLTAGE, "V of the motors") if volts else (MAX_PRESSURE, "MPa of the pneumatic muscle")
    for i, v in enumerate(cfg[section]["levels"]):
        if v > top:
            hint = "" if volts else " (levels are in V only with actuator.kind: twisted_string)"
            return [f"config key {section}.levels[{i}]: {v} is greater than the maximum of {top:g} {what}{hint}"]
    return []


def statics_errors(cfg: Mapping) -> list[str]:
    """nominal.method statics solves the free-mode equilibrium of linear cables
    (`workspace.equilibria`): refused, naming the key, with sweep.mode grounded, a != 1 or the
    twisted-string actuator."""
    if cfg["nominal"].get("method", "averaging") != "statics":
        return []
    out, a = [], float(cfg["params"]["cable_exponent"])
    if a != 1.0:
        out.append(
            f"config key nominal.method: statics needs linear cables (params.cable_exponent = 1), got a = {a:g}; "
            "use nominal.method: averaging"
        )
    if cfg["sweep"]["mode"] != "free":
        out.append(
            f"config key nominal.method: statics is the free mode's equilibrium, but sweep.mode = "
            f"{cfg['sweep']['mode']}; use nominal.method: averaging"
        )
    if _unit(cfg) == "V":
        out.append(
            "config key nominal.method: statics solves the pneumatic muscle's equilibrium, but "
            "actuator.kind = twisted_string (a motor's stall is not built into the statics); use "
            "nominal.method: averaging"
        )
    return out


def section_errors(cfg: Mapping, section: str) -> list[str]:
    """What the schema cannot check in section `two_pair` (levels increasing, discard < hold, hold
    a whole number of recording intervals) or `gravity` (slopes increasing, validate_slopes among
    them, grid_step a whole number of ramp increments locomotion.ramp_rate x interval); one
    message per problem, naming the key. `cfg` holds the section and those it refers to."""
    out = []
    if section == "two_pair":
        s, dt = cfg["two_pair"], float(cfg["sim"]["dt"])
        lv = s["levels"]
        out += level_errors(cfg, "two_pair")
        bad = [i for i in range(1, len(lv)) if lv[i] <= lv[i - 1]]
        if bad:
            out.append(
                f"config key two_pair.levels[{bad[0]}]: {lv[bad[0]]} is not greater than "
                f"{lv[bad[0] - 1]} ({_unit(cfg)}, strictly increasing)"
            )
        if s["discard"] >= s["hold"]:
            out.append(f"config key two_pair.discard: {s['discard']} s is not less than two_pair.hold = {s['hold']} s")
        if not whole_steps(s["hold"], s["record_every"] * dt):
            out.append(
                f"config key two_pair.hold: {s['hold']} s is not a whole number of recording intervals "
                f"(two_pair.record_every x sim.dt = {s['record_every'] * dt:g} s)"
            )
    elif section == "gravity":
        g, loc = cfg["gravity"], cfg["locomotion"]
        if list(g["slopes"]) != sorted(g["slopes"]):
            out.append(f"config key gravity.slopes: {list(g['slopes'])} must be increasing (deg)")
        bad = [a for a in g["validate_slopes"] if a not in g["slopes"]]
        if bad:
            out.append(
                f"config key gravity.validate_slopes: {bad} deg are not among gravity.slopes {list(g['slopes'])}"
            )
        unit, top = (_unit(cfg), MAX_VOLTAGE if _unit(cfg) == "V" else MAX_PRESSURE)
        if g["max_pressure"] > top:
            hint = "" if unit == "V" else " (in V only with actuator.kind: twisted_string)"
            top_ = f"{top:g} {unit}{hint}"
            out.append(f"config key gravity.max_pressure: {g['max_pressure']} is greater than the maximum of {top_}")
        step = loc["ramp_rate"] * loc["interval"]
        if not whole_steps(g["grid_step"], step):
            out.append(
                f"config key gravity.grid_step: {g['grid_step']} {unit} is not a whole number of ramp "
                f"increments ({step:g} {unit} = locomotion.ramp_rate x locomotion.interval)"
            )
    else:
        raise ValueError(f"no cross-key checks for section {section!r}")
    return out
