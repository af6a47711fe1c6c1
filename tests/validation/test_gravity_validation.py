"""Validation of the gravity-aware workspace: a grounded roll of the controller tips the robot at
the workspace's pressure, and the verdicts follow the numbers."""

import numpy as np
import pytest

from tensegrity.locomotion.settings import RollSettings
from tensegrity.physics import topology as topo
from tensegrity.physics.params import Params
from tensegrity.validation import gravity as vg
from tensegrity.validation import pages
from tensegrity.validation.common import FAIL, INFO, SKIP
from tensegrity.workspace import gravity as gv
from tensegrity.workspace.nominal import Nominal

pytestmark = pytest.mark.unit
ISO = topo.face_number(topo.CONTACT_FACES["isosceles"])  # (10,11,12)


@pytest.fixture(scope="module")
def sweep():
    """#11 ramped on (10,11,12) on flat ground: it rolls over 10-11 (the paper's second roll)."""
    return gv.run(Params(), ISO, [11], [0.0], [0.0], gv.GravitySetup(max_pressure=2.6, strut_damping=0.0))


def test_a_grounded_roll_tips_where_the_gravity_workspace_says(sweep):
    assert sweep.rolled[0, 0, 0] and tuple(sweep.tip_edge[0, 0, 0]) == (10, 11)
    rc = vg.check_rolls(Params(strut_damping=1.0), {"isosceles": sweep}, [0.0], RollSettings(), 2.6)
    assert rc.pair.tolist() == [11]
    assert rc.rolled_to[0] == topo.face_number((6, 10, 11))
    assert rc.difference[0] < 0.1, (rc.workspace_tip, rc.roll_tip)
    # the controller's own tip (a support node lifted 1 mm) comes later: the robot falls slowly
    assert rc.lift_tip[0] > rc.roll_tip[0]


def _free_from(sw: gv.GravitySweep, shift: float = 0.0) -> Nominal:
    """The flat-ground data of `sw` as if it were a free nominal CoG, CoG moved by `shift` m;
    after the roll (NaN) the CoG is put far out on the ray from the triangle's centre through
    its last position, so that it lies across the edge the robot rolled over."""
    k = np.arange(1, sw.pressure.size, 2)
    cog = sw.cog[0, 0][:, k].copy()
    cog[..., 0] += shift
    margin = np.nan_to_num(sw.margin[0, 0][:, k], nan=-1.0)
    support = np.where(np.isnan(sw.support[0, 0][:, k]), sw.support[0, 0][:, :1], sw.support[0, 0][:, k])
    for b in range(cog.shape[0]):
        ok = np.flatnonzero(np.isfinite(cog[b, :, 0]))
        centre = support[b, ok[-1]].mean(axis=0)
        cog[b, ok[-1] + 1 :] = centre + 10 * (cog[b, ok[-1]] - centre)
    return Nominal.of_pairs("isosceles", sw.face, "free", sw.pressure[k], sw.pairs, cog, support, margin)


def test_check_4_on_the_ramp_compares_what_it_is_given(sweep):
    same = vg.flat_comparison(sweep, _free_from(sweep), 5e-3)
    assert same.in_plane_max == 0.0 and same.shift_ok and same.roll_ok
    moved = vg.flat_comparison(sweep, _free_from(sweep, 0.01), 5e-3)
    assert moved.in_plane_max == pytest.approx(0.01) and not moved.shift_ok
    rc = vg.RollCheck(
        *(
            np.array(v)
            for v in (
                ["isosceles"] * 2,
                [0.0, 15.0],
                [0.0, 90.0],
                [11, 12],
                [1.8, 1.0],
                [1.85, 1.3],
                [1.9, 1.4],
                [0.05, 0.3],
                [[10, 11], [10, 12]],
                [1, 2],
            )
        )
    )
    rows, st = vg.verdicts(rc, {"isosceles": same}, 0.1)
    assert st == {"G.1": FAIL, "G.2": INFO, "G.3": INFO}  # G.2, G.3: the paper's assumption, reported
    # in volts the motors lag the ramp: G.2's shift is not gravity's, so it is not evaluated, saying
    # why; G.1 and G.3 are what they were
    lag_rows, lag_st = vg.verdicts(rc, {"isosceles": moved}, 0.1, lag=vg.MOTOR_LAG)
    assert lag_st == {"G.1": FAIL, "G.2": SKIP, "G.3": INFO}
    assert lag_rows[1].measured == vg.MOTOR_LAG and "mm" not in lag_rows[1].measured
    plain = vg.verdicts(rc, {"isosceles": moved}, 0.1)[0]
    assert [r.measured for r in lag_rows[::2]] == [r.measured for r in plain[::2]]
    assert "0.300 MPa" in rows[0].measured and "#12" in rows[0].measured
    text = pages.markdown("t", [pages.counts(list(st.values()))], [pages.verdict_table(rows), vg.roll_table(rc)])
    assert "| G.1 |" in text and "10-12" in text and "0 of 1 checks passed, 1 failed" in text


def test_near_the_tipping_point_the_ramp_holds_as_the_roll_does():
    """#10 on a 15 deg slope across its face (heading 90): the robot creeps over the edge at a
    constant pressure. A steady ramp (no hold) overshoots the roll's tipping pressure; with the
    controller's hold on lift the workspace matches the grounded roll (check G.1)."""
    params, equi = Params(strut_damping=1.0), topo.face_number(topo.CONTACT_FACES["equilateral"])
    steady = gv.run(params, equi, [10], [15.0], [90.0], gv.GravitySetup(max_pressure=1.0, hold_time=0.0))
    held = gv.run(params, equi, [10], [15.0], [90.0], gv.GravitySetup(max_pressure=1.0))
    rc = vg.check_rolls(params, {"equilateral": held}, [15.0], RollSettings(), 1.0)
    assert held.tip_pressure[0, 0, 0] < steady.tip_pressure[0, 0, 0] - 0.05
    assert rc.difference[0] < 0.1 < abs(rc.roll_tip[0] - steady.tip_pressure[0, 0, 0]), (
        rc.roll_tip,
        held.tip_pressure,
        steady.tip_pressure,
    )
