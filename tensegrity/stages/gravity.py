"""Rules `gravity` and `slope_limit` (workflow/rules/gravity.smk): the gravity-aware workspace
(results/workspace_gravity.nc, its figure) and the slope limits (results/slope_limit.nc, its
figure). Their validation is rule `validate`'s (`stages.validate.validate_gravity`)."""

from __future__ import annotations

import os
from pathlib import Path

from ..io import datasets, formats, settings
from ..io.formats import gravity as gf
from ..physics import topology as topo
from ..workspace.gravity import GravitySetup
from . import provenance


def gravity(cfg: dict, out_path: str | os.PathLike) -> Path:
    """Stage `gravity`: the gravity-aware workspace of both contact cases, every pair of
    gravity.pairs on every slope and heading (results/workspace_gravity.nc)."""
    from ..workspace import gravity as gv

    setup, g = settings.build(GravitySetup, cfg), cfg["gravity"]
    params = settings.params(cfg)
    sweeps = {}
    for contact, face in topo.CONTACT_FACES.items():
        sw = sweeps[contact] = gv.run(params, face, g["pairs"], g["slopes"], g["headings"], setup)
        print(
            f"{contact}: stands at {int(sw.stood.sum())} of {sw.stood.size} slope/heading cases; "
            f"{int(sw.rolled.sum())} of {sw.rolled.size} ramps rolled",
            flush=True,
        )
    ds = gf.gravity_dataset(sweeps, setup)
    return datasets.write(
        ds,
        out_path,
        cfg,
        "Gravity-aware workspace: single pairs ramped on flat ground and slopes until the robot rolls",
        stage="gravity",
        allow_nan=gf.GRAVITY_ALLOW_NAN,
    )


def gravity_figure(cfg: dict, gravity_path: str | os.PathLike, figure_path: str | os.PathLike) -> Path:
    """Stage `gravity_figure`: the tipping pressures of the gravity-aware workspace file
    `gravity_path` (results/figures/workspace_gravity.png)."""
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
    with optimised actions of any set of pairs (`workspace.slope_multi`)."""
    from ..render.gravity import slope_limit_figure
    from ..workspace import slope_limit as sl
    from ..workspace.sensitivity import ActuationSettings
    from ..workspace.slope_multi import multi_limits

    setup = settings.build(GravitySetup, cfg)
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
    )
    act = settings.build(ActuationSettings, cfg)
    multi = multi_limits(ws, params, sweeps, lim, setup, act, int(cfg["gravity"]["multi_iterations"]))
    for k, kind in enumerate(lim.kinds):
        for c, contact in enumerate(lim.contacts):
            print(
                f"{kind:9s} {contact:12s} simulated "
                + " ".join(f"{v:5.1f}" for v in lim.simulated[k, c])
                + " | free "
                + " ".join(f"{v:5.1f}" for v in lim.predicted_free[k, c])
                + " | any set of pairs "
                + " ".join(f"{v:5.1f}" for v in multi.simulated[k, c]),
                flush=True,
            )
    ds = gf.slope_limit_dataset(
        lim,
        multi,
        {
            "friction_angle_deg": sl.friction_angle(params),
            "max_pressure_MPa": setup.max_pressure,
            "two_pair_combinations": int(two_pair_path is not None),
        },
    )
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
    )
    return path
