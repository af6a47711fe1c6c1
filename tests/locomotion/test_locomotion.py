"""tensegrity.locomotion: workspace lookup, planner, rolls and runs (issue 4, items 2-4).

The workspace here is computed once per session by the independent static solver
(tensegrity.physics.statics) at 0.8..4.8 MPa; it agrees with the dynamic free-mode workspace of the
pipeline to 0.03 mm. Expected pressures come from it: #10 tips the robot off (9,10,12) at
4.2 MPa, #11 off (10,11,12) at 2.2 MPa (design.md section 4).
"""

import math

import numpy as np
import pytest
import xarray as xr

from tensegrity import cli
from tensegrity import locomotion as lo
from tensegrity.io import datasets, formats
from tensegrity.io.formats import run as run_formats
from tensegrity.physics import contact as ct
from tensegrity.physics import dynamics as d
from tensegrity.physics import frames
from tensegrity.physics import topology as topo
from tensegrity.physics.params import Params
from tensegrity.physics.terrain import Terrain

EQUI = topo.face_number(topo.CONTACT_FACES["equilateral"])  # (9,10,12)
ISO = topo.face_number(topo.CONTACT_FACES["isosceles"])  # (10,11,12)

LEVELS = [0.8, 1.6, 2.4, 3.2, 4.0, 4.8]
NEXT = topo.face_number((6, 10, 11))
DAMPED = Params(strut_damping=1.0)  # the rolling runs' default (config locomotion.strut_damping)


def as_dataset(ws):
    """The workspace with the contract of results/workspace.nc (design.md section 5)."""

    def var(dims, data, units):
        return (dims, data, {"units": units, "long_name": "x"})

    return xr.Dataset(
        {
            "cog": var(("face", "pair", "pressure", "axis"), ws.cog, "m"),
            "support": var(("face", "pair", "pressure", "corner", "axis"), ws.support, "m"),
            "margin": var(("face", "pair", "pressure"), frames.margin_2d(ws.cog[..., :2], ws.support[..., :2]), "m"),
            "face_nodes": var(("face", "corner"), topo.FACES + 1, "1"),
        },
        coords={
            "face": ("face", np.arange(1, 21), {"units": "1", "long_name": "face"}),
            "pair": ("pair", np.arange(1, 13), {"units": "1", "long_name": "pair"}),
            "pressure": ("pressure", ws.levels, {"units": "MPa", "long_name": "pressure"}),
            "corner": ("corner", [1, 2, 3], {"units": "1", "long_name": "corner"}),
            "axis": ("axis", ["x", "y", "z"], {"units": "1", "long_name": "axis"}),
        },
    )


@pytest.fixture(scope="module")
def ws_path(ws, tmp_path_factory):
    path = tmp_path_factory.mktemp("ws") / "workspace.nc"
    return datasets.write(as_dataset(ws), path, {}, "test workspace")


def standing(face, terrain=None, yaw=0.0):
    s = d.stand_on(Params(), face, terrain or Terrain.flat(), yaw_deg=yaw)
    return d.nodes(s.x, s.q, 0.5)[0]


def outward(nodes, face, edge):
    k = [topo.edge_nodes(face, j) for j in range(3)].index(edge)
    return ct.edge_outward(nodes[topo.FACES[face - 1]])[k]


# ------------------------------------------------------------------------- workspace, plan


def test_workspace_file_round_trip(ws, ws_path):
    back = formats.read_workspace(ws_path)
    assert np.array_equal(back.levels, ws.levels)
    assert np.allclose(back.cog, ws.cog, atol=0) and np.allclose(back.support, ws.support, atol=0)
    assert back.max_pressure == 4.8
    assert list(back.pairs(EQUI)) == list(range(1, 13))


@pytest.mark.parametrize("face", [EQUI, ISO, 3, 17])
def test_prediction_on_flat_ground_is_the_workspace(ws, face):
    """Standing symmetric on flat ground, the current frame is the workspace's frame and
    gravity is its -z: predict must return the workspace's own margins."""
    pred = lo.predict(ws, face, standing(face), [(p,) for p in range(1, 13)])
    expect = frames.margin_2d(ws.cog[face - 1, ..., :2], ws.support[face - 1, ..., :2])
    assert np.allclose(pred.margin[:, 1:], expect, atol=1e-12)
    assert np.allclose(pred.margin[:, 0], ct.judge(standing(face), face).margin, atol=1e-12)


def test_prediction_on_a_slope_moves_the_projection_downhill_by_h_tan(ws):
    angle = 10.0
    flat = lo.predict(ws, EQUI, standing(EQUI), [(10,)])
    slope = lo.predict(ws, EQUI, standing(EQUI, Terrain.slope(angle)), [(10,)])
    h = ws.cog[EQUI - 1, 9, :, 2]
    shift = np.linalg.norm(slope.projection_2d[0, 1:] - flat.projection_2d[0, 1:], axis=-1)
    assert np.allclose(shift, h * math.tan(math.radians(angle)), rtol=1e-9)


def test_paper_first_roll_is_pair_10_over_edge_10_12(ws):
    p = standing(EQUI)
    pl = lo.plan(ws, (9, 10, 12), p, direction=outward(p, EQUI, (10, 12)))
    assert pl.pairs == (10,) and pl.pair == 10
    assert pl.edge == (10, 12) and pl.next_face == ISO
    assert pl.pressure == pytest.approx(4.2, abs=0.05)  # the paper's 4.2 MPa (III.C)
    assert pl.alignment == pytest.approx(1.0) and pl.predicted and pl.reach < 0
    assert pl.margin == pytest.approx(0.0884, abs=1e-4)
    text = str(pl)
    assert "#10" in text and "10-12" in text and "(10,11,12)" in text


def test_paper_second_roll_is_pair_11_over_edge_10_11(ws):
    p = standing(ISO)
    pl = lo.plan(ws, ISO, p, direction=outward(p, ISO, (10, 11)))
    assert pl.pairs == (11,) and pl.edge == (10, 11) and pl.next_face == NEXT
    assert pl.pressure == pytest.approx(2.2, abs=0.05)
    assert pl.pressure < 4.2  # less than #10 needs on (9,10,12), as in the paper


@pytest.mark.parametrize("edge,pair", [((10, 12), 10), ((9, 10), 9), ((9, 12), 12)])
def test_each_edge_of_the_equilateral_face_has_its_pair(ws, edge, pair):
    p = standing(EQUI, yaw=37.0)
    pl = lo.plan(ws, EQUI, p, direction=outward(p, EQUI, edge))
    assert pl.pairs == (pair,) and pl.edge == edge
    assert pl.next_face == topo.neighbour(EQUI, edge)
    # a goal far along the same direction gives the same choice
    goal = p.mean(0)[:2] + 5.0 * outward(p, EQUI, edge)[:2]
    assert lo.plan(ws, EQUI, p, goal=goal).pairs == (pair,)


def test_plan_is_deterministic_and_avoids_rocking_back(ws):
    p = standing(ISO)
    u = outward(p, ISO, (10, 12))
    a, b = lo.plan(ws, ISO, p, direction=u), lo.plan(ws, ISO, p, direction=u)
    assert a.reasons == b.reasons and repr(a.candidates) == repr(b.candidates)  # NaN-safe
    assert a.edge == (10, 12)
    back = lo.plan(ws, ISO, p, direction=u, avoid=[EQUI])  # just came from (9,10,12)
    assert back.edge == (10, 11) and back.next_face == NEXT
    only = lo.plan(ws, ISO, p, direction=u, avoid=[EQUI, NEXT])
    assert only.edge == (10, 12) and "visited recently" in str(only)


def test_uphill_needs_a_combination_of_pairs(ws):
    """On a 10 degree slope the CoG projection sits ~40 mm downhill: no single pair takes it
    over the uphill edge of (9,10,12) (#10 reaches only 3.8 mm past it on flat ground)."""
    terrain = Terrain.slope(10.0)
    p = standing(EQUI, terrain, yaw=-75.0)  # edge 10-12 faces uphill (+x)
    pl = lo.plan(ws, EQUI, p, direction=(1.0, 0.0), terrain=terrain)
    assert len(pl.pairs) == 2 and 10 in pl.pairs and pl.edge == (10, 12) and pl.predicted
    assert "combinations" in str(pl)
    single = lo.plan(ws, EQUI, p, direction=(1.0, 0.0), combine=False)
    assert single.edge != (10, 12) or not single.predicted


def test_plan_bad_input(ws):
    p = standing(EQUI)
    for face in (0, 21, (1, 2, 3)):
        with pytest.raises(ValueError, match="unknown face"):
            lo.plan(ws, face, p, direction=(1, 0))
    q = p.copy()
    q[2, 2] = np.nan
    with pytest.raises(ValueError, match="NaN"):
        lo.plan(ws, EQUI, q, direction=(1, 0))
    with pytest.raises(ValueError, match="exactly one"):
        lo.plan(ws, EQUI, p)
    with pytest.raises(ValueError, match="exactly one"):
        lo.plan(ws, EQUI, p, direction=(1, 0), goal=(1, 0))
    with pytest.raises(ValueError, match="zero"):
        lo.plan(ws, EQUI, p, goal=p.mean(0)[:2])
    with pytest.raises(ValueError, match="horizontal"):
        lo.plan(ws, EQUI, p, direction=(0, 0, 1))
    with pytest.raises(ValueError, match="nothing under node"):
        lo.plan(ws, EQUI, p + [9.0, 0, 0], direction=(1, 0), terrain=Terrain.random(1, size=2.0))
    empty = lo.Workspace.from_arrays(LEVELS, np.full_like(ws.cog, np.nan), ws.support)
    with pytest.raises(ValueError, match="no curve"):
        lo.plan(empty, EQUI, p, direction=(1, 0))


def test_settings_are_checked():
    with pytest.raises(ValueError, match="ramp_rate"):
        lo.RollSettings(ramp_rate=-1.0)
    with pytest.raises(ValueError, match="whole number of time steps"):
        lo.RollSettings(interval=0.00015)
    with pytest.raises(ValueError, match="max_rolls"):
        lo.RollSettings(max_rolls=2.5)
    from tensegrity.io import config
    from tensegrity.io.settings import build
    from tensegrity.stages.config import stage_config

    cfg = stage_config(config.validate({"locomotion": {"max_rolls": 7}, "sim": {"dt": 5e-5}}), "locomotion_runs")
    s = build(lo.RollSettings, cfg)
    assert s.max_rolls == 7 and s.dt == 5e-5
    with pytest.raises(KeyError, match="config key locomotion.ramp_rate is needed"):  # never a silent default
        build(lo.RollSettings, {"locomotion": {}, "sim": {"dt": 1e-4}})


# ------------------------------------------------------------------------- rolling (slower)


@pytest.fixture(scope="module")
def paper(ws):
    return lo.roll_over(ws, [(10, 12), (10, 11)], DAMPED)


def test_paper_experiment(paper):
    """Paper IV.B: #10 rolls the robot from (9,10,12) onto (10,11,12), then #11 onto
    (6,10,11). With gravity the robot tips below the free-mode workspace's pressures (4.2 and
    2.2 MPa): the structure sags toward the edge."""
    assert paper.outcome == "arrived", paper.message
    assert paper.faces == [EQUI, ISO, NEXT]
    first, second = (st.used for st in paper.steps)
    assert first.pairs == (10,) and second.pairs == (11,)
    assert 3.7 < first.tip_pressure < 4.2
    assert 1.7 < second.tip_pressure < 2.2
    assert [len(st.attempts) for st in paper.steps] == [1, 1]
    assert paper.travelled > 0.2


def test_run_dataset_round_trip(paper, tmp_path):
    terrain = Terrain.flat()
    path = datasets.write(
        run_formats.run_dataset(paper, terrain, DAMPED, "paper"),
        tmp_path / "paper.nc",
        {},
        "paper run",
        allow_nan=run_formats.RUN_ALLOW_NAN,
    )
    ds = datasets.read(path)
    assert list(ds["faces"].values) == [EQUI, ISO, NEXT]
    assert ds["step_pair"].values.tolist() == [[10, 0], [11, 0]]
    assert ds["tip_pressure"].values == pytest.approx([st.used.tip_pressure for st in paper.steps])
    assert ds.attrs["outcome"] == "arrived"
    assert ds["nodes"].shape == (len(paper.record.t), 12, 3)
    back = run_formats.terrain_from_dataset(ds)
    assert back.kind == "plane" and back.height(1.0, 2.0) == terrain.height(1.0, 2.0)
    assert datasets.strut_radius(ds) == DAMPED.strut_radius and datasets.strut_length(ds) == DAMPED.strut_length


def test_locomotion_run_stage_writes_the_paper_run(paper, ws_path, tmp_path, capsys):
    """stages.locomotion.locomotion_runs (the workflow's rule): the workspace file in, the run
    dataset out, with the stage's configuration keys merged over the workspace's provenance."""
    from tensegrity.io import config
    from tensegrity.stages.config import stage_config
    from tensegrity.stages.locomotion import locomotion_runs

    cfg = stage_config(config.load(), "locomotion_runs")
    (out,) = locomotion_runs(cfg, ["paper"], ws_path, [tmp_path / "paper.nc"])
    ds = datasets.read(out)
    assert ds.attrs["outcome"] == "arrived" and ds.attrs["run"] == "paper"
    assert list(ds["faces"].values) == [EQUI, ISO, NEXT]
    assert ds["step_pair"].values.tolist() == [[10, 0], [11, 0]]
    assert datasets.provenance_config(ds)["locomotion"]["goal_distance"] == cfg["locomotion"]["goal_distance"]
    assert "run paper: arrived" in capsys.readouterr().out
    with pytest.raises(ValueError, match="unknown locomotion run"):
        locomotion_runs(cfg, ["moon"], ws_path, [tmp_path / "moon.nc"])


@pytest.fixture(scope="module")
def flat_run(ws):
    return lo.roll_to(ws, (1.2, 0.7), DAMPED)


def test_roll_to_a_goal_on_flat_ground(flat_run):
    run = flat_run
    assert run.outcome == "arrived", run.message
    assert run.distance_to_goal <= 0.3
    assert 3 <= run.rolls <= 20
    for a, b in zip(run.steps, run.steps[1:]):
        assert b.face == a.face_after
    assert np.all(np.diff(run.record.t) > 0)


def test_runs_are_deterministic_and_batches_equal_single_runs(ws, flat_run):
    s = lo.RollSettings(max_rolls=2)
    single = lo.roll_to(ws, (1.2, 0.7), DAMPED, settings=s)
    assert np.array_equal(single.record.nodes, flat_run.record.nodes[: len(single.record.t)])
    both = lo.roll_many(ws, [(1.2, 0.7), (-0.4, -1.0)], DAMPED, settings=s)
    assert np.array_equal(both[0].record.nodes, single.record.nodes)
    other = lo.roll_to(ws, (-0.4, -1.0), DAMPED, settings=s)
    assert np.array_equal(both[1].record.nodes, other.record.nodes)
    assert single.outcome == "step_limit" and len(single.steps) == 2


def test_downhill_on_a_10_degree_slope(ws):
    run = lo.roll_to(ws, (-1.0, 0.0), DAMPED, Terrain.slope(10.0))
    assert run.outcome == "arrived", run.message


def test_a_face_change_with_no_node_lifted_is_no_roll(ws):
    """On rough ground the robot can rest on four nodes: its contact face flips to the
    neighbouring face while no node of its support lifts. A roll goes on raising the pressure
    through such a flip, and lets go once a node of the start face has lifted as well (the robot
    tips over). Before, the flip alone released the roll: on 0.05 m terrain, seed 2, the robot
    rocked 2 mm between (1,9,10) and (9,10,12) at 0.2-0.6 MPa, seven attempts in a row: "stuck"."""
    from dataclasses import replace

    from tensegrity.locomotion.control import roll_controller
    from tensegrity.locomotion.lockstep import observe

    s = lo.RollSettings()
    state = d.stand_on(DAMPED, EQUI, Terrain.flat())
    (obs,) = observe(DAMPED, Terrain.flat(), state, s)
    gen = roll_controller(DAMPED, s, obs, (10,), ws.max_pressure)
    first = next(gen)
    flip = replace(obs, face=topo.neighbour(EQUI, (10, 12)), t=obs.t + s.interval)
    second = gen.send(flip)
    assert second[9] > first[9]  # still ramping
    gap = obs.gap.copy()
    gap[8] += 10 * s.lift_tolerance  # node 9, the apex across edge 10-12, lifts
    third = gen.send(replace(flip, gap=gap, t=flip.t + s.interval))
    assert third[9] < second[9]  # released: it rolls


def test_a_robot_that_stays_tipped_gets_the_whole_escalation(ws):
    """Wedged in a hollow, the robot can lean on a fourth node: a support node stays lifted a
    few mm while it does not tip over. After one hold the ramp goes on to the workspace's
    highest level at ramp_rate. Before, the persisting lift held the pressure again at every
    step (0.02 MPa per hold_time): on 0.05 m terrain, seed 3, attempts crept from 1.3 to 1.7 MPa
    until the safety net released them, short of the 2.0 MPa planned: "stuck"."""
    from dataclasses import replace

    from tensegrity.locomotion.control import roll_controller
    from tensegrity.locomotion.lockstep import observe

    s = lo.RollSettings()
    state = d.stand_on(DAMPED, EQUI, Terrain.flat())
    (obs,) = observe(DAMPED, Terrain.flat(), state, s)
    gen = roll_controller(DAMPED, s, obs, (10,), ws.max_pressure)
    pres = next(gen)
    gap = obs.gap.copy()
    gap[8] += 5 * s.lift_tolerance  # node 9, the apex across edge 10-12, stays up
    tipped = replace(obs, gap=gap)
    need = ws.max_pressure / s.ramp_rate + 2 * s.hold_time  # s: the ramp and one hold, and slack
    peak = 0.0
    for k in range(1, int(round(need / s.interval)) + 1):
        pres = gen.send(replace(tipped, t=obs.t + k * s.interval))
        peak = max(peak, pres[9])
    assert peak == pytest.approx(ws.max_pressure)


def test_stuck_when_the_workspace_cannot_roll_the_robot(ws):
    """A workspace swept only to 1.6 MPa rolls nothing off (9,10,12): the run stops "stuck"
    after trying max_attempts candidates in the world (lookahead 0), each escalated to 1.6 MPa,
    and says so."""
    low = lo.Workspace.from_arrays(LEVELS[:2], ws.cog[:, :, :2], ws.support[:, :, :2])
    run = lo.roll_to(
        low, (2.0, 0.0), DAMPED, settings=lo.RollSettings(max_attempts=2, combine=False, escape_attempts=0, lookahead=0)
    )
    assert run.outcome == "stuck"
    assert len(run.steps) == 1 and len(run.steps[0].attempts) == 2
    assert all(a.peak_pressure == pytest.approx(1.6) and not a.rolled for a in run.steps[0].attempts)
    assert "predicted no roll" in run.message and "(9,10,12)" in run.message


def test_leaving_the_terrain_is_an_outcome(ws):
    terrain = Terrain.random(seed=3, size=1.2, amplitude=0.002)
    run = lo.roll_to(ws, (0.55, 0.0), DAMPED, terrain, settings=lo.RollSettings(arrive_tolerance=0.01))
    assert run.outcome == "off_terrain"
    assert "no terrain under it" in run.message


def test_bad_run_input(ws):
    with pytest.raises(ValueError, match="closer than its size"):
        lo.roll_to(ws, (0.3, 0.1))
    with pytest.raises(ValueError, match="finite world point"):
        lo.roll_to(ws, (np.nan, 2.0))
    with pytest.raises(ValueError, match="finite world point"):
        lo.roll_to(ws, (1.0,))
    with pytest.raises(ValueError, match="nothing under the goal"):
        lo.roll_to(ws, (5.0, 0.0), terrain=Terrain.random(seed=1, size=2.0))
    with pytest.raises(ValueError, match="nothing under the robot"):
        lo.roll_to(ws, (2.0, 0.0), terrain=Terrain.random(seed=1, size=2.0), position=(4.0, 0.0))
    with pytest.raises(ValueError, match="free mode"):
        lo.roll_to(ws, (2.0, 0.0), terrain=Terrain.none())
    s = d.stand_on(Params(), EQUI)
    x = s.x.copy()
    x[0, 1, 1] = np.nan
    with pytest.raises(ValueError, match="not finite"):
        lo.roll_to(ws, (2.0, 0.0), state=d.State(x, s.v, s.q, s.w, s.anchor, s.stuck))
    with pytest.raises(ValueError, match="2 robots for 1 run"):
        lo.roll_to(ws, (2.0, 0.0), state=d.stand_on(Params(), EQUI, batch=2))
    with pytest.raises(ValueError, match="pairs of node numbers"):
        lo.roll_over(ws, [(1, 2, 3)])
    run = lo.roll_over(ws, [(1, 2)], DAMPED)
    assert run.outcome == "stuck" and "1-2 is not an edge of face (9,10,12)" in run.message


def test_command_line_plan(ws_path, capsys):
    assert cli.main(["plan", "--workspace", str(ws_path), "--face", "9,10,12", "--direction", "75"]) == 0
    out = capsys.readouterr().out
    assert "chosen #10" in out and "10-12" in out
    assert cli.main(["plan", "--workspace", str(ws_path), "--face", "1,2,3", "--direction", "75"]) == cli.EXIT_INPUT
    assert "unknown face" in capsys.readouterr().err


# ------------------------------------------------------------------------------- figures


def test_state_figures_show_the_projection_inside_and_outside(tmp_path):
    from tensegrity.render import locomotion as rl

    p = standing(EQUI)
    out = rl.fig_state(p, Terrain.flat(), EQUI, tmp_path / "fig8.png", "stable")
    assert out["stands"] and out["margin"] == pytest.approx(0.0884, abs=1e-4)
    assert {"cog", "cog projection", "gravity line", "support triangle"} <= set(out["actors"])
    tipped = p.copy()
    tipped[:, :2] += 0.3 * (p[[9, 11]].mean(0) - p.mean(0))[:2] / 0.09  # CoG out over 10-12
    tipped[topo.FACES[EQUI - 1]] = p[topo.FACES[EQUI - 1]]
    out = rl.fig_state(tipped, Terrain.flat(), EQUI, tmp_path / "fig9.png", "rolling")
    assert not out["stands"] and out["edge"] == (10, 12) and out["next_face"] == ISO
    assert "rolling arrow" in out["actors"]
    terrain = Terrain.slope(10.0)
    out = rl.fig_slope(standing(EQUI, terrain), terrain, EQUI, tmp_path / "fig10.png", "slope")
    assert out["angle"] == pytest.approx(10.0, abs=0.1) and out["shift"] > 0.03
    for name in ("fig8", "fig9", "fig10"):
        img = __import__("imageio.v2", fromlist=["imread"]).imread(tmp_path / f"{name}.png")
        assert img.shape[:2] == (900, 1200) and img[..., :3].std() > 20  # not blank


def test_path_figure_and_animation_of_a_run(paper, tmp_path):
    from tensegrity.render import animation
    from tensegrity.render import runs as rr

    ds = run_formats.run_dataset(paper, Terrain.flat(), DAMPED, "paper")
    terrain, t = run_formats.terrain_from_dataset(ds), ds["time"].values
    step_end = np.searchsorted(t, ds["t_end"].values)  # each step's last sample
    assert np.array_equal(t[step_end], ds["t_end"].values)
    out = rr.fig_path(
        ds["nodes"].values,
        terrain,
        tmp_path / "top.png",
        "paper",
        faces=ds["next_face"].values,
        step_end=step_end,
        goal=ds["goal"].values,
    )
    assert out["contacts"] == 2 and {"cog track", "contact 1", "contact 2"} <= set(out["actors"])
    anim = animation.animate(
        ds["nodes"].values, t, ds["pressure"].values, terrain, tmp_path / "run.gif", fps=5, speed=10.0, size=(320, 240)
    )
    assert anim["frames"] >= 5 and (tmp_path / "run.gif").stat().st_size > 10_000
