"""The stages of the gravity-aware workspace, the slope limit and their validation (issue 10,
items 2 and 4), files to files, as `stages` does for the workspace pipeline. `cfg` holds the
sections of STAGE_CONFIG["gravity"] (params, sim, locomotion, gravity), merged over the inputs'
provenance. The rules are workflow/rules/gravity.smk.
"""
from __future__ import annotations

import os
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np
import xarray as xr

from .io import datasets, formats, gravity_formats as gf
from .io.cross_checks import section_errors
from .locomotion.demos import locomotion_params
from .physics import topology as topo

CONTACTS = list(topo.CONTACT_FACES)


def settings(cfg: Mapping) -> dict:
    """The ramp and limit settings from the config sections gravity, locomotion and sim; raises
    ValueError naming a bad key before any simulation (`io.cross_checks.section_errors`; the
    configuration's validation makes the same checks before any job)."""
    g, loc = cfg["gravity"], cfg["locomotion"]
    out = {"ramp_rate": float(loc["ramp_rate"]), "interval": float(loc["interval"]),
           "lift_tolerance": float(loc["lift_tolerance"]), "hold_time": float(loc["hold_time"]),
           "settle": float(g["settle"]), "max_pressure": float(g["max_pressure"]),
           "grid_step": float(g["grid_step"]), "dt": float(cfg["sim"]["dt"]),
           "iterations": int(g["iterations"]), "free_step": float(g["free_step"])}
    errors = section_errors(cfg, "gravity")
    if errors:
        raise ValueError("; ".join(errors))
    return out


def run_gravity(cfg: Mapping, out_path: str | os.PathLike, figure_path: str | os.PathLike | None = None) -> Path:
    """Stage `gravity`: the gravity-aware workspace of both contact cases
    (results/workspace_gravity.nc) and, if `figure_path`, its figure of tipping pressures."""
    from .workspace import gravity as gv
    s, g = settings(cfg), cfg["gravity"]
    params = locomotion_params(cfg)  # the rolling simulations' parameters
    sweeps = {}
    for contact in CONTACTS:
        sweeps[contact] = gv.run(params, topo.CONTACT_FACES[contact], g["pairs"], g["slopes"], g["headings"],
                                 s["ramp_rate"], s["max_pressure"], s["settle"], s["grid_step"],
                                 s["interval"], s["dt"], lift_tolerance=s["lift_tolerance"],
                                 hold_time=s["hold_time"])
        sw = sweeps[contact]
        print(f"{contact}: stands at {int(sw.stood.sum())} of {sw.stood.size} slope/heading cases; "
              f"{int(sw.rolled.sum())} of {sw.rolled.size} ramps rolled", flush=True)
    attrs = {k: v for k, v in s.items() if k in ("ramp_rate", "interval", "settle", "max_pressure",
                                                           "lift_tolerance", "hold_time")}
    ds = gf.gravity_dataset(sweeps, {f"{k}_setting": v for k, v in attrs.items()})
    path = datasets.write(ds, out_path, dict(cfg), "Gravity-aware workspace: single pairs ramped on flat ground "
                          "and slopes until the robot rolls", stage="gravity", allow_nan=gf.GRAVITY_ALLOW_NAN)
    if figure_path:
        _tip_figure(ds, figure_path)
    return path


def _tip_figure(ds: Any, figure_path: str | os.PathLike) -> None:
    from .render.gravity import tip_figure
    tip_figure(figure_path, [str(c) for c in ds["contact"].values], ds["slope"].values, ds["heading"].values,
               ds["tip_pressure"].values, ds["stood"].values.astype(bool), float(ds.attrs["max_pressure_setting"]))


def render_gravity(gravity_path: str | os.PathLike, figure_path: str | os.PathLike) -> Path:
    """The figure of tipping pressures of the gravity-aware workspace file `gravity_path`
    (results/workspace_gravity.nc), to `figure_path` (the workflow draws it in the job of the
    slope limit, which imports matplotlib anyway)."""
    _tip_figure(datasets.read(gravity_path), figure_path)
    return Path(figure_path)


class FreeLookup:
    """The free workspace as `workspace.slope_limit` reads it (`slope_limit.Lookup`)."""

    def __init__(self, ws: Any):  # locomotion.lookup.Workspace
        self.ws = ws
        self._actions: dict[int, list[tuple[int, ...]]] = {}

    def predict(self, face: int, nodes: np.ndarray, actions: Sequence[Sequence[int]]) -> Any:  # lookup.Prediction
        from .locomotion.lookup import predict
        return predict(self.ws, face, nodes, actions)

    def actions(self, face: int) -> list[tuple[int, ...]]:
        """The swept single pairs, then the two-pair combinations measured on `face`."""
        if face not in self._actions:
            singles = [(int(p),) for p in self.ws.pairs(face)]
            combos = [] if self.ws.combos is None else [tuple(int(q) for q in c) for c in self.ws.combos]
            self._actions[face] = singles + [c for c in combos if self.ws.measured(face, c) is not None]
        return self._actions[face]


def run_slope_limit(cfg: Mapping, gravity_path: str | os.PathLike, workspace_path: str | os.PathLike,
                    out_path: str | os.PathLike, figure_path: str | os.PathLike,
                    two_pair_path: str | os.PathLike | None = None) -> Path:
    """Stage `slope_limit`: results/slope_limit.nc and results/figures/slope_limit.png. With
    `two_pair_path` (results/workspace_two_pair.nc) the free prediction also tries the measured
    two-pair combinations; the simulated check drives single pairs only."""
    from .render.gravity import slope_limit_figure
    from .workspace import slope_limit as sl
    s = settings(cfg)
    src = datasets.read(gravity_path)
    ws = formats.read_workspace(workspace_path)
    if two_pair_path:
        from .io.two_pair_formats import read_two_pair
        ws = ws.with_two_pair(*read_two_pair(two_pair_path))
    params = locomotion_params(cfg)  # the rolling simulations' parameters
    lim = sl.limits(FreeLookup(ws), params, gf.sweeps_from_dataset(src), s)
    for k, kind in enumerate(lim.kinds):
        for c, contact in enumerate(lim.contacts):
            print(f"{kind:9s} {contact:12s} simulated " + " ".join(f"{v:5.1f}" for v in lim.simulated[k, c])
                  + " | free " + " ".join(f"{v:5.1f}" for v in lim.predicted_free[k, c]), flush=True)
    ds = gf.slope_limit_dataset(lim, {"friction_angle_deg": sl.friction_angle(params),
                                      "max_pressure_MPa": s["max_pressure"],
                                      "two_pair_combinations": int(two_pair_path is not None)})
    prov = {**datasets.provenance_config(src), **datasets.provenance_config(workspace_path), **cfg}
    path = datasets.write(ds, out_path, prov, "Slope limits: steepest slopes to stand, roll uphill and roll "
                          "downhill under control", stage="slope_limit", allow_nan=gf.SLOPE_LIMIT_ALLOW_NAN)
    slope_limit_figure(figure_path, lim.kinds, lim.contacts, lim.headings, lim.simulated, lim.predicted_free,
                       lim.predicted_gravity, sl.friction_angle(params), s["max_pressure"])
    return path


TITLE = "Validation of the gravity-aware workspace"


def validate_gravity(cfg: Mapping, gravity_path: str | os.PathLike, nominal_paths: Sequence[str | os.PathLike],
                     nc_path: str | os.PathLike, md_path: str | os.PathLike,
                     html_path: str | os.PathLike | None = None) -> list[Path]:
    """Stage `validate_gravity`: checks G.1-G.3 (`validation.gravity`) to
    results/validation/gravity.nc, .md and .html. Failed checks do not raise."""
    from .locomotion.control import RollSettings
    from .validation import gravity as vg, pages
    from .validation.common import CheckSettings
    s, g = settings(cfg), cfg["gravity"]
    src = datasets.read(gravity_path)
    sweeps = gf.sweeps_from_dataset(src)
    rc = vg.check_rolls(locomotion_params(cfg), sweeps, g["validate_slopes"],
                        RollSettings.from_config(cfg["locomotion"], s["dt"]), s["max_pressure"])
    flat = {}
    for p in nominal_paths:
        nd = datasets.read(p)
        contact = str(nd.attrs["contact"])
        if contact in sweeps:
            flat[contact] = vg.flat_comparison(sweeps[contact], {
                "pairs": list(nd["pair"].values), "levels": nd["pressure"].values, "cog": nd["cog"].values,
                "support": nd["support"].values, "margin": nd["margin"].values}, CheckSettings.grounded_tolerance)
    rows, st = vg.verdicts(rc, flat, float(g["tip_tolerance"]))
    for r in rows:
        print(f"  {r.id} {r.status}: {r.measured}", flush=True)
    var = datasets.var
    ds = xr.Dataset(
        {"contact_of_roll": (("roll",), rc.contact, {"long_name": "contact case of the roll"}),
         "slope": var(("roll",), rc.slope, "degree", "ground slope"),
         "heading": var(("roll",), rc.heading, "degree", "uphill direction in the face's support frame"),
         "pair": var(("roll",), rc.pair, "1", "pair driven"),
         "workspace_tip_pressure": var(("roll",), rc.workspace_tip, "MPa", "tipping pressure of the gravity-aware workspace"),
         "roll_tip_pressure": var(("roll",), rc.roll_tip, "MPa", "pressure of the grounded roll at which its CoG projection along gravity left the triangle"),
         "lift_tip_pressure": var(("roll",), rc.lift_tip, "MPa", "pressure held when a support node lifted in the roll (NaN: no roll)"),
         "difference": var(("roll",), rc.difference, "MPa", "absolute difference of the two tipping pressures"),
         "rolled_to": var(("roll",), rc.rolled_to, "1", "face the roll ended on (0: none)"),
         "in_plane_shift_max": var(("contact",), [flat[c].in_plane_max if flat.get(c) else np.nan for c in CONTACTS],
                                   "m", "largest in-plane CoG shift on flat ground against the free nominal CoG"),
         "status": (("check",), [st[k] for k in sorted(st)], {"long_name": "verdict of each check"})},
        coords={"check": ("check", sorted(st), {"long_name": "check number"}),
                "contact": ("contact", CONTACTS, {"long_name": "contact case"})})
    prov = {**datasets.provenance_config(src), **cfg}
    note = (f"Ramps at {s['ramp_rate']:g} MPa/s in steps of {s['interval']:g} s after {s['settle']:g} s at rest; "
            f"grounded rolls with the controller's settings (config locomotion) up to {s['max_pressure']:g} MPa.")
    tables = [pages.verdict_table(rows), vg.roll_table(rc)]
    lead = [pages.counts([r.status for r in rows]), note]
    paths = [datasets.write(ds, nc_path, prov, "Validation of the gravity-aware workspace", stage="validate_gravity",
                            allow_nan=["workspace_tip_pressure", "roll_tip_pressure", "lift_tip_pressure", "difference", "in_plane_shift_max"]),
             datasets.write_text(md_path, pages.markdown(TITLE, lead, tables))]
    if html_path:
        paths.append(datasets.write_text(html_path, pages.html_page(TITLE, lead, tables)))
    return paths
