"""`tensegrity stage NAME` runs a stage with the function and the configuration keys its rule
uses: on the tiny run's inputs it writes files byte for byte the rule's (the provenance does not
depend on how a file was made)."""

from pathlib import Path

import pytest

from tensegrity import cli

TINY = Path(__file__).with_name("tiny.yaml")
C = ("equilateral", "isosceles")
CASES = {  # stage -> its arguments, given the tiny run's folder r and the output x
    "nominal": lambda r, x: [
        *(f"sweep_paths={p}" for p in sorted((r / "sweeps/equilateral").glob("*.nc"))),
        f"out_path={x}",
    ],
    "workspace": lambda r, x: [*(f"nominal_paths={r}/nominal/{c}.nc" for c in C), f"out_path={x}"],
    "curves": lambda r, x: [f"nominal_path={r}/nominal/isosceles.nc", f"out_path={x}"],
    "curves_json": lambda r, x: [*(f"curve_paths={r}/curves/{c}.nc" for c in C), f"out_path={x}"],
    "two_pair_map": lambda r, x: [*(f"contact_paths={r}/two_pair/{c}.nc" for c in C), f"out_path={x}"],
    "two_pair_surfaces": lambda r, x: [*(f"contact_paths={r}/two_pair/{c}.nc" for c in C), f"out_path={x}"],
}
MADE_BY_THE_RULE = {
    "nominal": "nominal/equilateral.nc",
    "workspace": "workspace.nc",
    "curves": "curves/isosceles.nc",
    "curves_json": "curves/curves.json",
    "two_pair_map": "workspace_two_pair.nc",
    "two_pair_surfaces": "curves/two_pair.json",
}


@pytest.mark.parametrize("stage", sorted(CASES))
def test_a_stage_run_from_the_command_line_writes_the_rules_file(tiny, tmp_path, stage):
    out = tmp_path / Path(MADE_BY_THE_RULE[stage]).name
    assert cli.main(["stage", stage, "--config", str(TINY), *CASES[stage](tiny / "results", out)]) == 0
    assert out.read_bytes() == (tiny / "results" / MADE_BY_THE_RULE[stage]).read_bytes()
