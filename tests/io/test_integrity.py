"""Corrupted files fail loudly: Fletcher-32 checksums in every dataset, load-time checks of what
the planner and `tensegrity query` read, and no temporaries left behind by killed writers."""

import json
import os
import subprocess
import sys
import time

import netCDF4
import numpy as np
import pytest
import xarray as xr

from tensegrity import atomic, cli
from tensegrity.io import config, datasets, formats
from tensegrity.physics import topology as topo
from tensegrity.workspace import query

# A float pattern that occurs nowhere else in the file: found by its bytes, then flipped.
PATTERN = np.arange(1, 4097, dtype=float) * 1.0000000001e-3 + np.pi


@pytest.fixture(scope="module")
def cfg():
    return config.load()


def sample() -> xr.Dataset:
    return xr.Dataset(
        {
            "big": (("i",), PATTERN, {"units": "m", "long_name": "a pattern of 4096 floats"}),
            "face": ((), np.int64(3), {"units": "1", "long_name": "contact face number"}),
            "kind": (("axis",), np.array(["a", "b", "c"]), {"long_name": "labels"}),
        },
        coords={
            "i": ("i", np.arange(PATTERN.size), {"units": "1", "long_name": "index"}),
            "axis": ("axis", ["x", "y", "z"], {"units": "1", "long_name": "support-frame axis"}),
        },
    )


def flip_data(path, nbytes=4096):
    """Flip `nbytes` bytes in the middle of the stored PATTERN (the file's data region)."""
    raw = bytearray(path.read_bytes())
    start = raw.find(PATTERN.tobytes()[:64])
    assert start > 0, "pattern not found in the file"
    mid = start + PATTERN.nbytes // 2 - nbytes // 2
    for k in range(mid, mid + nbytes):
        raw[k] ^= 0xFF
    path.write_bytes(bytes(raw))


def test_numeric_arrays_have_checksums_coordinates_no_fill(tmp_path, cfg):
    path = datasets.write(sample(), tmp_path / "x.nc", cfg, "t")
    with netCDF4.Dataset(path) as f:
        for name in ("big", "i"):
            assert f[name].filters()["fletcher32"], name
        assert "_FillValue" not in f["i"].ncattrs()  # CF 2.5.1: coordinates have none
        assert "_FillValue" in f["big"].ncattrs()  # data variables keep NaN as fill
    xr.testing.assert_identical(datasets.read(path).drop_attrs(deep=False), sample())


def test_corrupted_data_fails_naming_the_file(tmp_path, cfg):
    path = datasets.write(sample(), tmp_path / "corrupt.nc", cfg, "t")
    flip_data(path)
    with pytest.raises(datasets.CorruptDatasetError, match=r"corrupt\.nc.*corrupted") as e:
        datasets.read(path)
    assert isinstance(e.value, ValueError)
    with pytest.raises(FileNotFoundError, match="missing.nc"):
        datasets.read(tmp_path / "missing.nc")
    (tmp_path / "junk.nc").write_bytes(b"not netCDF at all" * 100)
    with pytest.raises(datasets.CorruptDatasetError, match="junk.nc"):
        datasets.read(tmp_path / "junk.nc")


def small_workspace(tmp_path, cfg, levels=(1.2, 2.4)):
    """A workspace.nc of the contract: pair #10 only, the rest NaN; small plausible numbers."""
    P = len(levels)
    rng = np.random.default_rng(1)
    cog = np.full((topo.N_FACES, topo.N_PAIRS, P, 3), np.nan)
    sup = np.full((topo.N_FACES, topo.N_PAIRS, P, 3, 3), np.nan)
    margin = np.full((topo.N_FACES, topo.N_PAIRS, P), np.nan)
    tri = np.array([[-0.2, -0.1, 0.0], [0.2, -0.1, 0.0], [0.0, 0.2, 0.0]])
    cog[:, 9] = rng.normal(scale=0.01, size=(topo.N_FACES, P, 3)) + [0, 0, 0.19]
    sup[:, 9] = tri + rng.normal(scale=1e-3, size=(topo.N_FACES, P, 3, 3))
    margin[:, 9] = 0.05
    ws = {"cog": cog, "support": sup, "margin": margin, "tip_pressure": np.full((topo.N_FACES, topo.N_PAIRS), np.nan)}
    ds = formats.workspace_dataset(np.asarray(levels), ws, 0.5)
    return datasets.write(
        ds, tmp_path / "workspace.nc", cfg, "Workspace", stage="map", allow_nan=formats.WORKSPACE_ALLOW_NAN
    )


def curves_json(tmp_path, levels=(1.2, 2.4)):
    lo, hi = levels[0], levels[-1]
    axis = lambda v: {
        "kind": "polynomial",
        "model": "poly1",
        "breaks": [lo, hi],
        "coefs": [[0.0, v]],
        "pmin": lo,
        "pmax": hi,
        "cv_rmse": None,
    }
    doc = {
        "units": {"pressure": "MPa", "cog": "m"},
        "contacts": {
            "equilateral": {
                "face_nodes": [9, 12, 10],
                "pairs": {"10": {"x": axis(0.01), "y": axis(-0.02), "z": axis(0.19)}},
            }
        },
    }
    p = tmp_path / "curves.json"
    p.write_text(json.dumps(doc))
    return p


def test_workspace_loads_and_query_answers(tmp_path, cfg):
    ws = small_workspace(tmp_path, cfg)
    assert formats.read_workspace(ws).levels.tolist() == [1.2, 2.4]
    ans = query.query(formats.read_curves(curves_json(tmp_path)), formats.read_workspace(ws), 8, 10, 1.8)
    assert np.isfinite(ans.margin)


def test_query_on_corrupted_workspace_exits_3_naming_the_file(tmp_path, cfg, capsys):
    ws = small_workspace(tmp_path, cfg)
    cj = curves_json(tmp_path)
    argv = ["query", "--face", "8", "--pair", "10", "--pressure", "1.8", "--curves", str(cj), "--workspace", str(ws)]
    assert cli.main(argv) == 0
    capsys.readouterr()
    raw = bytearray(ws.read_bytes())
    mid = len(raw) // 2
    raw[mid : mid + 4096] = bytes(b ^ 0xFF for b in raw[mid : mid + 4096])
    ws.write_bytes(bytes(raw))
    assert cli.main(argv) == 3
    err = capsys.readouterr().err
    assert str(ws) in err
    # and through the installed command, as a user runs it
    r = subprocess.run([sys.executable, "-m", "tensegrity.cli", *argv], capture_output=True, text=True)
    assert r.returncode == 3 and str(ws) in r.stderr, r.stderr


def _rewrite(ds, path, cfg):
    return datasets.write(
        ds, path, cfg, "Workspace", allow_nan=[v for v in formats.WORKSPACE_ALLOW_NAN if v in ds.variables]
    )


@pytest.mark.parametrize(
    "damage, message",
    [
        (lambda ds: ds.assign_coords(pressure=("pressure", [2.4, 1.2], ds.pressure.attrs)), "strictly increasing"),
        (lambda ds: ds.assign_coords(pressure=("pressure", [-1.2, 2.4], ds.pressure.attrs)), "positive"),
        (lambda ds: ds.assign(cog=ds.cog.where(ds.pair != 10, 1e20)), "'cog' reaches 1e\\+20 m"),
        (lambda ds: ds.assign(support=ds.support.where(ds.pair != 10, -7.0)), "'support' reaches 7 m"),
        (lambda ds: ds.assign(cog=ds.cog.where((ds.pair != 10) | (ds.face != 3), np.inf)), "infinite"),
        (lambda ds: ds.assign(cog=ds.cog.where((ds.pair != 10) | (ds.face != 3))), "NaN at the same"),
        (lambda ds: ds.isel(face=slice(0, 19)), "coordinate 'face'"),
        (lambda ds: ds.drop_vars("support"), "no variable 'support'"),
        (lambda ds: ds.assign(cog=ds.cog.rename(axis="corner").drop_vars("corner")), "'cog' has dimensions"),
        (lambda ds: ds.assign(margin=ds.margin * 0 + 3.0), "'margin'"),
        (lambda ds: ds.assign(tip_pressure=xr.full_like(ds.tip_pressure, 9.9)), "'tip_pressure'"),
    ],
)
def test_workspace_contract_checked_on_load(tmp_path, cfg, damage, message):
    good = datasets.read(small_workspace(tmp_path, cfg))
    bad = _rewrite(damage(good), tmp_path / "bad.nc", cfg)
    with pytest.raises(ValueError, match=message) as e:
        formats.read_workspace(bad)
    assert "bad.nc" in str(e.value)


@pytest.mark.parametrize(
    "damage, message",
    [
        (lambda c: c.update(breaks=[2.4, 1.2]), "strictly increasing"),
        (lambda c: c.update(coefs=[[0.0, float("nan")]]), "finite"),
        (lambda c: c.update(coefs=[[0.0, 0.1], [0.0, 0.1]]), "1 rows"),
        (lambda c: c.update(pmax=7.0), "pmin"),
        (lambda c: c.pop("breaks"), "malformed"),
    ],
)
def test_curves_contract_checked_on_load(tmp_path, damage, message):
    p = curves_json(tmp_path)
    doc = json.loads(p.read_text())
    damage(doc["contacts"]["equilateral"]["pairs"]["10"]["y"])
    p.write_text(json.dumps(doc))
    with pytest.raises(ValueError, match=message) as e:
        formats.read_curves(p)
    assert "curves.json" in str(e.value)
    p.write_bytes(b'{"contacts": {\x00\xff')
    with pytest.raises(ValueError, match="curves.json.*not valid JSON"):
        formats.read_curves(p)


def test_query_outside_the_workspace_pairs_is_refused(tmp_path, cfg):
    path = small_workspace(tmp_path, cfg)
    ws = formats.read_workspace(path)
    doc = formats.read_curves(curves_json(tmp_path))
    doc["contacts"]["equilateral"]["pairs"]["9"] = doc["contacts"]["equilateral"]["pairs"]["10"]
    with pytest.raises(ValueError, match="workspace.nc.*no support triangle for pair #9"):
        query.query(doc, ws, 8, 9, 1.8, wsname=str(path))


# ------------------------------------------------------------- temporaries of killed writers


def test_stale_temporaries_are_removed_before_writing(tmp_path, cfg):
    target = tmp_path / "pair10.nc"
    dead = subprocess.run(
        [sys.executable, "-c", "import os; print(os.getpid())"], capture_output=True, text=True
    ).stdout.strip()  # a PID that has exited
    killed = tmp_path / f".pair10.{dead}.0123abcd.tmp.nc"  # a writer that was killed
    old = tmp_path / f".pair10.{os.getppid()}.89abcdef.tmp.nc"  # a live PID, but long untouched
    young = tmp_path / f".pair10.{os.getppid()}.deadbeef.tmp.nc"  # a live writer still at work
    other = tmp_path / f".pair11.{dead}.0123abcd.tmp.nc"  # another target's
    unrelated = tmp_path / ".pair10.notes.tmp.nc"  # not our naming scheme
    for p in (killed, old, young, other, unrelated):
        p.write_bytes(b"\x89HDF partial")
    past = time.time() - 3600
    os.utime(old, (past, past))
    datasets.write(sample(), target, cfg, "t")
    left = sorted(p.name for p in tmp_path.iterdir())
    assert left == sorted([target.name, young.name, other.name, unrelated.name])
    atomic.write_text(tmp_path / "pair11.nc", "x")  # the text writer cleans its target's too
    assert atomic.temporary(target).name.startswith(".pair10.") and atomic.temporary(target).suffix == ".nc"
    assert not other.exists()


def test_a_two_pair_workspace_of_another_run_is_refused(tmp_path, cfg):
    """`read_workspace(path, two_pair)` (plan, roll, the runs, `load_workspace`) refuses a two-pair
    file made with another robot, naming both files and the key; `io.provenance` compares the
    keys both files hold."""
    from tensegrity.io import provenance

    ws = small_workspace(tmp_path, cfg)
    other = config.merge(cfg, {"params": {"strut_length": 0.6}})
    two = datasets.write(sample(), tmp_path / "workspace_two_pair.nc", other, "t")
    with pytest.raises(
        ValueError,
        match=r"workspace\.nc and .*workspace_two_pair\.nc were made by different.*"
        r"params\.strut_length: 0\.5 against 0\.6",
    ):
        formats.read_workspace(ws, two)
    assert provenance.differences({"a": {"x": 1, "y": 2}}, {"a": {"x": 1, "y": 3}, "b": {"z": 0}}) == ["a.y"]
    provenance.check_together({"one": {"a": {"x": 1}}, "two": {"b": {"x": 2}}, "old": None})  # nothing shared


def test_a_roll_record_that_contradicts_itself_is_refused():
    """A study's roll record with success 1 and a NaN tipping pressure (once written, issue 35)
    is refused naming the design; a consistent record passes."""
    from tensegrity.io.formats.study import _check_rolls
    from tensegrity.studies.evaluate import RollOutcome

    good = RollOutcome(True, np.array([3.6, 1.8]), np.array([17, 4]))
    failed = RollOutcome(False, np.array([3.6, np.nan]), np.array([17, 0]))
    _check_rolls([good, failed], np.array([1, 2]))
    bad = RollOutcome(True, np.array([np.nan, 1.8]), np.array([17, 4]))
    with pytest.raises(ValueError, match="design 7: both rolls succeeded"):
        _check_rolls([good, bad], np.array([6, 7]))
    nowhere = RollOutcome(False, np.array([3.6, 2.0]), np.array([17, 0]))
    with pytest.raises(ValueError, match="design 3: a tipping pressure"):
        _check_rolls([nowhere], np.array([3]))
