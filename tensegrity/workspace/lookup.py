"""Workspace lookup (paper III.C step 2; docs/design.md §2, 5, 6).

`Workspace` holds the 20-face workspace as arrays (the contract of results/workspace.nc), with the
unactuated robot prepended as the 0 MPa point. `predict` places a face's curves in the support
frame of the robot's *current*, deformed support triangle and projects the CoG along gravity onto
the support plane (slopes, paper Fig. 10). No files here: `io.formats.read_workspace` reads one.
"""

from __future__ import annotations

import functools
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, replace

import numpy as np
from numpy.typing import ArrayLike

from ..physics import contact as ct
from ..physics import frames
from ..physics import topology as topo

__all__ = ["Workspace", "Prediction", "predict", "Face", "Action"]

Face = int | Sequence[int]  # a face: 1..20, or its three 1-based node numbers in any order
Action = Sequence[int]  # 1-based pairs driven together at the same pressure


@dataclass(frozen=True)
class Workspace:
    """levels (P,) MPa; cog (20, 12, P, 3) m and support (20, 12, P, 3, 3) m in each face's
    support frame (NaN where a pair was not swept); rest_cog (20, 3) m and rest_support
    (20, 3, 3) m: the unactuated symmetric robot in the same frames (the 0 MPa point).
    Optional measured two-pair curves (`with_two_pair`): combos (C, 2) 1-based pairs ascending,
    combo_cog (20, C, P, 3) m and combo_support (20, C, P, 3, 3) m, both pairs at each level.
    strut_length m: the robot's S (NaN: not known)."""

    levels: np.ndarray
    cog: np.ndarray
    support: np.ndarray
    rest_cog: np.ndarray
    rest_support: np.ndarray
    combos: np.ndarray | None = None
    combo_cog: np.ndarray | None = None
    combo_support: np.ndarray | None = None
    strut_length: float = float("nan")

    def __post_init__(self):
        lv = np.asarray(self.levels, float)
        if lv.ndim != 1 or lv.size < 1 or np.any(np.diff(lv) <= 0) or lv[0] <= 0:
            raise ValueError("workspace levels must be positive, strictly increasing MPa")
        P = lv.size
        shapes = {"cog": (20, 12, P, 3), "support": (20, 12, P, 3, 3), "rest_cog": (20, 3), "rest_support": (20, 3, 3)}
        for name, shape in shapes.items():
            if np.shape(getattr(self, name)) != shape:
                raise ValueError(f"workspace {name} must have shape {shape}, got {np.shape(getattr(self, name))}")
        for name in ("cog", "support"):  # NaN: a pair not swept; never inf
            if np.any(np.isinf(getattr(self, name))):
                raise ValueError(f"workspace {name} holds infinite values")
        for name in ("rest_cog", "rest_support"):
            if not np.all(np.isfinite(getattr(self, name))):
                raise ValueError(f"workspace {name} must be finite")
        object.__setattr__(self, "levels", lv)

    @classmethod
    def from_arrays(cls, levels: ArrayLike, cog: ArrayLike, support: ArrayLike, strut_length: float = 0.5) -> Workspace:
        """From cog (20, 12, P, 3) m and support (20, 12, P, 3, 3) m at `levels` (P,) MPa; the
        0 MPa point is the symmetric robot of strut length `strut_length` m
        (`frames.rest_frame`)."""
        rest = [frames.rest_frame(f, strut_length) for f in range(1, topo.N_FACES + 1)]
        return cls(
            np.asarray(levels, float),
            np.asarray(cog, float),
            np.asarray(support, float),
            np.stack([r[0] for r in rest]),
            np.stack([r[1] for r in rest]),
            strut_length=float(strut_length),
        )

    def with_two_pair(self, combos: ArrayLike, levels: ArrayLike, cog: ArrayLike, support: ArrayLike) -> Workspace:
        """This workspace with the measured two-pair curves of the two-pair workspace
        (`io.two_pair_formats.read_two_pair`): combos (C, 2) 1-based, levels (L,) MPa, cog
        (20, C, L, L, 3) m and support (20, C, L, L, 3, 3) m, [f, c, i, j] = face f+1 with
        combos[c, 0] at levels[i] and combos[c, 1] at levels[j]. The diagonal (equal pressures)
        is interpolated linearly onto this workspace's levels, from the unactuated robot (0 MPa)
        below levels[0]; a level above levels[-1] is NaN (that combination on that face then
        falls back to superposition, see `curve`)."""
        cb, lv = np.asarray(combos, int), np.asarray(levels, float)
        cog, sup = np.asarray(cog, float), np.asarray(support, float)
        C, L = len(cb), lv.size
        if cb.shape != (C, 2) or np.any(cb[:, 0] >= cb[:, 1]) or cb.min(initial=1) < 1 or cb.max(initial=12) > 12:
            raise ValueError(f"two-pair combos must be (C, 2) ascending pairs 1..12, got shape {cb.shape}")
        if lv.ndim != 1 or L < 2 or np.any(np.diff(lv) <= 0):
            raise ValueError("two-pair levels must be at least two strictly increasing MPa")
        for name, a, shape in (("cog", cog, (20, C, L, L, 3)), ("support", sup, (20, C, L, L, 3, 3))):
            if a.shape != shape:
                raise ValueError(f"two-pair {name} must have shape {shape}, got {a.shape}")
        # the unactuated robot is the 0 MPa point of every combination: levels below the
        # first two-pair level are interpolated from it
        k, lv = np.arange(L), np.concatenate([[0.0], lv])
        x = self.levels
        j = np.clip(np.searchsorted(lv, x) - 1, 0, L - 1)  # linear weights onto our levels
        w = (x - lv[j]) / (lv[j + 1] - lv[j])
        on = []
        for a, rest in ((cog, self.rest_cog), (sup, self.rest_support)):
            d = np.concatenate(
                [np.broadcast_to(rest[:, None, None], (20, C, 1) + rest.shape[1:]), a[:, :, k, k]], axis=2
            )  # (20, C, L+1, ...): both at lv
            wb = w.reshape((-1,) + (1,) * (d.ndim - 3))
            v = d[:, :, j] * (1 - wb) + d[:, :, j + 1] * wb
            v[:, :, x > lv[-1] + 1e-12] = np.nan
            on.append(v)
        return replace(self, combos=cb, combo_cog=on[0], combo_support=on[1])

    def measured(self, face: int, action: Action) -> int | None:
        """Index of the measured two-pair curve of `action` (two 1-based pairs) on 1-based
        `face`, None if there is none (no two-pair data, or NaN anywhere along it)."""
        if self.combos is None or len(action) != 2:
            return None
        k = self._combo_index.get(tuple(sorted(int(q) for q in action)))
        return k if k is not None and self._combo_complete[face - 1, k] else None

    @functools.cached_property
    def _combo_index(self) -> dict[tuple[int, int], int]:
        """(a, b) a < b -> row of `combos` (the first, if listed twice)."""
        out: dict[tuple[int, int], int] = {}
        for k, c in enumerate(self.combos):
            out.setdefault(tuple(sorted(int(q) for q in c)), k)
        return out

    @functools.cached_property
    def _combo_complete(self) -> np.ndarray:
        """(20, n) whether a combination's measured curve is finite everywhere on a face."""
        return np.isfinite(self.combo_cog).reshape(*self.combo_cog.shape[:2], -1).all(axis=2)

    @property
    def max_pressure(self) -> float:
        """The highest swept level, MPa: where escalation stops."""
        return float(self.levels[-1])

    @property
    def pressures(self) -> np.ndarray:
        """(P + 1,) MPa: 0 followed by the levels."""
        return np.concatenate([[0.0], self.levels])

    def pairs(self, face: int) -> np.ndarray:
        """1-based pairs with a complete curve on 1-based `face`."""
        ok = np.all(np.isfinite(self.cog[face - 1]), axis=(1, 2))
        return np.flatnonzero(ok) + 1

    def actions(self, face: int) -> list[tuple[int, ...]]:
        """The actions measured on 1-based `face`: the swept single pairs, then the two-pair
        combinations with a measured curve there (`measured`)."""
        singles = [(int(p),) for p in self.pairs(face)]
        combos = [] if self.combos is None else [tuple(int(q) for q in c) for c in self.combos]
        return singles + [c for c in combos if self.measured(face, c) is not None]

    def curve(self, face: int, actions: Iterable[Action]) -> tuple[np.ndarray, np.ndarray]:
        """CoG (A, P+1, 3) m and support (A, P+1, 3, 3) m in the support frame of 1-based
        `face` for each of A actions (tuples of 1-based pairs driven at the same pressure), the
        rest state first. Two pairs take the measured two-pair curve (`with_two_pair`) where
        there is one; otherwise (fallback) pairs are superposed: rest + sum of the single
        displacements (an estimate that underestimates the shift: 46 mm for 58 mm measured, #10
        with #6 on (9,10,12)). The arrays are read-only: kept for the next call with the same
        face and actions (a planner asks again for every pose)."""
        acts = tuple(tuple(int(q) for q in act) for act in actions)
        key = (int(face), acts)
        if key not in self._curves:
            self._curves[key] = self._curve(int(face), acts)
        return self._curves[key]

    @functools.cached_property
    def _curves(self) -> dict:
        """(face, actions) -> `curve`."""
        return {}

    def _curve(self, face: int, actions: tuple[tuple[int, ...], ...]) -> tuple[np.ndarray, np.ndarray]:
        """`curve`, computed."""
        f = face - 1
        rest_cog, rest_support = self.rest_cog[f], self.rest_support[f]
        cog = np.concatenate([np.broadcast_to(rest_cog, (12, 1, 3)), self.cog[f]], axis=1)
        support = np.concatenate([np.broadcast_to(rest_support, (12, 1, 3, 3)), self.support[f]], axis=1)
        out_cog, out_support = [], []
        for act in actions:
            c = self.measured(face, act)
            if c is not None:
                out_cog.append(np.concatenate([rest_cog[None], self.combo_cog[f, c]]))
                out_support.append(np.concatenate([rest_support[None], self.combo_support[f, c]]))
                continue
            idx = np.asarray(act, int) - 1
            out_cog.append(rest_cog + np.sum(cog[idx] - rest_cog, axis=0))
            out_support.append(rest_support + np.sum(support[idx] - rest_support, axis=0))
        n = self.levels.size + 1
        out = (
            np.reshape(out_cog, (len(out_cog), n, 3)),
            np.reshape(out_support, (len(out_support), n, 3, 3)),
        )  # A = 0: empty arrays
        for a in out:
            a.flags.writeable = False
        return out


@dataclass(frozen=True)
class Prediction:
    """Workspace curves of A actions placed on the current support triangle, n = P + 1 samples.
    pressure (n,) MPa; cog (A, n, 3) m and projection (A, n, 3) m (the CoG moved along gravity
    onto the support plane), world frame; projection_2d (A, n, 2) m and support (A, n, 3, 2) m:
    the projection and the support triangle in the face's support frame (in-plane x, y);
    margin (A, n) m (positive inside); edge_dist (A, n, 3) m signed distances to the edge lines
    (edge k joins corners k, k+1)."""

    pressure: np.ndarray
    cog: np.ndarray
    projection: np.ndarray
    projection_2d: np.ndarray
    support: np.ndarray
    margin: np.ndarray
    edge_dist: np.ndarray


_UP = np.array([0.0, 0.0, 1.0])  # the support plane's normal in its own frame


def predict(workspace: Workspace, face: Face, nodes: ArrayLike, actions: Iterable[Action]) -> Prediction:
    """Where the workspace puts the CoG projection for `actions` (tuples of 1-based pairs) on
    `face` (1..20 or three node numbers), in the support frame of the current triangle of
    `nodes` (12, 3) m, projected along gravity (paper Fig. 10)."""
    f = topo.face_number(face)
    p = ct.check_nodes(nodes)
    origin, rot = frames.face_frame(p, f)
    gravity = rot @ ct.GRAVITY_DIR  # in the support frame
    if gravity[2] > -1e-6:
        raise ValueError(
            f"face {topo.face_label(f)} is not below the robot: gravity does not press it onto its support"
        )
    cog, support = workspace.curve(f, actions)
    proj = ct.project_along_gravity(cog, np.zeros(3), _UP, gravity / np.linalg.norm(gravity))
    margin = frames.margin_2d(proj[..., :2], support[..., :2])
    dist = frames.edge_distances(proj[..., :2], support[..., :2])
    return Prediction(
        workspace.pressures, origin + cog @ rot, origin + proj @ rot, proj[..., :2], support[..., :2], margin, dist
    )
