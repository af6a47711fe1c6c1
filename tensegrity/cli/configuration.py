"""`tensegrity config show|check`: the configuration every command reads, and which files it
comes from (`config_sources`)."""

from __future__ import annotations

import argparse


def config_sources(path: str | None) -> str:
    """Which files `io.config.load(path)` reads, in words."""
    from ..io import config

    base = config.base_file()
    where = str(base) if base else "no config/config.yaml: the schema's defaults"
    return where if path is None else f"{path} merged over {where}"


def cmd_config(args: argparse.Namespace) -> int:
    """`config show [FILE]`: the resolved, validated configuration (defaults filled in) as YAML,
    FILE (or --config FILE) merged over config/config.yaml as `snakemake --configfile FILE` does;
    `config check FILE`: validate FILE merged in the same way (what Snakemake and every command
    would run with it), naming every bad key (exit 3). config/config.yaml is the current
    directory's, else the checkout's, else the schema's defaults."""
    import yaml

    from ..io import config

    if args.action == "check" and not args.file:
        raise ValueError("config check needs a FILE")
    path = args.file or args.config
    read = config_sources(path) + "".join(f", then --set {kv}" for kv in args.set or ())
    try:
        cfg = config.load(path, overrides=args.set or None)
    except config.ConfigError as e:
        raise config.ConfigError([*e.errors, f"(read: {read})"]) from None
    if args.action == "check":
        print(f"{args.file}: valid (read: {read})")
    else:
        print(f"# {read}; defaults filled in\n{yaml.safe_dump(cfg, sort_keys=False, default_flow_style=False)}", end="")
    return 0
