"""The simulated counterpart of the paper's Fig. 12 (issue 31): the prototype (twisted-string
actuators) at the start, after roll 1 and after roll 2 of section IV.B, the face it stands on
shaded and numbered, the driven pair's cables in the pair's colour; below, the voltages on the
two pairs and the face it rests on over time. Drawn from arrays off-screen (matplotlib's Agg
canvas), written atomically (`files.save_figure`)."""

from __future__ import annotations

import os
from collections.abc import Sequence

import numpy as np
from matplotlib.figure import Figure

from ..physics import topology as topo
from .files import save_figure
from .scene import CABLE_COLOUR, PAIR_COLOURS, STRUT_COLOURS

__all__ = ["fig_prototype"]


def _robot(ax, nodes: np.ndarray, face: int, pair: int, title: str, half: float) -> None:
    """One snapshot: struts, cables (the pair's in its colour), the resting face shaded with its
    nodes numbered, on a ground square of half-width `half` m about the CoG."""
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection

    ax.computed_zorder = False  # drawn in this order: the ground, the face, cables, struts, numbers
    c = nodes.mean(axis=0)
    g = np.array([[-1, -1], [1, -1], [1, 1], [-1, 1]]) * half + c[:2]
    ax.add_collection3d(Poly3DCollection([np.c_[g, np.zeros(4)]], color="0.9", zorder=0))
    hot = set(topo.PAIR_CABLES[pair - 1]) if pair else set()
    for k, (a, b) in enumerate(topo.CABLES):
        colour, lw = (PAIR_COLOURS[pair - 1], 2.6) if k in hot else (CABLE_COLOUR, 0.8)
        ax.plot(*nodes[[a, b]].T, color=colour, lw=lw, zorder=2 + (k in hot))
    for k, (a, b) in enumerate(topo.STRUTS):
        ax.plot(*nodes[[a, b]].T, color=STRUT_COLOURS[k], lw=4.0, solid_capstyle="round", zorder=4)
    if face:
        tri = np.asarray(topo.FACES[face - 1])
        ax.add_collection3d(Poly3DCollection([nodes[tri]], color="#e6194b", alpha=0.45, zorder=1))
        for n in tri:
            p = nodes[n] + 0.25 * (nodes[n] - c) * [1, 1, 0]
            ax.text(*p, str(n + 1), fontsize=10, weight="bold", ha="center", va="center", zorder=5)
    top = 1.9 * float(c[2])
    ax.set(xlim=(c[0] - half, c[0] + half), ylim=(c[1] - half, c[1] + half), zlim=(0, top))
    ax.set_box_aspect((2 * half, 2 * half, top), zoom=1.1)
    ax.view_init(elev=18, azim=-60)
    ax.set_axis_off()
    ax.set_title(title, fontsize=10)


def fig_prototype(
    path: str | os.PathLike,
    nodes: np.ndarray,
    faces: Sequence[int],
    pairs: Sequence[int],
    titles: Sequence[str],
    t: np.ndarray,
    volts: np.ndarray,
    volt_pairs: Sequence[int],
    face_t: np.ndarray,
    title: str,
) -> dict:
    """Three snapshots nodes (3, 12, 3) m, each on its face (1-based, 0: none) with its driven
    pair (0: none) cables highlighted, under `titles`; below them the voltages (T, 2) V of
    `volt_pairs` and the resting face (T,) (0: none) over t (T,) s. Returns what it drew."""
    nodes, t, volts, face_t = (np.asarray(a) for a in (nodes, t, volts, face_t))
    fig = Figure(figsize=(12.0, 8.2), layout="constrained")
    grid = fig.add_gridspec(3, 3, height_ratios=[2.4, 1.0, 0.8])
    half = 1.08 * float(np.abs(nodes[..., :2] - nodes.mean(axis=1, keepdims=True)[..., :2]).max())
    for k in range(3):
        _robot(fig.add_subplot(grid[0, k], projection="3d"), nodes[k], faces[k], pairs[k], titles[k], half)
    av = fig.add_subplot(grid[1, :])
    for j, p in enumerate(volt_pairs):
        av.plot(t, volts[:, j], color=PAIR_COLOURS[p - 1], lw=1.6, label=f"#{p}")
    av.set(ylabel="voltage (V)", xlim=(t[0], t[-1]), ylim=(0, max(1.0, 1.15 * float(volts.max()))))
    av.legend(loc="upper right", fontsize=9)
    af = fig.add_subplot(grid[2, :], sharex=av)
    shown = [int(f) for f in dict.fromkeys(face_t.tolist())]  # in order of appearance
    order = sorted(shown, key=lambda f: (f != 0, shown.index(f)))
    level = {f: i for i, f in enumerate(order)}
    af.step(t, [level[int(f)] for f in face_t], where="post", color="0.2", lw=1.6)
    af.set_yticks(range(len(order)), [topo.face_label(f) if f else "none" for f in order], fontsize=8)
    af.set(xlabel="time from the first roll's voltage (s)", ylabel="resting face", ylim=(-0.5, len(order) - 0.5))
    for a in (av, af):
        a.grid(alpha=0.3)
    fig.suptitle(title, fontsize=11)
    save_figure(fig, path)
    return {"path": str(path), "title": title, "faces": [int(f) for f in faces], "face_labels": order}
