"""Figures of the gravity-aware workspace and the slope limit (issue 10), drawn from arrays
off-screen (matplotlib's Agg canvas); each PNG is written atomically (`files.save_figure`)."""

from __future__ import annotations

import os
from collections.abc import Sequence
from pathlib import Path

import numpy as np
from matplotlib import colormaps
from matplotlib.figure import Figure

from .files import save_figure

_KIND_COLOUR = {"stand": "tab:green", "uphill": "tab:red", "downhill": "tab:blue"}


def slope_limit_figure(
    path: str | os.PathLike,
    kinds: Sequence[str],
    contacts: Sequence[str],
    headings: np.ndarray,
    simulated: np.ndarray,
    predicted_free: np.ndarray,
    predicted_gravity: np.ndarray,
    friction: float,
    max_pressure: float,
    unit: str = "MPa",
    multi: np.ndarray | None = None,
    cables: np.ndarray | None = None,
) -> Path:
    """Slope limit (deg) vs heading (deg), one panel per contact case, one colour per kind:
    simulated with single pairs (solid), predicted from the free workspace (dashed), the
    gravity-aware grid (markers); arrays (kind, contact, heading). Beside them, where given and
    not all NaN: `multi` (kind, contact, heading), simulated with optimised actions of any set of
    pairs (dash-dot), and `cables` (contact, heading), the uphill limit with the 24 cables one by
    one (dotted, squares). Written to the PNG `path`. `unit`: of the actuation level, MPa
    (pressures) or V (motor voltages)."""
    args = (kinds, contacts, headings, simulated, predicted_free, predicted_gravity, friction, max_pressure, unit)
    return save_figure(slope_limit_axes(*args, multi=multi, cables=cables), path)


def slope_limit_axes(
    kinds: Sequence[str],
    contacts: Sequence[str],
    headings: np.ndarray,
    simulated: np.ndarray,
    predicted_free: np.ndarray,
    predicted_gravity: np.ndarray,
    friction: float,
    max_pressure: float,
    unit: str = "MPa",
    multi: np.ndarray | None = None,
    cables: np.ndarray | None = None,
) -> Figure:
    """The Figure of `slope_limit_figure` (same arguments but the path), not yet written."""
    fig = Figure(figsize=(6.2 * len(contacts), 4.8))
    axes = fig.subplots(1, len(contacts), sharey=True, squeeze=False)
    for c, (ax, contact) in enumerate(zip(axes[0], contacts)):
        for k, kind in enumerate(kinds):
            col = _KIND_COLOUR.get(kind, "k")
            wide = {"stand": 5.0, "uphill": 2.0, "downhill": 1.6}.get(kind, 2.0)  # stand under downhill
            ax.plot(
                headings,
                simulated[k, c],
                "-",
                color=col,
                lw=wide,
                alpha=0.55 if kind == "stand" else 1.0,
                label=f"{kind}: simulated",
            )
            ax.plot(headings, predicted_free[k, c], "--", color=col, lw=1.2, label=f"{kind}: free workspace")
            ax.plot(
                headings, predicted_gravity[k, c], "o", color=col, ms=5, mfc="none", label=f"{kind}: gravity-aware grid"
            )
            if multi is not None and np.isfinite(multi[k, c]).any() and kind != "stand":
                ax.plot(headings, multi[k, c], "-.", color=col, lw=1.4, label=f"{kind}: any set of pairs")
        if cables is not None and np.isfinite(cables[c]).any():
            ax.plot(headings, cables[c], ":s", color="darkred", lw=1.6, ms=4, label="uphill: 24 cables one by one")
        ax.axhline(friction, color="0.4", lw=1, ls=":")
        ax.text(headings[0], friction + 0.4, f"friction angle {friction:.1f} deg", fontsize=8, color="0.3")
        ax.set_title(f"{contact} contact face")
        ax.set_xlabel("uphill heading in the face's support frame (deg)")
        ax.set_xticks(headings)
        # below 0 by a marker's size: the grid's 0 deg markers (cannot stand) drew cut in half
        ax.set_ylim(-0.04 * (friction + 4), friction + 4)
        ax.grid(alpha=0.3)
    axes[0, 0].set_ylabel("steepest slope (deg)")
    entries: dict = {}  # label: handle, over both panels (a line may be drawn in one only)
    for ax in axes[0]:
        for h, label in zip(*ax.get_legend_handles_labels()):
            entries.setdefault(label, h)
    ncol = 3 if len(entries) <= 9 else 4
    fig.legend(list(entries.values()), list(entries), loc="lower center", ncol=ncol, fontsize=8, frameon=False)
    levels = "pressures" if unit == "MPa" else "motor voltages"
    fig.suptitle(
        f"Slope limits: stand, roll uphill, roll downhill under control ({levels} up to {max_pressure:g} {unit})"
    )
    rows = -(-len(entries) // ncol)
    fig.tight_layout(rect=(0, 0.07 + 0.034 * rows, 1, 0.95))
    return fig


def tip_figure(
    path: str | os.PathLike,
    contacts: Sequence[str],
    slopes: np.ndarray,
    headings: np.ndarray,
    tip: np.ndarray,
    stood: np.ndarray,
    max_pressure: float,
    unit: str = "MPa",
) -> Path:
    """Least tipping pressure over the pairs (`unit`: MPa, or V for motor voltages) vs heading
    (deg), one line per slope, one panel per contact; tip (contact, slope, heading, pair), stood
    (contact, slope, heading)."""
    level = "pressure" if unit == "MPa" else "motor voltage"
    fig = Figure(figsize=(6.2 * len(contacts), 4.4))
    axes = fig.subplots(1, len(contacts), sharey=True, squeeze=False)
    cmap = colormaps["viridis"]
    for c, (ax, contact) in enumerate(zip(axes[0], contacts)):
        for i, a in enumerate(slopes):
            t = tip[c, i]
            least = np.array([np.nanmin(r) if np.isfinite(r).any() else np.nan for r in t])
            col = cmap(i / max(1, len(slopes) - 1))
            ax.plot(headings, least, "-o", color=col, ms=4, label=f"{a:g} deg")
            fall = ~stood[c, i]
            if fall.any():
                ax.plot(headings[fall], np.zeros(fall.sum()), "x", color=col, ms=8)
        ax.set_title(f"{contact} contact face (x: does not stand)")
        ax.set_xlabel("uphill heading in the face's support frame (deg)")
        ax.set_xticks(headings)
        ax.set_ylim(-0.2, max_pressure)
        ax.grid(alpha=0.3)
    axes[0, 0].set_ylabel(f"least tipping {level} over the pairs ({unit})")
    axes[0, -1].legend(title="slope", fontsize=8)
    fig.suptitle(f"Gravity-aware workspace: {level} at which the robot rolls")
    fig.tight_layout(rect=(0, 0, 1, 0.95))
    return save_figure(fig, path)
