"""Figures of a design study, drawn from arrays off-screen (matplotlib's Agg canvas, no display):
sensitivity indices with their 95 % intervals, the response map over two parameters, and the
robustness of the paper's roll sequence. Each PNG is written atomically (`files.save_figure`).
"""

from __future__ import annotations

import os
from collections.abc import Mapping, Sequence
from pathlib import Path

import numpy as np
from matplotlib.figure import Figure

from .files import save_figure

_LABEL = {
    "saltelli": "Sobol indices (Saltelli design)",
    "morris": "Morris elementary effects",
    "delta": "delta and S1 indices (SALib delta)",
}
_CONF = {"S1": "S1_conf", "ST": "ST_conf", "mu_star": "mu_star_conf", "delta": "delta_conf"}


def sensitivity_bars(
    parameters: Sequence[str],
    outputs: Sequence[str],
    method: str,
    indices: Mapping[str, np.ndarray],
    path: str | os.PathLike,
) -> Path:
    """One panel per output: bars of each index (arrays (outputs, parameters)) per parameter,
    with the 95 % confidence interval as error bars. NaN indices (study not run in full) are
    said in the title."""
    names = [n for n in indices if not n.endswith("_conf")]
    fig = Figure(figsize=(4.2 * len(outputs) + 0.6, 4.0), layout="constrained")
    axs = fig.subplots(1, len(outputs), squeeze=False)[0]
    x = np.arange(len(parameters))
    w = 0.8 / len(names)
    for o, ax in enumerate(axs):
        for j, n in enumerate(names):
            val = np.asarray(indices[n])[o]
            err = np.asarray(indices[_CONF[n]])[o] if _CONF.get(n) in indices else None
            ax.bar(x + (j - (len(names) - 1) / 2) * w, np.nan_to_num(val), w, yerr=err, capsize=3, label=n)
        ax.set_xticks(x, [p.replace("_", "\n") for p in parameters])
        missing = np.isnan(np.asarray(indices[names[0]])[o]).all()
        ax.set_title(f"{outputs[o]}" + (" (not computed: partial study)" if missing else ""), fontsize=10)
        ax.axhline(0, color="0.5", lw=0.8)
        ax.legend(fontsize=8)
    axs[0].set_ylabel("index (error bars: 95 % confidence interval)")
    fig.suptitle(f"Sensitivity of the study outputs: {_LABEL.get(method, method)}", fontsize=11)
    return save_figure(fig, path)


def response_map(
    p1: np.ndarray,
    p2: np.ndarray,
    objective: np.ndarray,
    min_margin: np.ndarray,
    name1: tuple[str, str],
    name2: tuple[str, str],
    best: np.ndarray,
    path: str | os.PathLike,
) -> Path:
    """Two panels over the designs' values of two parameters (name, units): the objective (MPa,
    lowest tipping pressure of the best pair; grey crosses: a pair falls at the reference
    pressure) and the smallest margin (mm) at the reference pressure; the best designs ringed."""
    fig = Figure(figsize=(10.0, 4.4), layout="constrained")
    axs = fig.subplots(1, 2)
    ok = np.isfinite(objective)
    panels = (
        (objective, "objective: lowest tipping pressure, all standing (MPa)", "viridis", ok),
        (1000 * min_margin, "smallest margin at the reference pressure (mm)", "RdBu", np.ones_like(ok)),
    )
    for ax, (val, title, cmap, sel) in zip(axs, panels):
        if sel.sum():
            kw = {}
            if cmap == "RdBu":
                lim = float(np.nanmax(np.abs(val))) or 1.0
                kw = {"vmin": -lim, "vmax": lim}
            sc = ax.scatter(p1[sel], p2[sel], c=val[sel], cmap=cmap, s=36, edgecolors="k", linewidths=0.3, **kw)
            fig.colorbar(sc, ax=ax, shrink=0.9)
        if (~sel).any():
            ax.scatter(p1[~sel], p2[~sel], marker="x", color="0.5", s=30, label="not all pairs standing")
            ax.legend(fontsize=8, loc="best")
        ax.set_xlabel(f"{name1[0]} ({name1[1]})")
        ax.set_ylabel(f"{name2[0]} ({name2[1]})")
        ax.set_title(title, fontsize=10)
    if len(best):
        axs[0].scatter(p1[best], p2[best], s=160, facecolors="none", edgecolors="red", linewidths=1.5)
        axs[0].annotate(
            "best", (p1[best[0]], p2[best[0]]), xytext=(6, 6), textcoords="offset points", color="red", fontsize=9
        )
    fig.suptitle(f"Response over {name1[0]} and {name2[0]} ({len(p1)} designs)", fontsize=11)
    return save_figure(fig, path)


def robustness(
    success: np.ndarray,
    tip: np.ndarray,
    X: np.ndarray,
    names: Sequence[tuple[str, str]],
    rate: tuple[float, float, float],
    path: str | os.PathLike,
) -> Path:
    """rate: success rate and its 95 % interval (low, high). Left: histograms of the grounded
    tipping pressures (N, 2) MPa of the two rolls (#10, #11); right: the samples over the first
    two uncertain parameters, success (o) or failure (x)."""
    fig = Figure(figsize=(10.0, 4.2), layout="constrained")
    a, b = fig.subplots(1, 2)
    for r, (label, color) in enumerate(
        (("roll 1: #10, (9,10,12) -> (10,11,12)", "C0"), ("roll 2: #11, (10,11,12) -> (6,10,11)", "C1"))
    ):
        t = tip[:, r][np.isfinite(tip[:, r])]
        if t.size:
            a.hist(t, bins=max(5, min(20, t.size // 2)), alpha=0.6, color=color, label=f"{label} (n={t.size})")
    a.set_xlabel("grounded tipping pressure (MPa)")
    a.set_ylabel("samples")
    a.legend(fontsize=8)
    a.set_title("tipping pressures of the paper's roll sequence", fontsize=10)
    ok = np.asarray(success, bool)
    j = 1 if X.shape[1] > 1 else 0
    b.scatter(X[ok, 0], X[ok, j], marker="o", color="C2", s=28, label=f"success ({ok.sum()})")
    b.scatter(X[~ok, 0], X[~ok, j], marker="x", color="C3", s=36, label=f"failure ({(~ok).sum()})")
    b.set_xlabel(f"{names[0][0]} ({names[0][1]})")
    b.set_ylabel(f"{names[j][0]} ({names[j][1]})")
    b.legend(fontsize=8, loc="best", framealpha=0.9)
    b.set_title("samples: did the sequence succeed?", fontsize=10)
    fig.suptitle(
        f"Robustness of the paper's roll sequence: success rate {100 * rate[0]:.0f} % "
        f"(95 % interval {100 * rate[1]:.0f}-{100 * rate[2]:.0f} %), {ok.size} samples",
        fontsize=11,
    )
    return save_figure(fig, path)
