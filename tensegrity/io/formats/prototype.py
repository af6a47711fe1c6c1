"""The prototype's experiment file (docs/datasets.md, "The paper's experiment"): section IV.B run
with the twisted-string actuators (`validation.prototype`), the faces each step lands on beside
the paper's, the lowest rolling voltages with their multisection bracket, and the two rolls at the
paper's voltages as a time series with three snapshots of the robot.

- results/validation/prototype.nc: `prototype_dataset`, read back by `read_prototype`.
"""

from __future__ import annotations

import os

import numpy as np
import xarray as xr

from ... import paper
from ...physics import topology as topo
from ...validation.prototype import Experiment, Protocol, Trace
from ...validation.prototype_check import Steps
from .. import datasets

PROTOTYPE_ALLOW_NAN = ["landing_time", "lowest_voltage", "lowest_voltage_error"]
SNAPSHOTS = ("start", "after roll 1", "after roll 2")


def steps(e: Experiment, searched: bool = True) -> Steps:
    """The three steps of section IV.B and the search of `e` (`searched`: rounds > 0) as check 8
    reads them."""
    (p1, _, f1), (p2, _, f2) = paper.EXPERIMENT
    start = topo.face_number(paper.START_FACE)
    return Steps(
        pair=np.array([p1, p2, p1]),
        voltage=np.array([paper.VOLTAGE[p1], paper.VOLTAGE[p2], paper.VOLTAGE[p2]]),
        start_face=np.array([start, topo.face_number(f1), start]),
        paper_face=np.array([topo.face_number(f1), topo.face_number(f2), start]),
        face=np.array([e.face_1, e.face_2, e.face_low]),
        locked=np.array([e.locked_1, e.locked_2, False]),
        lowest=np.array([e.lowest_1, e.lowest_2]),
        error=np.array([e.lowest_1 - e.lower_1, e.lowest_2 - e.lower_2]),
        paper_voltage=np.array([paper.VOLTAGE[p1], paper.VOLTAGE[p2]]),
        searched=searched,
    )


def prototype_dataset(
    e: Experiment, trace: Trace, protocol: Protocol, rounds: int, points: int, strut_length: float
) -> xr.Dataset:
    """results/validation/prototype.nc of the experiment `e` and its `trace`, run by `protocol`
    with struts of `strut_length` m, the lowest voltages searched by `rounds` rounds of `points`
    voltages over 0-12 V."""
    var, s = datasets.var, steps(e, rounds > 0)
    roll_pairs = s.pair[:2]
    data = {
        "step_pair": var(("step",), s.pair, "1", "pair driven in the step"),
        "step_voltage": var(("step",), s.voltage, "V", "voltage on the pair's two motors while driven"),
        "start_face": var(("step",), s.start_face, "1", "face the robot stands on at the step's start"),
        "paper_face": var(("step",), s.paper_face, "1", "face the prototype stood on after the step (IV.B)"),
        "face": var(("step",), s.face, "1", "face the simulated robot stands on after the step (0: none)"),
        "locked": var(
            ("step",), s.locked.astype(np.int8), "1", "1 if a strand pair ended the step twisted past its lock"
        ),
        "landing_time": var(
            ("step",),
            [e.time_1, e.time_2, np.nan],
            "s",
            "time from the voltage's start to the landing on the final face (NaN: not recorded)",
        ),
        "lowest_voltage": var(
            ("pair",),
            s.lowest,
            "V",
            "lowest voltage that rolls the robot on to the paper's face (the top of the multisection "
            "bracket; NaN: not searched, or none in the span rolls)",
            span_V=[0.0, 12.0],
            rounds=int(rounds),
            points=int(points),
        ),
        "lowest_voltage_error": var(
            ("pair",),
            s.error,
            "V",
            "width of the multisection bracket: the lowest rolling voltage lies in "
            "(lowest_voltage - lowest_voltage_error, lowest_voltage]",
        ),
        "paper_voltage": var(("pair",), s.paper_voltage, "V", "voltage the prototype was driven at (IV.B)"),
        "voltage": var(("time", "pair"), trace.volts, "V", "voltage commanded on the pair's motors"),
        "resting_face": var(("time",), trace.face, "1", "face the robot rests on (0: none)"),
        "cog": var(("time", "axis"), trace.cog, "m", "centre of gravity, world frame"),
        "nodes": var(("snapshot", "node", "axis"), trace.nodes, "m", "node positions, world frame"),
        "snapshot_name": (("snapshot",), np.array(SNAPSHOTS), {"long_name": "when the snapshot was taken"}),
        **datasets.geometry_vars(strut_length),
    }
    coords = {
        "step": ("step", np.arange(1, 4), {"units": "1", "long_name": "step of IV.B: roll 1, roll 2, no roll"}),
        "pair": ("pair", roll_pairs, {"units": "1", "long_name": "actuator pair number"}),
        "time": ("time", trace.t, {"units": "s", "long_name": "time from the first roll's voltage"}),
        "snapshot": ("snapshot", np.arange(1, 4), {"units": "1", "long_name": "snapshot number"}),
        "node": ("node", np.arange(1, topo.N_NODES + 1), {"units": "1", "long_name": "node number"}),
        "axis": ("axis", np.array(["x", "y", "z"]), {"long_name": "world-frame axis"}),
    }
    ds = xr.Dataset(data, coords=coords)
    ds.attrs.update(drive_s=protocol.drive, settle_s=protocol.settle, dt_s=protocol.dt)
    return ds


def read_prototype(path: str | os.PathLike) -> Steps:
    """The numbers check 8 reads of results/validation/prototype.nc."""
    ds = datasets.read(path)
    return Steps(
        pair=ds["step_pair"].values,
        voltage=ds["step_voltage"].values,
        start_face=ds["start_face"].values,
        paper_face=ds["paper_face"].values,
        face=ds["face"].values,
        locked=ds["locked"].values.astype(bool),
        lowest=ds["lowest_voltage"].values,
        error=ds["lowest_voltage_error"].values,
        paper_voltage=ds["paper_voltage"].values,
        searched=int(ds["lowest_voltage"].attrs["rounds"]) > 0,
    )
