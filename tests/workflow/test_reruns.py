"""What an edit re-runs (README, "Extending the sweeps"): after the finished tiny run, editing
any configuration key that only validation or figures read, one at a time, re-runs no simulation
job (`snakemake -n`); editing a key of the robot re-runs them all."""

import re
import subprocess
import sys
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import yaml

from tensegrity.io import config
from tensegrity.stages.config import FIGURE, SIMULATION, STAGES, VALIDATION, readers

TINY = Path(__file__).with_name("tiny.yaml")

# a valid new value of every key that only validation or figures read, on the tiny configuration
EDITS = {
    "validate.ranking_pressure": 3.6,
    "validate.tip_pressure_tolerance": 0.3,
    "validate.orbit_tolerance": 2.0e-4,
    "validate.statics_pressures": [1.2, 2.4],
    "validate.statics_tolerance": 2.0e-4,
    "validate.faces": [1, 7, 9, 17],
    "validate.mapping_tolerance": 2.0e-4,
    "validate.grounded_settle": 0.4,
    "validate.grounded_tolerance": 4.0e-3,
    "validate.timestep_tolerance": 2.0e-4,
    "validate.averaging_tolerance": 1.0e-4,
    "two_pair.check_combos": [[9, 10]],
    "two_pair.check_faces": [1],
    "two_pair.tolerance": 2.0e-4,
    "gravity.validate_slopes": [15],
    "gravity.tip_tolerance": 0.3,
    "locomotion.animation_fps": 12,
    "locomotion.animation_speed": 6.0,
    "prototype.drive": 25.0,
    "prototype.settle": 3.0,
    "prototype.rounds": 2,
    "prototype.points": 3,
}
SIMULATION_RULES = {st.rule for st in STAGES.values() if st.kind == SIMULATION and st.rule}


def _leaf_keys() -> list[str]:
    props = config.schema()["properties"]
    return [f"{s}.{k}" for s, p in props.items() if "properties" in p for k in p["properties"]]


def test_the_edits_cover_every_key_only_checks_and_figures_read():
    only = {k for k in _leaf_keys() if readers(k) and all(STAGES[s].kind in (VALIDATION, FIGURE) for s in readers(k))}
    assert only == set(EDITS)


def _dry_run(wd, key, value) -> set[str]:
    section, name = key.split(".")
    over = f"{section}={yaml.safe_dump({name: value}, default_flow_style=True).strip()}"
    r = subprocess.run(
        [sys.executable, "-m", "snakemake", "-n", "--configfile", str(TINY), "--config", over],
        cwd=wd,
        capture_output=True,
        text=True,
    )
    assert r.returncode == 0, r.stderr[-2000:]
    return set(re.findall(r"^(?:local)?rule (\w+):", r.stdout + r.stderr, re.M)) - {"all"}


def test_an_edit_of_a_check_or_figure_key_reruns_no_simulation(tiny):
    config.validate(
        config.merge(
            yaml.safe_load(TINY.read_text()), {k.split(".")[0]: {k.split(".")[1]: v} for k, v in EDITS.items()}
        )
    )  # every edit is valid
    with ThreadPoolExecutor(2) as pool:
        jobs = dict(zip(EDITS, pool.map(lambda kv: _dry_run(tiny, *kv), EDITS.items())))
    for key, rules in jobs.items():
        assert rules, f"editing {key} re-runs nothing: its reader does not see it"
        assert not rules & SIMULATION_RULES, f"editing {key} re-runs {sorted(rules)}"
        assert all(STAGES[s].rule in rules for s in readers(key)), (key, rules)


def test_an_edit_of_the_robot_reruns_every_simulation(tiny):
    rules = _dry_run(tiny, "params.strut_radius", 0.011)
    assert SIMULATION_RULES - {"study_chunk"} <= rules
