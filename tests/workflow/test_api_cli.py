"""The public Python API and the command line."""

import io
import json
import subprocess
import sys

import numpy as np
import pytest

import tensegrity
from tensegrity import cli
from tensegrity.cli import args as cli_args
from tensegrity.io import config, datasets


def test_public_names_resolve_to_their_modules():
    """Every name of the public API is the object of the module `_API` names (lazy import)."""
    import importlib

    for name, (module, attr) in tensegrity._API.items():
        assert getattr(tensegrity, name) is getattr(importlib.import_module(f"tensegrity.{module}"), attr), name
    assert set(tensegrity.__all__) == {"__version__", "load_workspace", *tensegrity._API}
    with pytest.raises(AttributeError, match="no attribute 'roll'"):
        _ = tensegrity.roll


def test_a_curve_evaluates_without_scipy(tmp_path):
    curve = {"breaks": [0.4, 2.0, 4.8], "coefs": [[1.0, 0.0, 0.5], [2.0, 0.1, 0.3]]}
    code = (
        "import sys; sys.modules['sklearn'] = None; sys.modules['scipy'] = None\n"
        "from tensegrity.workspace import fit\n"
        f"print(float(fit.evaluate({curve!r}, 3.0)))"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert float(out.stdout) == pytest.approx(2.0 * 1.0**2 + 0.1 * 1.0 + 0.3)


SMALL = [
    "--set",
    "sweep.pairs=[9, 10, 11]",
    "--set",
    "sweep.levels=[1.2, 2.4, 3.6, 4.8]",
    "--set",
    "sweep.hold=0.3",
    "--set",
    "nominal.discard=0.1",
]


@pytest.fixture(scope="module")
def small_results(tmp_path_factory):
    """A small pipeline run (3 pairs, 4 levels) through `tensegrity stage`, the rules' functions."""
    d = tmp_path_factory.mktemp("res")

    def stage(*argv):
        assert cli.main(["stage", *argv, *SMALL]) == 0

    for c in ("equilateral", "isosceles"):
        stage("sweep", f"contact={c}", f"out_dir={d / 'sweeps' / c}")
        stage(
            "nominal",
            *(f"sweep_paths={p}" for p in sorted((d / "sweeps" / c).glob("*.nc"))),
            f"out_path={d / 'nominal' / f'{c}.nc'}",
        )
        stage("curves", f"nominal_path={d / 'nominal' / f'{c}.nc'}", f"out_path={d / 'curves' / f'{c}.nc'}")
    stage(
        "curves_json",
        *(f"curve_paths={d / 'curves' / f'{c}.nc'}" for c in ("equilateral", "isosceles")),
        f"out_path={d / 'curves.json'}",
    )
    stage(
        "workspace",
        *(f"nominal_paths={d / 'nominal' / f'{c}.nc'}" for c in ("equilateral", "isosceles")),
        f"out_path={d / 'workspace.nc'}",
    )
    return d


def test_stage_names_a_missing_or_unknown_argument(small_results, capsys):
    assert cli.main(["stage", "curves", "nominal_path=x.nc"]) == cli.EXIT_INPUT
    assert "missing argument(s) out_path" in capsys.readouterr().err
    assert cli.main(["stage", "curves", "nominal=x.nc", "out_path=y.nc"]) == cli.EXIT_INPUT
    assert "'nominal=x.nc' is not ARG=VALUE with ARG one of nominal_path, out_path" in capsys.readouterr().err
    assert cli.main(["stage", "slope_limit"]) == 0  # alone: the stage's arguments
    assert "gravity_path=... workspace_path=..." in capsys.readouterr().out


def test_stage_files_carry_the_keys_their_stage_reads(small_results):
    """The provenance of a file made by `tensegrity stage` is the rule's: the stage's keys merged
    over its inputs' (the curves: fit.*, nominal.discard, the sweep's keys; no validate section)."""
    cfg = datasets.provenance_config(small_results / "curves" / "equilateral.nc")
    assert set(cfg) == {"params", "sim", "sweep", "nominal", "fit"}
    assert set(cfg["sim"]) == {"dt", "record_every"} and set(cfg["nominal"]) == {"discard", "method"}
    assert cfg["sweep"]["levels"] == [1.2, 2.4, 3.6, 4.8] and "contacts" not in cfg["sweep"]


def test_query_matches_the_nominal_cog_at_a_swept_level(small_results, capsys):
    code = cli.main(
        [
            "query",
            "--curves",
            str(small_results / "curves.json"),
            "--workspace",
            str(small_results / "workspace.nc"),
            "--face",
            "9,10,12",
            "--pair",
            "10",
            "--pressure",
            "2.4",
            "--json",
        ]
    )
    assert code == 0
    out = json.loads(capsys.readouterr().out)
    nom = datasets.read(small_results / "nominal" / "equilateral.nc")
    cv = datasets.read(small_results / "curves" / "equilateral.nc")["cv_rmse"].sel(pair=10).values
    err = np.abs(np.array(out["cog_m"]) - nom["cog"].sel(pair=10, pressure=2.4).values)
    assert np.all(err <= 3 * cv + 1e-6)  # the curve passes within its cross-validated error
    assert out["stands"] and out["margin_m"] > 0.01


def test_query_on_a_mapped_face_agrees_with_the_workspace(small_results):
    curves = tensegrity.load_curves(small_results / "curves.json")
    ws = datasets.read(small_results / "workspace.nc")
    lookup = tensegrity.load_workspace(small_results / "workspace.nc")
    face = 7  # (6,10,11), reached by a reflection
    pair = int(ws["pair"].values[np.isfinite(ws["cog"].sel(face=face, pressure=3.6)[:, 0]).values][0])
    ans = tensegrity.query_workspace(curves, lookup, face, pair, 3.6)
    canon = tensegrity.query_workspace(curves, lookup, 8, ans.source_pair, 3.6)  # (9,10,12)
    np.testing.assert_allclose(np.abs(ans.cog), np.abs(canon.cog), atol=1e-12)  # x may flip
    cv = datasets.read(small_results / "curves" / "equilateral.nc")["cv_rmse"].sel(pair=ans.source_pair).values
    err = np.abs(ans.cog - ws["cog"].sel(face=face, pair=pair, pressure=3.6).values)
    assert np.all(err <= 3 * cv + 1e-6)
    assert ans.margin == pytest.approx(canon.margin, abs=1e-9)


@pytest.mark.parametrize(
    "argv,needle",
    [
        (["simulate", "--pair", "13", "--pressure", "1", "--out", "x.nc"], "unknown pair 13"),
        (["simulate", "--pair", "10", "--pressure", "-1", "--out", "x.nc"], "pressure"),
        (["simulate", "--pair", "10", "--pressure", "1", "--out", "x.nc", "--set", "sim.dt=0.1"], "sim.dt"),
        (["simulate", "--face", "1,2,3", "--pair", "10", "--pressure", "1", "--out", "x.nc"], "unknown face"),
    ],
)
def test_bad_input_exits_3_naming_the_argument(tmp_path, capsys, monkeypatch, argv, needle):
    monkeypatch.chdir(tmp_path)
    assert cli.main(argv) == cli.EXIT_INPUT
    assert needle in capsys.readouterr().err
    assert not (tmp_path / "x.nc").exists()


def test_usage_error_exits_2(capsys):
    with pytest.raises(SystemExit) as e:
        cli.main(["simulate", "--pressure", "abc"])
    assert e.value.code == cli.EXIT_USAGE


def test_simulate_writes_a_dataset(tmp_path):
    out = tmp_path / "run.nc"
    assert cli.main(["simulate", "--pair", "10", "--pressure", "2.0", "--duration", "0.2", "--out", str(out)]) == 0
    ds = datasets.read(out)
    assert ds["nodes"].dims == ("time", "node", "axis") and ds.sizes["time"] == 200
    assert float(ds["pressure_cmd"].sel(pair=10)[-1]) == 2.0


def test_every_subcommand_has_help():
    for sub in cli.build_parser()._subparsers._group_actions[0].choices:
        r = subprocess.run([sys.executable, "-m", "tensegrity.cli", sub, "--help"], capture_output=True, text=True)
        assert r.returncode == 0 and "usage" in r.stdout


def test_render_command_draws_a_dataset_and_refuses_a_foreign_file(small_results, tmp_path, capsys):
    out = tmp_path / "ws.png"
    assert cli.main(["render", str(small_results / "workspace.nc"), "--face", "1,5,6", "--out", str(out)]) == 0
    assert out.stat().st_size > 20_000
    bad = tmp_path / "bad.nc"
    bad.write_text("not a netCDF")
    assert cli.main(["render", str(bad), "--out", str(tmp_path / "x.png")]) == cli.EXIT_INPUT
    assert "bad.nc" in capsys.readouterr().err


# ---------------------------------------------------------------- one parser per argument kind


def test_numbers_after_an_option_may_be_negative():
    assert cli_args.join_negative_values(["roll", "--goal", "-1.2,1.5", "--yaw", "-30"]) == [
        "roll",
        "--goal=-1.2,1.5",
        "--yaw=-30",
    ]
    assert cli_args.join_negative_values(["plan", "--face", "9,10,12", "-h"]) == ["plan", "--face", "9,10,12", "-h"]
    args = cli.build_parser().parse_args(cli_args.join_negative_values(["plan", "--goal", "-1.2,-0.5", "--yaw", "-30"]))
    assert args.goal == [-1.2, -0.5] and args.yaw == -30
    args = cli.build_parser().parse_args(cli_args.join_negative_values(["plan", "--direction", "-90"]))
    np.testing.assert_allclose(args.direction, [0.0, -1.0], atol=1e-15)


def test_the_same_terrain_spec_builds_the_same_ground_under_every_command():
    """Regression: `--terrain random:3` was a 6 m field under simulate and a 12 m one under
    roll/plan."""
    p = cli.build_parser()
    sim = p.parse_args(["simulate", "--pair", "10", "--pressure", "1", "--out", "x.nc", "--terrain", "random:3"])
    roll = p.parse_args(["roll", "--goal", "1,1", "--terrain", "random:3"])
    plan = p.parse_args(["plan", "--goal", "1,1", "--terrain", "random:3"])
    for other in (roll, plan):
        np.testing.assert_array_equal(sim.terrain.heights, other.terrain.heights)
        assert sim.terrain.origin == other.terrain.origin and sim.terrain.spacing == other.terrain.spacing


@pytest.mark.parametrize(
    "cmd",
    [
        ["simulate", "--pair", "10", "--pressure", "1", "--out", "x.nc"],
        ["roll", "--goal", "1,1", "--workspace", "missing.nc"],
    ],
)
def test_a_fractional_face_is_refused_by_every_command(tmp_path, monkeypatch, capsys, cmd):
    """Regression: `roll --face 9.5` was truncated to face 9."""
    monkeypatch.chdir(tmp_path)
    assert cli.main([*cmd, "--face", "9.5"]) == cli.EXIT_INPUT
    assert "unknown face 9.5" in capsys.readouterr().err


@pytest.mark.parametrize("option, value", [("--duration", "0"), ("--duration", "-1"), ("--ramp", "-1")])
def test_durations_are_checked_and_named(capsys, option, value):
    with pytest.raises(SystemExit) as e:
        cli.main(["simulate", "--pair", "10", "--pressure", "1", "--out", "x.nc", option, value])
    assert e.value.code == cli.EXIT_USAGE
    assert f"argument {option}" in capsys.readouterr().err


def test_config_show_and_check(tmp_path, capsys):
    import yaml

    assert cli.main(["config", "show"]) == 0
    assert yaml.safe_load(capsys.readouterr().out) == config.load()
    bad = tmp_path / "bad.yaml"
    bad.write_text("sweep:\n  levels: [0.4, -0.8]\n")
    assert cli.main(["config", "check", str(bad)]) == cli.EXIT_INPUT
    assert "sweep.levels[1]" in capsys.readouterr().err


def test_render_draws_the_reference_support_of_the_datasets_strut_length(tmp_path, monkeypatch):
    """Regression: `tensegrity render` drew the support triangle of a 0.5 m strut whatever
    strut length the dataset was made with."""
    from tensegrity.io import formats
    from tensegrity.physics import frames
    from tensegrity.render import face_workspace as paper

    P, n = 2, 1
    ds = formats.nominal_dataset(
        [10],
        [1.0, 2.0],
        np.full((n, P, 3), 0.1),
        np.zeros((n, P, 3)),
        np.zeros((n, P, 3, 3)),
        np.full((n, P), 0.05),
        np.array([np.nan]),
        np.zeros((n, P), np.int8),
        np.full((n, P), 1e-5),
        {"contact": "equilateral", "face": 8, "face_nodes": [9, 12, 10], "mode": "free"},
        0.8,
    )
    path = datasets.write(ds, tmp_path / "n.nc", {}, "test", stage="nominal", allow_nan=formats.NOMINAL_ALLOW_NAN)
    seen = {}
    monkeypatch.setattr(paper, "fig_workspace", lambda lines, support, out, **kw: seen.update(support=support))
    from tensegrity.stages.render import render_dataset

    render_dataset(path, tmp_path / "n.png")
    np.testing.assert_allclose(seen["support"], frames.rest_frame(8, 0.8)[1])
    assert not np.allclose(seen["support"], frames.rest_frame(8, 0.5)[1])
    # a file written before the geometry was stored in it: the strut length of its provenance
    old = datasets.write(
        ds.drop_vars(["strut_length", "rest_cog", "rest_support"]),
        tmp_path / "old.nc",
        {"params": {"strut_length": 0.7}},
        "test",
        allow_nan=formats.NOMINAL_ALLOW_NAN,
    )
    assert datasets.strut_length(old) == 0.7 and datasets.strut_length(path) == 0.8


class _Terminal(io.StringIO):
    def isatty(self) -> bool:
        return True


@pytest.mark.parametrize("terminal", [False, True])
def test_progress_counts_simulated_seconds_on_a_terminal_only(monkeypatch, terminal):
    """The bar of `roll` and `simulate` (`progress.bar`, fed by the simulations' progress
    callback, here `lockstep`'s) counts simulated seconds on a terminal; elsewhere it writes
    nothing."""
    from tensegrity.cli import progress
    from tensegrity.locomotion import RollSettings
    from tensegrity.locomotion.lockstep import lockstep
    from tensegrity.physics import dynamics as d
    from tensegrity.physics.params import Params
    from tensegrity.physics.terrain import Terrain

    err = _Terminal() if terminal else io.StringIO()
    monkeypatch.setattr(sys, "stderr", err)
    params, flat, s = Params(), Terrain.flat(), RollSettings()

    def hold_three(b, obs):
        for _ in range(3):
            yield np.zeros(12)

    with progress.bar(None, "test") as bar:
        lockstep(params, flat, d.stand_on(params, 1, flat), hold_three, s, bar.update)
        if terminal:  # a disabled bar counts nothing
            assert bar.n == pytest.approx(3 * s.interval)
    assert ("test: 0.1 s simulated" in err.getvalue()) == terminal
    assert (err.getvalue() == "") != terminal


def test_files_of_different_runs_are_refused_naming_both(small_results, tmp_path, capsys):
    """curves.json of a robot with 0.6 m struts beside the default workspace: `query` refuses
    (it answered "rolls" for a robot that stands); curves without a configuration (written before
    files named theirs) are still read."""
    doc = json.loads((small_results / "curves.json").read_text())
    assert doc["config"]["params"]["strut_length"] == 0.5 and "fit" in doc["config"]
    doc["config"]["params"]["strut_length"] = 0.6
    other = tmp_path / "curves.json"
    other.write_text(json.dumps(doc))
    argv = ["query", "--workspace", str(small_results / "workspace.nc"), "--face", "8", "--pair", "10"]
    assert cli.main([*argv, "--pressure", "3.0", "--curves", str(other)]) == cli.EXIT_INPUT
    err = capsys.readouterr().err
    assert str(other) in err and "workspace.nc" in err and "params.strut_length: 0.6 against 0.5" in err
    del doc["config"]
    other.write_text(json.dumps(doc))
    assert cli.main([*argv, "--pressure", "3.0", "--curves", str(other)]) == 0


def test_query_at_zero_pressure_is_the_unactuated_robot(small_results, capsys):
    from tensegrity.physics import frames

    argv = ["query", "--curves", str(small_results / "curves.json"), "--workspace", str(small_results / "workspace.nc")]
    assert cli.main([*argv, "--face", "7", "--pair", "10", "--pressure", "0", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    cog, support = frames.rest_frame(7, 0.5)
    np.testing.assert_allclose(out["cog_m"], cog, atol=1e-7)
    np.testing.assert_allclose(out["support_m"], support, atol=1e-7)
    assert out["stands"] and out["margin_m"] > 0.05


def test_version_faces_and_a_face_as_a_table(small_results, tmp_path, capsys):
    import tensegrity

    with pytest.raises(SystemExit) as e:
        cli.main(["--version"])
    assert e.value.code == 0 and capsys.readouterr().out.strip() == f"tensegrity {tensegrity.__version__}"
    assert cli.main(["faces"]) == 0
    rows = capsys.readouterr().out.splitlines()[1:]
    assert len(rows) == 20 and rows[7].split()[:3] == ["8", "(9,10,12)", "equilateral"]
    assert rows[19].split()[2] == "isosceles"
    out = tmp_path / "face8.csv"
    assert (
        cli.main(["table", "--face", "9,10,12", "--workspace", str(small_results / "workspace.nc"), "--out", str(out)])
        == 0
    )
    lines = out.read_text().splitlines()
    assert lines[0] == "pair,pressure_MPa,cog_x_m,cog_y_m,cog_z_m,margin_m,tip_pressure_MPa"
    ws = tensegrity.load_workspace(small_results / "workspace.nc")
    assert len(lines) == 1 + len(ws.pairs(8)) * (len(ws.levels) + 1)  # the 0 MPa row of each pair first
    first = lines[1].split(",")
    assert first[1] == "0" and float(first[4]) == pytest.approx(ws.rest_cog[7][2], abs=1e-9)
    row = next(r.split(",") for r in lines if r.startswith("10,2.4,"))
    k = list(ws.levels).index(2.4)
    assert [float(v) for v in row[2:5]] == pytest.approx(ws.cog[7, 9, k].tolist(), abs=1e-9)
