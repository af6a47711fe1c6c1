"""Parameters (physics/params.py): the rest length's one home, replace, and the units."""

import math
import re
from dataclasses import fields

import numpy as np

from tensegrity.physics.params import Params, rest_length


def test_rest_length_gives_the_pretension_in_the_symmetric_state():
    S, T0, K = 0.5, 20.0, 1000.0
    assert rest_length(S, T0, K) == S * math.sqrt(6) / 4 - T0 / K == Params().cable_rest_length
    assert isinstance(rest_length(S, T0, K), float)
    L = rest_length(np.array([0.5, 0.6]), T0, np.array([1000.0, 1200.0]))
    np.testing.assert_array_equal(L, [0.5 * math.sqrt(6) / 4 - 20 / 1000, 0.6 * math.sqrt(6) / 4 - 20 / 1200])
    batch = Params(strut_length=np.array([0.5, 0.6]), cable_stiffness=np.array([1000.0, 1200.0]))
    np.testing.assert_array_equal(batch.cable_rest_length, L)


def test_replace_recomputes_the_rest_length_unless_given():
    p = Params().replace(cable_pretension=10.0)
    assert p.cable_rest_length == rest_length(0.5, 10.0, 1000.0)
    assert Params().replace(cable_stiffness=800.0, cable_rest_length=0.29).cable_rest_length == 0.29
    assert Params().replace(friction=0.5).cable_rest_length == Params().cable_rest_length


def test_every_field_has_its_unit_in_the_docstring():
    documented = re.findall(r"^\s{8}(\w+): ", Params.__doc__.split("Attributes:")[1], re.M)
    assert documented == [f.name for f in fields(Params)]
