"""A non-editable install, run from outside the checkout: the configuration schema ships as
package data, so `tensegrity config show` and `config check` work anywhere."""

import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="module")
def installed(tmp_path_factory):
    """The package installed (not editable) into a scratch site directory."""
    site = tmp_path_factory.mktemp("site")
    build = tmp_path_factory.mktemp("src")
    # a copy of the package sources: the build never writes into the checkout
    subprocess.run(["cp", "-r", str(ROOT / "tensegrity"), str(ROOT / "pyproject.toml"), str(build)], check=True)
    r = subprocess.run(
        [
            sys.executable,
            "-m",
            "pip",
            "install",
            "-q",
            "--no-deps",
            "--no-build-isolation",
            "--target",
            str(site),
            str(build),
        ],
        capture_output=True,
        text=True,
    )
    assert r.returncode == 0, r.stderr[-2000:]
    return site


def _run(site, cwd, *args):
    env = {**os.environ, "PYTHONPATH": str(site)}
    return subprocess.run(
        [sys.executable, "-m", "tensegrity.cli", *args], cwd=cwd, env=env, capture_output=True, text=True, timeout=120
    )


def test_the_installed_package_is_used(installed, tmp_path):
    env = {**os.environ, "PYTHONPATH": str(installed)}
    r = subprocess.run(
        [sys.executable, "-c", "import tensegrity; print(tensegrity.__file__)"],
        cwd=tmp_path,
        env=env,
        capture_output=True,
        text=True,
    )
    assert r.stdout.strip().startswith(str(installed))


def test_config_show_outside_the_checkout(installed, tmp_path):
    r = _run(installed, tmp_path, "config", "show")
    assert r.returncode == 0, r.stderr
    import yaml

    shown = yaml.safe_load(r.stdout)
    assert shown["params"]["strut_length"] == 0.5 and shown["sim"]["dt"] == 1e-4
    assert set(shown) >= {"params", "sim", "sweep", "nominal", "fit", "validate", "locomotion"}


def test_config_check_good_and_bad_files_outside_the_checkout(installed, tmp_path):
    good = tmp_path / "good.yaml"
    good.write_text((ROOT / "tests/workflow/tiny.yaml").read_text())
    r = _run(installed, tmp_path, "config", "check", str(good))
    assert r.returncode == 0 and "valid" in r.stdout, r.stderr
    bad = tmp_path / "bad.yaml"
    bad.write_text("params:\n  strut_lenght: 0.6\nsim:\n  dt: -1\n")
    r = _run(installed, tmp_path, "config", "check", str(bad))
    assert r.returncode == 3
    assert "params.strut_lenght" in r.stderr and "strut_length" in r.stderr and "sim.dt" in r.stderr
