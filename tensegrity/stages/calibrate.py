"""`tensegrity calibrate`: the model of a measured robot (docs/design.md §9, docs/datasets.md
"Calibration"). No rule runs it; it is a stage all the same (`tensegrity stage calibrate`)."""

from __future__ import annotations

import os
from collections.abc import Sequence
from pathlib import Path

from ..io import datasets, settings
from ..io.formats.measured import read_measured

__all__ = ["calibrate", "parse_fit"]


def parse_fit(fit: str | Sequence[str]) -> tuple[str, ...]:
    """'a,b,c' (or a list of such) -> ('a', 'b', 'c')."""
    items = [fit] if isinstance(fit, str) else list(fit)
    return tuple(n.strip() for item in items for n in item.split(",") if n.strip())


def calibrate(
    cfg: dict,
    measured: str | os.PathLike,
    fit: Sequence[str],
    out_path: str | os.PathLike,
    report_path: str | os.PathLike | None = None,
    mode: str = "",
    initial: str = "fit",
    frame: str = "fit",
    check: float = 0.25,
    residual: str | None = None,
    starts: int = 0,
    windows: int | None = None,
) -> list[Path]:
    """Stage `calibrate`: fit the `params` keys `fit` ('a,b,c' or a list; for a run driven in
    volts, replayed with the `actuator.twisted_string` section, its keys `actuator.twisted_string.<key>`)
    to the measured trajectory `measured` (a run file or a motion-capture CSV) in `mode` ('free',
    'grounded'; default the file's attribute `mode`), the other parameters and sim.dt from `cfg`; the initial
    state fitted too (`initial` 'fit') or taken from the first samples ('data'), the grounded
    frame's tilt and height fitted ('fit') or levelled from the first sample ('data'); a prediction
    check on the last `check` of the samples (0: none); `residual` 'positions' (node coordinates)
    or 'shape' (cable lengths, blind to where the ground puts the robot; None: the mode's default,
    shape grounded and positions free, `model.DEFAULT_RESIDUAL`); `starts` extra fits from
    parameters drawn within a factor 2 of the configured ones, the lowest cost kept; `windows` time
    windows refitted for the intervals of a model that misfits (None: 4 grounded, 0 free;
    `calibration.discrepancy`). Writes the calibrated configuration
    `out_path` (YAML, a `params:` section) and, if given, the report `report_path` (netCDF) with
    its figure beside it (same name, .png). Every input is checked before the fit starts."""
    from ..calibration import calibrate as fit_model
    from ..calibration.discrepancy import split
    from ..calibration.model import RESIDUALS
    from ..io.formats.calibration import allow_nan, calibrated_yaml, calibration_dataset

    names = parse_fit(fit)
    for opt, val in (("initial", initial), ("frame", frame)):
        if val not in ("fit", "data"):
            raise ValueError(f"{opt}: {val!r} is not 'fit' or 'data'")
    if residual is not None and residual not in RESIDUALS:
        raise ValueError(f"residual: {residual!r} is not one of {', '.join(RESIDUALS)}")
    params = settings.params(cfg)
    dt = float(settings.value(cfg, "sim.dt"))
    m = read_measured(measured)
    # the measurement says the actuator: a run in volts has the twisted strings (actuator.kind
    # is not read; calibrated.yaml writes the run's)
    motors = settings.twisted_strings(cfg) if m.command == "voltage" else None
    mode = mode or m.mode
    if not mode:
        raise ValueError(f"{measured}: the file does not say its mode; give --mode free or --mode grounded")
    if starts < 0:
        raise ValueError(f"starts: {starts!r} extra starts; give 0 or more")
    if windows:  # ValueError naming windows before the fit, if too many for the samples
        split(m, windows)
    c = fit_model(
        m, params, names, mode, dt, initial == "fit", frame == "fit", check, motors, residual, starts, windows=windows
    )
    header = (
        f"calibrated by tensegrity calibrate from {measured} ({mode} mode, residual {c.problem.residual})\n"
        f"fitted: {', '.join(names)}; residual RMS {c.rms_mm:.3g} mm\n"
        "use: --config FILE, or snakemake --configfile FILE"
    )
    from .. import atomic

    out = [atomic.write_text(out_path, calibrated_yaml(c, header))]
    if report_path is not None:
        from ..render.calibration import calibration_figure
        from . import provenance

        ds = calibration_dataset(c)
        inputs = [measured] if Path(measured).suffix.lower() != ".csv" else []
        out.append(
            datasets.write(
                ds,
                report_path,
                provenance(cfg, *inputs),
                f"Calibration of {', '.join(names)} from {Path(measured).name}",
                stage="calibrate",
                allow_nan=allow_nan(ds),
            )
        )
        out.append(
            calibration_figure(
                Path(report_path).with_suffix(".png"),
                m.t,
                c.measured,
                c.simulated,
                f"{Path(measured).name}: measured (dots) and calibrated model (lines), {mode} mode",
                c.prediction.get("fit_until", float("nan")),
                c.prediction.get("simulated"),
            )
        )
    return out
