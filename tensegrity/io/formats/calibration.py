"""The files of `tensegrity calibrate` (docs/datasets.md, "Calibration"): the calibrated
configuration (`calibrated_yaml`: a `params:` section every command and `snakemake --configfile`
accept) and the report (`calibration_dataset`: estimates, intervals, correlations, residuals,
the prediction check and the fit's provenance)."""

from __future__ import annotations

import numpy as np
import xarray as xr
import yaml

from ...calibration.fit import Calibration
from ...calibration.model import ACTUATOR
from ...physics import topology as topo
from .. import datasets
from .actuation import PNEUMATIC, TWISTED

__all__ = ["UNITS", "CALIBRATION_ALLOW_NAN", "calibration_dataset", "calibrated_yaml"]

# UDUNITS units of the Params fields a calibration may fit (docs/design.md §4)
UNITS = {
    "strut_length": "m",
    "strut_radius": "m",
    "strut_mass": "kg",
    "cable_exponent": "1",
    "cable_stiffness": "N m-1",
    "cable_pretension": "N",
    "cable_damping": "N s m-1",
    "muscle_min_length": "m",
    "muscle_gain": "N MPa-1 m-1",
    "gravity": "m s-2",
    "ground_stiffness": "N m-1",
    "ground_damping": "N s m-1",
    "friction": "1",
    "friction_stiffness": "N m-1",
    "friction_damping": "N s m-1",
    "strut_damping": "s-1",
}
# and of the twisted strings' keys (a run in volts; physics/twisted.py, config/README.md)
UNITS |= {
    ACTUATOR + k: u
    for k, u in {
        "rated_voltage": "V",
        "stall_torque": "N m",
        "stall_current": "A",
        "no_load_speed": "rad s-1",
        "no_load_current": "A",
        "gear_ratio": "1",
        "rotor_inertia": "kg m2",
        "viscous_friction": "N m s rad-1",
        "string_length": "m",
        "string_radius": "m",
        "spring_stiffness": "N m-1",
        "fibre_stiffness": "N m-1",
        "pretension": "N",
        "damping": "N s m-1",
    }.items()
}
_STATS = ("standard_error", "lower_95", "upper_95", "check_estimate")
CALIBRATION_ALLOW_NAN = ("measured", "residual", "relative_error", "correlation") + tuple(
    f"{k}_{s}" for k in UNITS for s in _STATS
)


def allow_nan(ds: xr.Dataset) -> list[str]:
    """The variables of a calibration report that may hold NaN (not determined, not measured)."""
    return [v for v in CALIBRATION_ALLOW_NAN if v in ds.variables]


def calibration_dataset(c: Calibration) -> xr.Dataset:
    """The report of calibration c: per fitted parameter its estimate, start, standard error,
    95 % interval (NaN: not determined) and the prediction check's estimate, in its own units;
    their relative standard errors and correlations; measured and simulated nodes (T, 12, 3) m
    in the world frame of the fit and the residual (NaN where not measured); attributes: the
    mode, the combinations not determined, what gave each interval (`interval_method`: linearised
    or profile), the residual RMS, the prediction check, the frame."""
    var = datasets.var
    n = len(c.names)
    check = c.prediction.get("estimate", np.full(n, np.nan))
    out = {}
    for j, k in enumerate(c.names):
        u = UNITS[k]
        out[k] = var((), c.estimate[j], u, f"calibrated {k}")
        out[f"{k}_start"] = var((), c.start[j], u, f"{k} the fit started from (the configuration)")
        out[f"{k}_standard_error"] = var((), c.unc.se[j], u, f"standard error of {k} (NaN: not determined)")
        how = {"interval_method": c.unc.method[j]}  # linearised, profile or windows (open below/above), none
        out[f"{k}_lower_95"] = var((), c.unc.lower[j], u, f"lower end of the 95 % interval of {k}", **how)
        out[f"{k}_upper_95"] = var((), c.unc.upper[j], u, f"upper end of the 95 % interval of {k}", **how)
        out[f"{k}_check_estimate"] = var((), check[j], u, f"{k} fitted on the first part only (prediction check)")
    R, o = c.problem.frame(c.x)
    resid = c.simulated - c.measured
    pred = {k: c.prediction.get(k, np.nan) for k in ("fit_until", "rms_fit_mm", "rms_predict_mm")}
    ds = xr.Dataset(
        {
            **out,
            "relative_error": var(("parameter",), c.unc.se / np.abs(c.estimate), "1", "standard error / estimate"),
            "correlation": var(("parameter", "parameter_b"), c.unc.corr, "1", "correlation of the estimates"),
            "measured": var(("time", "node", "axis"), c.measured, "m", "measured node positions, fit's world frame"),
            "simulated": var(("time", "node", "axis"), c.simulated, "m", "node positions, calibrated model"),
            "residual": var(("time", "node", "axis"), resid, "m", "simulated minus measured node position"),
            "frame_rotation": var(("axis", "axis_b"), R, "1", "rotation R of world = R measured + offset"),
            "frame_offset": var(("axis",), o, "m", "offset of world = R measured + offset"),
        },
        coords={
            "parameter": ("parameter", list(c.names), {"long_name": "fitted parameter"}),
            "parameter_b": ("parameter_b", list(c.names), {"long_name": "fitted parameter (second index)"}),
            "time": ("time", c.problem.m.t, {"units": "s", "long_name": "time"}),
            "node": ("node", np.arange(1, topo.N_NODES + 1), {"units": "1", "long_name": "node number"}),
            "axis": ("axis", ["x", "y", "z"], {"units": "1", "long_name": "world axis"}),
            "axis_b": ("axis_b", ["x", "y", "z"], {"units": "1", "long_name": "measurement axis"}),
        },
        attrs={
            "measured": c.problem.m.source,
            "mode": c.problem.mode,
            "residual": c.problem.residual,
            "fitted": ", ".join(c.names),
            "unknowns": ", ".join(c.problem.names[n:]) or "none",
            "not_determined": "; ".join(c.unc.undetermined) or "none",
            "interval_methods": "; ".join(f"{k}: {m}" for k, m in zip(c.names, c.unc.method, strict=True)),
            "profile_refits": c.unc.refits,
            "restarts": len(c.restarts),
            "restarted_by": "; ".join(c.restarts) or "none",
            "start_costs_m2": np.asarray(c.costs, float),
            "residual_rms_mm": c.rms_mm,
            "residual_sd_mm": c.unc.s * 1e3,
            "degrees_of_freedom": c.unc.dof,
            "singular_value_ratios": c.unc.singular,
            "check_fit_until_s": pred["fit_until"],
            "check_rms_fit_mm": pred["rms_fit_mm"],
            "check_rms_predict_mm": pred["rms_predict_mm"],
            "function_evaluations": c.nfev,
            "optimizer": f"scipy.optimize.least_squares trf: {c.message}",
        },
    )
    return ds


def calibrated_yaml(c: Calibration, header: str) -> str:
    """The calibrated configuration: a `params:` section (every field of the configuration's
    section, the fitted ones calibrated) after the comment lines `header`, for `--config FILE`
    and `snakemake --configfile FILE`; for a run in volts also `actuator.twisted_string` (every
    key of the strings, the fitted ones calibrated); `actuator.kind` is the run's (twisted_string
    for a run in volts, pneumatic for one in MPa), so that the commands and the pipeline drive the
    calibrated robot with its own actuator. Parameters the data could not determine keep a comment,
    and so do intervals given by the profile likelihood (the linearised ones are in the report)."""
    from ..config import validate

    section, params = validate({})["params"], c.params
    for k in section:
        section[k] = float(getattr(params, k))
    out = {"params": section, "actuator": {"kind": PNEUMATIC}}
    motors = c.motors
    if motors is not None:
        strings = {k: float(getattr(motors, k)) for k in validate({})["actuator"]["twisted_string"]}
        out["actuator"] = {"kind": TWISTED, "twisted_string": strings}
    lines = [f"# {h}" for h in header.splitlines()]
    lines += [f"# not determined by the measurement: {u}" for u in c.unc.undetermined]
    lines += [
        f"# 95 % interval of {k} by its profile likelihood{m[len('profile') :]}: [{lo:.6g}, {hi:.6g}]"
        for k, m, lo, hi in zip(c.names, c.unc.method, c.unc.lower, c.unc.upper, strict=True)
        if m.startswith("profile")
    ]
    lines += [
        f"# 95 % interval of {k} from refits on time windows (model discrepancy){m[len('windows') :]}: "
        f"[{lo:.6g}, {hi:.6g}]"
        for k, m, lo, hi in zip(c.names, c.unc.method, c.unc.lower, c.unc.upper, strict=True)
        if m.startswith("windows")
    ]
    return "\n".join(lines) + "\n" + yaml.safe_dump(out, sort_keys=False)
