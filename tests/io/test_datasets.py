"""tensegrity.io.datasets: contract checks, attributes, atomic and reproducible writes."""

import re
import time

import numpy as np
import pytest
import xarray as xr

import tensegrity
from tensegrity.io import config, datasets


@pytest.fixture(scope="module")
def cfg():
    return config.load()


def sample() -> xr.Dataset:
    rng = np.random.default_rng(0)
    t = np.arange(20) * 1e-3
    return xr.Dataset(
        {
            "cog": (
                ("time", "axis"),
                rng.normal(size=(20, 3)),
                {"units": "m", "long_name": "centre of gravity in the support frame"},
            ),
            "pressure_cmd": (("time",), np.full(20, 0.4), {"units": "MPa", "long_name": "commanded pressure"}),
            "face": ((), np.int64(3), {"units": "1", "long_name": "contact face number"}),
        },
        coords={"time": ("time", t, {"units": "s", "long_name": "time"}), "axis": ("axis", ["x", "y", "z"])},
        attrs={"comment": "kept"},
    )


def test_write_read_round_trip_and_attributes(tmp_path, cfg):
    ds = sample()
    path = datasets.write(ds, tmp_path / "deep" / "er" / "pair10.nc", cfg, "Sweep of pair 10", stage="sweep")
    assert path.is_file()
    back = datasets.read(path)
    xr.testing.assert_identical(back.drop_attrs(deep=False), ds.drop_attrs(deep=False))
    assert back.attrs["title"] == "Sweep of pair 10"
    assert back.attrs["source"] == f"tensegrity {tensegrity.__version__}"
    assert back.attrs["Conventions"] == "CF-1.10"
    assert back.attrs["history"] == f"created by tensegrity {tensegrity.__version__} sweep"
    assert not re.search(r"\d{4}-\d\d-\d\d|\d\d:\d\d", back.attrs["history"])
    assert back.attrs["comment"] == "kept"
    assert datasets.provenance_config(back) == cfg
    assert datasets.provenance_config(path) == cfg
    assert ds.attrs == {"comment": "kept"}  # the caller's dataset is not modified
    # read() closed the file: it can be replaced at once
    datasets.write(ds, path, cfg, "again")


def test_history_is_appended(tmp_path, cfg):
    ds = sample().assign_attrs(history="created by tensegrity 0.1.0 sweep")
    back = datasets.read(datasets.write(ds, tmp_path / "n.nc", cfg, "t", stage="nominal"))
    assert back.attrs["history"].splitlines() == [
        "created by tensegrity 0.1.0 sweep",
        f"created by tensegrity {tensegrity.__version__} nominal",
    ]


def test_rewrite_is_byte_identical(tmp_path, cfg):
    ds = sample()
    a = datasets.write(ds, tmp_path / "a.nc", cfg, "t", stage="sweep").read_bytes()
    time.sleep(1.1)  # anything stamped with the time (to the second) would now differ
    b = datasets.write(ds, tmp_path / "other" / "b.nc", cfg, "t", stage="sweep").read_bytes()
    datasets.write(ds, tmp_path / "a.nc", cfg, "t", stage="sweep")
    assert a == b == (tmp_path / "a.nc").read_bytes()


@pytest.mark.parametrize(
    "var, attr", [("cog", "units"), ("pressure_cmd", "long_name"), ("time", "units"), ("face", "long_name")]
)
def test_missing_units_or_long_name(tmp_path, cfg, var, attr):
    ds = sample()
    del ds[var].attrs[attr]
    with pytest.raises(ValueError, match=f"variable '{var}' has no '{attr}'"):
        datasets.write(ds, tmp_path / "x.nc", cfg, "t")
    assert not list(tmp_path.iterdir())


def test_string_coordinates_need_no_units(tmp_path, cfg):
    ds = sample().assign_coords(contact=("contact", ["equilateral", "isosceles"]))
    datasets.write(ds, tmp_path / "x.nc", cfg, "t")


@pytest.mark.parametrize("bad", [np.nan, np.inf])
def test_non_finite_rejected_unless_allowed(tmp_path, cfg, bad):
    ds = sample()
    ds["cog"][3, 1] = bad
    with pytest.raises(ValueError, match="variable 'cog' holds 1 non-finite"):
        datasets.write(ds, tmp_path / "x.nc", cfg, "t")
    assert not (tmp_path / "x.nc").exists()
    back = datasets.read(datasets.write(ds, tmp_path / "x.nc", cfg, "t", allow_nan=["cog"]))
    assert not np.isfinite(back["cog"][3, 1])
    with pytest.raises(ValueError, match="allow_nan names no variable of the dataset: cgo"):
        datasets.write(ds, tmp_path / "y.nc", cfg, "t", allow_nan=["cgo"])


def test_non_finite_coordinate_rejected(tmp_path, cfg):
    ds = sample()
    ds = ds.assign_coords(time=("time", np.r_[np.nan, ds.time.values[1:]], ds.time.attrs))
    with pytest.raises(ValueError, match="variable 'time' holds"):
        datasets.write(ds, tmp_path / "x.nc", cfg, "t")


@pytest.mark.parametrize("when", ["before", "after"])
def test_failed_write_leaves_nothing(tmp_path, cfg, monkeypatch, when):
    """A crash before or after the bytes reach the temporary file leaves neither it nor the target."""
    original = xr.Dataset.to_netcdf

    def crash(self, path, *args, **kwargs):
        if when == "after":
            original(self, path, *args, **kwargs)
        else:
            open(path, "wb").write(b"\x89HDF\r\n partial")
        raise OSError("disk full")

    monkeypatch.setattr(xr.Dataset, "to_netcdf", crash)
    out = tmp_path / "results"
    with pytest.raises(OSError, match="disk full"):
        datasets.write(sample(), out / "pair10.nc", cfg, "t")
    assert list(out.iterdir()) == []


def test_failed_write_keeps_previous_file(tmp_path, cfg, monkeypatch):
    path = datasets.write(sample(), tmp_path / "x.nc", cfg, "old")
    before = path.read_bytes()

    def crash(self, path, *args, **kwargs):
        raise KeyboardInterrupt

    monkeypatch.setattr(xr.Dataset, "to_netcdf", crash)
    with pytest.raises(KeyboardInterrupt):
        datasets.write(sample(), path, cfg, "new")
    assert path.read_bytes() == before
    assert [p.name for p in tmp_path.iterdir()] == ["x.nc"]


def test_provenance_config_requires_attribute():
    with pytest.raises(ValueError, match="no 'config' attribute"):
        datasets.provenance_config(sample())
