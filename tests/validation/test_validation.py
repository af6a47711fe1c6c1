"""The checks (tensegrity.validation): every check passes on a case where the claim holds and fails
on one where it does not (a check that cannot fail is a defect). The checks return numbers and
statuses; `summary` words them. The validate stage itself: tests/stages/test_validate.py."""

from dataclasses import replace

import numpy as np
import pytest

from tensegrity.physics import frames, statics
from tensegrity.physics import topology as topo
from tensegrity.physics.params import Params
from tensegrity.validation import checks, grounded, paper, summary
from tensegrity.validation import runs as demo_runs
from tensegrity.validation.common import FAIL, PASS, SKIP
from tensegrity.validation.nominals import simulate_nominal
from tensegrity.workspace import mapping
from tensegrity.workspace.lookup import Workspace
from tensegrity.workspace.nominal import Nominal
from tensegrity.workspace.sweep import SweepSetup

EQUI = topo.face_number(topo.CONTACT_FACES["equilateral"])  # (9,10,12)
ISO = topo.face_number(topo.CONTACT_FACES["isosceles"])  # (10,11,12)

P = Params()
FREE = Params(gravity=0.0)
DISCARD = 0.2  # s, the pipeline's nominal average (config nominal.discard)


def nominal(contact, face, pairs, levels, cog, support, mode="free"):
    """The nominal CoG of a contact case (as results/nominal/{contact}.nc holds it) from arrays
    of the swept pairs (n, P, 3), (n, P, 3, 3); the margin of the CoG in the triangle."""
    cog, support = np.asarray(cog, float), np.asarray(support, float)
    margin = frames.margin_2d(cog[..., :2], support[..., :2])
    return Nominal.of_pairs(contact, face, mode, levels, pairs, cog, support, margin)


def from_run(contact, face, run, levels, mode="free"):
    return nominal(contact, face, run.pairs, levels, run.cog, run.support, mode)


def status(result, vid):
    return result.status[vid]


def measured(result, vid):
    """The `measured` text of verdict `vid` of a check's result."""
    return next(r.measured for r in summary.verdicts(result) if r.id == vid)


# ------------------------------------------------------------------ 1. paper statements

LEVELS = [2.0, 2.4, 4.0, 4.4]  # brackets #11's tip (2.2 MPa) and #10's (4.2 MPa)


@pytest.fixture(scope="module")
def static_nominals():
    """Both contact cases' nominal CoG from the static equilibrium (fast and exact), all pairs."""
    out = {}
    nodes = {}
    for p in range(1, 13):
        start = None
        for k, lev in enumerate(LEVELS):
            prs = np.zeros(12)
            prs[p - 1] = lev
            nodes[p, k] = start = statics.equilibrium(P, prs, start=start)
    for contact, face in (("equilateral", EQUI), ("isosceles", ISO)):
        cs = [[frames.in_support_frame(nodes[p, k], face) for k in range(len(LEVELS))] for p in range(1, 13)]
        out[contact] = nominal(
            contact,
            face,
            np.arange(1, 13),
            LEVELS,
            [[c[0] for c in row] for row in cs],
            [[c[1] for c in row] for row in cs],
        )
    return out


def with_pair_data(n, pair, from_pair):
    """A copy of the nominal `n` in which `pair` holds the data of `from_pair`."""
    arrays = {name: getattr(n, name).copy() for name in ("cog", "support", "margin")}
    for a in arrays.values():
        a[pair - 1] = a[from_pair - 1]
    return replace(n, **arrays)


def test_paper_statements_hold_on_the_static_workspace(static_nominals):
    chk = paper.check_paper(static_nominals)
    assert list(chk.status.items()) == [(k, PASS) for k in ("1.1", "1.2", "1.3", "1.4", "1.5")], chk.status
    tipp = chk.tip_pressure
    assert abs(tipp[0, 9] - 4.2) < 0.1 and 2.0 < tipp[1, 10] < 2.4
    assert set(chk.tip_edge[0, 9]) == {10, 12} and set(chk.tip_edge[1, 10]) == {10, 11}
    assert set(np.argsort(-chk.migration[0])[:3] + 1) == {9, 10, 12} == set(chk.ranking[:3])
    assert np.nanmax(chk.orbit_difference) < 1e-6  # statics is exactly symmetric
    assert sorted(map(tuple, chk.orbit_pairs)) == [(1, 8, 11), (2, 3, 5), (4, 6, 7), (9, 10, 12)]
    assert measured(chk, "1.2") == "#10: 4.21 MPa over edge 10-12 (standing on (9,10,12))"


def test_wrong_ranking_fails(static_nominals):
    bad = dict(static_nominals, equilateral=with_pair_data(static_nominals["equilateral"], 9, 1))
    chk = paper.check_paper(bad)
    assert status(chk, "1.1") == FAIL
    assert status(chk, "1.5") == FAIL  # #9 no longer moves like #10 and #12
    assert status(chk, "1.2") == PASS  # #10 itself is untouched


def test_wrong_tip_edge_or_pressure_fails(static_nominals):
    eq = static_nominals["equilateral"]
    chk = paper.check_paper(dict(static_nominals, equilateral=with_pair_data(eq, 10, 12)))
    assert status(chk, "1.2") == FAIL and "edge 10-12" not in measured(chk, "1.2")
    # the same data reported at 20 % higher pressures: #10 leaves at about 5 MPa, not 4.2
    scaled = {k: replace(n, levels=n.levels * 1.2) for k, n in static_nominals.items()}
    chk = paper.check_paper(scaled, ranking_pressure=2.4)
    assert status(chk, "1.2") == FAIL and status(chk, "1.3") == PASS
    chk = paper.check_paper(scaled, ranking_pressure=9.0)
    assert status(chk, "1.1") == SKIP and measured(chk, "1.1") == "9 MPa is outside the swept levels"


def test_second_roll_must_cross_10_11_at_a_lower_pressure(static_nominals):
    iso = with_pair_data(static_nominals["isosceles"], 11, 1)  # #1 never tips the robot
    chk = paper.check_paper(dict(static_nominals, isosceles=iso))
    assert status(chk, "1.3") == FAIL and status(chk, "1.4") == FAIL
    assert measured(chk, "1.4") == "#11 never (up to 4.4 MPa), #10 4.21 MPa"
    chk = paper.check_paper({"equilateral": static_nominals["equilateral"]})
    assert status(chk, "1.3") == SKIP and status(chk, "1.4") == SKIP
    assert measured(chk, "1.3") == "#11 not swept isosceles case not computed"
    assert status(chk, "1.2") == PASS


def test_orbit_compares_each_member_from_its_own_corner(static_nominals):
    """The members' CoGs in the one support frame are not 120 deg rotations of each other (the
    deformed triangle is not equilateral); seen from their own corners they coincide."""
    n = static_nominals["equilateral"]
    cog, sup = n.cog, n.support
    diff, spread = paper.orbit_spread(cog, sup, EQUI, (9, 10, 12))
    assert diff.max() < 1e-6 and spread.max() < 1e-6
    moved = cog.copy()
    moved[11, :, 0] += 2e-4  # #12 0.2 mm off
    assert paper.orbit_spread(moved, sup, EQUI, (9, 10, 12))[0].min() > 1.5e-4


# ----------------------------------------------------------------------- 2. statics


@pytest.fixture(scope="module")
def free_run():
    """A short free-mode staircase of #10 and #4 on (9,10,12), averaged as the pipeline does."""
    setup = SweepSetup(levels=(1.2, 2.4), hold=1.0)
    return setup, simulate_nominal(FREE, EQUI, [10, 4], setup, DISCARD)


def test_statics_check_passes_on_the_dynamic_nominal_and_fails_when_perturbed(free_run):
    setup, run = free_run
    nominals = {"equilateral": from_run("equilateral", EQUI, run, setup.levels)}
    chk = checks.check_statics(P, nominals, [1.2, 2.4], 1e-4)
    assert status(chk, "2") == PASS
    diff = chk.difference
    assert np.nanmax(diff) < 1e-4 and np.isfinite(diff[0, [3, 9]]).all() and np.isnan(diff[1]).all()
    cog = run.cog.copy()
    cog[1, 1, 0] += 2e-4  # #4 at 2.4 MPa, 0.2 mm off
    bad = {"equilateral": nominal("equilateral", EQUI, run.pairs, setup.levels, cog, run.support)}
    chk = checks.check_statics(P, bad, [1.2, 2.4], 1e-4)
    assert status(chk, "2") == FAIL and "#4 at 2.4 MPa" in measured(chk, "2")


def test_statics_check_is_not_evaluated_off_the_levels_or_in_the_grounded_mode(free_run):
    setup, run = free_run
    nominals = {"equilateral": from_run("equilateral", EQUI, run, setup.levels)}
    assert status(checks.check_statics(P, nominals, [3.0]), "2") == SKIP
    on_ground = {"equilateral": from_run("equilateral", EQUI, run, setup.levels, mode="grounded")}
    chk = checks.check_statics(P, on_ground, [2.4])
    assert status(chk, "2") == SKIP and "grounded mode" in measured(chk, "2")


# ------------------------------------------------------------------ 3. mapping


@pytest.fixture(scope="module")
def small_workspace():
    """The workspace of #10 and #11 at one level, mapped from both canonical faces."""
    setup = SweepSetup(levels=(2.4,), hold=0.5)
    full = {}
    for face in (EQUI, ISO):
        run = simulate_nominal(FREE, face, [10, 11], setup, DISCARD)
        c, s = np.full((12, 1, 3), np.nan), np.full((12, 1, 3, 3), np.nan)
        c[[9, 10]], s[[9, 10]] = run.cog, run.support
        full[str(topo.FACE_TYPES[face - 1])] = (c, s)
    cog, sup = np.full((20, 12, 1, 3), np.nan), np.full((20, 12, 1, 3, 3), np.nan)
    for face in range(1, 21):
        cog[face - 1], sup[face - 1] = mapping.map_face(face, *full[str(topo.FACE_TYPES[face - 1])])
    return setup, Workspace.from_arrays([2.4], cog, sup, FREE.strut_length), full


def test_mapping_check_passes_for_the_symmetry_map(small_workspace):
    setup, ws, _ = small_workspace
    chk = checks.check_mapping(FREE, ws, [1, 7, 9, 18], setup, DISCARD, 1e-4)
    assert status(chk, "3") == PASS, summary.verdicts(chk)
    d = chk.difference
    assert np.isfinite(d).sum() == 4 * 2 and np.nanmax(d) < 1e-9  # free dynamics are equivariant


def test_mapping_check_fails_for_a_wrong_map_or_a_small_sample(small_workspace):
    setup, ws, full = small_workspace
    # face 1 given the canonical data of the same pair numbers (no permutation): a wrong mapping
    cog, sup = ws.cog.copy(), ws.support.copy()
    cog[0], sup[0] = full["equilateral"]
    bad = replace(ws, cog=cog, support=sup)
    chk = checks.check_mapping(FREE, bad, [1, 7, 9, 18], setup, DISCARD, 1e-4)
    assert status(chk, "3") == FAIL and np.nanmax(chk.difference[0]) > 1e-3
    # the right CoG but the triangle's corners in the wrong order
    sup = ws.support.copy()
    sup[6] = ws.support[6][..., [1, 2, 0], :]  # face 7, (6,10,11)
    bad = replace(ws, support=sup)
    chk = checks.check_mapping(FREE, bad, [1, 7, 9, 18], setup, DISCARD, 1e-4)
    assert status(chk, "3") == FAIL and np.nanmax(chk.difference) < 1e-9
    assert np.nanmax(chk.support_difference[1]) > 1e-2
    chk = checks.check_mapping(FREE, ws, [1, 9], setup, DISCARD, 1e-4)  # one face of each kind is too few
    assert status(chk, "3") == FAIL and np.nanmax(chk.difference) < 1e-9
    assert chk.kinds == {"equilateral": 1, "isosceles": 1} and chk.faces_with_data == 2
    chk = checks.check_mapping(FREE, replace(ws, levels=[2.0]), [1, 9], setup, DISCARD, 1e-4)
    assert status(chk, "3") == SKIP and measured(chk, "3") == "the workspace was swept at other levels"


# ------------------------------------------------------------------ 4. grounded vs free


def _synthetic(shift, end_face, free_xy=(0.0, 0.0)):
    """Two levels of one pair on (9,10,12): free CoG at free_xy, grounded CoG moved by shift."""
    cog0, tri = frames.in_support_frame(topo.reference_nodes(), EQUI)
    fc = np.tile(cog0, (1, 2, 1))
    fc[..., :2] = free_xy
    fs = np.tile(tri, (1, 2, 1, 1))
    fm = frames.margin_2d(fc[..., :2], fs[..., :2])
    gc = fc + shift
    gm = frames.margin_2d(gc[..., :2], fs[..., :2])
    return [1.0, 2.0], EQUI, fc, fs, fm, gc, gm, np.array([end_face])


def test_compare_grounded_judges_the_shift_with_its_tolerance():
    args = _synthetic([1e-3, 0.0, -3e-3], [EQUI, EQUI])
    out = grounded.compare_grounded(*args, tolerance=5e-3)
    assert out.shift_ok and out.roll_ok and abs(out.in_plane_max - 1e-3) < 1e-12
    assert not grounded.compare_grounded(*args, tolerance=5e-4).shift_ok  # 1 mm is not under 0.5 mm


def test_compare_grounded_flags_rolls_and_their_disagreement():
    # the robot rolls at the second level, where the free CoG is still inside: NaN + mismatch
    out = grounded.compare_grounded(*_synthetic([0.0, 0.0, 0.0], [EQUI, ISO]), tolerance=5e-3)
    assert out.rolled.tolist() == [[False, True]] and np.isnan(out.shift[0, 1]).all()
    assert out.roll_pressure[0] == 2.0 and out.roll_face[0] == ISO and np.isnan(out.free_roll_pressure[0])
    assert not out.roll_ok
    # free CoG beyond edge 10-12 at both levels; the grounded robot rolls over it at once: agreement
    tri = frames.in_support_frame(topo.reference_nodes(), EQUI)[1]
    nodes = list(topo.FACES[EQUI - 1] + 1)
    mid = 0.5 * (tri[nodes.index(10), :2] + tri[nodes.index(12), :2])
    out = grounded.compare_grounded(*_synthetic([0.0, 0.0, 0.0], [ISO, ISO], free_xy=1.2 * mid), tolerance=5e-3)
    assert out.free_roll_face[0] == ISO == out.roll_face[0] and out.roll_ok
    # ... but rolling onto another face is a disagreement
    out = grounded.compare_grounded(*_synthetic([0.0, 0.0, 0.0], [10, 10], free_xy=1.2 * mid), tolerance=5e-3)
    assert not out.roll_ok


def test_grounded_check_reports_where_the_robot_rolled():
    """A step to 2.4 MPa on #10 rolls the grounded robot onto (10,11,12) although the free CoG
    stays 19 mm inside: 4.2 fails, with the roll in the numbers; #1 stands and moves little."""
    setup = SweepSetup(levels=(2.4,), hold=1.0)
    run = simulate_nominal(FREE, EQUI, [10, 1], setup, DISCARD)
    nominals = {"equilateral": from_run("equilateral", EQUI, run, setup.levels)}
    chk = grounded.check_grounded(P, nominals, setup, DISCARD, settle=0.5, tolerance=5e-3)
    assert status(chk, "4.2") == FAIL and "#10 rolls at 2.4 MPa onto (10,11,12)" in measured(chk, "4.2")
    assert status(chk, "4.1") == PASS
    assert chk.rolled[0, 9, 0] and not chk.rolled[0, 0, 0]
    assert np.isnan(chk.shift[0, 9]).all()
    assert 0 < np.linalg.norm(chk.shift[0, 0, 0, :2]) < 5e-3
    table = summary.tables(chk)[0][2]
    assert [row[:2] for row in table] == [["(9,10,12)", "#1"], ["(9,10,12)", "#10"]]
    assert table[1][2:] == ["n/a", "n/a", "n/a", "-", "2.4 -> (10,11,12)"]
    assert status(grounded.check_grounded(P, nominals, setup, DISCARD, settle=0.5, tolerance=1e-5), "4.1") == FAIL


# ------------------------------------------------------------------ 5. time step


def test_timestep_check_passes_and_fails_when_perturbed():
    setup = SweepSetup(levels=(2.4,), hold=0.5)
    run = simulate_nominal(FREE, EQUI, [10], setup, DISCARD)
    ok = checks.check_timestep(
        FREE, {"equilateral": from_run("equilateral", EQUI, run, setup.levels)}, setup, DISCARD, 1e-4
    )
    assert status(ok, "5") == PASS and np.nanmax(ok.difference) < 5e-5
    cog = run.cog + [3e-4, 0, 0]
    bad = {"equilateral": nominal("equilateral", EQUI, run.pairs, setup.levels, cog, run.support)}
    chk = checks.check_timestep(FREE, bad, setup, DISCARD, 1e-4)
    assert status(chk, "5") == FAIL and measured(chk, "5").startswith("largest 0.3 mm (#10 at 2.4 MPa")


def test_checks_without_a_complete_pair_are_not_evaluated():
    """A contact case with no pair swept at every level is left out (no empty simulation)."""
    cog0, tri = frames.in_support_frame(topo.reference_nodes(), EQUI)
    cog = np.tile(cog0, (1, 1, 1))
    cog[0, 0, 0] = np.nan
    nominals = {"equilateral": nominal("equilateral", EQUI, [10], [2.4], cog, np.tile(tri, (1, 1, 1, 1)))}
    setup = SweepSetup(levels=(2.4,), hold=0.5)
    chk = checks.check_timestep(FREE, nominals, setup, DISCARD)
    assert status(chk, "5") == SKIP and measured(chk, "5") == "no sweep"
    chk = grounded.check_grounded(P, nominals, setup, DISCARD)
    assert chk.status == {"4.1": SKIP, "4.2": SKIP} and not chk.faces
    chk = checks.check_statics(P, nominals, [2.4])
    assert status(chk, "2") == SKIP and measured(chk, "2") == "no pair swept at every level"


# ------------------------------------------------------------------ 6. demonstration runs


def run(outcome, goal=(1.0, 0.0, np.nan), final=(0.9, 0.1, 0.2), rolls=3):
    """What check 6 reads of a run file (results/locomotion/{run}.nc)."""
    return demo_runs.RunSummary(outcome, f"{outcome} because", rolls, np.array(goal, float), np.array(final, float))


def test_runs_check_fails_for_a_run_that_did_not_arrive():
    good = run("arrived")
    bad = run("no_contact", goal=(1.0, 0.0, 0.0), final=(-0.5, 0.0, 0.1))
    edges = run("arrived", goal=(np.nan,) * 3)
    res = demo_runs.check_runs({"paper": edges, "flat": good})
    assert (
        res.status == {"6": PASS} and np.isnan(res.distance[0]) and res.distance[1] == pytest.approx(0.1414, abs=1e-4)
    )
    res = demo_runs.check_runs({"paper": edges, "flat": good, "slope_up": bad})
    assert res.status == {"6": FAIL} and list(res.arrived) == [True, True, False]
    (row,) = summary.verdicts(res)
    assert (
        row.status == FAIL and "slope_up no_contact (3 rolls, 1.50 m from the goal): no_contact because" in row.measured
    )
    title, header, rows = summary.tables(res)[0]
    assert [r[:2] for r in rows] == [["paper", "arrived"], ["flat", "arrived"], ["slope_up", "no_contact"]]
    assert demo_runs.check_runs({}).status == {"6": SKIP}
    assert np.isnan(run("arrived", final=(np.nan,) * 3).distance)  # a run file without samples
