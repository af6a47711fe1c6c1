"""Terrain (physics/terrain.py): the terrain in words. (Its query against the kernel's is pinned
in test_twins.py, its text spec in test_rules.py.)"""

import pytest

from tensegrity.physics.terrain import Terrain, from_spec


@pytest.mark.parametrize(
    "terrain, words",
    [
        (Terrain.flat(), "flat ground"),
        (Terrain.flat(0.3), "flat ground"),
        (Terrain.slope(0.04), "flat ground"),
        (Terrain.slope(0.06), "a 0.06 deg slope"),
        (Terrain.slope(10.0, 45.0), "a 10 deg slope"),
        (Terrain.slope(-12.5), "a 12.5 deg slope"),
        (Terrain.random(seed=1), "uneven terrain (height field)"),
        (Terrain.none(), "no ground"),
        (from_spec("slope:7.25:90"), "a 7.25 deg slope"),
    ],
)
def test_describe_says_the_terrain_in_the_words_of_the_figure_titles(terrain, words):
    assert terrain.describe() == words
