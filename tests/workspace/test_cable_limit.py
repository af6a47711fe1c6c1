"""The uphill limit with actions of the 24 cables one by one (issue 30 item 1; results/slope_limit.nc
`simulated_cables`, `slope_multi.uphill_limits`): bisected up from the pair limit, so never below
it; above it where the statics' cable actions roll the robot and no pair action does (the
isosceles face at heading 270, uphill across its gap edge 11-12, which no cable spans); the
variables' units and attributes as docs/datasets.md gives them."""

from types import SimpleNamespace

import numpy as np
import pytest

from tensegrity.io import datasets
from tensegrity.io.formats import gravity as gf
from tensegrity.physics import topology as topo
from tensegrity.physics.params import Params
from tensegrity.workspace import gravity as gv
from tensegrity.workspace import slope_limit as sl
from tensegrity.workspace.slope_multi import MultiLimits, uphill_limits

SETUP = gv.GravitySetup()
PARAMS = SETUP.rolling(Params())
CONTACT = "isosceles"
HEADINGS = np.array([0.0, 270.0])
# per heading: the simulated stand limit's bracket and the uphill simulated_multi of the default run
# (docs/planner_evaluation.md, "The slope limit with both searches for pair actions")
STAND, STAND_HIGH, MULTI = np.array([13.1, 29.5]), np.array([13.8, 31.3]), np.array([13.0, 19.6])


def _inputs() -> tuple:
    """SlopeLimits and MultiLimits of the isosceles face at HEADINGS (kinds stand, uphill,
    downhill; downhill not asked), and its sweeps (only the face is read)."""
    nan = np.full((3, 1, 2), np.nan)
    sim = np.stack([STAND, MULTI, np.full(2, np.nan)])[:, None]
    high = np.stack([STAND_HIGH, STAND_HIGH, np.full(2, np.nan)])[:, None]
    lim = sl.SlopeLimits(
        sl.KINDS, (CONTACT,), HEADINGS, nan, nan, sim, np.zeros(nan.shape, int), nan, np.full(nan.shape, ""), high
    )
    multi = MultiLimits(sim, high, np.zeros((*nan.shape, topo.N_PAIRS)), nan, np.zeros(nan.shape, int))
    sweeps = {CONTACT: SimpleNamespace(face=topo.face_number(topo.CONTACT_FACES[CONTACT]))}
    return lim, multi, sweeps


def test_cables_never_below_the_pairs_and_above_them_across_the_gap_edge():
    """One bisection step each. Heading 0: at the mid slope 13.45 deg the statics find a pair
    action, so the cable action there is that pair action lifted and the cables' bracket is the
    pairs' (simulated_multi's, copied, not simulated). Heading 270: at 25.45 deg the statics find no pair action over
    11-12 (their limit 19.7 deg) and the "pairs" bisection keeps 19.6 deg; the cable action rolls
    the robot uphill there (our simulator, one pressure per cable), so the cables' limit is
    25.45 deg, its bracket reaching the stand limit's high end."""
    lim, multi, sweeps = _inputs()
    pairs = uphill_limits(None, PARAMS, sweeps, lim, multi, SETUP, 0.005, 1, "pairs")
    cables = uphill_limits(None, PARAMS, sweeps, lim, multi, SETUP, 0.005, 1, "cables")
    assert (cables[0] >= MULTI).all() and (cables[0] >= pairs[0]).all(), (cables, pairs)
    np.testing.assert_allclose(pairs[0][0], MULTI)
    np.testing.assert_allclose(pairs[1][0, 1], 0.5 * (MULTI[1] + STAND_HIGH[1]))
    np.testing.assert_allclose(cables[0][0, 1], 0.5 * (MULTI[1] + STAND_HIGH[1]))
    np.testing.assert_allclose(cables[1][0, 1], STAND_HIGH[1])
    assert cables[0][0, 0] == MULTI[0] and cables[1][0, 0] == lim.simulated_high[1, 0, 0]  # the pairs' bracket
    assert (cables[1] > cables[0]).all()  # a bracket
    assert not pairs[2].any() and not cables[2][0, 0].any()  # no action rolled above the start
    w = cables[2][0, 1][topo.PAIR_CABLES]  # (12, 2): the action at 25.45 deg drives single cables
    assert ((w > 0).sum(1) == 1).any() and w.max() == 1.0


def test_not_computed_is_nan_and_a_bad_criterion_is_refused():
    lim, multi, sweeps = _inputs()
    lo, hi, w = uphill_limits(None, PARAMS, sweeps, lim, multi, SETUP, 0.005, 0)
    assert lo.shape == hi.shape == (1, 2) and np.isnan(lo).all() and np.isnan(hi).all()
    assert w.shape == (1, 2, topo.N_CABLES) and not w.any()
    with pytest.raises(ValueError, match="criterion 'cable'"):
        uphill_limits(None, PARAMS, sweeps, lim, multi, SETUP, 0.005, 1, "cable")


@pytest.mark.parametrize("computed", [True, False])
def test_the_file_holds_the_bracket_in_degrees_with_its_error(tmp_path, computed):
    """simulated_cables and simulated_cables_high (contact, heading) deg, long_name and a comment
    that states the error (the bisection bracket), cables_weights (contact, heading, cable) with
    each cable's pair and nodes, as written and read back; NaN (weights 0) where not computed."""
    lim, multi, _ = _inputs()
    w = np.zeros((1, 2, topo.N_CABLES))
    w[0, 1, topo.PAIR_CABLES[5, 0]] = 1.0  # one cable of pair 6
    cables = (np.array([[13.0, 25.45]]), np.array([[13.8, 31.3]]), w) if computed else None
    ds = gf.slope_limit_dataset(lim, multi, {"friction_angle_deg": 38.7}, cables)
    path = datasets.write(ds, tmp_path / "s.nc", {}, "test", allow_nan=gf.SLOPE_LIMIT_ALLOW_NAN)
    s = datasets.read(path)
    for name in ("simulated_cables", "simulated_cables_high"):
        v = s[name]
        assert v.dims == ("contact", "heading")
        assert v.attrs["units"] == "degree" and "24 cables" in s["simulated_cables"].attrs["long_name"]
        assert "bisection bracket [simulated_cables, simulated_cables_high]" in v.attrs["comment"]
        assert np.isnan(v.values).all() != computed
    assert s["cables_weights"].dims == ("contact", "heading", "cable") and s["cables_weights"].attrs["units"] == "1"
    assert s["cable"].values.tolist() == list(range(1, 25)) and sorted(s["cable_pair"].values) == sorted(
        [*range(1, 13)] * 2
    )
    if computed:
        assert float(s["simulated_cables"].sel(contact=CONTACT, heading=270.0)) == 25.45
        on = s["cables_weights"].sel(contact=CONTACT, heading=270.0) > 0
        assert s["cable_pair"].values[on.values].tolist() == [6]
        assert sorted(s["cable_nodes"].values[on.values][0]) in ([6, 11], [5, 6])  # pair 6: (6,11), (5,6)
