"""The figure of a calibration (issue 32): measured against simulated trajectories, drawn from
arrays off-screen (matplotlib's Agg canvas), written atomically (`files.save_figure`)."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
from matplotlib.figure import Figure

from .files import save_figure

__all__ = ["calibration_figure"]


def calibration_figure(
    path: str | os.PathLike,
    t: np.ndarray,
    measured: np.ndarray,
    simulated: np.ndarray,
    title: str,
    fit_until: float = float("nan"),
    check: np.ndarray | None = None,
) -> Path:
    """Three panels over time t (T,) s: the two nodes that move most (x, y, z from their start,
    mm), measured (dots) and simulated (lines), from nodes (T, 12, 3) m (NaN: not measured);
    and the RMS distance per sample (mm), of the fit and of the prediction check: nodes `check`
    (T, 12, 3) m simulated with the parameters fitted up to `fit_until` s (marked: the samples
    after it were predicted, not fitted)."""
    fig = Figure(figsize=(9.0, 8.0), layout="constrained")
    ax = fig.subplots(3, 1, sharex=True)
    travel = np.nanmax(np.linalg.norm(measured - measured[:1], axis=-1), axis=0)
    nodes = np.argsort(-np.nan_to_num(travel, nan=-1.0))[:2]
    colours = ("tab:red", "tab:green", "tab:blue")
    every = max(1, len(t) // 200)  # dots a reader can tell apart
    for i, a in enumerate("xyz"):
        for panel, k in enumerate(nodes):
            m, s = measured[:, k] * 1e3, simulated[:, k] * 1e3
            off = s[0, i]  # each coordinate from its start, so the three share one scale
            ax[panel].plot(t[::every], m[::every, i] - off, ".", color=colours[i], ms=3, label=f"{a} measured")
            ax[panel].plot(t, s[:, i] - off, "-", color=colours[i], lw=1.0, label=f"{a} simulated")
    for panel, k in enumerate(nodes):
        ax[panel].set_ylabel(f"node {k + 1}\nfrom its start (mm)")
    for pos, style, label in ((simulated, "-", "fitted to every sample"), (check, "--", "prediction check")):
        if pos is not None:
            err = np.sqrt(np.nanmean(np.sum((pos - measured) ** 2, axis=-1), axis=-1)) * 1e3
            ax[2].plot(t, err, style, color="0.2" if style == "-" else "tab:purple", lw=1.0, label=label)
    ax[2].legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    ax[2].set_ylabel("RMS node distance,\nsimulated - measured (mm)")
    ax[2].set_xlabel("time (s)")
    ax[2].set_ylim(bottom=0)
    for a in ax:
        a.grid(alpha=0.3)
        if np.isfinite(fit_until):
            a.axvline(fit_until, color="0.4", ls="--", lw=1)
    if np.isfinite(fit_until):
        ax[2].text(fit_until, ax[2].get_ylim()[1] * 0.9, "  check: predicted", fontsize=8, color="0.3", va="top")
    ax[0].legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0))  # outside: hides no data
    fig.suptitle(title, fontsize=10)
    return save_figure(fig, path)
