"""Configuration files read strictly, and the configuration's error type.

PyYAML (and so Snakemake) keeps the last of two equal keys in a mapping; `read_yaml` refuses
them, naming file, line and key, and `check_files` does it for every file a run loaded.
`ConfigError` is the error of every configuration check (`io.config`), one message per problem.
"""

from __future__ import annotations

import os
from collections.abc import Iterable
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


def check_files(paths: Iterable[str | os.PathLike]) -> None:
    """Re-read every configuration file in `paths` strictly (`read_yaml`); raises one ConfigError
    listing every file with a duplicate key or a YAML error. The Snakefile runs it on the files
    Snakemake loaded itself (`workflow.configfiles`), whose parser keeps the last of two keys."""
    errors = []
    for p in paths:
        try:
            read_yaml(p)
        except ConfigError as e:
            errors += e.errors
    if errors:
        raise ConfigError(errors)
