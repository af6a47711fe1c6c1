"""Rules `gravity` and `slope_limit` (workflow/rules/gravity.smk): the gravity-aware workspace
(results/workspace_gravity.nc, its figure) and the slope limits (results/slope_limit.nc, its
figure). Their validation is rule `validate`'s (`stages.validate.validate_gravity`)."""

from __future__ import annotations

import os
from pathlib import Path

from ..io import datasets, formats, settings
from ..io.formats import actuation
from ..io.formats import gravity as gf
from ..physics import topology as topo
from ..workspace.gravity import GravitySetup
from . import provenance


def gravity(cfg: dict, out_path: str | os.PathLike) -> Path:
    """Stage `gravity`: the gravity-aware workspace of both contact cases, every pair of
    gravity.pairs on every slope and heading (results/workspace_gravity.nc). With the
    twisted-string actuator (an `actuator` section in `cfg`) the ramp (locomotion.ramp_rate V/s,
    gravity.max_pressure and grid_step V) and the tipping levels are motor voltages, and the
    file says V (`formats.actuation`)."""
    from ..workspace import gravity as gv

    setup, g = settings.build(GravitySetup, cfg), cfg["gravity"]
    params, motors = settings.params(cfg), _motors(cfg)
    sweeps = {}
    for contact, face in topo.CONTACT_FACES.items():
        sw = sweeps[contact] = gv.run(params, face, g["pairs"], g["slopes"], g["headings"], setup, motors=motors)
        print(
            f"{contact}: stands at {int(sw.stood.sum())} of {sw.stood.size} slope/heading cases; "
            f"{int(sw.rolled.sum())} of {sw.rolled.size} ramps rolled",
            flush=True,
        )
    kind = actuation.PNEUMATIC if motors is None else actuation.TWISTED
    return datasets.write(
        actuation.relabel(gf.gravity_dataset(sweeps, setup), kind),
        out_path,
        cfg,
        "Gravity-aware workspace: single pairs ramped on flat ground and slopes until the robot rolls",
        stage="gravity",
        allow_nan=gf.GRAVITY_ALLOW_NAN,
    )


def gravity_figure(cfg: dict, gravity_path: str | os.PathLike, figure_path: str | os.PathLike) -> Path:
    """Stage `gravity_figure`: the tipping pressures (or motor voltages: the file's unit) of the
    gravity-aware workspace file `gravity_path` (results/figures/workspace_gravity.png)."""
    from ..render.gravity import tip_figure

    ds = datasets.read(gravity_path)
    return tip_figure(
        figure_path,
        [str(c) for c in ds["contact"].values],
        ds["slope"].values,
        ds["heading"].values,
        ds["tip_pressure"].values,
        ds["stood"].values.astype(bool),
        float(ds.attrs["max_pressure_setting"]),
        actuation.units(actuation.kind_of(ds)),
    )


def slope_limit(
    cfg: dict,
    gravity_path: str | os.PathLike,
    workspace_path: str | os.PathLike,
    out_path: str | os.PathLike,
    figure_path: str | os.PathLike,
    two_pair_path: str | os.PathLike | None = None,
) -> Path:
    """Stage `slope_limit`: results/slope_limit.nc and results/figures/slope_limit.png. With
    `two_pair_path` (results/workspace_two_pair.nc) the free prediction also tries the measured
    two-pair combinations; the simulated check drives single pairs only; beside it, the limit
    with optimised actions of any set of pairs (`workspace.slope_multi`). With the twisted-string
    actuator everything is in volts (the inputs must be too), but the optimised actions are not
    computed (NaN, the attribute `multi_not_computed` says why). Beside them, the uphill limit
    with actions of the 24 cables one by one (`slope_multi.uphill_limits`, gravity.cable_iterations
    bisection steps from simulated_multi; in volts NaN, `cables_not_computed` says why)."""
    from ..render.gravity import slope_limit_figure
    from ..workspace import slope_limit as sl
    from ..workspace.sensitivity import ActuationSettings
    from ..workspace.slope_multi import multi_limits, uphill_limits

    setup, motors = settings.build(GravitySetup, cfg), _motors(cfg)
    actuator = actuation.PNEUMATIC if motors is None else actuation.TWISTED
    _same_kind(actuator, gravity_path, workspace_path, two_pair_path)
    ws = formats.read_workspace(workspace_path, two_pair_path)
    params = setup.rolling(settings.params(cfg))
    sweeps = gf.read_gravity(gravity_path)
    lim = sl.limits(
        ws,
        params,
        sweeps,
        setup,
        iterations=int(cfg["gravity"]["iterations"]),
        free_step=float(cfg["gravity"]["free_step"]),
        motors=motors,
    )
    act = settings.build(ActuationSettings, cfg)
    # the optimised actions solve the statics of the muscles (eq. 1-2): none in volts
    multi_iterations = int(cfg["gravity"]["multi_iterations"]) if motors is None else 0
    multi = multi_limits(ws, params, sweeps, lim, setup, act, multi_iterations)
    cable_iterations = int(cfg["gravity"]["cable_iterations"]) if motors is None else 0
    cables = uphill_limits(ws, params, sweeps, lim, multi, setup, act.actuation_margin, cable_iterations)
    for k, kind in enumerate(lim.kinds):
        for c, contact in enumerate(lim.contacts):
            print(
                f"{kind:9s} {contact:12s} simulated "
                + " ".join(f"{v:5.1f}" for v in lim.simulated[k, c])
                + " | free "
                + " ".join(f"{v:5.1f}" for v in lim.predicted_free[k, c])
                + " | any set of pairs "
                + " ".join(f"{v:5.1f}" for v in multi.simulated[k, c])
                + (" | cables " + " ".join(f"{v:5.1f}" for v in cables[0][c]) if k == 1 else ""),
                flush=True,
            )
    unit = actuation.units(actuator)
    attrs = {
        "friction_angle_deg": sl.friction_angle(params),
        f"max_pressure_{unit}": setup.max_pressure,
        "two_pair_combinations": int(two_pair_path is not None),
    }
    if motors is not None:
        attrs["multi_not_computed"] = MULTI_NOT_IN_VOLTS
        attrs["cables_not_computed"] = CABLES_NOT_IN_VOLTS
    ds = actuation.relabel_texts(gf.slope_limit_dataset(lim, multi, attrs, cables), actuator)
    path = datasets.write(
        ds,
        out_path,
        provenance(cfg, gravity_path, workspace_path),
        "Slope limits: steepest slopes to stand, roll uphill and roll downhill under control",
        stage="slope_limit",
        allow_nan=gf.SLOPE_LIMIT_ALLOW_NAN,
    )
    slope_limit_figure(
        figure_path,
        lim.kinds,
        lim.contacts,
        lim.headings,
        lim.simulated,
        lim.predicted_free,
        lim.predicted_gravity,
        sl.friction_angle(params),
        setup.max_pressure,
        unit,
        multi=multi.simulated,
        cables=cables[0],
    )
    return path


MULTI_NOT_IN_VOLTS = (
    "the slope limit with optimised actions of any set of pairs (simulated_multi) is not computed "
    "with the twisted-string actuator: its actions are solved on the statics of the pneumatic "
    "muscles (eq. 1-2, workspace.sensitivity), which knows no motor stall"
)

CABLES_NOT_IN_VOLTS = (
    "the uphill limit with actions of the 24 cables (simulated_cables) is not computed with the "
    "twisted-string actuator: its actions are solved on the statics of the pneumatic muscles "
    "(eq. 1-2, workspace.cable_actions), which knows no motor stall"
)


def _motors(cfg: dict):
    """The twisted strings of `cfg` (an `actuator` section: `stage_config` adds it for
    twisted_string only), or None for the pneumatic muscles."""
    return settings.motors(cfg) if "actuator" in cfg else None


def _same_kind(kind: str, *paths) -> None:
    """ValueError naming the file if an input file is of another actuator than `kind` (the
    configured one): a slope limit of volts ramps read against a workspace of pressures has no
    unit."""
    for path in paths:
        if path is not None and (got := actuation.kind_of(datasets.read_attrs(path))) != kind:
            raise ValueError(
                f"{path} is of the {got} actuator, but config key actuator.kind is {kind}: "
                "make every input of the slope limit with one actuator.kind"
            )
