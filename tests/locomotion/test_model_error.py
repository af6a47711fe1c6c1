"""A planner whose model of the robot and ground is not the world's (`roll_to(..., model=)`):
it judges its candidate rolls by simulating them with the model's physics, while the robot
moves with the world's (benchmarks/bench_locomotion.py `--world`)."""

import dataclasses
import re

from tensegrity import locomotion as lo
from tensegrity.locomotion.settings import RollSettings
from tensegrity.physics.params import Params
from tensegrity.physics.terrain import Terrain

DAMPED = Params(strut_damping=1.0)


def test_the_planner_foresees_with_its_model_and_the_robot_rolls_in_the_world(ws):
    """On a 15 deg slope with friction 0.8 the robot stands and the exact planner makes a roll.
    A planner that believes the ground is ice (friction 0.02, below tan 15 deg = 0.27) foresees
    every candidate sliding away, so it makes none, although the world would have held."""
    slope, s = Terrain.slope(15.0), RollSettings(max_rolls=1, optimised_actions=False)
    exact = lo.roll_to(ws, (0.0, 2.0), DAMPED, slope, settings=s)
    assert exact.rolls == 1 and exact.steps[0].face_after not in (None, exact.start_face)
    ice = lo.roll_to(ws, (0.0, 2.0), DAMPED, slope, settings=s, model=dataclasses.replace(DAMPED, friction=0.02))
    assert ice.outcome == "stuck" and ice.rolls == 0 and ice.start_face == exact.start_face
    assert re.search(r"\(\d+ tumble or slide, 0 do not roll, 0 return, 0 land elsewhere\)", ice.message)


def test_a_roll_the_world_refuses_is_planned_again_without_it(ws):
    """The model foresees a roll that the world, with less friction, does not make (its nodes
    slide instead of pivoting). Until stop 55 the run ended stuck there; now it plans again from
    where the robot stands, without the refused action, and rolls on. With an exact model this
    never happens: the world makes each roll with the bits it was foreseen with."""
    slope = Terrain.slope(15.0)
    run = lo.roll_to(
        ws,
        (2.0, 0.0),
        dataclasses.replace(DAMPED, friction=0.6),
        slope,
        settings=RollSettings(max_rolls=5),
        model=DAMPED,
    )
    refused = [i for i, st in enumerate(run.steps) if not st.rolled]
    assert refused and refused[0] + 1 < len(run.steps), [st.face_after for st in run.steps]
    st, nxt = run.steps[refused[0]], run.steps[refused[0] + 1]
    act = st.attempts[0].pairs
    assert st.face_after == st.face and any(r.pairs == act and r.rolled for r in st.simulated)
    assert nxt.face == st.face and nxt.rolled and all(a.pairs != act for a in nxt.attempts)
