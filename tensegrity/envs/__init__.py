"""Gymnasium environments over the batched kernel (issue 33, item 2). Importing this package
registers `tensegrity/Roll-v0`:

    import gymnasium as gym, tensegrity.envs
    env = gym.make("tensegrity/Roll-v0")                       # one robot (`single.RollEnv`)
    envs = gym.make_vec("tensegrity/Roll-v0", num_envs=64, vectorization_mode="vector_entry_point")

The task (observation, action, reward, termination) is `core`'s; keywords of make / make_vec
are `RollTask`'s fields (e.g. terrain="slope:10", goal_heading=30) and `params`.
Layer: physics and paper only; gymnasium is the one outside import.
"""

from __future__ import annotations

import gymnasium as gym

ROLL = "tensegrity/Roll-v0"

if ROLL not in gym.registry:
    gym.register(
        id=ROLL,
        entry_point="tensegrity.envs.single:RollEnv",
        vector_entry_point="tensegrity.envs.vector:RollVectorEnv",
    )
