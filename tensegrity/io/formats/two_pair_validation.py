"""The two-pair validation file (docs/datasets.md, "Two-pair workspace"): every number of checks
(a)-(d) of the two-pair workspace, with units and long names, and the verdicts.

- results/validation/two_pair.nc: `two_pair_validation_dataset` (`validation.two_pair`).
"""

from __future__ import annotations

import numpy as np
import xarray as xr

from ...physics.topology import CONTACTS
from ...validation.two_pair import TwoPairCheck
from ...workspace import two_pair as tp
from .. import datasets

TWO_PAIR_ALLOW_NAN = [
    "statics_difference",
    "direct_difference",
    "path_difference",
    "superposition_error",
    "measured_shift",
    "tip_pressure",
    "single_tip_pressure",
    "averaging_error",
]


def two_pair_validation_dataset(r: TwoPairCheck) -> xr.Dataset:
    """results/validation/two_pair.nc: the numbers of checks (a)-(d) of the two-pair workspace
    (`validation.two_pair.validate`; (d) if it ran) and the verdicts."""
    var = datasets.var
    sup, P = r.superposition, r.superposition["error"].shape[-1]
    extra = {}
    if r.averaging is not None:
        extra["averaging_error"] = var(
            ("contact", "combo", "level_a", "level_b"),
            r.averaging,
            "m",
            "estimated averaging error of the two-pair nominal CoG (d; NaN: mapped)",
            goal_m=r.averaging_tolerance,
        )
    return xr.Dataset(
        {
            "statics_difference": var(
                ("contact", "check", "point"), r.statics, "m", "nominal minus static-equilibrium CoG distance (a)"
            ),
            "direct_difference": var(
                ("face", "check"),
                r.direct,
                "m",
                "largest CoG distance of the mapped grid from a direct simulation along the same staircase (b)",
            ),
            "path_difference": var(
                ("face", "check"),
                r.path,
                "m",
                "largest CoG distance of the mapped grid from a direct simulation along the other staircase order (b2)",
            ),
            "check_pairs": var(("check", "member"), r.combos, "1", "actuator pairs of the check combinations"),
            "superposition_error": var(
                ("contact", "combo", "level_a", "level_b"),
                sup["error"],
                "m",
                "in-plane distance of the summed single-pair shifts from the measured two-pair CoG shift (c)",
            ),
            "measured_shift": var(
                ("contact", "combo", "level_a", "level_b"),
                sup["measured"],
                "m",
                "in-plane CoG shift from the unactuated robot, two pairs",
            ),
            "tip_pressure": var(
                ("contact", "combo"),
                sup["tip"],
                "MPa",
                "least equal pressure of both pairs at which the CoG leaves the triangle",
            ),
            "single_tip_pressure": var(
                ("contact",), sup["single_tip"], "MPa", "least tipping pressure of any single pair"
            ),
            "pressure_a": var(("level_a",), r.levels, "MPa", "muscle pressure of the first pair"),
            "verdict": (
                ("verdict",),
                np.array([f"{v.id}: {v.status}: {v.measured}" for v in r.rows]),
                {"long_name": "verdicts"},
            ),
            **extra,
        },
        coords={
            "contact": ("contact", list(CONTACTS), {"long_name": "contact case"}),
            "face": ("face", r.faces, {"units": "1", "long_name": "face number"}),
            "check": ("check", np.arange(1, len(r.combos) + 1), {"units": "1", "long_name": "check combination"}),
            "member": ("member", [1, 2], {"units": "1", "long_name": "member of the combination"}),
            "point": (
                "point",
                [1, 2, 3],
                {"units": "1", "long_name": "grid corner: (top, top), (low, top), (top, low)"},
            ),
            "combo": ("combo", np.arange(1, len(tp.COMBOS) + 1), {"units": "1", "long_name": "combination number"}),
            "level_a": ("level_a", np.arange(1, P + 1), {"units": "1", "long_name": "level index of the first pair"}),
            "level_b": ("level_b", np.arange(1, P + 1), {"units": "1", "long_name": "level index of the second pair"}),
        },
    )
