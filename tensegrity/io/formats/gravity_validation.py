"""The gravity validation file (docs/datasets.md, "Gravity-aware workspace and slope limit"):
the grounded rolls of check G.1 against the gravity-aware workspace, the in-plane CoG shift on
flat ground (G.2) and the verdicts, with units and long names.

- results/validation/gravity.nc: `gravity_validation_dataset` (`validation.gravity`).
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np
import xarray as xr

from ...physics.topology import CONTACTS
from ...validation.gravity import RollCheck
from ...validation.grounded import GroundedComparison
from .. import datasets

GRAVITY_ALLOW_NAN = [
    "workspace_tip_pressure",
    "roll_tip_pressure",
    "lift_tip_pressure",
    "difference",
    "in_plane_shift_max",
]


def gravity_validation_dataset(
    rc: RollCheck, flat: Mapping[str, GroundedComparison | None], status: Mapping[str, str]
) -> xr.Dataset:
    """results/validation/gravity.nc: the grounded rolls of check G.1 (`validation.gravity.
    check_rolls`), the in-plane CoG shift on flat ground per contact case (G.2, NaN: not
    compared) and the status of each check."""
    var = datasets.var
    return xr.Dataset(
        {
            "contact_of_roll": (("roll",), rc.contact, {"long_name": "contact case of the roll"}),
            "slope": var(("roll",), rc.slope, "degree", "ground slope"),
            "heading": var(("roll",), rc.heading, "degree", "uphill direction in the face's support frame"),
            "pair": var(("roll",), rc.pair, "1", "pair driven"),
            "workspace_tip_pressure": var(
                ("roll",), rc.workspace_tip, "MPa", "tipping pressure of the gravity-aware workspace"
            ),
            "roll_tip_pressure": var(
                ("roll",),
                rc.roll_tip,
                "MPa",
                "pressure of the grounded roll at which its CoG projection along gravity left the triangle",
            ),
            "lift_tip_pressure": var(
                ("roll",), rc.lift_tip, "MPa", "pressure held when a support node lifted in the roll (NaN: no roll)"
            ),
            "difference": var(("roll",), rc.difference, "MPa", "absolute difference of the two tipping pressures"),
            "rolled_to": var(("roll",), rc.rolled_to, "1", "face the roll ended on (0: none)"),
            "in_plane_shift_max": var(
                ("contact",),
                [flat[c].in_plane_max if flat.get(c) else np.nan for c in CONTACTS],
                "m",
                "largest in-plane CoG shift on flat ground against the free nominal CoG",
            ),
            "status": (("check",), [status[k] for k in sorted(status)], {"long_name": "verdict of each check"}),
        },
        coords={
            "check": ("check", sorted(status), {"long_name": "check number"}),
            "contact": ("contact", list(CONTACTS), {"long_name": "contact case"}),
        },
    )
