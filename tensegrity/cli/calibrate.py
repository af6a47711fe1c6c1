"""`tensegrity calibrate MEASURED --fit a,b,c --out calibrated.yaml [--report report.nc]`."""

from __future__ import annotations

import argparse

import numpy as np


def cmd_calibrate(args: argparse.Namespace) -> int:
    """Fit named `params` keys to a measured trajectory (a run file of `tensegrity simulate
    --out`, or a motion-capture CSV: time_s, n1_x .. n12_z in m, p1 .. p12 in MPa); the other
    parameters come from the configuration (--config, --set). A run of the twisted strings is
    driven in volts (voltage_cmd, or v1 .. v12 in V) and replayed with the actuator.twisted_string
    section; its keys are fitted by their configuration names, actuator.twisted_string.<key>.
    Writes a YAML with a `params:` section (and `actuator.twisted_string` for a run in volts) that --config and
    `snakemake --configfile` accept, and with --report a netCDF of estimates, 95 % intervals,
    correlations and residuals, and its figure (same name, .png)."""
    from ..io import datasets
    from ..stages.calibrate import calibrate, parse_fit
    from . import args as cli_args

    cfg = cli_args.stage_cfg(args, "calibrate")  # with actuator.twisted_string: a run in volts
    out = calibrate(
        cfg,
        args.measured,
        parse_fit(args.fit),
        args.out,
        args.report,
        mode=args.mode or "",
        initial=args.initial,
        frame=args.frame,
        check=args.check,
        residual=args.residual,
        starts=args.starts,
        windows=args.windows,
    )
    print(f"wrote {', '.join(map(str, out))}")
    if args.report:
        ds = datasets.read(args.report)
        print(f"{'parameter':<20} {'estimate':>12} {'std. error':>11} {'95 % interval':>27} unit, interval from")
        for k in ds["parameter"].values:
            e, se = float(ds[k]), float(ds[f"{k}_standard_error"])
            lo, hi = float(ds[f"{k}_lower_95"]), float(ds[f"{k}_upper_95"])
            how = ds[f"{k}_lower_95"].attrs.get("interval_method", "")  # a profile has no std. error
            print(f"{k:<20} {e:>12.6g} {se:>11.3g} {f'[{lo:.6g}, {hi:.6g}]':>27} {ds[k].attrs['units']}, {how}")
        a = ds.attrs
        print(f"residual RMS {a['residual_rms_mm']:.3g} mm", end="")
        if np.isfinite(a["check_rms_predict_mm"]):
            print(
                f"; prediction check: fitted up to {a['check_fit_until_s']:.3g} s "
                f"(RMS {a['check_rms_fit_mm']:.3g} mm), predicted the rest (RMS {a['check_rms_predict_mm']:.3g} mm)",
                end="",
            )
        print()
        if a["restarts"]:
            print(f"restarted {a['restarts']} times from a lower point found by {a['restarted_by']}")
        if ds.attrs["start_costs_m2"].size > 1:
            costs = ", ".join(f"{v:.6g}" for v in ds.attrs["start_costs_m2"])
            print(f"cost |r|^2 of each start's fit (m^2; configured start first, the lowest kept): {costs}")
        if a["not_determined"] != "none":
            print(f"not determined by this measurement: {a['not_determined']}")
    return 0


def add_parser(sub: argparse._SubParsersAction, common: argparse.ArgumentParser) -> None:
    """The `calibrate` command's arguments."""
    p = sub.add_parser(
        "calibrate", parents=[common], help="fit parameters to a measured trajectory", description=cmd_calibrate.__doc__
    )
    p.add_argument("measured", help="run file (tensegrity simulate --out) or motion-capture CSV")
    p.add_argument(
        "--fit",
        required=True,
        help="params keys to fit, e.g. cable_stiffness,cable_damping; a run in volts: actuator.twisted_string.<key>",
    )
    p.add_argument("--out", required=True, help="calibrated configuration to write (YAML, a params: section)")
    p.add_argument("--report", help="report to write (netCDF) and its figure beside it (.png)")
    p.add_argument("--mode", choices=["free", "grounded"], help="default: the file's attribute mode")
    p.add_argument(
        "--initial", choices=["fit", "data"], default="fit", help="initial state fitted too (default) or from the data"
    )
    p.add_argument(
        "--frame",
        choices=["fit", "data"],
        default="fit",
        help="grounded: the frame's tilt and height fitted too (default) or levelled from the first sample",
    )
    p.add_argument(
        "--residual",
        choices=["positions", "shape"],
        help="fit the node positions or the shape, the 24 cable lengths: blind to where the ground puts the "
        "robot, so insensitive to a contact that is not the model's (README); default: shape for a grounded "
        "run, positions for a free one",
    )
    p.add_argument(
        "--check",
        type=float,
        default=0.25,
        help="fraction of samples predicted in the check (default 0.25; 0: none)",
    )
    p.add_argument(
        "--starts",
        type=int,
        default=0,
        help="extra fits from parameters drawn (seeded Latin hypercube) within a factor 2 of the configured ones; "
        "the lowest cost is kept (default 0: the configured start only)",
    )
    p.add_argument(
        "--windows",
        type=int,
        help="time windows refitted on their own when the residuals say the model misfits: the spread of their "
        "estimates gives the intervals (default 4 grounded, 0 free; 0: no interval for a misfit)",
    )
    p.set_defaults(func=cmd_calibrate)
