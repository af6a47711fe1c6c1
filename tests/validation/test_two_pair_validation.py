"""Validation of the two-pair workspace (validation.two_pair): the statics check passes on the
simulated nominal and fails on a displaced one; the verdict tables carry every row."""

from dataclasses import replace

import numpy as np
import pytest

from tensegrity.physics.params import Params
from tensegrity.validation import pages
from tensegrity.validation import two_pair as v
from tensegrity.validation.common import FAIL, PASS
from tensegrity.workspace import two_pair as tp
from tensegrity.workspace.nominal import TwoPairNominal

ISO, LEVELS = 20, [2.4, 4.8]


@pytest.fixture(scope="module")
def contact():
    params = Params()
    reps = np.array([[10, 11]])
    r = tp.sweep(params, ISO, reps, tp.TwoPairSetup(levels=tuple(LEVELS)))
    ws, swept, std = tp.contact_workspace(ISO, reps, r, LEVELS)
    return params, TwoPairNominal("isosceles", ISO, np.array(LEVELS), ws["cog"], ws["tip_pressure"])


def test_statics_check_passes_and_can_fail(contact):
    params, nominal = contact
    combos = np.array([[10, 11]])
    diff, st = v.check_statics(params, {"isosceles": nominal}, combos, 1e-4)
    assert st == PASS and np.isfinite(diff[1]).all() and np.isnan(diff[0]).all()
    cog = nominal.cog.copy()
    cog[tp.combo_index(10, 11), -1, -1, 0] += 2e-3  # 2 mm off at the top corner
    diff2, st2 = v.check_statics(params, {"isosceles": replace(nominal, cog=cog)}, combos, 1e-4)
    assert st2 == FAIL and diff2[1, 0, 0] > 1.5e-3


def test_verdict_tables_hold_every_row():
    rows = [v.Verdict("a", "s|x", "1 mm", "under 0.1 mm", PASS), v.Verdict("b2", "p", "2 mm", "reported", v.INFO)]
    lead, tables = [pages.counts([r.status for r in rows])], [pages.verdict_table(rows)]
    md, page = pages.markdown("t", lead, tables), pages.html_page("t", lead, tables)
    assert md.count("\n| ") == 3 and "s\\|x" in md and "REPORTED" in md
    assert "1 of 1 checks passed, 0 failed" in md  # a reported row is not counted as a check
    assert page.count("<tr>") == 3 and "PASS" in page
