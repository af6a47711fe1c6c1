"""Rolling locomotion (paper III.C-D, IV; docs/design.md §6).

- `lookup`: the 20-face `Workspace` (arrays; measured two-pair curves with `with_two_pair`) and
  `predict`, the CoG projection of any pair on the current support triangle, along gravity.
- `plan`: `plan` ranks the pairs (and two-pair combinations) that roll the robot toward a target.
- `control`: `roll` and `settle` in the dynamic simulator, driven by `RollSettings`;
  `lockstep` simulates a batch of robots, one controller each.
- `brake`: the actuation that holds the robot on a face (slopes) and the escape order of
  actions off a face where the planned candidates failed.
- `runs`: `roll_to`, `roll_many`, `roll_over` (plan, roll, repeat; `drive`: the controller of
  one run); `outcome`: the `Run` and its `Step`s they return, and `describe`, a run in words.
- `demos`: the workflow's demonstration runs (`DEMOS`, `demo_setup`).

Files are read and written elsewhere: `io.formats` (workspace, run datasets) and
`stages.locomotion_run`. Numbers people see (faces, pairs, nodes) start at 1; pressures in MPa,
lengths in m, times in s.
"""

from ..workspace.lookup import Prediction, Workspace, predict
from .control import RollResult, roll, settle
from .demos import DEMOS
from .lockstep import Record
from .outcome import OUTCOMES, Run, Step, describe
from .plan import Candidate, Plan, plan
from .runs import roll_many, roll_over, roll_to
from .settings import RollSettings

__all__ = [
    "Workspace",
    "Prediction",
    "predict",
    "Candidate",
    "Plan",
    "plan",
    "RollSettings",
    "RollResult",
    "Record",
    "roll",
    "settle",
    "Step",
    "Run",
    "roll_to",
    "roll_many",
    "roll_over",
    "describe",
    "OUTCOMES",
    "DEMOS",
]
