"""What `tensegrity calibrate` reads and writes: bad measurements and bad requests are refused
before any fit, naming what is wrong; the calibrated configuration is one every command accepts;
the report holds estimates, intervals, correlations and residuals, and its figure is drawn."""

import numpy as np
import pytest
import xarray as xr

from tensegrity.calibration import Measurement, calibrate
from tensegrity.cli import main
from tensegrity.io import config, datasets
from tensegrity.io.formats.measured import CSV_COLUMNS, read_measured, write_measured_csv


@pytest.fixture
def csv_lines(free_run, tmp_path):
    """The lines of a CSV of the free run (header first)."""
    path = write_measured_csv(free_run.head(12), tmp_path / "m.csv")
    return path.read_text().splitlines()


def _write(tmp_path, lines):
    p = tmp_path / "bad.csv"
    p.write_text("\n".join(lines) + "\n")
    return p


def test_csv_round_trip_and_any_column_order(free_run, csv_lines, tmp_path):
    m = read_measured(tmp_path / "m.csv")
    assert np.array_equal(m.nodes, free_run.nodes[:12]) and np.array_equal(m.pressure, free_run.pressure[:12])
    rows = [line.split(",") for line in csv_lines]
    order = np.random.default_rng(1).permutation(len(CSV_COLUMNS))
    shuffled = _write(tmp_path, [",".join(r[i] for i in order) + ",note" for r in rows])
    assert np.array_equal(read_measured(shuffled).nodes, m.nodes)


@pytest.mark.parametrize(
    "edit, message",
    [
        (lambda rows: [[c for j, c in enumerate(r) if j != CSV_COLUMNS.index("n5_y")] for r in rows], "no column n5_y"),
        (lambda rows: rows[:4] + [rows[3]] + rows[5:], "time of .* does not increase: sample 4"),
        (
            lambda rows: [r if i != 6 else r[:-3] + [""] + r[-2:] for i, r in enumerate(rows)],
            "has no pressure for pair 10",
        ),
        (lambda rows: [r if i != 1 else r[:7] + [""] + r[8:] for i, r in enumerate(rows)], "lacks node 3"),
        (lambda rows: [r if i != 5 else [str(float(r[0]) + 0.003)] + r[1:] for i, r in enumerate(rows)], "not on the"),
        (lambda rows: [r if i != 3 else r[:2] + ["1,2"] + r[3:] for i, r in enumerate(rows)], "fields"),
        (lambda rows: [r if i != 3 else r[:2] + ["abc"] + r[3:] for i, r in enumerate(rows)], "column n1_y: 'abc'"),
    ],
    ids=[
        "missing node column",
        "time not increasing",
        "NaN pressure",
        "first sample incomplete",
        "off grid",
        "fields",
        "text",
    ],
)
def test_bad_measurements_are_named(csv_lines, tmp_path, truth, edit, message):
    rows = edit([line.split(",") for line in csv_lines])
    with pytest.raises(ValueError, match=message):
        m = read_measured(_write(tmp_path, [",".join(r) for r in rows]))
        calibrate(m, truth, ("cable_damping",), "free", 1e-4)  # the grid is checked by the fit


def test_a_netcdf_without_node_positions_is_refused(tmp_path):
    ds = xr.Dataset({"cog": datasets.var(("time", "axis"), np.zeros((3, 3)), "m", "centre of gravity")})
    datasets.write(ds, tmp_path / "x.nc", {}, "not a run")
    with pytest.raises(ValueError, match="no variable 'nodes'"):
        read_measured(tmp_path / "x.nc")


@pytest.mark.parametrize(
    "fit, mode, dt, message",
    [
        (("stiffness",), "free", 1e-4, "'stiffness' is not a parameter that can be fitted"),
        (("friction",), "free", 1e-4, "friction has no effect in the free mode"),
        (("cable_damping", "cable_damping"), "free", 1e-4, "named twice"),
        (("strut_damping",), "free", 1e-4, "starts at 0"),
        (("cable_damping",), "sideways", 1e-4, "mode 'sideways'"),
        (("cable_damping",), "free", 3e-4, "does not divide the sampling interval"),
    ],
)
def test_bad_requests_are_refused_before_any_simulation(free_run, truth, fit, mode, dt, message):
    with pytest.raises(ValueError, match=message):
        calibrate(free_run.head(5), truth, fit, mode, dt)


def test_measurement_needs_matching_shapes():
    with pytest.raises(ValueError, match=r"pressure: expected shape \(4, 12\)"):
        Measurement(np.arange(4.0), np.zeros((4, 12, 3)), np.zeros((4, 11)))


def test_calibrate_command_writes_a_configuration_every_command_accepts(tmp_path, monkeypatch, capsys):
    """simulate -> calibrate (free mode, initial state fitted, prediction check) -> config check;
    the report and its figure; the printout says what gave each interval; a bad key exits 3
    naming it."""
    monkeypatch.chdir(tmp_path)
    coarse = ["--set", "sim.record_every=100"]  # samples at 100 Hz
    assert (
        main(
            [
                "simulate",
                "--face",
                "8",
                "--pair",
                "10",
                "--pressure",
                "2",
                "--duration",
                "0.3",
                "--out",
                "run.nc",
                *coarse,
            ]
        )
        == 0
    )
    args = ["calibrate", "run.nc", "--fit", "cable_damping,muscle_gain", "--out", "cal.yaml", "--report", "rep.nc"]
    assert main([*args, "--set", "params.muscle_gain=560", "--set", "params.cable_damping=2.2"]) == 0
    rows = [ln for ln in capsys.readouterr().out.splitlines() if ln.startswith(("muscle_gain", "cable_damping"))]
    assert len(rows) == 2 and all(ln.endswith(", linearised") for ln in rows), rows
    assert main(["config", "check", "cal.yaml"]) == 0
    cfg = config.load("cal.yaml")
    ds = datasets.read("rep.nc")
    assert cfg["params"]["muscle_gain"] == pytest.approx(589.0, rel=1e-3) == float(ds["muscle_gain"])
    assert cfg["params"]["cable_damping"] == pytest.approx(2.0, rel=1e-3)
    assert cfg["actuator"]["kind"] == "pneumatic"  # the run's actuator, whatever --set said
    assert ds["correlation"].shape == (2, 2) and ds.attrs["mode"] == "free" and ds.attrs["residual_rms_mm"] < 1e-3
    assert ds["residual"].dims == ("time", "node", "axis") and ds.sizes["time"] == 30
    assert np.isfinite(ds.attrs["check_rms_predict_mm"])
    from PIL import Image

    png = np.asarray(Image.open("rep.png").convert("L"), float)
    assert png.shape[0] > 500 and png.std() > 10  # drawn, not blank
    assert main(["calibrate", "run.nc", "--fit", "cable_stiff", "--out", "x.yaml"]) == 3
    assert not (tmp_path / "x.yaml").exists()
