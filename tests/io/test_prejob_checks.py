"""Configurations that pass the schema but would fail inside a job, after Snakemake deleted its
old outputs (issue 35, item 3), refused by `io.config.validate` (and `io.study_config`) before
any job, naming the key: a goal closer than the robot's size, a job over the cost limits of
`io.job_costs`, a sample size the design's sampler needs."""

import math

import numpy as np
import pytest

from tensegrity.io import config, job_costs, study_config
from tensegrity.io.config import ConfigError


@pytest.mark.parametrize(
    "over, ok",
    [
        ({"locomotion": {"goal_distance": 0.1}}, False),
        ({"locomotion": {"goal_distance": 0.5}}, True),  # the strut length itself
        ({"locomotion": {"goal_distance": 0.55}, "params": {"strut_length": 0.6}}, False),
        ({"locomotion": {"goal_distance": 0.1, "runs": ["paper"]}}, True),  # rolls over given edges
        ({"locomotion": {"goal_distance": 0.1, "runs": []}}, True),
    ],
)
def test_goal_distance_is_at_least_the_strut_length(over, ok):
    if ok:
        config.validate(over)
        return
    with pytest.raises(ConfigError, match=r"^config key locomotion\.goal_distance: .* less than the strut length"):
        config.validate(over)


@pytest.mark.parametrize("heading", np.arange(0.0, 360.0, 7.5))
def test_a_goal_at_the_strut_length_is_accepted_by_the_runs(heading):
    """The runs' own check (`locomotion.runs._check_goal`) takes a goal at exactly the strut
    length, whatever round-off its heading gives, as the configuration check does."""
    from tensegrity.locomotion.demos import Scenarios, demo_setup
    from tensegrity.locomotion.runs import _check_goal
    from tensegrity.physics.terrain import Terrain

    goal = demo_setup("flat", Scenarios(goal_distance=0.5, goal_heading=float(heading)))["goal"]
    _check_goal(goal, Terrain.flat(), np.zeros(3), 0.5)
    with pytest.raises(ValueError, match="closer than its size"):
        _check_goal(0.999 * goal, Terrain.flat(), np.zeros(3), 0.5)


COSTLY = [
    ({"sweep": {"hold": 1.0e9}}, "sweep.hold", "a sweep job hold 196 PiB"),
    ({"sweep": {"settle": 1.0e6}}, "sweep.settle", "a sweep job"),
    ({"sim": {"record_every": 1}, "sweep": {"hold": 5.0}}, "sim.record_every", "over the limit of 8 GiB"),
    ({"two_pair": {"hold": 100.0}}, "two_pair.hold", "the two-pair job hold 39.1 GiB"),
    ({"locomotion": {"ramp_rate": 1.0e-5}}, "locomotion.ramp_rate", "the gravity job"),
    ({"gravity": {"settle": 1.0e5}}, "gravity.settle", "robot-steps"),
]


@pytest.mark.parametrize("over, key, words", COSTLY, ids=[k for _, k, _ in COSTLY])
def test_a_job_over_the_cost_limits_is_refused_naming_the_key(over, key, words):
    with pytest.raises(ConfigError) as e:
        config.validate(over)
    assert len(e.value.errors) == 1
    assert e.value.errors[0].startswith(f"config key {key}: ")
    assert words in e.value.errors[0]


def test_the_default_jobs_are_far_within_the_limits():
    """As config/README.md says: the two-pair job holds the most samples (0.8 GiB), the gravity
    job simulates the most steps (9e7), 1000 times less than the limit."""
    cfg = config.defaults()
    costs = {e.__name__: e(cfg) for e in (job_costs.sweep, job_costs.two_pair, job_costs.gravity)}
    assert all(c.burden() < 0.1 for c in costs.values())
    assert max(costs, key=lambda k: costs[k].memory) == "two_pair"
    assert job_costs._size(costs["two_pair"].memory) == "802 MiB"
    assert max(costs, key=lambda k: costs[k].steps) == "gravity"
    assert f"{costs['gravity'].steps:.0e}" == "9e+07" and job_costs.STEP_LIMIT / costs["gravity"].steps > 1000
    assert job_costs._size(job_costs.MEMORY_LIMIT) == "8 GiB"


def test_the_estimates_count_what_the_jobs_hold():
    """The sweep's samples are those the simulator records; the gravity ramp's those
    `workspace.gravity` allocates; the two-pair robots one per stabiliser orbit; a study chunk
    holds `studies.evaluate._blocks` samples at a time."""
    from tensegrity.studies import evaluate
    from tensegrity.workspace import gravity as gv
    from tensegrity.workspace.sweep import SweepSetup, run

    small = {"pairs": [10, 11], "levels": [1.0, 2.0], "hold": 0.05, "settle": 0.02, "contacts": ["isosceles"]}
    cfg = config.merge(config.defaults(), {"sweep": small})  # the estimate alone: no other check
    res = run(config.params_from_config(cfg), (10, 11, 12), [10, 11], SweepSetup((1.0, 2.0), 0.05, 0.02))
    cost = job_costs.sweep(cfg)
    assert cost.samples == pytest.approx(res.cog.shape[0] * res.cog.shape[1])
    assert cost.robot_seconds == pytest.approx(2 * (0.02 + 2 * 0.05))
    assert (job_costs.GRAVITY_TOP, job_costs.GRAVITY_HOLDS) == (gv.HOLD, gv.MAX_HOLD)
    g = config.defaults()
    setup = gv.GravitySetup()
    per_robot = setup.levels()[0].size + math.ceil(gv.MAX_HOLD / setup.interval - 1e-9)
    robots = len(g["gravity"]["pairs"]) * (1 + 4 * len(g["gravity"]["headings"]))  # 0 deg: one heading
    assert job_costs.gravity(g).samples == robots * per_robot
    assert [job_costs._orbits(tuple(range(1, 13)), c) for c in ("equilateral", "isosceles")] == [22, 38]
    st = _study(design={"method": "lhs", "n": 16}, workspace={"hold": 0.5, "sample_every": 5})
    held = max(round(b / 5e-4) for b in evaluate._blocks(0.5, 1e-4, 5))  # samples of the longest block
    assert job_costs.study_chunk(st, 1e-4).samples == st["chunk_size"] * 2 * 12 * held


def _study(**over):
    base = {"parameters": {"cable_stiffness": {"low": 800.0, "high": 1200.0, "units": "N/m"}}}
    return study_config.validate({**base, **over}, dt=1e-4)


@pytest.mark.parametrize(
    "design, ok, key",
    [
        ({"method": "sobol", "n": 10}, False, "design.n: 10 is not a power of 2"),
        ({"method": "sobol", "n": 16}, True, None),
        ({"method": "saltelli", "n": 12}, False, "design.n: 12 is not a power of 2"),
        ({"method": "saltelli", "n": 64}, True, None),
        ({"method": "morris", "n": 1}, False, "design.n: 1 Morris trajectory"),
        ({"method": "morris", "n": 5, "morris_levels": 5}, False, "design.morris_levels: 5 is odd"),
        ({"method": "morris", "n": 5, "morris_levels": 6}, True, None),
        ({"method": "lhs", "n": 10}, True, None),
    ],
)
def test_sample_sizes_the_samplers_need(design, ok, key):
    if ok:
        _study(design=design)
        return
    with pytest.raises(ConfigError, match=f"^study key {key}"):
        _study(design=design)


@pytest.mark.parametrize(
    "over, key",
    [
        ({"chunk_size": 100000}, "chunk_size"),
        ({"workspace": {"hold": 1.0e6}}, "workspace.hold"),
        ({"chunk_size": 1000, "workspace": {"sample_every": 1}}, "chunk_size"),
    ],
)
def test_a_chunk_over_the_cost_limits_is_refused_naming_the_key(over, key):
    with pytest.raises(ConfigError, match=f"^study key {key}: .* makes a chunk job"):
        _study(design={"method": "lhs", "n": 16}, **over)


def test_the_twisted_string_actuator_passes_the_checks_and_its_levels_are_volts():
    """`actuator.kind: twisted_string` runs the workspace pipeline in volts (issue 31), so the
    configuration checks let it through, with the sweep's levels read in V; the stages and commands
    that do not run it refuse it naming the key (tests/workspace/test_volts.py)."""
    from tensegrity.io import config

    cfg = config.load(None, ["actuator.kind=twisted_string", "sweep.levels=[6.0, 11.1]"])
    assert cfg["actuator"]["kind"] == "twisted_string" and cfg["sweep"]["levels"] == [6.0, 11.1]
    with pytest.raises(config.ConfigError, match=r"sweep.levels\[1\]: 11.1 is greater than the maximum of 10 MPa"):
        config.load(None, ["sweep.levels=[6.0, 11.1]"])  # the same levels are pressures of the muscle
