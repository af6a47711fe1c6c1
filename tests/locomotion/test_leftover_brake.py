"""A brake left on before an unbraked roll (issue 30, evaluation seed 715445 on terrain 0.05 m):
the robot relaxes as it comes off; that is not the roll's lift."""

import numpy as np

from tensegrity import locomotion as lo
from tensegrity.locomotion.control import roll_controller
from tensegrity.locomotion.lockstep import lockstep
from tensegrity.physics import contact as ct
from tensegrity.physics import dynamics as d
from tensegrity.physics import topology as topo
from tensegrity.physics.params import Params
from tensegrity.physics.terrain import Terrain

EQUI = topo.face_number(topo.CONTACT_FACES["equilateral"])  # (9,10,12)
DAMPED = Params(strut_damping=1.0)  # the rolling runs' default
ROUGH = Terrain.random(3, size=6.0, amplitude=0.05)  # height std 0.05 m


def test_a_leftover_brake_lets_the_robot_relax_before_the_ramp_takes_its_lift_reference():
    """#7 held at 2.4 MPa (as a braked settle leaves it) deforms the robot on rough ground; an
    unbraked roll of #10 from there lets #7 go at brake_rate, which lifts a support node by more
    than lift_tolerance as the robot relaxes. Read as the roll's lift, it held #10 (here at
    0.42 MPa) and the roll gave up, not rolled; in 715445 every candidate of the step ended so
    at 0.02 MPa ("do not roll") and the run was stuck. Now #10 stays at 0 until #7 is off and the robot has settled,
    then ramps from there: it rolls the robot or reaches max_pressure."""
    s = lo.RollSettings()
    left = np.zeros(topo.N_PAIRS)
    left[6] = 2.4  # #7, MPa

    def ctl(b, obs):
        for _ in range(100):  # 2 s: the robot stands deformed
            obs = yield left
        face, gap = obs.face, obs.gap.copy()
        res, _ = yield from roll_controller(DAMPED, s, obs, (10,), 4.8)
        return face, gap, res

    (((face, gap, res), _, rec),) = lockstep(DAMPED, ROUGH, d.stand_on(DAMPED, EQUI, ROUGH), ctl, s)
    assert face is not None and res.face_before == face
    assert res.rolled or res.peak_pressure == 4.8, res  # the ramp is not given up at the relaxation
    mine = rec.t > res.t_start - 1e-9  # the roll's intervals
    p, nodes = rec.pressure[mine], rec.nodes[mine]  # (T, 12) MPa, (T, 12, 3) m
    assert np.all(np.diff(np.r_[2.4, p[:, 6]]) >= -s.brake_rate * s.interval - 1e-9)  # let go at brake_rate
    ramp = int(np.argmax(p[:, 9] > 0))  # #10's first interval
    assert ramp > 0 and np.all(p[ramp - 1 :, 6] == 0.0)  # #10 waits until #7 is off
    support = topo.FACES[face - 1]
    lift = ct.clearance(nodes[:ramp], ROUGH, float(DAMPED.strut_radius))[:, support] - gap[support]
    assert lift.max() > s.lift_tolerance  # the relaxation lifts a support node
