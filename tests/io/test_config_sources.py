"""Which configuration a command reads (issue 35, item 3): config/config.yaml of the current
directory first, as Snakemake reads it, then the checkout's, then the schema's defaults; a file
given to a command merged over it as `snakemake --configfile` merges it; an empty file refused
everywhere, naming it."""

import pytest
import yaml

from tensegrity import cli
from tensegrity.io import config
from tensegrity.io.config import ConfigError


def _project(tmp_path, text="params:\n  strut_length: 0.6\nsweep:\n  hold: 0.5\n"):
    """A project copy: a folder with its own config/config.yaml."""
    (tmp_path / "config").mkdir()
    (tmp_path / "config" / "config.yaml").write_text(text)
    return tmp_path


def test_the_current_directory_comes_first_then_the_checkout_then_the_defaults(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    assert config.base_file() == config.DEFAULT_PATH  # no config/ here: the checkout's
    _project(tmp_path)
    assert config.base_file() == tmp_path / "config" / "config.yaml"
    cfg = config.load()
    assert cfg["params"]["strut_length"] == 0.6 and cfg["sweep"]["hold"] == 0.5
    assert cfg["sweep"]["pairs"] == list(range(1, 13))  # the rest: the schema's defaults
    monkeypatch.setattr(config, "DEFAULT_PATH", tmp_path / "nowhere" / "config.yaml")
    (tmp_path / "config" / "config.yaml").unlink()
    assert config.base_file() is None and config.load() == config.defaults()


def test_a_file_merges_over_the_base_as_snakemakes_configfile(tmp_path, monkeypatch):
    """`snakemake --configfile my.yaml` = config/config.yaml updated by my.yaml (mappings merge,
    lists and scalars replace), then --config; `config.load` and every command do the same."""
    monkeypatch.chdir(_project(tmp_path))
    mine = tmp_path / "my.yaml"
    mine.write_text("params:\n  cable_stiffness: 2000.0\nsweep:\n  pairs: [10, 11]\n")
    cfg = config.load(mine, overrides=["sweep.hold=0.4"])
    assert cfg["params"]["strut_length"] == 0.6  # from the base
    assert cfg["params"]["cable_stiffness"] == 2000.0 and cfg["sweep"]["pairs"] == [10, 11]  # from the file
    assert cfg["sweep"]["hold"] == 0.4  # from the override
    base = yaml.safe_load((tmp_path / "config" / "config.yaml").read_text())
    over = {"sweep": {"hold": 0.4}}
    assert cfg == config.validate(config.merge(config.merge(base, yaml.safe_load(mine.read_text())), over))
    assert config.load(tmp_path / "config" / "config.yaml") == config.load()  # the base over itself


def test_config_show_and_check_read_the_project_and_merge_the_file(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(_project(tmp_path))
    assert cli.main(["config", "show"]) == 0
    out = capsys.readouterr().out
    assert out.startswith(f"# {tmp_path / 'config' / 'config.yaml'}; defaults filled in\n")
    assert yaml.safe_load(out) == config.load() and yaml.safe_load(out)["params"]["strut_length"] == 0.6
    mine = tmp_path / "my.yaml"
    mine.write_text("sweep:\n  pairs: [10]\n")
    for argv in (["config", "show", str(mine)], ["config", "show", "--config", str(mine)]):
        assert cli.main(argv) == 0
        shown = yaml.safe_load(capsys.readouterr().out)
        assert shown["sweep"]["pairs"] == [10] and shown["params"]["strut_length"] == 0.6
    assert cli.main(["config", "check", str(mine)]) == 0
    assert f"{mine}: valid (read: {mine} merged over {tmp_path / 'config' / 'config.yaml'})" in capsys.readouterr().out
    # valid alone, not over this base: nominal.discard 0.6 s is not less than the base's hold 0.5 s
    late = tmp_path / "late.yaml"
    late.write_text("nominal:\n  discard: 0.6\n")
    config.validate(yaml.safe_load(late.read_text()))
    assert cli.main(["config", "check", str(late)]) == cli.EXIT_INPUT
    err = capsys.readouterr().err
    assert "config key nominal.discard: 0.6 s is not less than sweep.hold = 0.5 s" in err
    assert f"(read: {late} merged over {tmp_path / 'config' / 'config.yaml'})" in err


@pytest.mark.parametrize("text", ["", "# only a comment\n", "\n\n"])
def test_an_empty_file_is_refused_everywhere_naming_it(tmp_path, monkeypatch, capsys, text):
    """Snakemake refuses an empty config file (`--configfile` before the Snakefile runs, and
    config/config.yaml), so the commands do too; `{}` is the file that changes nothing."""
    monkeypatch.chdir(tmp_path)
    empty = tmp_path / "empty.yaml"
    empty.write_text(text)
    with pytest.raises(ConfigError, match=f"config file {empty}: the file is empty.*write {{}}"):
        config.load(empty)
    with pytest.raises(ConfigError, match="the file is empty"):
        config.check_files([empty])
    for argv in (["config", "check", str(empty)], ["config", "show", str(empty)]):
        assert cli.main(argv) == cli.EXIT_INPUT
        assert f"config file {empty}: the file is empty" in capsys.readouterr().err
    _project(tmp_path, text)  # an empty config/config.yaml of the project
    with pytest.raises(ConfigError, match="config/config.yaml: the file is empty"):
        config.load()
    nothing = tmp_path / "nothing.yaml"
    nothing.write_text("{}\n")
    (tmp_path / "config" / "config.yaml").write_text("{}\n")
    assert config.load(nothing) == config.defaults()


def test_a_file_that_is_not_a_mapping_is_refused(tmp_path):
    p = tmp_path / "list.yaml"
    p.write_text("- 1\n- 2\n")
    with pytest.raises(ConfigError, match=f"config file {p}: expected a mapping of sections, got list"):
        config.load(p)


def test_the_snakefile_names_an_empty_config_yaml_before_snakemake_reads_it():
    from pathlib import Path

    text = (Path(__file__).resolve().parents[2] / "Snakefile").read_text()
    assert text.index('check_config_files(["config/config.yaml"])') < text.index('configfile: "config/config.yaml"')
