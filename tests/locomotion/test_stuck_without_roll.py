"""A run that ends stuck without any roll (stop 47: `drive` makes no roll where none simulated
ahead is acceptable, where it used to make the first foreseen to stay on its face), and every
consumer of such a run: its words (`describe`), its file (`run_dataset` and the readers), its
figures (`stages.locomotion`), check 6 and the benchmark's lines; and the step lines that say
whether an action was weighted or per cable."""

import dataclasses
import importlib.util
from pathlib import Path

import numpy as np
import pytest

from tensegrity import locomotion as lo
from tensegrity.io import datasets
from tensegrity.io.formats import run as run_formats
from tensegrity.locomotion.control import RollResult
from tensegrity.locomotion.outcome import action_kind
from tensegrity.locomotion.plan import plan
from tensegrity.locomotion.settings import RollSettings
from tensegrity.physics import topology as topo
from tensegrity.physics.params import Params
from tensegrity.physics.terrain import Terrain
from tensegrity.validation.common import FAIL
from tensegrity.validation.runs import check_runs

EQUI = topo.face_number(topo.CONTACT_FACES["equilateral"])  # (9,10,12)
DAMPED = Params(strut_damping=1.0)
ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="module")
def low(ws):
    """A run planned from `ws` cut to its lowest level, 0.8 MPa, where no action rolls the robot:
    every one of the 78 single and two-pair candidates simulated ahead stays on (9,10,12) (0.9 s)."""
    weak = lo.Workspace.from_arrays(ws.levels[:1], ws.cog[:, :, :1], ws.support[:, :, :1])
    return lo.roll_to(weak, (2.0, 0.0), DAMPED, settings=RollSettings(optimised_actions=False))


def _write(run, path, terrain=None):
    ds = run_formats.run_dataset(run, terrain or Terrain.flat(), DAMPED, path.stem)
    return datasets.write(ds, path, {}, "t", allow_nan=run_formats.RUN_ALLOW_NAN)


def test_no_acceptable_roll_ends_the_run_stuck_without_a_roll(low):
    """With the fallback roll (before stop 47) this run made #10 up to 0.8 MPa: one step, not
    rolled. Now it makes none: no step, the start face kept, the planning CPU kept."""
    assert low.outcome == "stuck" and low.steps == () and low.rolls == 0
    assert "78 candidate rolls simulated on face (9,10,12)" in low.message and "78 do not roll" in low.message
    assert low.start_face == EQUI and low.faces == [EQUI] and low.stuck_cpu > 0
    text = lo.describe(low, "low")
    assert text.startswith("run low: stuck (every one of the 78") and "0 rolls" in text
    assert text.splitlines()[1] == "  no step: the robot made no roll (it rests on (9,10,12))"


def test_a_run_without_a_roll_writes_a_readable_file(low, tmp_path):
    path = _write(low, tmp_path / "low.nc")
    ds = datasets.read(path)
    assert ds.sizes["step"] == 0 and ds["faces"].values.tolist() == [EQUI]
    assert ds.attrs["outcome"] == "stuck" and int(ds.attrs["rolls"]) == 0
    assert run_formats.terrain_from_dataset(ds).kind == "plane"
    with pytest.raises(ValueError, match=r"run 'low' has 0 step\(s\), not a step 1"):
        run_formats.run_sample(ds, Terrain.flat(), 1, "stable")
    summary = run_formats.read_run_summaries([path])["low"]
    assert summary.outcome == "stuck" and summary.rolls == 0 and summary.distance == pytest.approx(2.0, abs=0.01)
    res = check_runs({"low": summary})
    assert res.status["6"] == FAIL and res.rolls.tolist() == [0] and res.outcome == ("stuck",)
    assert run_formats.not_arrived([path]) == [("low", "stuck", low.message)]


def test_a_run_without_a_roll_gets_its_figures(low, tmp_path):
    """Fig. 8-10 and the path figures of a run that made no roll: the robot at rest on its start
    face, the titles saying it made no roll and why (was a ValueError, before it an IndexError)."""
    from tensegrity.stages import locomotion as stage

    path = _write(low, tmp_path / "paper.nc")
    figs = [tmp_path / f"fig{n}.png" for n in (8, 9, 10)]
    out = stage.state_figures({}, path, path, *figs)
    assert [o["face"] for o in out] == [EQUI] * 3 and all(f.stat().st_size > 10_000 for f in figs)
    assert out[0]["stands"] and out[0]["title"].startswith(
        "Fig. 8  Not rolled: at rest on (9,10,12), run 'paper' made no roll: stuck\n(every one of the 78"
    )
    assert out[1]["title"].startswith("Fig. 9  Not rolled: at rest on (9,10,12)")
    assert all(len(line) <= 125 for o in out for line in o["title"].splitlines())  # no line leaves the figure
    assert "; run 'paper' made no roll: stuck\n(every" in out[2]["title"]
    assert out[0]["title"].endswith(" ... (0 tumble or slide, 78 do not roll, 0 return, 0 land elsewhere))")
    top, three_d = tmp_path / "top.png", tmp_path / "3d.png"
    paths = stage.path_figures({}, path, top, three_d)
    assert "stuck, 0 rolls" in paths[0]["title"] and top.stat().st_size > 10_000 and three_d.is_file()


def test_a_run_on_no_face_is_named_by_the_state_figures(ws, tmp_path):
    """A robot that tumbles down 35 deg while settling rests on no face: no face to draw it on."""
    from tensegrity.stages import locomotion as stage

    slope = Terrain.slope(35.0)
    run = lo.roll_to(ws, (2.0, 0.0), DAMPED, slope, settings=RollSettings(optimised_actions=False))
    assert run.outcome == "no_contact" and run.steps == () and run.faces == [] and run.start_face is None
    assert "settled on no face" in lo.describe(run, "steep")
    path = _write(run, tmp_path / "steep.nc", slope)
    assert datasets.read(path).sizes["visit"] == 0
    figs = [tmp_path / f"fig{n}.png" for n in (8, 9, 10)]
    with pytest.raises(ValueError, match=r"Fig. 8 and 9 .*steep\.nc.* rests on no face \(outcome 'no_contact'"):
        stage.state_figures({}, path, path, *figs)


def _bench():
    spec = importlib.util.spec_from_file_location("bench_locomotion_h47", ROOT / "benchmarks" / "bench_locomotion.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def _weighted(low, ws, weights, pairs):
    """`low` given one step that rolled by an action of `weights` (None: `pairs` together)."""
    pl = plan(ws, EQUI, low.record.nodes[-1], direction=np.array([1.0, 0.0, 0.0]))
    c = low.record.cog[-1]
    r = RollResult(pairs, True, EQUI, topo.face_number((10, 11, 12)), 2.5, 3.0, 1.0, 2.0, c, c, weights=weights)
    return dataclasses.replace(low, steps=(lo.Step(EQUI, pl, (r,), r.face_after, (), 0.1),), stuck_cpu=0.0), r


def test_the_step_lines_say_whether_an_action_was_weighted_or_per_cable(low, ws, capsys):
    w12 = np.zeros(12)
    w12[[2, 6]] = (0.62, 1.0)
    w24 = np.zeros(24)
    w24[[4, 5, 12, 20]] = (1.0, 0.5, 0.25, 0.75)
    kinds = {None: "", "w12": " (weighted: #3 0.62, #7 1.00)", "w24": " (per cable: 4 of 24 cables)"}
    bench = _bench()
    for key, w in ((None, None), ("w12", w12), ("w24", w24)):
        pairs = (3, 7) if w is not None else (10,)
        run, r = _weighted(low, ws, w, pairs)
        assert action_kind(r) == kinds[key]
        step = lo.describe(run, "w").splitlines()[1]
        assert f"rolled by {pairs}{kinds[key]} at 2.50 MPa (peak 3.00), 1 attempt(s)" in step
        bench.steps([({"goal": 0.0}, run)], "MPa")
        lines = capsys.readouterr().out.splitlines()
        plus = "+".join(f"#{q}" for q in pairs)
        assert lines[1].startswith(f"    (9,10,12) -> (10,11,12) by {plus}{kinds[key]}, tip 2.50 MPa"), lines
    assert "(weighted" not in lo.describe(low, "low")


def test_the_benchmark_reports_a_run_without_a_roll(low, capsys):
    bench = _bench()
    row = bench.report("flat", [({"goal": 0.0, "azimuth": 0.0, "yaw": 0.0}, low)], 1.0, 0.3)
    out = capsys.readouterr().out
    assert "start faces: (9,10,12) 1" in out and "stuck after 0 rolls" in out
    assert row["arrived"] == "0/1" and row["cpu"] == pytest.approx(low.stuck_cpu)  # per roll: 0 rolls count as 1
    bench.steps([({"goal": 0.0}, low)], "MPa")
    lines = capsys.readouterr().out.splitlines()
    assert lines[0] == "  goal at 0 deg: stuck, faces [8]"
    assert lines[1].startswith("    no roll from (9,10,12): planning ") and lines[1].endswith(" s CPU")
