"""Rule `validate` (workflow/rules/validate.smk): the workspace checked against the paper, statics,
symmetry, the grounded mode and dt/2, and the demonstration runs (results/validation/validation.nc,
summary.md, summary.html); the two-pair workspace against statics, direct simulation and
superposition (two_pair.*); the gravity-aware workspace against grounded rolls (gravity.*).
Failed checks do not raise: they are verdicts in the files."""

from __future__ import annotations

import dataclasses
import os
from collections.abc import Iterable, Sequence
from pathlib import Path

from .. import atomic
from ..io import datasets, settings
from ..io.formats import actuation
from ..io.formats import gravity as gf
from ..io.formats import gravity_validation as gvf
from ..io.formats import run as run_formats
from ..io.formats import two_pair as tpf
from ..io.formats import two_pair_validation as tpvf
from ..io.formats import validation as vf
from ..io.formats import workspace as wf
from ..io.formats.nominal import read_nominals
from ..locomotion.settings import RollSettings
from ..validation import pages
from ..validation.common import CheckSettings
from ..validation.nominals import common_levels
from ..workspace.sweep import SweepSetup
from ..workspace.two_pair import TwoPairSetup
from . import provenance


def _kind(cfg: dict):
    """The twisted strings of `cfg` (an `actuator` section: `stage_config` adds it for
    twisted_string only) or None, and the actuator kind of the files."""
    motors = settings.motors(cfg) if "actuator" in cfg else None
    return motors, actuation.PNEUMATIC if motors is None else actuation.TWISTED


def _worded(kind: str, obj):
    """`obj` (a string, a Verdict, a table (title, header, rows) or a list of them) in the wording
    of `kind` (`actuation.words`: pressure -> motor voltage, MPa -> V; identity for pneumatic)."""
    if kind == actuation.PNEUMATIC:
        return obj
    if isinstance(obj, str):
        return actuation.words(obj, kind)
    if dataclasses.is_dataclass(obj):
        return dataclasses.replace(
            obj, **{k: _worded(kind, getattr(obj, k)) for k in ("statement", "measured", "reference")}
        )
    return type(obj)(_worded(kind, x) for x in obj)


def _log(result, kind: str) -> None:
    """Print each verdict of a check's `result` as it is known (the job's log), in the wording of
    `kind`."""
    from ..validation import summary

    for row in _worded(kind, list(summary.verdicts(result))):
        print(f"  {row.id} {row.status}: {row.measured}", flush=True)


def _pages(
    md_path: str | os.PathLike,
    html_path: str | os.PathLike | None,
    title: str,
    lead: Sequence[str],
    tables: Sequence,
    kind: str = actuation.PNEUMATIC,
) -> list[Path]:
    """A validation page as Markdown and, if `html_path`, HTML (`validation.pages`), in the
    wording of the actuator `kind`."""
    lead, tables = _worded(kind, list(lead)), _worded(kind, list(tables))
    out = [atomic.write_text(md_path, pages.markdown(title, lead, tables))]
    if html_path:
        out.append(atomic.write_text(html_path, pages.html_page(title, lead, tables)))
    return out


def validate(
    cfg: dict,
    nominal_paths: Sequence[str | os.PathLike],
    workspace_path: str | os.PathLike | None,
    nc_path: str | os.PathLike,
    md_path: str | os.PathLike,
    html_path: str | os.PathLike | None = None,
    run_paths: Sequence[str | os.PathLike] = (),
    prototype_path: str | os.PathLike | None = None,
) -> list[Path]:
    """Stage `validate`: every check of `validation.checks` on the pipeline's nominal CoG files
    (results/nominal/{contact}.nc), workspace (results/workspace.nc) and demonstration runs
    (`run_paths`; none: check 6 is not evaluated), and check 8 on the prototype's experiment
    (results/validation/prototype.nc, stage `validate_prototype`; None: no check 8); writes
    validation.nc, the Markdown summary and, if `html_path`, the HTML summary. Returns the paths
    written. With the twisted-string actuator (the files in volts) the checks run in volts where
    they can (`checks.run_checks`) and the files say V."""
    from ..validation import checks, report

    motors, kind = _kind(cfg)
    nominals = read_nominals(nominal_paths)
    workspace = wf.read_workspace(workspace_path) if workspace_path else None
    setup, checks_ = settings.build(SweepSetup, cfg), settings.build(CheckSettings, cfg)
    discard = float(cfg["nominal"]["discard"])
    results = checks.run_checks(
        settings.params(cfg),
        setup,
        discard,
        nominals,
        workspace,
        checks_,
        on_result=lambda r: _log(r, kind),
        runs=run_formats.read_run_summaries(run_paths),
        motors=motors,
    )
    if prototype_path:
        from ..io.formats.prototype import read_prototype
        from ..validation.prototype_check import check_prototype

        results.append(check_prototype(read_prototype(prototype_path)))
        _log(results[-1], kind)
    levels = common_levels(nominals)
    ds, allow = vf.workspace_validation_dataset(results, levels, checks_.faces, checks_.statics_pressures)
    note = (
        "Every number, with units: validation.nc. Sweeps: "
        f"{', '.join(f'{p:g}' for p in setup.levels)} MPa held {setup.hold:g} s, "
        f"{setup.mode} mode, dt {setup.dt:g} s, nominal = mean after the first {discard:g} s of each level."
    )
    prov = provenance(
        cfg,
        *nominal_paths,
        *([workspace_path] if workspace_path else []),
        *([prototype_path] if prototype_path else []),
    )
    path = datasets.write(
        actuation.relabel_texts(ds, kind),
        nc_path,
        prov,
        "Validation of the workspace against the paper, statics, symmetry, "
        "the grounded mode and a halved time step, and of the demonstration runs",
        stage="validate",
        allow_nan=allow,
    )
    return [
        path,
        *_pages(md_path, html_path, report.TITLE, [report.counts(results), note], report.summary_tables(results), kind),
    ]


def validate_two_pair(
    cfg: dict,
    contact_paths: Sequence[str | os.PathLike],
    two_pair_path: str | os.PathLike,
    workspace_path: str | os.PathLike,
    nc_path: str | os.PathLike,
    md_path: str | os.PathLike,
    html_path: str | os.PathLike | None = None,
) -> list[Path]:
    """Stage `validate_two_pair`: the two-pair workspace against statics, direct simulation of
    two_pair.check_combos on two_pair.check_faces, and superposition, and its averaging error
    against validate.averaging_tolerance (`validation.two_pair`);
    writes results/validation/two_pair.nc, .md and .html (in volts with the twisted-string
    actuator: the statics check is then not evaluated)."""
    from ..validation import two_pair as v

    motors, kind = _kind(cfg)
    setup, s = settings.build(TwoPairSetup, cfg), cfg["two_pair"]
    contacts = tpf.read_two_pair_nominals(contact_paths)
    grid_cog, staircase = tpf.read_two_pair_grid(two_pair_path)
    single = datasets.read(workspace_path)
    r = v.validate(
        settings.params(cfg),
        setup,
        contacts,
        grid_cog,
        staircase,
        wf.workspace_from_dataset(single),
        wf.tip_pressures(single),
        combos=s["check_combos"],
        faces=s["check_faces"],
        tolerance=float(s["tolerance"]),
        averaging_tolerance=float(cfg["validate"]["averaging_tolerance"]),
        motors=motors,
    )
    for row in _worded(kind, r.rows):
        print(f"  {row.id} {row.status}: {row.measured}", flush=True)
    note = (
        f"Levels {', '.join(f'{x:g}' for x in setup.levels)} MPa held {setup.hold:g} s "
        f"(nominal: mean after {setup.discard:g} s), free mode. Every number: two_pair.nc."
    )
    prov = provenance(cfg, *contact_paths, two_pair_path, workspace_path)
    path = datasets.write(
        actuation.relabel_texts(tpvf.two_pair_validation_dataset(r), kind),
        nc_path,
        prov,
        v.TITLE,
        stage="validate_two_pair",
        allow_nan=tpvf.TWO_PAIR_ALLOW_NAN,
    )
    return [
        path,
        *_pages(
            md_path,
            html_path,
            v.TITLE,
            [pages.counts([x.status for x in r.rows]), note],
            [pages.verdict_table(r.rows)],
            kind,
        ),
    ]


def validate_gravity(
    cfg: dict,
    gravity_path: str | os.PathLike,
    nominal_paths: Sequence[str | os.PathLike],
    nc_path: str | os.PathLike,
    md_path: str | os.PathLike,
    html_path: str | os.PathLike | None = None,
) -> list[Path]:
    """Stage `validate_gravity`: checks G.1-G.3 (`validation.gravity`) of the gravity-aware
    workspace on gravity.validate_slopes, within gravity.tip_tolerance; writes
    results/validation/gravity.nc, .md and .html. With the twisted-string actuator (the file in
    volts) G.1 rolls the controller in volts (`RollSettings.motors`), G.2 and G.3 compare in volts."""
    from ..validation import gravity as vg

    motors, kind = _kind(cfg)
    g, s = cfg["gravity"], settings.build(RollSettings, cfg)
    sweeps = gf.read_gravity(gravity_path)
    rc = vg.check_rolls(settings.params(cfg), sweeps, g["validate_slopes"], s, float(g["max_pressure"]))
    flat = {
        contact: vg.flat_comparison(sweeps[contact], free, CheckSettings.grounded_tolerance)
        for contact, free in read_nominals(nominal_paths).items()
        if contact in sweeps
    }
    lag = None if motors is None else vg.MOTOR_LAG
    rows, status = vg.verdicts(rc, flat, float(g["tip_tolerance"]), lag=lag)
    rows = _worded(kind, rows)
    for r in rows:
        print(f"  {r.id} {r.status}: {r.measured}", flush=True)
    note = (
        f"Ramps at {s.ramp_rate:g} MPa/s in steps of {s.interval:g} s after {float(g['settle']):g} s at rest; "
        f"grounded rolls with the controller's settings (config locomotion) up to {float(g['max_pressure']):g} MPa."
    )
    path = datasets.write(
        actuation.relabel_texts(gvf.gravity_validation_dataset(rc, flat, status), kind),
        nc_path,
        provenance(cfg, gravity_path),
        vg.TITLE,
        stage="validate_gravity",
        allow_nan=gvf.GRAVITY_ALLOW_NAN,
    )
    return [
        path,
        *_pages(
            md_path,
            html_path,
            vg.TITLE,
            [pages.counts([r.status for r in rows]), note],
            [pages.verdict_table(rows), vg.roll_table(rc)],
            kind,
        ),
    ]


def runs_warning(paths: Iterable[str | os.PathLike]) -> str:
    """The end-of-workflow warning naming the demonstration runs among the files `paths` that did
    not arrive ('' if every existing run arrived; the Snakefile's `onsuccess`)."""
    bad = run_formats.not_arrived(paths)
    if not bad:
        return ""
    lines = [
        f"WARNING: {len(bad)} demonstration run(s) did not arrive (validation check 6 FAILS; "
        f"see results/validation/summary.md):"
    ]
    lines += [f"  {name}: {outcome} ({message})" for name, outcome, message in bad]
    return "\n".join(lines)
