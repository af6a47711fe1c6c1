"""The dataset contract file by file (docs/design.md §5, docs/datasets.md): one module per file
family, each with the builder of its files (`*_dataset`: arrays or results -> an xarray Dataset
with units and long names, written by `io.datasets.write`) and, where the package reads them
back, the reader (`read_*`) with its contract check.

- `common`: coordinates and the robot's geometry every file shares;   `actuation`: the unit (MPa or V);
- `sweep`: results/sweeps/{contact}/pairNN.nc;   `nominal`: results/nominal/{contact}.nc;
- `curves`: results/curves/{contact}.nc, curves.json;   `workspace`: results/workspace.nc;
- `two_pair`: results/two_pair/{contact}.nc, workspace_two_pair.nc, curves/two_pair.json;
- `gravity`: results/workspace_gravity.nc, slope_limit.nc;   `run`: results/locomotion/{run}.nc;
- `validation`: results/validation/validation.nc;   `two_pair_validation`: validation/two_pair.nc;
- `gravity_validation`: results/validation/gravity.nc;   `study`: results/studies/<name>/*.nc;
- `simulation`: the output of `tensegrity simulate`.
The names of the light modules (no simulator, no validation) are available here too.
"""

from . import actuation
from .common import AXES, coords, rest_vars
from .curves import CURVES_ALLOW_NAN, check_curves, curves_dataset, curves_document, read_curves
from .nominal import NOMINAL_ALLOW_NAN, nominal_dataset, nominal_from_dataset, read_nominal, read_nominals
from .simulation import simulation_dataset
from .sweep import SWEEP_FILE, sweep_dataset
from .workspace import (
    WORKSPACE_ALLOW_NAN,
    check_workspace,
    config_of,
    read_workspace,
    workspace_dataset,
    workspace_from_dataset,
)

__all__ = [
    "actuation",
    "AXES",
    "coords",
    "rest_vars",
    "CURVES_ALLOW_NAN",
    "check_curves",
    "curves_dataset",
    "curves_document",
    "read_curves",
    "NOMINAL_ALLOW_NAN",
    "nominal_dataset",
    "nominal_from_dataset",
    "read_nominal",
    "read_nominals",
    "simulation_dataset",
    "SWEEP_FILE",
    "sweep_dataset",
    "WORKSPACE_ALLOW_NAN",
    "check_workspace",
    "read_workspace",
    "workspace_dataset",
    "workspace_from_dataset",
    "config_of",
]
