"""The two-pair workspace (issue 10): symmetry reduction, mapping against direct sweeps,
statics, the reader contract, the fitted surfaces' evaluator, bad configuration."""

import numpy as np
import pytest

from tensegrity.io.config import ConfigError, defaults, params_from_config, validate
from tensegrity.io.formats import two_pair as tpf
from tensegrity.physics import statics
from tensegrity.workspace import surfaces
from tensegrity.workspace import two_pair as tp

EQ, ISO = 8, 20
LEVELS = [2.4, 4.8]
HOLD, DISCARD = 1.0, 0.2
SETUP = tp.TwoPairSetup(levels=tuple(LEVELS), hold=HOLD, discard=DISCARD)


@pytest.fixture(scope="module")
def params():
    return params_from_config(defaults())


@pytest.fixture(scope="module")
def iso(params):
    """The whole isosceles canonical face from its orbit representatives (cheap grid)."""
    reps = tp.representatives(ISO)
    r = tp.sweep(params, ISO, reps, SETUP)
    return reps, r, tp.map_face(ISO, ISO, reps, r["cog"], r["support"])


def test_orbit_counts_and_every_combination_recovered():
    assert len(tp.COMBOS) == 66 and len(tp.stabiliser(EQ)) == 3 and len(tp.stabiliser(ISO)) == 2
    for face in (EQ, ISO):
        reps = tp.representatives(face)
        orbits = {}
        for c in tp.COMBOS.tolist():
            orbits.setdefault(min(tp.image(s, c)[0] for s in tp.stabiliser(face)), set()).add(tuple(c))
        assert sorted(orbits) == [tuple(r) for r in reps.tolist()]
        assert set().union(*orbits.values()) == set(map(tuple, tp.COMBOS.tolist()))
        # C3 acts freely on the 66 combinations (22 orbits); the mirror fixes 10 of them (38 orbits)
    assert len(tp.representatives(EQ)) == 22 and len(tp.representatives(ISO)) == 38


def test_mapped_combinations_equal_direct_sweeps(params, iso):
    reps, _, (cog, support, path) = iso
    assert np.isfinite(cog).all() and np.isfinite(support).all()
    ws = tp.map_workspace(LEVELS, {"isosceles": (tp.COMBOS, cog, support, path)})
    swept = set(map(tuple, reps.tolist()))
    mapped = [k for k, c in enumerate(tp.COMBOS.tolist()) if tuple(c) not in swept]  # by the mirror
    for face, rows in ((ISO, mapped[:2]), (12, [tp.combo_index(10, 11)])):  # face 12: another face
        order = ws["staircase"][face - 1, rows]
        d = tp.sweep(params, face, order, SETUP)["cog"][:, 2]
        swap = order[:, 0] > order[:, 1]
        d[swap] = d[swap].swapaxes(1, 2)
        np.testing.assert_allclose(d, ws["cog"][face - 1, rows], atol=1e-9)


def test_equilateral_rotation_maps_exactly(params):
    """A 3-fold rotation moves the reference corner: the data of the other corners' frames."""
    reps = np.array([[9, 10]])
    r = tp.sweep(params, EQ, reps, SETUP)
    cog, _, path = tp.map_face(EQ, EQ, reps, r["cog"], r["support"])
    got = np.flatnonzero(np.isfinite(cog[:, 0, 0, 0]))
    assert len(got) == 3  # the orbit of #9+#10 under the rotations
    d = tp.sweep(params, EQ, path[got], SETUP)["cog"][:, 0]
    swap = path[got, 0] > path[got, 1]
    d[swap] = d[swap].swapaxes(1, 2)
    np.testing.assert_allclose(d, cog[got], atol=1e-9)


def test_nominal_agrees_with_statics(params, iso):
    reps, r, (cog, _, _) = iso
    k = tp.combo_index(10, 11)
    p = np.zeros(12)
    p[[9, 10]] = 4.8, 2.4
    s = statics.support_cog(statics.equilibrium(params, p), ISO)[0]
    assert np.linalg.norm(s - cog[k, 1, 0]) < 1e-4  # m, the stage's tolerance (validate_two_pair)
    assert np.linalg.norm(cog[k, 1, 0, :2] - cog[k, 0, 0, :2]) > 5e-3  # the pressure did move it


def test_reader_contract(tmp_path, iso):
    _, _, (cog, support, path) = iso
    ws = tp.map_workspace(LEVELS, {"isosceles": (tp.COMBOS, cog, support, path)})
    ds = tpf.workspace_dataset(LEVELS, tp.COMBOS[::-1], {k: v[:, ::-1] for k, v in ws.items()}, {}, 0.5)
    from tensegrity.io import datasets

    f = datasets.write(
        ds, tmp_path / "w.nc", defaults(), "test", allow_nan=[k for k in tpf.ALLOW_NAN if k != "cog_std"]
    )
    combos, levels, c, s = tpf.read_two_pair(f)
    assert combos.dtype.kind == "i" and combos.shape == (66, 2) and np.array_equal(combos, tp.COMBOS)
    assert np.array_equal(levels, LEVELS) and c.shape == (20, 66, 2, 2, 3) and s.shape == (20, 66, 2, 2, 3, 3)
    k = tp.combo_index(10, 11)
    np.testing.assert_array_equal(c[ISO - 1, k], cog[k])
    assert np.isnan(c[:8]).all()  # no equilateral case given


def test_json_evaluator_matches_the_fit():
    rng = np.random.default_rng(0)
    pa, pb = np.meshgrid([0.8, 1.6, 2.4, 3.2], [0.8, 1.6, 2.4, 3.2], indexing="ij")
    v = 0.01 + 0.003 * pa - 0.002 * pb + 0.0007 * pa * pb + 1e-6 * rng.standard_normal(pa.shape)
    surf = surfaces.fit_surface(pa, pb, v, max_degree=3, folds=4)
    assert surf["degree"] == 2  # the cross term needs degree 2; degree 3 does not pay
    doc = tpf.surfaces_document({"isosceles": ([10, 11, 12], [[10, 11]], [[surf, surf, surf]])})
    import json

    back = json.loads(json.dumps(doc))["contacts"]["isosceles"]["combos"]["10,11"]["y"]
    design = np.stack([pa.ravel() ** i * pb.ravel() ** j for i, j in surf["powers"]], -1)
    np.testing.assert_allclose(tpf.evaluate_surface(back, pa, pb).ravel(), design @ surf["coefs"], atol=1e-15)
    assert np.abs(tpf.evaluate_surface(back, pa, pb) - v).max() < 1e-5


@pytest.mark.parametrize(
    "section, key", [({"hold": -1.0}, "two_pair.hold"), ({"check_combos": [[3, 3]]}, "two_pair.check_combos")]
)
def test_schema_names_the_bad_key(section, key):
    with pytest.raises(ConfigError, match=key.replace(".", r"\.")):
        validate({"two_pair": section})


@pytest.mark.parametrize(
    "section, key",
    [
        ({"levels": [2.4, 1.2]}, "two_pair.levels"),
        ({"hold": 0.3, "discard": 0.3}, "two_pair.discard"),
        ({"hold": 0.0333}, "two_pair.hold"),
    ],
)
def test_stage_check_names_the_bad_key(tmp_path, section, key):
    with pytest.raises(ConfigError, match=key.replace(".", r"\.")):  # before any job
        validate({"two_pair": section})
    s = {**defaults()["two_pair"], **section}
    with pytest.raises(ValueError, match=key.replace(".", r"\.")):  # and the setup itself, before any work
        tp.TwoPairSetup(levels=tuple(s["levels"]), hold=s["hold"], discard=s["discard"], record_every=s["record_every"])
    assert not (tmp_path / "x.nc").exists()
