"""Configuration files read strictly, and the configuration's error type.

PyYAML (and so Snakemake) keeps the last of two equal keys in a mapping; `read_yaml` refuses
them, naming file, line and key. `read_file` reads a configuration file, which must be a mapping
of sections: an empty file (or one of comments only) is refused naming it, as Snakemake refuses
it before the Snakefile runs ("Config file must be given as JSON or YAML with keys at top
level", naming no file). `check_files` does both for every file a run loaded.
`ConfigError` is the error of every configuration check (`io.config`), one message per problem.
"""

from __future__ import annotations

import os
from collections.abc import Iterable, Mapping
from typing import Any

import yaml


class ConfigError(ValueError):
    """An invalid configuration. `errors` lists one message per problem, each naming its key."""

    def __init__(self, errors: str | list[str]):
        self.errors = [errors] if isinstance(errors, str) else list(errors)
        super().__init__("\n".join(self.errors))


class _StrictLoader(yaml.SafeLoader):
    """SafeLoader that refuses duplicate keys (PyYAML silently keeps the last one)."""


def _construct_mapping(loader: _StrictLoader, node: yaml.MappingNode, deep: bool = False):
    seen = set()
    for key_node, _ in node.value:
        if key_node.tag == "tag:yaml.org,2002:merge":
            continue
        key = loader.construct_object(key_node, deep=True)
        if key in seen:
            raise ConfigError(
                f"config file {key_node.start_mark.name} line {key_node.start_mark.line + 1}: duplicate key {key!r}"
            )
        seen.add(key)
    return loader.construct_mapping(node, deep=deep)


_StrictLoader.add_constructor(yaml.resolver.BaseResolver.DEFAULT_MAPPING_TAG, _construct_mapping)


def read_yaml(path: str | os.PathLike) -> Any:
    """The YAML file `path`, read strictly: a key given twice in a mapping is a ConfigError
    naming the file, line and key (PyYAML, and so Snakemake, would silently keep the last)."""
    with open(path, encoding="utf-8") as f:
        try:
            return yaml.load(f, Loader=_StrictLoader)
        except yaml.YAMLError as e:
            raise ConfigError(f"config file {path}: {e}") from None


def read_file(path: str | os.PathLike) -> dict:
    """The configuration file `path` (`read_yaml`), which must hold a mapping of sections: an
    empty file is a ConfigError naming it (write `{}` for a file that changes nothing)."""
    cfg = read_yaml(path)
    if cfg is None:
        raise ConfigError(
            f"config file {path}: the file is empty; a configuration file holds a mapping of sections "
            "(Snakemake refuses an empty one too): write {} for a file that changes nothing"
        )
    if not isinstance(cfg, Mapping):
        raise ConfigError(f"config file {path}: expected a mapping of sections, got {type(cfg).__name__}")
    return dict(cfg)


def check_files(paths: Iterable[str | os.PathLike]) -> None:
    """Re-read every configuration file in `paths` strictly (`read_file`); raises one ConfigError
    listing every file with a duplicate key, a YAML error or no mapping (an empty file). The
    Snakefile runs it on the files Snakemake loaded itself (`workflow.configfiles`), whose parser
    keeps the last of two keys, and on config/config.yaml before Snakemake reads it."""
    errors = []
    for p in paths:
        try:
            read_file(p)
        except ConfigError as e:
            errors += e.errors
    if errors:
        raise ConfigError(errors)
