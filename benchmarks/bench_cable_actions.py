"""Would 24 independent cable actuators extend the uphill slope limit? (issue 30: actions "of the
24 cables one by one, as the prototype can"), by the statics, before any kernel change.

Per contact case (the equilateral and isosceles faces) and heading of the uphill direction in
the face's support frame, the steepest slope at which the statics (`workspace.cable_actions`:
the rigid robot posed on the slope, its grounded `sensitivity.Model`) find an action within
--max-pressure MPa (default: the config's gravity.max_pressure, the slope limit's) that puts the
CoG projection over an edge with an uphill component while it stays --margin m inside the other
two up to then (the criterion of `sensitivity.edge_action`), by three criteria:

- pairs, least total: `edge_action` on the 12 pair pressures (the actions whose simulation gives
  results/slope_limit.nc `simulated_multi`);
- pairs: also the deepest-crossing search (`cable_actions.reach_action`);
- cables: the same two searches on the 24 cable pressures, and the pair actions lifted.

and the statics' stand limit (the rigid robot's CoG projection inside its face at 0 MPa), above
which nothing climbs. Each limit is a scan up from 0 deg in --step deg to the first failure, then
--iterations bisection steps: printed as the slope found (the bracket's high end in
parentheses).

Beside them, by direct simulation of pair actions: with --gravity and --workspace
(results/workspace_gravity.nc, results/workspace.nc), the stand limit and `simulated_multi`
computed as the stage slope_limit does
(`slope_limit.limits`, `slope_multi.multi_limits`, 3 bisection steps), and the limit with the
statics' "pairs" actions and with their "cables" actions (`slope_multi.uphill_limits`, as the
stage computes simulated_cables: bisection from simulated_multi to the stand limit's high end, or
from 0 deg where simulated_multi is NaN, 4 steps); without them, stand and simulated_multi read
from --slope-limit if that file has them (else "-"). CPU time at the end.
Prints figures; asserts nothing.

--mujoco: where the cables' statics limit passes the pairs' by more than 1 deg, the cable action
the statics find at slopes between the two limits (up to the simulated stand limit) is ramped in
MuJoCo (`bridges.mjcf`: 24 actuators, one per cable; flat plane with gravity tilted by the slope,
strut damping 0 as the export needs; the ramp of the slope limit without its holds where a node
lifts), judged as `slope_limit._sim_ok` judges (`gravity.tip`: the first edge the projection
crosses, uphill if its outward normal has an uphill component); as a control, the pair action of
the pairs' limit at the same slopes, in MuJoCo and in our simulator. MuJoCo's contact is its own
(pyramidal cones, soft constraints), not ours: where it rolls that control too, it does not tell
cables from pairs.

--ours [SLOPE ...]: the same cases, in our simulator (it takes one pressure per cable): the cable
action the statics find at each slope (default: as --mujoco's, else the slopes given, deg) and, as
the controls, the pair action of the pairs' limit lifted to its cables (the same bits as per pair)
and the cable action's pairs (each pair it uses on both cables, at its larger cable's pressure),
ramped as the slope limit ramps (`gravity.ramp`, its holds where a node lifts; all in one batch),
judged as `slope_limit._sim_ok` judges.

Usage: .venv/bin/python benchmarks/bench_cable_actions.py [--contacts equilateral isosceles]
       [--headings 0 45 ...] [--step 1] [--iterations 4] [--max-pressure 5]
       [--gravity results/workspace_gravity.nc --workspace results/workspace.nc]
       [--slope-limit results/slope_limit.nc] [--mujoco] [--ours [SLOPE ...]] [--tiny]
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np

from tensegrity.io import config
from tensegrity.io import settings as io_settings
from tensegrity.physics import topology as topo
from tensegrity.workspace import cable_actions as ca
from tensegrity.workspace.gravity import GravitySetup
from tensegrity.workspace.sensitivity import ActuationSettings


def _read(path: str, contacts: list[str], headings: list[float]) -> dict:
    """(contact, heading) -> {"stand": (lo, hi), "multi": (lo, hi)[, "cables": (lo, hi)]} deg from
    a slope_limit.nc (uphill simulated_multi and its high end; the stand limit's bracket;
    simulated_cables and its high end if the file has them); {} if no file or no
    simulated_multi."""
    if not Path(path).exists():
        return {}
    import xarray as xr

    ds = xr.open_dataset(path)
    if "simulated_multi" not in ds:
        return {}
    out = {}
    for c in contacts:
        for h in headings:
            if c in ds.contact.values and h in ds.heading.values:
                up, st = {"kind": "uphill", "contact": c, "heading": h}, {"kind": "stand", "contact": c, "heading": h}
                out[c, h] = {
                    "stand": (float(ds["simulated"].sel(st)), float(ds["simulated_high"].sel(st))),
                    "multi": (float(ds["simulated_multi"].sel(up)), float(ds["simulated_multi_high"].sel(up))),
                }
                if "simulated_cables" in ds:  # the stage's, cable_iterations steps
                    ch = {"contact": c, "heading": h}
                    lo, hi = ds["simulated_cables"].sel(ch), ds["simulated_cables_high"].sel(ch)
                    out[c, h]["cables"] = (float(lo), float(hi))
    return out


def _simulate(a, params, setup, contacts: list[str], headings: list[float], margin: float) -> dict:
    """As `_read`, computed (module docstring), with "pairs" and "cables": the brackets with the
    statics' pair and cable actions (`slope_multi.uphill_limits`, as the stage computes
    simulated_cables)."""
    from tensegrity.io import formats
    from tensegrity.io.formats import gravity as gf
    from tensegrity.workspace import slope_limit as sl
    from tensegrity.workspace.slope_multi import multi_limits, uphill_limits

    sweeps = gf.read_gravity(a.gravity)
    sweeps = {c: sweeps[c] for c in contacts}
    for c in contacts:
        if not np.array_equal(sweeps[c].headings, headings):
            raise SystemExit(f"{a.gravity}: headings {sweeps[c].headings.tolist()} are not --headings {headings}")
    look = formats.read_workspace(a.workspace)
    lim = sl.limits(look, params, sweeps, setup, 3)
    m = multi_limits(look, params, sweeps, lim, setup, ActuationSettings(margin), 3)
    pairs = uphill_limits(look, params, sweeps, lim, m, setup, margin, 4, "pairs")
    cables = uphill_limits(look, params, sweeps, lim, m, setup, margin, 4, "cables")
    out = {}
    for c, contact in enumerate(lim.contacts):
        for j, h in enumerate(headings):
            out[contact, h] = {
                "stand": (lim.simulated[0, c, j], lim.simulated_high[0, c, j]),
                "multi": (m.simulated[1, c, j], m.simulated_high[1, c, j]),
                "pairs": (pairs[0][c, j], pairs[1][c, j]),
                "cables": (cables[0][c, j], cables[1][c, j]),
            }
    return out


def _mujoco_tip(params, setup: GravitySetup, face: int, slope: float, heading: float, w24: np.ndarray) -> str:
    """The ramp s w24 (cable pressures) in MuJoCo (module docstring): 'uphill 4.37 MPa (11-12)',
    'not uphill ...', 'no tip' or 'does not stand'."""
    import mujoco

    from tensegrity.bridges.mjcf import mjcf
    from tensegrity.physics.terrain import Terrain
    from tensegrity.workspace import gravity as gv
    from tensegrity.workspace import slope_limit as sl
    from tensegrity.workspace.slopes import gravity_frame, place

    p0 = params.replace(strut_damping=0.0)
    g, th = float(p0.gravity), np.radians(slope)
    xml = mjcf(p0, "grounded", setup.dt, place(p0, face, Terrain.flat(), (0.0, 0.0), heading))
    old = f'gravity="0 0 {-g!r}"'
    assert old in xml
    model = mujoco.MjModel.from_xml_string(
        xml.replace(old, f'gravity="{float(-g * np.sin(th))!r} 0 {float(-g * np.cos(th))!r}"')
    )
    data = mujoco.MjData(model)
    sites = [mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_SITE, f"node{n + 1}") for n in range(topo.N_NODES)]
    rot = np.array([[np.cos(th), 0, -np.sin(th)], [0, 1, 0], [np.sin(th), 0, np.cos(th)]])  # plane -> slope
    level, n_settle = setup.levels()
    shapes = {"pressure": (), "cog": (3,), "support": (3, 3), "proj": (2,), "margin": ()}
    rec = {k: np.full((1, level.size, *v), np.nan) for k, v in shapes.items()}
    gone = level.size
    for t in range(level.size):
        data.ctrl[:] = np.minimum(level[t] * w24, 10.0)
        mujoco.mj_step(model, data, nstep=int(round(setup.interval / setup.dt)))
        out = gravity_frame(data.site_xpos[sites] @ rot.T, face)
        rec["pressure"][0, t] = level[t]
        for k, v in zip(("cog", "support", "proj", "margin"), out):
            rec[k][0, t] = v
        if t + 1 == n_settle and out[3] <= 0:
            return "does not stand"
        if out[3] < -gv.FALLING:
            gone = t + 1
            break
    p, k, e = gv.tip(rec, 0, face, n_settle, gone)
    if e is None:
        return "no tip"
    u = np.array([np.cos(np.radians(heading)), np.sin(np.radians(heading))])
    up = float(np.dot(sl.direction(rec["support"][0, k], face, e), u)) > 0
    return f"{'uphill' if up else 'not uphill'} {p:.2f} MPa ({e[0]}-{e[1]})"


def _gains(rows: list):
    """The poses of `rows` where the cables' statics limit lies over 1 deg above the pairs' (which
    have an action): contact, heading, the limits, face, pairs' and cables' limit deg, and the
    cables' limit capped at the simulated stand limit."""
    for contact, h, lim, s in rows:
        lo, hi = lim["pairs"][0], lim["cables"][0]
        if hi - lo > 1.0 and lim["pairs"][2] is not None:
            top = min(hi, s["stand"][0]) if "stand" in s else hi
            yield contact, h, lim, topo.face_number(topo.CONTACT_FACES[contact]), lo, hi, top


def _mujoco(rows: list, params, setup: GravitySetup, margin: float) -> None:
    """The --mujoco table (module docstring)."""
    from tensegrity.workspace import slope_limit as sl

    print("\n| contact | heading deg | slope deg | cable action, MuJoCo | pair action, ours | pair action, MuJoCo |")
    print("|---|---|---|---|---|---|")
    for contact, h, lim, face, lo, hi, top in _gains(rows):
        if top - lo <= 1.0:  # the cables' gain lies above the simulated stand limit
            print(f"| {contact} | {h:g} | {lo:.1f}-{hi:.1f} | above the simulated stand limit {top:.1f} deg | | |")
            continue
        pair = lim["pairs"][2].weights
        for slope in np.round(np.linspace(lo, top, 4), 1):
            c = ca.verdict(params, face, float(slope), h, setup.max_pressure, margin).actions.get("cables")
            cab = _mujoco_tip(params, setup, face, float(slope), h, c.weights) if c is not None else "no action"
            ok, tip, _ = sl._sim_ok(None, params, 1, face, np.array([slope]), np.array([h]), pair[None], setup)
            ours = f"uphill {tip[0]:.2f} MPa" if ok[0] else "no uphill roll"
            mj = _mujoco_tip(params, setup, face, float(slope), h, topo.cable_levels(pair))
            print(f"| {contact} | {h:g} | {slope:.1f} | {cab} | {ours} | {mj} |")


def _ours_tips(params, setup: GravitySetup, face: int, slopes, heading: float, w24: np.ndarray) -> list[str]:
    """The ramps s w24[j] (cable pressures (J, 24)) on slopes[j] deg in our simulator, in one batch
    (module docstring): per robot a string as `_mujoco_tip`'s."""
    from tensegrity.physics import dynamics as d
    from tensegrity.workspace import gravity as gv
    from tensegrity.workspace import slope_limit as sl
    from tensegrity.workspace.slopes import place, slope_field

    terrain, centres = slope_field(slopes)
    state = d.State.concat([place(params, face, terrain, c, heading) for c in centres])
    level, n_settle = setup.levels()
    rec, gone = gv.ramp(params, terrain, face, state, w24, level, n_settle, setup)
    u = np.array([np.cos(np.radians(heading)), np.sin(np.radians(heading))])
    out = []
    for j in range(len(slopes)):
        p, k, e = gv.tip(rec, j, face, n_settle, gone[j])
        if gone[j] <= n_settle or e is None:
            out.append("does not stand" if gone[j] <= n_settle else "no tip")
            continue
        up = float(np.dot(sl.direction(rec["support"][j, k], face, e), u)) > 0
        out.append(f"{'uphill' if up else 'not uphill'} {p:.2f} MPa ({e[0]}-{e[1]})")
    return out


def _ours(rows, params, setup: GravitySetup, margin: float, given: list[float]) -> None:
    """The --ours table (module docstring)."""
    print(
        "\n| contact | heading deg | slope deg | cable action | cable action, ours | its pairs, ours "
        "| pair action, ours |"
    )
    print("|---|---|---|---|---|---|---|")
    for contact, h, lim, face, lo, _hi, top in _gains(rows):
        slopes = np.array(given, float) if given else np.round(np.linspace(lo, top, 4), 1)
        acts = [ca.verdict(params, face, float(m), h, setup.max_pressure, margin).actions.get("cables") for m in slopes]
        have = [i for i, c in enumerate(acts) if c is not None]
        pair = topo.cable_levels(lim["pairs"][2].weights)
        cables = np.array([acts[i].weights for i in have]).reshape(-1, topo.N_CABLES)
        pairs = topo.cable_levels(cables[:, topo.PAIR_CABLES].max(-1))  # both cables of each pair used
        w = np.concatenate([cables, pairs, np.tile(pair, (slopes.size, 1))])
        tips = _ours_tips(params, setup, face, np.concatenate([slopes[have], slopes[have], slopes]), h, w)
        n = len(have)
        cab, its = dict(zip(have, tips[:n])), dict(zip(have, tips[n : 2 * n]))
        for i, m in enumerate(slopes):
            cells = (f"{m:.1f}", _action(acts[i]), cab.get(i, "no action"), its.get(i, "-"), tips[2 * n + i])
            print(f"| {contact} | {h:g} | {' | '.join(cells)} |")


def _action(a) -> str:
    if a is None:
        return "-"
    used = np.flatnonzero(a.weights)
    what = "cables" if a.weights.size == topo.N_CABLES else "pairs"
    return f"{used.size} {what} over {a.edge[0]}-{a.edge[1]} at {a.scale:.2f} MPa"


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--contacts", nargs="+", default=list(topo.CONTACTS), choices=topo.CONTACTS)
    ap.add_argument("--headings", nargs="+", type=float, default=None, help="deg (default: the config's)")
    ap.add_argument("--step", type=float, default=1.0, help="deg, the scan's step")
    ap.add_argument("--iterations", type=int, default=4, help="bisection steps after the scan")
    ap.add_argument("--max-pressure", type=float, default=None, help="MPa (default: gravity.max_pressure)")
    ap.add_argument("--slope-limit", default="results/slope_limit.nc", help="stand, simulated_multi from here")
    ap.add_argument("--gravity", default=None, help="results/workspace_gravity.nc: simulate (with --workspace)")
    ap.add_argument("--workspace", default=None, help="results/workspace.nc")
    ap.add_argument("--mujoco", action="store_true", help="ramp the cable actions in MuJoCo (docstring)")
    ap.add_argument("--ours", nargs="*", type=float, default=None, help="ramp them in our simulator (docstring)")
    ap.add_argument("--tiny", action="store_true", help="isosceles, heading 90, step 12 deg, 1 bisection step")
    a = ap.parse_args()
    cfg = config.load()
    setup = io_settings.build(GravitySetup, cfg)
    params = setup.rolling(io_settings.params(cfg))
    margin = io_settings.build(ActuationSettings, cfg).actuation_margin
    top = setup.max_pressure if a.max_pressure is None else a.max_pressure
    headings = [float(h) for h in (cfg["gravity"]["headings"] if a.headings is None else a.headings)]
    if a.tiny:
        a.contacts, headings, a.step, a.iterations = ["isosceles"], [90.0], 12.0, 1
    if a.step <= 0 or a.iterations < 0:
        ap.error("--step must be positive and --iterations not negative")
    if (a.gravity is None) != (a.workspace is None):
        ap.error("--gravity and --workspace go together")
    c0 = time.process_time()
    if a.gravity is not None:
        sim, source = _simulate(a, params, setup, a.contacts, headings, margin), "simulated here"
    else:
        sim, source = _read(a.slope_limit, a.contacts, headings), f"read from {a.slope_limit}"
    c1 = time.process_time()
    print(
        f"uphill limits by the statics, up to {top:g} MPa, margin {margin * 1e3:g} mm, scan {a.step:g} deg + "
        f"{a.iterations} bisection steps; by simulation: {source if sim else '(none)'}\n"
    )
    print(
        "| contact | heading deg | stand deg | pairs, least total deg | pairs deg | cables deg "
        "| sim. stand deg | simulated_multi deg | sim. with pairs deg | sim. with cables deg "
        "| cable action at its limit |"
    )
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    rows = []
    for contact in a.contacts:
        face = topo.face_number(topo.CONTACT_FACES[contact])
        for h in headings:
            lim = ca.limit(params, face, h, top, margin, a.step, a.iterations)
            s = sim.get((contact, h), {})
            rows.append((contact, h, lim, s))
            cells = [f"{lim[c][0]:.1f} ({lim[c][1]:.1f})" for c in ("stand", *ca.CRITERIA)]
            cells += [
                f"{s[k][0]:.1f} ({s[k][1]:.1f})" if k in s else "-" for k in ("stand", "multi", "pairs", "cables")
            ]
            print(f"| {contact} | {h:g} | {' | '.join(cells)} | {_action(lim['cables'][2])} |")
    print()
    for contact in a.contacts:
        got = [(h, lim) for c, h, lim, _ in rows if c == contact]
        for crit in ca.CRITERIA:
            v = np.array([lim[crit][0] for _, lim in got])
            print(
                f"{contact}, {crit}: {np.nanmin(v):.1f}-{np.nanmax(v):.1f} deg; headings >= 20 deg: "
                f"{[h for h, lim in got if lim[crit][0] >= 20] or 'none'}, >= 24 deg: "
                f"{[h for h, lim in got if lim[crit][0] >= 24] or 'none'}"
            )
        gain = np.array([lim["cables"][0] - lim["pairs"][0] for _, lim in got])
        print(f"{contact}: cables - pairs {np.nanmin(gain):.1f} to {np.nanmax(gain):.1f} deg")
        for crit, key in (("pairs_least", "multi"), ("pairs", "pairs"), ("stand", "stand")):
            err = np.array([lim[crit][0] - s[key][0] for c, _, lim, s in rows if c == contact and key in s])
            if np.isfinite(err).any():
                print(
                    f"{contact}: statics {crit} - simulated ({key}): mean {np.nanmean(err):+.1f} deg, "
                    f"{np.nanmin(err):+.1f} to {np.nanmax(err):+.1f} deg"
                )
    if a.mujoco:
        _mujoco(rows, params, setup, margin)
    if a.ours is not None:
        _ours(rows, params, setup, margin, a.ours)
    print(f"\nCPU {time.process_time() - c0:.1f} s (the simulations {c1 - c0:.1f} s)")


if __name__ == "__main__":
    main()
