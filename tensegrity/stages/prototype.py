"""Rules `validate_prototype` (workflow/rules/validate.smk) and `render_prototype`
(workflow/rules/render.smk): the paper's experiment (IV.B) with the prototype's twisted-string
actuators in the grounded simulation (results/validation/prototype.nc; validation check 8 reads
it), and its figure, the simulated counterpart of Fig. 12 (results/figures/fig12_prototype.png).
The experiment runs the prototype whatever `actuator.kind`: the pipeline's robot stays pneumatic."""

from __future__ import annotations

import os
from pathlib import Path

from ..io import datasets, settings
from ..physics import topology as topo
from . import provenance

TITLE = "The paper's experiment (IV.B) with the prototype's twisted-string actuators, grounded simulation"


def validate_prototype(cfg: dict, nc_path: str | os.PathLike) -> Path:
    """Stage `validate_prototype`: section IV.B (`validation.prototype.experiment_trace`) with
    the robot of `params` and the motors of `actuator.twisted_string`, the protocol and search of
    `prototype`; writes results/validation/prototype.nc. Returns its path."""
    from ..io.formats import prototype as pf
    from ..validation import prototype as pt
    from ..validation.prototype_check import check_prototype, prototype_verdicts

    s = settings.build(pt.ExperimentSettings, cfg)
    params, motors = settings.params(cfg), settings.twisted_strings(cfg)
    protocol = s.protocol(float(settings.value(cfg, "sim.dt")))
    e, trace = pt.experiment_trace(params, motors, protocol, rounds=s.rounds, points=s.points)
    for row in prototype_verdicts(check_prototype(pf.steps(e, s.rounds > 0))):
        print(f"  {row.id} {row.status}: {row.measured}", flush=True)
    ds = pf.prototype_dataset(e, trace, protocol, s.rounds, s.points, params.strut_length)
    return datasets.write(
        ds, nc_path, provenance(cfg), TITLE, stage="validate_prototype", allow_nan=pf.PROTOTYPE_ALLOW_NAN
    )


def prototype_figure(cfg: dict, nc_path: str | os.PathLike, out: str | os.PathLike) -> dict:
    """Stage `prototype_figure`: Fig. 12 simulated from results/validation/prototype.nc: the
    robot at the start, after roll 1 and after roll 2, the voltages and the resting face over
    time (`render.prototype`). Returns what the figure drew."""
    from ..render import prototype as fig12

    ds = datasets.read(nc_path)
    pairs, volts = [int(p) for p in ds["step_pair"].values[:2]], ds["step_voltage"].values[:2]
    faces = [int(ds["start_face"].values[0]), *(int(f) for f in ds["face"].values[:2])]
    at = lambda f: topo.face_label(f) if f else "no face"  # noqa: E731
    titles = [
        f"start: on {at(faces[0])}",
        f"#{pairs[0]} at {volts[0]:g} V: on {at(faces[1])}",
        f"then #{pairs[1]} at {volts[1]:g} V: on {at(faces[2])}",
    ]
    paper_path = " -> ".join(topo.face_label(f) for f in (ds["start_face"].values[0], *ds["paper_face"].values[:2]))
    title = (
        f"Fig. 12 simulated: the prototype (twisted strings, grounded) from {topo.face_label(faces[0])}; "
        f"paper: {paper_path}"
    )
    return fig12.fig_prototype(
        out,
        ds["nodes"].values,
        faces,
        [0, *pairs],
        titles,
        ds["time"].values,
        ds["voltage"].values,
        [int(p) for p in ds["pair"].values],
        ds["resting_face"].values,
        title,
    )


__all__ = ["validate_prototype", "prototype_figure", "TITLE"]
