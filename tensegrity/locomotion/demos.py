"""Locomotion runs as datasets (results/locomotion/*.nc), the workflow's demonstration runs,
and the `plan` and `roll` commands of the `tensegrity` command line. The planner and the
rolling loop are in `locomotion`."""
from __future__ import annotations

import math

import numpy as np
import xarray as xr

from ..physics import contact as ct
from ..io import datasets
from ..physics import dynamics as d
from ..physics import topology as topo
from ..physics.params import Params
from ..physics.terrain import Terrain
from .core import Run, Settings, Workspace, plan, roll_over, roll_to, settle


DEMOS = ("paper", "flat", "slope_up", "slope_down", "terrain")


def run_dataset(run: Run, terrain: Terrain, name: str = "") -> xr.Dataset:
    """A run as an xarray Dataset (design.md section 5, results/locomotion/*.nc): samples
    (time), steps (step, with the chosen pair(s) and pressures), the faces visited (visit) and
    the terrain, with units and long names. Nothing time-dependent (no wall time) is stored."""
    import xarray as xr
    rec, steps = run.record, run.steps
    n = len(steps)
    used = [st.used for st in steps]
    pairs = np.zeros((n, 2), np.int64)
    for i, r in enumerate(used):
        pairs[i, :len(r.pairs)] = r.pairs
    edge = np.array([st.plan.edge for st in steps], np.int64).reshape(n, 2)
    ds = xr.Dataset(
        {"nodes": datasets.var(("time", "node", "axis"), rec.nodes, "m", "node positions, world frame"),
         "cog": datasets.var(("time", "axis"), rec.cog, "m", "centre of gravity, world frame"),
         "pressure": datasets.var(("time", "pair"), rec.pressure, "MPa", "pressure applied to each actuator pair"),
         "contact_face": datasets.var(("time",), rec.face, "1", "face resting on the terrain (0: none)"),
         "face": datasets.var(("step",), np.array([st.face for st in steps], np.int64), "1", "face the step started on"),
         "next_face": datasets.var(("step",), np.array([st.face_after or 0 for st in steps], np.int64), "1",
                           "face the robot settled on after the step (0: none)"),
         "predicted_face": datasets.var(("step",), np.array([st.plan.next_face for st in steps], np.int64), "1",
                                "face the plan predicted (across the planned edge)"),
         "step_pair": datasets.var(("step", "slot"), pairs, "1", "actuator pair(s) driven in the step's rolling attempt (0: none)"),
         "planned_pressure": datasets.var(("step",), np.array([st.plan.pressure for st in steps]), "MPa",
                                  "least rolling pressure predicted by the workspace (NaN: no roll predicted)"),
         "tip_pressure": datasets.var(("step",), np.array([r.tip_pressure for r in used]), "MPa",
                              "pressure held when the robot tipped in the simulation (NaN: it did not roll)"),
         "peak_pressure": datasets.var(("step",), np.array([r.peak_pressure for r in used]), "MPa",
                               "highest pressure applied in the step's last attempt"),
         "edge": datasets.var(("step", "end"), edge, "1", "nodes of the planned edge"),
         "alignment": datasets.var(("step",), np.array([st.plan.alignment for st in steps]), "1",
                           "cosine between the planned edge's outward direction and the target direction"),
         "reach": datasets.var(("step",), np.array([st.plan.reach for st in steps]), "m",
                       "predicted margin at the workspace's highest level (negative: outside)"),
         "attempts": datasets.var(("step",), np.array([len(st.attempts) for st in steps], np.int64), "1",
                          "candidates tried in the step"),
         "t_start": datasets.var(("step",), np.array([st.attempts[0].t_start for st in steps]), "s", "start of the step"),
         "t_end": datasets.var(("step",), np.array([r.t_end for r in used]), "s", "end of the step (settled)"),
         "position": datasets.var(("step", "axis"), np.array([r.cog_after for r in used]).reshape(n, 3), "m",
                          "centre of gravity after the step, world frame"),
         "faces": datasets.var(("visit",), np.array(run.faces, np.int64), "1", "contact faces visited, in order"),
         "goal": datasets.var(("axis",), run.goal, "m", "goal, world frame (NaN: a run over given edges)"),
         "start": datasets.var(("axis",), run.start, "m", "centre of gravity at the start, world frame"),
         "terrain_heights": datasets.var(("tx", "ty"), terrain.heights, "m",
                                 "height field of the terrain (kind heightfield)")},
        coords={"time": ("time", rec.t, {"units": "s", "long_name": "time"}),
                "node": ("node", np.arange(1, 13), {"units": "1", "long_name": "node number"}),
                "pair": ("pair", np.arange(1, 13), {"units": "1", "long_name": "actuator pair number"}),
                "axis": ("axis", ["x", "y", "z"], {"units": "1", "long_name": "world axis"}),
                "step": ("step", np.arange(1, n + 1), {"units": "1", "long_name": "step number"}),
                "slot": ("slot", [1, 2], {"units": "1", "long_name": "pair slot (two pairs when combined)"}),
                "end": ("end", [1, 2], {"units": "1", "long_name": "edge end"}),
                "visit": ("visit", np.arange(1, len(run.faces) + 1), {"units": "1", "long_name": "visit number"})},
        attrs={"run": name, "outcome": run.outcome, "message": run.message, "rolls": run.rolls,
               "terrain_kind": terrain.kind, "terrain_normal": terrain.normal,
               "terrain_offset": float(terrain.offset), "terrain_origin": np.asarray(terrain.origin, float),
               "terrain_spacing": float(terrain.spacing)})
    return ds


def terrain_from_dataset(ds) -> Terrain:
    """The terrain a run dataset was simulated on."""
    return Terrain(kind=str(ds.attrs["terrain_kind"]), normal=np.asarray(ds.attrs["terrain_normal"], float),
                   offset=float(ds.attrs["terrain_offset"]), origin=tuple(np.asarray(ds.attrs["terrain_origin"], float)),
                   spacing=float(ds.attrs["terrain_spacing"]), heights=ds["terrain_heights"].values)


def demo_setup(cfg: dict, name: str) -> dict:
    """Terrain, goal or edges, and start of the demonstration run `name` (one of DEMOS) from
    the resolved configuration's `locomotion` section."""
    if name not in DEMOS:
        raise ValueError(f"unknown locomotion run {name!r}: use one of {DEMOS}")
    c = cfg["locomotion"]
    dist, head = float(c["goal_distance"]), math.radians(float(c["goal_heading"]))
    toward = dist * np.array([math.cos(head), math.sin(head)])
    if name == "paper":
        return {"terrain": Terrain.flat(), "edges": [(10, 12), (10, 11)]}
    if name == "flat":
        return {"terrain": Terrain.flat(), "goal": toward}
    if name in ("slope_up", "slope_down"):  # the slope rises toward +x
        sign = 1.0 if name == "slope_up" else -1.0
        return {"terrain": Terrain.slope(float(c["slope_angle"])), "goal": np.array([sign * dist, 0.0])}
    return {"terrain": Terrain.random(int(c["terrain_seed"]), size=2 * dist + 4.0,
                                      spacing=float(c["terrain_spacing"]),
                                      amplitude=float(c["terrain_amplitude"])), "goal": toward}


def locomotion_params(cfg: dict) -> Params:
    """Parameters of the rolling simulations: config `params` with locomotion.strut_damping."""
    from ..io.config import params_from_config
    return params_from_config(cfg).replace(strut_damping=float(cfg["locomotion"]["strut_damping"]))


def run_demo(cfg: dict, name: str, workspace_path, out_path):
    """Stage: the demonstration run `name` (one of DEMOS) from the workspace file; writes the
    run dataset to `out_path` and returns the path. Prints the steps and the outcome."""
    ws = Workspace.load(workspace_path)
    setup = demo_setup(cfg, name)
    params = locomotion_params(cfg)
    s = Settings.from_config(cfg["locomotion"], cfg["sim"]["dt"])
    if "edges" in setup:
        run = roll_over(ws, setup["edges"], params, setup["terrain"], settings=s)
    else:
        run = roll_to(ws, setup["goal"], params, setup["terrain"], settings=s)
    print(describe(run, name))
    cfg_prov = dict(datasets.provenance_config(workspace_path))
    cfg_prov.update(cfg)
    return datasets.write(run_dataset(run, setup["terrain"], name), out_path, cfg_prov,
                          f"Rolling locomotion run '{name}': {run.outcome}",
                          stage="locomotion", allow_nan=["planned_pressure", "tip_pressure", "goal"])


def describe(run: Run, name: str = "") -> str:
    """A few lines a person can read: the outcome and every step."""
    lines = [f"run {name}: {run.outcome} ({run.message}); {run.rolls} rolls, "
             f"{run.travelled:.2f} m travelled" + ("" if np.isnan(run.goal[0]) else
                                                   f", {run.distance_to_goal:.2f} m from the goal")]
    for k, st in enumerate(run.steps, 1):
        r = st.used
        lines.append(f"  step {k}: {topo.face_label(st.face)} -> "
                     f"{topo.face_label(st.face_after) if st.face_after else 'no face'}: planned "
                     f"{st.plan.pairs} at {st.plan.pressure:.2f} MPa over {st.plan.edge}; rolled by "
                     f"{r.pairs} at {r.tip_pressure:.2f} MPa (peak {r.peak_pressure:.2f}), "
                     f"{len(st.attempts)} attempt(s)")
    return "\n".join(lines)


# -------------------------------------------------------------------------- command line

def _floats(text: str, n: tuple[int, ...], what: str) -> np.ndarray:
    try:
        v = np.array([float(x) for x in str(text).replace(" ", "").split(",")])
    except ValueError:
        raise ValueError(f"{what} must be comma-separated numbers, got {text!r}") from None
    if not np.all(np.isfinite(v)):
        raise ValueError(f"{what} must be finite, got {text!r}")
    if v.size not in n:
        raise ValueError(f"{what} needs {' or '.join(map(str, n))} numbers, got {text!r}")
    return v


def _terrain_arg(text: str) -> Terrain:
    """flat | slope:ANGLE[:AZIMUTH] | random:SEED[:AMPLITUDE]"""
    kind, _, rest = text.partition(":")
    args = list(_floats(rest.replace(":", ","), (0, 1, 2), "terrain")) if rest else []
    if kind == "flat" and not args:
        return Terrain.flat()
    if kind == "slope" and 1 <= len(args) <= 2:
        return Terrain.slope(*args)
    if kind == "random" and 1 <= len(args) <= 2:
        return Terrain.random(int(args[0]), size=12.0, **({"amplitude": args[1]} if len(args) > 1 else {}))
    raise ValueError(f"terrain must be flat, slope:ANGLE[:AZIMUTH] or random:SEED[:AMPLITUDE], "
                     f"got {text!r}")


def add_cli(sub, parents=()) -> None:
    """Add the `plan` and `roll` subcommands to an argparse subparsers object. `parents`:
    parsers whose arguments they share; without one that defines --config, they get their own
    --config (and read --set overrides if a parent defines them)."""
    own_config = not any("--config" in p._option_string_actions for p in parents)
    for name, helptext in (("plan", "choose the pair and pressure that roll the robot toward a target"),
                           ("roll", "roll the robot toward a goal in the dynamic simulator")):
        p = sub.add_parser(name, help=helptext, description=helptext, parents=list(parents))
        p.add_argument("--workspace", default="results/workspace.nc", help="workspace file (results/workspace.nc)")
        if own_config:
            p.add_argument("--config", default=None, help="configuration file (default config/config.yaml)")
        p.add_argument("--face", default="9,10,12", help="contact face at the start: three node numbers or 1..20")
        p.add_argument("--terrain", default="flat", help="flat | slope:ANGLE[:AZIMUTH] | random:SEED[:AMPLITUDE]")
        p.add_argument("--yaw", type=float, default=0.0, help="turn of the robot about the terrain normal, deg")
        if name == "plan":
            tgt = p.add_mutually_exclusive_group(required=True)
            tgt.add_argument("--direction", help="target heading in deg from +x, or a vector x,y")
            tgt.add_argument("--goal", help="goal point x,y in m")
        else:
            p.add_argument("--goal", required=True, help="goal point x,y in m")
            p.add_argument("--out", help="write the run to this netCDF file")
        p.set_defaults(func=_cli_plan if name == "plan" else _cli_roll)


def _cli_common(a):
    from ..io import config
    cfg = config.load(a.config, overrides=getattr(a, "set", None) or None)
    face = _floats(a.face, (1, 3), "--face").astype(int)
    face = topo.face_number(int(face[0]) if face.size == 1 else tuple(face))
    terrain = _terrain_arg(a.terrain)
    params = locomotion_params(cfg)
    return cfg, face, terrain, params, Workspace.load(a.workspace)


def _cli_plan(a) -> int:
    cfg, face, terrain, params, ws = _cli_common(a)
    s = Settings.from_config(cfg["locomotion"], cfg["sim"]["dt"])
    state, _ = settle(params, d.stand_on(params, face, terrain, yaw_deg=a.yaw), terrain, s)
    nodes = d.nodes(state.x, state.q, params.strut_length)[0]
    here = ct.face_from_gaps(ct.clearance(nodes, terrain, float(params.strut_radius)), s.contact_tolerance)
    if a.goal is not None:
        pl = plan(ws, here, nodes, goal=_floats(a.goal, (2,), "--goal"), terrain=terrain,
                  combine=s.combine, min_alignment=s.min_alignment)
    else:
        v = _floats(a.direction, (1, 2), "--direction")
        v = np.array([math.cos(math.radians(v[0])), math.sin(math.radians(v[0]))]) if v.size == 1 else v
        pl = plan(ws, here, nodes, direction=v, terrain=terrain, combine=s.combine,
                  min_alignment=s.min_alignment)
    print(pl)
    return 0


def _cli_roll(a) -> int:
    cfg, face, terrain, params, ws = _cli_common(a)
    s = Settings.from_config(cfg["locomotion"], cfg["sim"]["dt"])
    run = roll_to(ws, _floats(a.goal, (2,), "--goal"), params, terrain, face=face, settings=s,
                  yaw_deg=a.yaw)
    print(describe(run))
    if a.out:
        datasets.write(run_dataset(run, terrain, "cli"), a.out, cfg, f"Rolling locomotion run: {run.outcome}",
                       stage="locomotion", allow_nan=["planned_pressure", "tip_pressure", "goal"])
    return 0 if run.outcome == "arrived" else 1
