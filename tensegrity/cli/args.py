"""Command-line values of the `tensegrity` command (`cli`): numbers, faces, terrains, points and
headings parsed by argparse, with messages that name the option; negative numbers after an
option (`--goal -1.2,1.5`) are joined to it before parsing (`join_negative_values`); the
configuration that --config and --set name (`load_cfg`, `stage_cfg`)."""

from __future__ import annotations

import argparse
import math
import re
from collections.abc import Callable
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from ..physics.terrain import Terrain


def floats(text: str, n: int | None = None, name: str = "value") -> list[float]:
    """Finite numbers separated by commas or spaces (exactly `n` if given); `name` is the option."""
    try:
        vals = [float(v) for v in text.replace(",", " ").split()]
    except ValueError:
        raise argparse.ArgumentTypeError(f"{name}: {text!r} is not a list of numbers") from None
    if n is not None and len(vals) != n:
        raise argparse.ArgumentTypeError(f"{name}: expected {n} numbers, got {text!r}")
    if not all(np.isfinite(vals)):
        raise argparse.ArgumentTypeError(f"{name}: {text!r} is not finite")
    return vals


def face(text: str) -> float | tuple[int, ...]:
    """A face on the command line: a number or three node numbers 'a,b,c'. Only the syntax is
    checked here; the command checks the face itself (topology.face_number, exit 3)."""
    parts = text.replace(",", " ").split()
    try:
        if len(parts) == 1:
            return float(parts[0])
        return tuple(int(p) for p in parts)
    except ValueError:
        raise argparse.ArgumentTypeError(
            f"face {text!r}: give a number 1..20 or three node numbers of a face, e.g. 9,10,12"
        ) from None


def terrain(text: str) -> Terrain:
    """A terrain spec (physics.terrain.from_spec, the one reading for every command)."""
    from ..physics.terrain import from_spec

    try:
        return from_spec(text)
    except ValueError as e:
        raise argparse.ArgumentTypeError(str(e)) from None


def positive(name: str) -> Callable[[str], float]:
    def parse(text: str) -> float:
        v = floats(text, 1, name)[0]
        if not v > 0:
            raise argparse.ArgumentTypeError(f"{name}: must be positive, got {text!r}")
        return v

    return parse


def non_negative(name: str) -> Callable[[str], float]:
    def parse(text: str) -> float:
        v = floats(text, 1, name)[0]
        if v < 0:
            raise argparse.ArgumentTypeError(f"{name}: must be >= 0, got {text!r}")
        return v

    return parse


_NUMBERS = re.compile(r"^-\.?\d[\d.eE+\-]*([, ]+-?\.?\d[\d.eE+\-]*)*$")


def join_negative_values(argv: list[str]) -> list[str]:
    """`--goal -1.2,1.5` -> `--goal=-1.2,1.5`: argparse would take a value that starts with '-'
    for an option, so numbers after an option are joined to it before parsing."""
    out: list[str] = []
    for tok in argv:
        if out and _NUMBERS.match(tok) and out[-1].startswith("--") and "=" not in out[-1]:
            out[-1] = f"{out[-1]}={tok}"
        else:
            out.append(tok)
    return out


def xy(name: str) -> Callable[[str], list[float]]:
    """A world point or vector 'x,y' (m); negative numbers need no '=' (see join_negative_values)."""

    def parse(text: str) -> list[float]:
        return floats(text, 2, name)

    return parse


def heading(text: str) -> list[float]:
    """A target heading in deg from +x, or a vector 'x,y'."""
    vals = floats(text, None, "--direction")
    if len(vals) == 1:
        return [math.cos(math.radians(vals[0])), math.sin(math.radians(vals[0]))]
    if len(vals) != 2:
        raise argparse.ArgumentTypeError(f"--direction: give a heading in deg or x,y, got {text!r}")
    return vals


def stage_arguments_first(argv: list[str], valued: tuple[str, ...] = ("--config", "--set")) -> list[str]:
    """`stage NAME --config F a=1 b=2` -> `stage NAME a=1 b=2 --config F`: argparse takes the
    stage's ARG=VALUE list only before the options, so they are moved there (the value of an
    option in `valued` stays with it)."""
    if len(argv) < 2 or argv[0] != "stage":
        return argv
    args, opts, rest = [], [], argv[2:]
    i = 0
    while i < len(rest):
        tok = rest[i]
        if tok in valued and i + 1 < len(rest):
            opts += rest[i : i + 2]
            i += 2
            continue
        (opts if tok.startswith("-") else args).append(tok)
        i += 1
    return argv[:2] + args + opts


def load_cfg(args: argparse.Namespace) -> dict:
    """The resolved configuration (`io.config.load`): the --config file merged over
    config/config.yaml (of the current directory, else of the checkout, else the schema's
    defaults) as `snakemake --configfile` merges it, or that file alone; then the --set
    overrides."""
    from ..io import config

    return config.load(args.config, overrides=args.set or None)


def stage_cfg(args: argparse.Namespace, stage: str) -> dict:
    """The keys of the resolved configuration that `stage` reads, as its rule passes them;
    ValueError naming actuator.kind if `stage` does not run with the configured actuator."""
    from ..stages.config import actuator_error, stage_config

    cfg = load_cfg(args)
    why = actuator_error(cfg, stage)  # a stage the configured actuator cannot run: before any work
    if why:
        raise ValueError(why)
    return stage_config(cfg, stage)
