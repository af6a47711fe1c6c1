"""Locomotion in volts (issue 31 item 3; docs/design.md §6, "Locomotion in volts"): the planner and
the rolls drive the prototype's twisted-string motors with the one roll law, levels in V; a pair
commanded 0 V unwinds its strands; the run file records `voltage_cmd(time, pair)` V; the
pneumatic runs are the bits they were."""

import hashlib
from dataclasses import replace

import numpy as np
import pytest

from tensegrity import paper
from tensegrity.io.formats import actuation
from tensegrity.io.formats.run import commands, run_dataset
from tensegrity.locomotion import Workspace, outcome, runs
from tensegrity.locomotion.lockstep import UNWIND_TOLERANCE, applied
from tensegrity.locomotion.settings import RollSettings
from tensegrity.physics import dynamics as d
from tensegrity.physics import topology as topo
from tensegrity.physics.params import Params
from tensegrity.physics.terrain import Terrain
from tensegrity.physics.twisted import TwistedString
from tensegrity.stages.config import actuator_error
from tensegrity.workspace import mapping
from tensegrity.workspace import sweep as sw

LEVEL = paper.VOLTAGE[10]  # 11.1 V: the paper's first roll, #10 from (9,10,12) onto (10,11,12)
# the rolls of the prototype: the motors take seconds to twist (design.md §10), so a level is held
# up to 20 s before the ramp goes on, and a robot has settled once its strands are unwound too
VOLTS = RollSettings(motors=TwistedString(), hold_time=20.0, settle_time=15.0)


@pytest.fixture(scope="module")
def volts_maps() -> dict:
    """The 20-face workspace arrays (`mapping.map_workspace`) in volts of #10 alone on the
    canonical equilateral face (9,10,12) at 11.1 V, from the free-mode sweep with the motors (3 s
    hold, the last second averaged); the other pairs and the isosceles faces are NaN."""
    face = topo.face_number(topo.CONTACT_FACES["equilateral"])
    res = sw.run(Params(), face, [10], sw.SweepSetup(levels=(LEVEL,), hold=3.0), TwistedString())
    last = res.t > res.t[-1] - 1.0
    cog, sup = res.cog[:, last].mean(axis=1)[:, None], res.support[:, last].mean(axis=1)[:, None]
    return mapping.map_workspace([LEVEL], {"equilateral": (np.array([10]), cog, sup)})


@pytest.fixture(scope="module")
def volts_ws(volts_maps) -> Workspace:
    return Workspace.from_arrays([LEVEL], volts_maps["cog"], volts_maps["support"])


def test_a_roll_in_volts_lands_where_the_workspace_says(volts_ws):
    """The paper's first roll planned from the workspace in volts and made in the grounded
    simulation with the motors: #10 over edge 10-12 of (9,10,12) onto (10,11,12), the face the
    plan names, at no more than the workspace's 11.1 V; then, released, the strands of #10 are
    back at rest (the 0 V command unwinds them: the gear friction would hold them twisted)."""
    run = runs.roll_over(volts_ws, [(10, 12)], Params(), Terrain.flat(), settings=VOLTS)
    assert run.outcome == "arrived", run.message
    (step,) = run.steps
    want = topo.face_number((10, 11, 12))
    assert (step.face, step.plan.pairs, step.plan.next_face) == (topo.face_number(paper.START_FACE), (10,), want)
    assert run.faces == [step.face, want] and step.used.pairs == (10,)
    assert 0 < step.used.tip_pressure <= LEVEL and step.used.peak_pressure == pytest.approx(LEVEL)
    twist = run.state.motor_angle[0, topo.PAIR_CABLES].mean(axis=1)
    assert np.all(np.abs(twist) <= UNWIND_TOLERANCE), twist
    # the file: the voltages applied, in V (negative while the strands unwind), the steps in V
    ds = run_dataset(run, Terrain.flat(), VOLTS.rolling(Params()), "paper", VOLTS.unit)
    assert "pressure" not in ds and ds.attrs["actuator"] == "twisted_string"
    assert ds["voltage_cmd"].dims == ("time", "pair") and ds["voltage_cmd"].attrs["units"] == "V"
    for k in ("planned_pressure", "tip_pressure", "peak_pressure"):
        assert ds[k].attrs["units"] == "V", k
    v, unit = commands(ds)
    assert unit == "V" and v.max() == pytest.approx(LEVEL) and v.min() < 0
    assert v[:, [q - 1 for q in range(1, 13) if q != 10]].max() <= 0  # only #10 was driven up
    text = outcome.describe(run, "paper", VOLTS.unit)
    assert "at 11.10 V" in text and "MPa" not in text


def test_zero_volts_unwinds_and_pressures_pass_as_commanded():
    """`lockstep.applied`: the muscles get the pressures as commanded; a pair of twisted strings
    commanded 0 V is driven back toward zero twist (against the sign of its twist, at most the
    rated 12 V), one commanded a voltage gets it, one at rest gets nothing."""
    st = d.stand_on(Params(), paper.START_FACE, Terrain.flat(), batch=1)
    levels = np.zeros((1, 12))
    levels[0, 3] = 5.0
    assert applied(RollSettings(), levels, st) is levels
    angle = np.zeros((1, 24))
    angle[0, topo.PAIR_CABLES[9]] = 300.0  # #10 twisted, released
    angle[0, topo.PAIR_CABLES[4]] = -2.0  # #5 twisted the other way
    angle[0, topo.PAIR_CABLES[3]] = 50.0  # #4 twisted and driven
    got = applied(VOLTS, levels, replace(st, motor_angle=angle, motor_speed=0 * angle))
    want = np.zeros(12)
    want[9], want[4], want[3] = -12.0, 4.0, 5.0
    assert np.array_equal(got[0], want)


def test_a_file_of_the_other_actuator_or_a_short_hold_is_refused_naming_it_and_the_key():
    volts, pneumatic = {"actuator": "twisted_string"}, {}
    actuation.require_kind(volts, "ws.nc", "twisted_string")
    actuation.require_kind(pneumatic, "ws.nc", "pneumatic")
    with pytest.raises(ValueError, match=r"ws\.nc is of the twisted_string actuator.*actuator\.kind is 'pneumatic'"):
        actuation.require_kind(volts, "ws.nc", "pneumatic")
    with pytest.raises(ValueError, match=r"ws\.nc is of the pneumatic actuator.*actuator\.kind is 'twisted_string'"):
        actuation.require_kind(pneumatic, "ws.nc", "twisted_string")
    # a hold shorter than the motors take to twist to the lock at no-load speed, L0 sin(atan(pi/2)) /
    # (r omega0) = 0.28 0.8436 / (4.5e-4 47.124) = 11.1 s: the roll would give up before its level
    with pytest.raises(ValueError, match=r"hold_time 1.0 s is shorter than the 11.1 s .*locomotion.hold_time >= 11.1"):
        RollSettings(motors=TwistedString())
    cfg = {"actuator": {"kind": "twisted_string"}}
    for stage in ("locomotion_runs", "state_figures", "path_figures", "animation"):
        assert actuator_error(cfg, stage) is None, stage
    assert "stage study_chunk" in actuator_error(cfg, "study_chunk")  # studies: still the muscles' only


# sha256 of the content of the tiny pneumatic run below, made with the code before locomotion in
# volts (main at aa57d3f) and after: the same bits (x86-64, the numba of environment.txt). The
# workspace is `ws` rounded to 1e-12 m (signed zeros folded): the static solve's last bits differ
# between OpenBLAS's kernels (OPENBLAS_CORETYPE Haswell, Sandybridge, Prescott: three hashes of the
# raw run, one of this; the hash pinned before stop 46 was the raw run's on another CPU's kernel)
PNEUMATIC_RUN = "3ec5f3e5f8eef46c5460421630cd24df8b04f0050e322d3642e2655732bc4027"


def test_a_pneumatic_run_is_the_bits_it_was(ws):
    s = RollSettings()
    exact = {k: np.round(getattr(ws, k), 12) + 0.0 for k in ("cog", "support", "rest_cog", "rest_support")}
    run = runs.roll_over(replace(ws, **exact), [(10, 12)], Params(), Terrain.flat(), settings=s)
    ds = run_dataset(run, Terrain.flat(), s.rolling(Params()), "tiny")
    assert "actuator" not in ds.attrs and ds["pressure"].attrs["units"] == "MPa" and "voltage_cmd" not in ds
    h = hashlib.sha256()
    for k in sorted(ds.variables):
        v = ds[k]
        h.update(k.encode())
        h.update(np.ascontiguousarray(v.values).tobytes())
        h.update(repr(sorted(v.attrs.items())).encode())
    h.update(repr(sorted((k, str(v)) for k, v in ds.attrs.items())).encode())
    assert h.hexdigest() == PNEUMATIC_RUN


def test_plan_refuses_a_workspace_of_the_other_actuator_naming_the_file_and_the_key(
    volts_maps, tmp_path, monkeypatch, capsys
):
    """`tensegrity plan` with a workspace file in volts: planned in V under actuator.kind
    twisted_string, refused before any simulation under the pneumatic configuration (and a
    pneumatic file under twisted_string), naming the file and actuator.kind."""
    from tensegrity import cli
    from tensegrity.io import datasets
    from tensegrity.io.formats import WORKSPACE_ALLOW_NAN, workspace_dataset

    monkeypatch.chdir(tmp_path)
    ds = workspace_dataset([LEVEL], volts_maps, 0.5)
    for kind in ("twisted_string", "pneumatic"):
        datasets.write(
            actuation.relabel(ds, kind), f"{kind}.nc", {}, "workspace", stage="map", allow_nan=WORKSPACE_ALLOW_NAN
        )
    volts = ["--set", "actuator.kind=twisted_string", "--set", "locomotion.hold_time=20"]
    argv = ["plan", "--direction", "0", "--two-pair", "none", "--workspace"]
    assert cli.main([*argv, "twisted_string.nc", *volts]) == 0
    out = capsys.readouterr().out
    assert "#10 toward edge 10-12" in out and "at 11.1 V" in out and "MPa" not in out, out
    for path, cfg, want in (("twisted_string.nc", [], "pneumatic"), ("pneumatic.nc", volts, "twisted_string")):
        assert cli.main([*argv, path, *cfg]) == cli.EXIT_INPUT
        err = capsys.readouterr().err
        assert f"{path} is of the" in err and f"config key actuator.kind is {want!r}" in err, err
