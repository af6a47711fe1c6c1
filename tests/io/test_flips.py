"""One flipped byte anywhere in a dataset file either fails to read or reads back identical
(issue 35): the `digest` attributes catch what HDF5's Fletcher-32 filter cannot, such as a
damaged chunk index that makes HDF5 return the fill value without reading any chunk."""

import numpy as np
import pytest
import xarray as xr

from tensegrity.io import config, datasets, digests

N_META, N_REST = 500, 150  # seeded samples of byte offsets: metadata region, the rest of the file


def workspace_like() -> xr.Dataset:
    """A small dataset shaped like workspace.nc: chunked float variables holding NaN and finite
    values, integer and string variables and coordinates, a scalar."""
    rng = np.random.default_rng(35)
    cog = rng.normal(scale=0.01, size=(8, 4, 3)) + [0.0, 0.0, 0.19]
    cog[[1, 5]] = np.nan
    margin = rng.uniform(-0.01, 0.05, size=(8, 4))
    margin[:, 0] = np.nan
    tip = np.full(8, np.nan)
    tip[[2, 3, 7]] = [1.6, 2.4, 4.0]
    m = {"units": "m"}
    return xr.Dataset(
        {
            "cog": (("face", "pressure", "axis"), cog, {**m, "long_name": "centre of gravity"}),
            "margin": (("face", "pressure"), margin, {**m, "long_name": "stability margin"}),
            "tip_pressure": ("face", tip, {"units": "MPa", "long_name": "tipping pressure"}),
            "face_nodes": (("face", "corner"), rng.integers(1, 13, size=(8, 3)), {"units": "1", "long_name": "nodes"}),
            "face_type": ("face", np.array(["equilateral", "isosceles"] * 4), {"long_name": "kind of face"}),
            "strut_length": ((), 0.5, {**m, "long_name": "strut length S of the robot"}),
        },
        coords={
            "face": ("face", np.arange(1, 9), {"units": "1", "long_name": "contact face number"}),
            "pressure": ("pressure", [0.4, 0.8, 1.2, 1.6], {"units": "MPa", "long_name": "pressure"}),
            "axis": ("axis", ["x", "y", "z"], {"units": "1", "long_name": "support-frame axis"}),
            "corner": ("corner", [1, 2, 3], {"units": "1", "long_name": "corner of the support triangle"}),
        },
        attrs={"contact": "equilateral"},
    )


@pytest.fixture(scope="module")
def written(tmp_path_factory):
    path = tmp_path_factory.mktemp("flips") / "workspace.nc"
    datasets.write(workspace_like(), path, config.load(), "Workspace", allow_nan=["cog", "margin", "tip_pressure"])
    return path


def data_spans(raw: bytes, ds: xr.Dataset) -> dict[str, tuple[int, int]]:
    """Where each float variable's values lie in the file's bytes (one chunk each)."""
    spans = {}
    for name in ("cog", "margin", "tip_pressure", "pressure"):
        b = np.ascontiguousarray(ds[name].values, dtype="<f8").tobytes()
        start = raw.find(b)
        assert start > 0 and raw.find(b, start + 1) < 0, name
        spans[name] = (start, start + len(b))
    return spans


def outcome(path, raw: bytes, k: int, good: xr.Dataset) -> str:
    """'raised' (by the digest: 'digest', else by HDF5), 'identical' or 'DIFFERENT: ...'."""
    bad = bytearray(raw)
    bad[k] ^= 0xFF
    path.write_bytes(bytes(bad))
    try:
        back = datasets.read(path)
    except datasets.CorruptDatasetError as e:
        assert str(path) in str(e)
        return "digest" if "does not match" in str(e) or "carries no" in str(e) else "raised"
    try:
        xr.testing.assert_identical(back, good)
    except AssertionError as e:
        return f"DIFFERENT at byte {k}: {e}"
    return "identical"


def flips(written, tmp_path, offsets) -> dict[str, int]:
    raw, good = written.read_bytes(), datasets.read(written)
    counts: dict[str, int] = {}
    for k in offsets:
        got = outcome(tmp_path / "flipped.nc", raw, int(k), good)
        assert not got.startswith("DIFFERENT"), got
        counts[got] = counts.get(got, 0) + 1
    return counts


def test_digests_recorded_checked_and_removed(written):
    import netCDF4

    with netCDF4.Dataset(written) as f:
        assert f.getncattr(digests.ATTR).startswith("sha256:")
        for name, v in f.variables.items():
            assert v.getncattr(digests.ATTR).startswith("sha256:"), name
    back = datasets.read(written)
    assert digests.ATTR not in back.attrs and all(digests.ATTR not in v.attrs for v in back.variables.values())
    xr.testing.assert_identical(back.drop_attrs(deep=False), workspace_like().drop_attrs(deep=False))
    assert datasets.robot_value(written, "strut_length") == 0.5


def test_metadata_flips_raise_or_read_identical(written, tmp_path):
    raw = written.read_bytes()
    first = min(a for a, _ in data_spans(raw, datasets.read(written)).values())
    offsets = np.random.default_rng(1).choice(first, size=min(N_META, first), replace=False)
    counts = flips(written, tmp_path, sorted(offsets))
    print(f"\n{len(offsets)} of the {first} metadata bytes flipped: {counts}")
    assert counts.get("digest", 0) + counts.get("raised", 0) > 0


def test_data_flips_raise_and_the_rest_raise_or_read_identical(written, tmp_path):
    raw = written.read_bytes()
    spans = data_spans(raw, datasets.read(written))
    inside = [a + (b - a) // 2 for a, b in spans.values()] + [b - 1 for a, b in spans.values()]
    counts = flips(written, tmp_path, inside)
    assert counts.get("identical", 0) == 0, counts  # a changed value never reads back
    first = min(a for a, _ in spans.values())
    rest = np.random.default_rng(2).choice(np.arange(first, len(raw)), size=N_REST, replace=False)
    counts = flips(written, tmp_path, sorted(rest))
    print(f"\n{N_REST} of the {len(raw) - first} bytes from the first data chunk on flipped: {counts}")


def test_emptied_variable_is_refused_naming_it(written):
    """The defect of issue 35 as `read` sees it: a variable decoded as its fill value (all NaN)."""
    with xr.open_dataset(written) as f:
        loaded = f.load()
    loaded["tip_pressure"].values[:] = np.nan
    with pytest.raises(datasets.CorruptDatasetError, match="workspace.nc.*'tip_pressure' does not match"):
        datasets._verified(loaded, written)
