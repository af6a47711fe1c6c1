"""Issue 10 item 3 on slopes: a brake that hands over to the roll (and comes and goes no faster
than brake_rate), a braked downhill roll that lands and holds. The workspace `ws` (conftest)
comes from the independent static solver."""

from dataclasses import replace

import numpy as np

from tensegrity import locomotion as lo
from tensegrity.locomotion.brake import Brake
from tensegrity.locomotion.control import roll_controller, settle, settle_controller
from tensegrity.locomotion.lockstep import lockstep, observe
from tensegrity.physics import dynamics as d
from tensegrity.physics import topology as topo
from tensegrity.physics.params import Params
from tensegrity.physics.terrain import Terrain

EQUI = topo.face_number(topo.CONTACT_FACES["equilateral"])  # (9,10,12)
DAMPED = Params(strut_damping=1.0)  # the rolling runs' default
SLOPE = Terrain.slope(15.0)


def _braked_roll(ws, pairs, expect):
    """Settle braked on (9,10,12) on the 15 deg slope (the brake comes on), then one braked
    roll of `pairs`, with or without the expected rolling pressure (MPa). Returns the
    RollResult and the pressures (T, 12) MPa of the roll."""
    s = lo.RollSettings(brake=True, settle_time=3.0)
    state = d.stand_on(DAMPED, EQUI, SLOPE)
    brake = Brake(ws, s.brake_margin)

    def ctl(b, obs):
        settling = lo.RollSettings(brake=True, settle_time=1.5)
        _, obs = yield from settle_controller(settling, obs, brake)
        res, obs = yield from roll_controller(DAMPED, s, obs, pairs, ws.max_pressure, brake, expect)
        return res

    ((res, _, rec),) = lockstep(DAMPED, SLOPE, state, ctl, s)
    return res, rec.pressure[rec.t > res.t_start]


def test_a_braked_roll_hands_over_and_tips_as_planned(ws):
    """On a 15 deg slope the unactuated robot on (9,10,12) needs a brake (the workspace puts its
    CoG projection < 35 mm inside). Kept on while the roll's pressure rises, the brake fights
    the roll: uphill, #6+#10 (planned at 2.5 MPa) does not roll at all. Handed over (fading
    out as the pressure nears the plan's), the robot tips within 0.25 MPa of the plan's
    pressure onto the planned face; the brake falls no faster than brake_rate."""
    target = (1.0, 0.0)  # uphill
    s = lo.RollSettings(brake=True)
    start = d.stand_on(DAMPED, EQUI, SLOPE)
    nodes = d.nodes(start.x, start.q, 0.5)[0]
    held = Brake(ws, s.brake_margin).for_face(EQUI, nodes)
    assert held.any()  # braked on this slope
    pl = lo.plan(ws, EQUI, nodes, direction=target)
    res, pres = _braked_roll(ws, pl.pairs, pl.pressure)
    assert res.rolled and res.face_after == pl.next_face
    assert abs(res.tip_pressure - pl.pressure) < 0.25
    brake_pairs = [q for q in np.flatnonzero(held) if q + 1 not in pl.pairs]
    assert np.all(np.diff(pres[:, brake_pairs], axis=0) >= -s.brake_rate * s.interval - 1e-9)
    fought, _ = _braked_roll(ws, pl.pairs, float("nan"))
    assert not fought.rolled or (fought.tip_pressure > pl.pressure + 0.5)


def test_a_braked_downhill_roll_lands_and_holds(ws):
    """Downhill over edge 9-10 on a 15 deg slope: unbraked, the robot tumbles on past the face
    across that edge (the CoG projection lands 27 mm inside by the workspace, less its sag);
    braked (the landing face's brake braced as it tips over and raised at 10 MPa/s), with a
    release as fast as the unbraked one's it stops on that face. With the defaults (a slow
    release where the brake acts, brake_release_time, and a brake raised at 6 MPa/s, which make
    whole runs on 15 deg arrive: benchmarks/bench_locomotion.py) the rolling pair pushes it on
    by a face or two, where it stops, still short of the unbraked tumble (0.51 against 0.61 m)."""
    edge = (9, 10)
    nxt = topo.neighbour(EQUI, edge)
    free = lo.roll_over(ws, [edge], DAMPED, SLOPE, settings=lo.RollSettings(brake=False, lookahead=0))
    held = lo.roll_over(
        ws, [edge], DAMPED, SLOPE, settings=lo.RollSettings(brake_release_time=0.4, brake_rate=10.0, lookahead=0)
    )
    slow = lo.roll_over(ws, [edge], DAMPED, SLOPE, settings=lo.RollSettings(lookahead=0))
    assert free.faces[0] == EQUI and free.faces[-1] != nxt
    assert held.faces == [EQUI, nxt] and held.outcome == "arrived"
    assert slow.outcome == "arrived"  # at rest on a face
    assert held.travelled < slow.travelled < free.travelled - 0.05


def test_a_roll_goes_on_from_the_pressures_applied_before(ws):
    """Braked, a controller starts from the pressures applied before it (`Obs.pressure`) and
    moves them by at most brake_rate: a roll handed a robot on (9,10,12) on the 15 deg slope
    with its brake only part way on goes on from there. Once, a roll put its face's full brake
    on at once; on a run down the slope, #10 braking at 2.8 MPa dropped to zero in one check
    interval where one attempt handed over to the next, and the kicked robot tumbled 2 m."""
    s = lo.RollSettings(brake=True)
    state, face = settle(DAMPED, d.stand_on(DAMPED, EQUI, SLOPE), SLOPE)  # it stands unbraked
    brake = Brake(ws, s.brake_margin)
    (obs,) = observe(DAMPED, SLOPE, state, s)
    full = brake.for_face(face, obs.nodes)
    assert face == EQUI and full.max() > 4 * s.brake_rate * s.interval
    pl = lo.plan(ws, face, obs.nodes, direction=(1.0, 0.0))
    for before in (np.zeros(topo.N_PAIRS), 0.5 * full):
        gen = roll_controller(DAMPED, s, replace(obs, pressure=before), pl.pairs, ws.max_pressure, brake, pl.pressure)
        first = next(gen)
        assert np.abs(first - before).max() <= s.brake_rate * s.interval + 1e-9
        assert np.any(first != before)  # on its way to the brake and the roll


def test_a_roll_planned_at_zero_pressure_lets_the_brake_go(ws):
    """Where the workspace puts the CoG projection outside the support already at zero pressure
    (plan pressure 0 MPa: only the brake holds the robot), the roll is the brake letting go,
    at brake_rate, while the rolling pair has barely started. Once, the brake stayed on until
    the pair reached the top of its range (4.8 MPa) and the robot, let go with that pressure
    on, tumbled down a 20 deg slope (benchmarks/bench_locomotion.py)."""
    s = lo.RollSettings(brake=True)
    state = d.stand_on(DAMPED, EQUI, SLOPE)
    brake = Brake(ws, s.brake_margin)
    (obs,) = observe(DAMPED, SLOPE, state, s)
    full = brake.for_face(EQUI, obs.nodes)
    assert full.max() > 4 * s.brake_rate * s.interval
    obs = replace(obs, face=EQUI, pressure=full)
    pair = next(q for q in range(1, 13) if full[q - 1] == 0)
    gen = roll_controller(DAMPED, s, obs, (pair,), ws.max_pressure, brake, 0.0)
    steps = int(np.ceil(full.max() / (s.brake_rate * s.interval))) + 1
    pres = [next(gen)] + [gen.send(obs) for _ in range(steps)]  # the robot does not move
    held = np.flatnonzero(full)
    assert np.all(np.asarray(pres)[-1, held] == 0.0)  # let go within full / brake_rate
    assert np.asarray(pres)[-1, pair - 1] <= len(pres) * s.ramp_rate * s.interval + 1e-9
    assert np.all(np.diff(np.asarray(pres)[:, held], axis=0) >= -s.brake_rate * s.interval - 1e-9)


def test_an_unbraked_roll_lets_a_leftover_brake_go_at_brake_rate(ws):
    """A roll judged unbraked (brake None) or a settle without a brake, started with a brake
    still on from before (`Obs.pressure`), brings it down at brake_rate; the roll's driven pair
    waits until it is off (`test_leftover_brake.py`). Once, an unbraked roll dropped 2.4-4.8 MPa
    to zero in one check interval: the robot snapped back to its rest shape, its CoG rose
    160-180 mm on terrain or it slid 0.6-1.1 m down a 10 deg slope, and every candidate
    simulated from there failed alike (docs/planner_evaluation.md)."""
    s = lo.RollSettings()
    (obs,) = observe(DAMPED, SLOPE, d.stand_on(DAMPED, EQUI, SLOPE), s)
    left = np.zeros(topo.N_PAIRS)
    left[[3, 8]] = ws.max_pressure, 2.4  # #4 and #9 (MPa), as the runs left them
    steps = int(np.ceil(left.max() / (s.brake_rate * s.interval))) + 1
    moving = replace(obs, speed=1.0)  # a settle that does not end before the brake is off
    roll = roll_controller(DAMPED, s, replace(obs, pressure=left), (10,), ws.max_pressure)
    for ctl, driven in ((roll, 9), (settle_controller(s, replace(moving, pressure=left)), None)):
        sent = obs if driven else moving  # the robot does not move
        pres = np.asarray([left, next(ctl)] + [ctl.send(sent) for _ in range(steps)])
        assert np.all(np.diff(pres[:, [3, 8]], axis=0) >= -s.brake_rate * s.interval - 1e-9)
        assert np.all(pres[-1, [3, 8]] == 0.0)  # let go within left / brake_rate
        assert np.all(pres[:, 9] == 0.0)  # the roll's pair is not raised meanwhile
