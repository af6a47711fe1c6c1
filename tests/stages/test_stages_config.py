"""The table of stages (`stages.config.STAGES`): every key a stage lists is a key of the schema,
every function it names exists, the Snakemake scripts call the registered functions and no other,
and `tensegrity stage` reaches every one."""

import ast
import inspect
from pathlib import Path

import pytest

from tensegrity import stages
from tensegrity.io import config
from tensegrity.stages.config import FIGURE, STAGES, VALIDATION, readers, stage_config

ROOT = Path(__file__).resolve().parents[2]
SCRIPTS = sorted((ROOT / "workflow" / "scripts").glob("*.py"))


def test_every_key_is_a_key_of_the_schema():
    props = config.schema()["properties"]
    for name, st in STAGES.items():
        for key in st.keys:
            section, _, k = key.partition(".")
            assert section in props and (not k or k in props[section]["properties"]), f"{name}: {key}"


def test_stage_config_holds_exactly_the_keys():
    cfg = stage_config(config.defaults(), "nominal")
    assert cfg == {"nominal": {"discard": 0.2, "method": "averaging"}}
    two = stage_config(config.defaults(), "two_pair")
    assert set(two["two_pair"]) == {"levels", "hold", "discard", "record_every", "pairs"}  # no tolerance
    with pytest.raises(KeyError, match="stage nominal: the configuration has no key nominal.discard"):
        stage_config({"nominal": {}}, "nominal")
    with pytest.raises(ValueError, match="unknown stage 'nominals'"):
        stage_config(config.defaults(), "nominals")


def test_simulation_stages_read_no_validation_or_figure_key():
    """A key that only checks or drawings read is in no simulation stage (the dry-run test in
    tests/workflow/test_reruns.py shows the consequence)."""
    assert readers("validate.statics_tolerance") == ["validate"]
    assert readers("two_pair.tolerance") == ["validate_two_pair"]
    assert readers("locomotion.animation_fps") == ["animation"]
    assert readers("gravity.tip_tolerance") == ["validate_gravity"]
    assert set(readers("params.strut_length")) >= {"sweep", "two_pair", "gravity", "locomotion_runs"}


def _script_calls(path: Path) -> set[str]:
    """'module:function' of every `stages.<module>.<function>(...)` call in a workflow script."""
    tree = ast.parse(path.read_text())
    modules = {
        a.asname or a.name
        for n in ast.walk(tree)
        if isinstance(n, ast.ImportFrom) and n.module == "tensegrity.stages"
        for a in n.names
    }
    return {
        f"{c.func.value.id}:{c.func.attr}"
        for c in ast.walk(tree)
        if isinstance(c, ast.Call)
        and isinstance(c.func, ast.Attribute)
        and isinstance(c.func.value, ast.Name)
        and c.func.value.id in modules
    }


def test_the_scripts_call_every_registered_stage_and_no_other():
    called = set().union(*(_script_calls(p) for p in SCRIPTS))
    registered = {st.function for st in STAGES.values() if st.rule}
    assert called == registered, (called - registered, registered - called)


@pytest.mark.parametrize("name", sorted(STAGES))
def test_every_stage_has_a_function_taking_cfg_first(name):
    fn = stages.function(name)
    first = next(iter(inspect.signature(fn).parameters))
    assert first == "cfg" and fn.__doc__, name
    assert STAGES[name].kind in ("simulation", "data", VALIDATION, FIGURE)
