"""Calibration check (docs/design.md §4): the pressure at which each pair rolls the
robot, in the free-mode workspace (staircase) and in the grounded simulation (slow ramp).
Prints figures; asserts nothing. Usage: python benchmarks/calibration.py [--quick]
(--quick: pairs #10 and #11 only, three grounded pressures; a smoke run, not the calibration)."""

from __future__ import annotations

import argparse

import numpy as np

from tensegrity.physics import dynamics as d
from tensegrity.physics import frames
from tensegrity.physics import topology as topo
from tensegrity.physics.params import Params
from tensegrity.physics.schedule import Schedule
from tensegrity.physics.terrain import Terrain
from tensegrity.workspace import nominal, sweep

LEVELS = np.round(np.arange(1, 13) * 0.4, 2)


def free_tip(face, pairs):
    """Tip pressure (MPa) per pair from the free-mode staircase (nominal margin crossing)."""
    res = sweep.run(Params(), face, pairs, sweep.SweepSetup(levels=tuple(LEVELS), hold=1.0))
    out = {}
    for b, pair in enumerate(pairs):
        _, _, _, margin = nominal.nominal(res.t, res.level, res.cog[b], res.support[b], len(LEVELS), 1.0, 0.2)
        out[pair] = (frames.first_crossing(LEVELS, margin)[0], margin)
    return out


def grounded_roll(face, pair, pressures, ramp=2.0, hold=2.0, steps=100):
    """For each final pressure (MPa), ramp pair `pair` slowly from 0 and hold; return whether
    the robot left `face` (its three nodes no longer all on the ground)."""
    params, terrain = Params(), Terrain.flat()
    B = len(pressures)
    s = d.stand_on(params, face, terrain, batch=B)
    s, _ = d.simulate(params, s, Schedule.constant(np.zeros(12), 1.0), terrain)  # settle
    frac = np.append(np.arange(1, steps + 1) / steps, 1.0)
    pres = np.zeros((B, steps + 1, 12))
    pres[:, :, pair - 1] = np.outer(pressures, frac)
    dur = np.append(np.full(steps, ramp / steps), hold)
    _, tr = d.simulate(params, s, Schedule(dur, pres), terrain, 1e-4, 100)
    z = tr.nodes(params.strut_length)[:, -1, topo.FACES[topo.face_number(face) - 1], 2]
    return z.max(axis=1) > 3 * params.strut_radius


def main(quick: bool = False):
    pairs_eq = [10] if quick else list(range(1, 13))
    print("free mode (paper III.A), staircase 0.4..4.8 MPa held 1 s, nominal after 0.2 s:")
    for name, face, pairs in (
        ("(9,10,12)", (9, 10, 12), pairs_eq),
        ("(10,11,12)", (10, 11, 12), [11] if quick else [10, 11, 12]),
    ):
        tips = free_tip(face, pairs)
        for pair, (tp, margin) in tips.items():
            print(
                f"  {name} #{pair:<2d} margin at 2.4 MPa {margin[5] * 1000:6.1f} mm, leaves the triangle at "
                f"{'never (<= 4.8)' if np.isnan(tp) else f'{tp:.2f} MPa'}"
            )
    print("grounded (gravity, ground, mu = 0.8), pressure ramped over 2 s then held 2 s:")
    for name, face, pair in (("(9,10,12)", (9, 10, 12), 10), ("(10,11,12)", (10, 11, 12), 11)):
        ps = np.array([2.0, 4.0, 5.0]) if quick else np.round(np.arange(1.0, 5.01, 0.2), 2)
        rolled = grounded_roll(face, pair, ps)
        first = ps[np.argmax(rolled)] if rolled.any() else float("nan")
        print(
            f"  {name} #{pair}: stands up to {ps[~rolled].max() if (~rolled).any() else 'none'} MPa, "
            f"rolls from {first} MPa (0.2 MPa resolution)"
        )


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--quick", action="store_true", help="a smoke run: two pairs, three pressures")
    main(ap.parse_args().quick)
