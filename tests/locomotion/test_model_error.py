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
