"""Calibrating the prototype's twisted strings from a run driven in volts (issue 32, item 5): the
strings' and motor's keys recovered without noise to 0.1 %, the combinations no trajectory can
separate named, and a file driven by both pressures and voltages, or by neither, refused."""

import numpy as np
import pytest
import xarray as xr

from tensegrity.calibration import calibrate
from tensegrity.calibration import synthetic as syn
from tensegrity.cli import main
from tensegrity.io import config, datasets, settings
from tensegrity.io.formats import common
from tensegrity.io.formats.measured import VOLTAGE_CSV_COLUMNS, read_measured, write_measured_csv
from tensegrity.physics.twisted import TwistedString

KEY = "actuator.twisted_string."
HOLD = 0.2  # s per voltage step (the first at 0 V: the robot stands still over the first samples)


@pytest.fixture(scope="module")
def strings() -> TwistedString:
    return TwistedString()


@pytest.fixture(scope="module")
def volt_run(truth, strings):
    """1.2 s of the free robot whose pairs 1, 5, 10 are driven by 24 V steps, 100 Hz, no noise
    (the strands twist by up to ~40 rad; the nodes move by up to 0.6 mm)."""
    return syn.measure(truth, syn.excitation(1.2, HOLD, level=24.0), HOLD, "free", rate=100.0, motors=strings)


def test_noise_free_run_in_volts_recovers_string_radius_and_stall_torque(volt_run, truth, strings):
    """A string key and a motor key, started 10 % and 15 % off, within 0.1 %; 3 robots per
    Jacobian (the robot stands still first, so its initial state is read exactly)."""
    start = strings.replace(string_radius=4.95e-4, stall_torque=0.0833)
    names = (KEY + "string_radius", KEY + "stall_torque")
    c = calibrate(volt_run, truth, names, "free", 1e-4, fit_initial=False, check=0.0, motors=start)
    true = np.array([strings.string_radius, strings.stall_torque])
    assert np.max(np.abs(c.estimate / true - 1)) < 1e-3, c.estimate
    assert not c.unc.undetermined and np.all((c.unc.lower <= c.estimate) & (c.estimate <= c.unc.upper))
    assert c.motors.string_radius == pytest.approx(c.estimate[0]) and c.params == truth


@pytest.mark.parametrize(
    "keys, named",
    [
        (("spring_stiffness", "fibre_stiffness"), "the product actuator.twisted_string.spring_stiffness^"),
        (("stall_current", "no_load_current"), "a common scale of actuator.twisted_string.stall_current, "),
    ],
    ids=["spring and fibre in series", "the currents' common scale"],
)
def test_combinations_no_trajectory_separates_are_named(volt_run, truth, strings, keys, named):
    """The kernel reads the spring and the fibre only as their series stiffness, and the
    datasheet currents only through their ratio (G, D, TC of (T4)): fitted together, the fit
    names the combination and gives no interval, and the motion is still reproduced."""
    start = strings.replace(**{keys[0]: 1.05 * getattr(strings, keys[0])})
    c = calibrate(volt_run, truth, tuple(KEY + k for k in keys), "free", 1e-4, False, check=0.0, motors=start)
    assert len(c.unc.undetermined) == 1 and c.unc.undetermined[0].startswith(named), c.unc.undetermined
    assert np.isnan(c.unc.se).all() and c.rms_mm < 1e-3


def _drop(rows, name):
    j = rows[0].index(name)
    return [r[:j] + r[j + 1 :] for r in rows]


@pytest.mark.parametrize(
    "edit, message",
    [
        (lambda rows: [r + (["p3"] if i == 0 else ["0"]) for i, r in enumerate(rows)], r"\(p3, v1, v2, v3 \.\.\.\)"),
        (lambda rows: [["p7" if c == "v7" else c for c in r] for r in rows], r"both pressures and voltages \(p7, v1"),
        (lambda rows: [["u" + c[1:] if c[0] == "v" else c for c in r] for r in rows], r"no column p1 \.\. p12 \(MPa\)"),
        (lambda rows: _drop(rows, "v12"), "no column v12"),
    ],
    ids=["both", "a pressure among voltages", "neither", "a voltage missing"],
)
def test_a_csv_driven_by_both_or_neither_is_refused_naming_the_columns(volt_run, tmp_path, edit, message):
    lines = write_measured_csv(volt_run.head(6), tmp_path / "v.csv").read_text().splitlines()
    rows = edit([line.split(",") for line in lines])
    path = tmp_path / "bad.csv"
    path.write_text("\n".join(",".join(r) for r in rows) + "\n")
    with pytest.raises(ValueError, match=message):
        read_measured(path)


def test_run_file_in_volts_is_read_and_one_with_both_commands_refused(volt_run, tmp_path):
    v = datasets.var
    data = {"nodes": v(("time", "node", "axis"), volt_run.nodes, "m", "node positions, world frame")}
    data["voltage_cmd"] = v(("time", "pair"), volt_run.pressure, "V", "pair voltages commanded")
    coords = {"time": ("time", volt_run.t, {"units": "s", "long_name": "time"}), **common.coords(np.arange(1, 13))}
    datasets.write(xr.Dataset(data, coords=coords, attrs={"mode": "free"}), tmp_path / "v.nc", {}, "a run in volts")
    m = read_measured(tmp_path / "v.nc")
    assert m.command == "voltage" and np.array_equal(m.pressure, volt_run.pressure) and m.mode == "free"
    data["pressure_cmd"] = v(("time", "pair"), 0 * volt_run.pressure, "MPa", "pair pressures commanded")
    datasets.write(xr.Dataset(data, coords=coords), tmp_path / "both.nc", {}, "both")
    with pytest.raises(ValueError, match="both pressures and voltages"):
        read_measured(tmp_path / "both.nc")


@pytest.mark.parametrize(
    "fit, which, message",
    [
        (("cable_stiffness",), "volts", "cable_stiffness has no effect in a run driven in volts"),
        ((KEY + "spring_stiff",), "volts", "'actuator.twisted_string.spring_stiff' is not a parameter"),
        ((KEY + "spring_stiffness",), "pressures", "driven by pressures"),
        ((KEY + "spring_stiffness",), "no motors", "driven in volts: .* give motors"),
        ((KEY + "viscous_friction",), "volts", "starts at 0; .*--set actuator.twisted_string.viscous_friction"),
    ],
)
def test_bad_requests_on_a_run_in_volts_are_refused(volt_run, free_run, truth, strings, fit, which, message):
    m, motors = {"volts": (volt_run, strings), "pressures": (free_run, strings), "no motors": (volt_run, None)}[which]
    with pytest.raises(ValueError, match=message):
        calibrate(m.head(5), truth, fit, "free", 1e-4, motors=motors)


def test_calibrate_command_on_a_csv_in_volts_writes_the_actuator_section(volt_run, tmp_path, monkeypatch):
    """CSV in volts -> calibrate -> config check: calibrated.yaml holds the twisted strings
    (every key, the fitted one calibrated), the report the estimate; a muscle key exits 3."""
    monkeypatch.chdir(tmp_path)
    path = write_measured_csv(volt_run, "run.csv")
    assert path.read_text().splitlines()[0] == ",".join(VOLTAGE_CSV_COLUMNS)
    key = KEY + "spring_stiffness"
    args = ["calibrate", "run.csv", "--fit", key, "--mode", "free", "--out", "cal.yaml", "--report", "r.nc"]
    sets = ["--set", f"{key}=1100", "--initial", "data"]
    assert main([*args, *sets]) == 0
    assert main(["config", "check", "cal.yaml"]) == 0
    cfg = config.load("cal.yaml")
    assert cfg["actuator"]["kind"] == "twisted_string"  # the run's actuator: every command drives it
    motors = settings.motors(cfg)
    assert motors.spring_stiffness == pytest.approx(1000.0, rel=1e-3)
    assert motors.string_radius == TwistedString().string_radius
    ds = datasets.read("r.nc")
    assert float(ds[key]) == pytest.approx(1000.0, rel=1e-3) and ds[key].attrs["units"] == "N m-1"
    assert main(["calibrate", "run.csv", "--fit", "cable_stiffness", "--mode", "free", "--out", "x.yaml"]) == 3
    assert not (tmp_path / "x.yaml").exists()


def test_simulate_writes_a_run_in_volts_that_calibrate_reads_back(tmp_path, monkeypatch):
    """`tensegrity simulate --voltage` with actuator.kind twisted_string writes voltage_cmd (V)
    and the state at t = 0 (motors untwisted) as its first sample; `tensegrity calibrate` on it
    (the same configuration) recovers the string radius, started 10 % off, to 0.1 %."""
    monkeypatch.chdir(tmp_path)
    volts = ["--set", "actuator.kind=twisted_string", "--set", "sim.record_every=100"]  # 100 Hz
    run = ["simulate", "--face", "8", "--pair", "1", "10", "--voltage", "24", "--duration", "0.5"]
    assert main([*run, "--out", "run.nc", *volts]) == 0
    ds = datasets.read("run.nc")
    assert "pressure_cmd" not in ds and ds["voltage_cmd"].attrs["units"] == "V"
    assert ds["time"].values[0] == 0.0 and ds["voltage_cmd"].values[1:, [0, 9]].min() == 24.0
    radius = TwistedString().string_radius
    key = KEY + "string_radius"
    args = ["calibrate", "run.nc", "--fit", key, "--out", "cal.yaml", "--report", "r.nc", "--initial", "data"]
    assert main([*args, "--check", "0", *volts, "--set", f"{key}={1.1 * radius}"]) == 0
    assert float(datasets.read("r.nc")[key]) == pytest.approx(radius, rel=1e-3)
    # the calibrated configuration alone drives the strings: a run in volts from it (no --set)
    # repeats the measured one (a pneumatic actuator.kind would refuse --voltage, exit 3)
    assert main([*run, "--out", "again.nc", "--config", "cal.yaml", "--set", "sim.record_every=100"]) == 0
    again = datasets.read("again.nc")["nodes"].values
    assert np.max(np.abs(again - ds["nodes"].values)) < 1e-6  # m: the radius to 0.1 %
    # the muscles' --pressure with the strings, or --voltage with the muscles: refused, exit 3
    assert main([*run[:-4], "--pressure", "1", "--out", "x.nc", *volts]) == 3
    assert main([*run, "--out", "x.nc"]) == 3 and not (tmp_path / "x.nc").exists()
