"""Terrains made of triangles: none (free mode), a plane (flat or a constant slope), or a
regular height field split into two triangles per cell (uneven ground).

The NumPy query here (`height`, `height_and_normal`) and the kernel's (kernel/contact.py
`terrain_contact`) find the same triangle by the same rule and give its exact normal
(tests/physics/test_twins.py pins them)."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike

KINDS = {"none": 0, "plane": 1, "heightfield": 2}
SPEC_FIELD_SIZE = 12.0  # m, side of the height field that a `random:` spec builds
SPEC_HELP = "flat | none | slope:ANGLE[:AZIMUTH] (deg) | random:SEED[:AMPLITUDE] (m)"


@dataclass(frozen=True)
class Terrain:
    """kind: 'none' | 'plane' | 'heightfield'. A plane is n . p = offset (n unit, up).
    A height field has heights (nx+1, ny+1) m at x = x0 + i*spacing, y = y0 + j*spacing. Cell
    (i, j) holds the point at (s, t) = ((x - x0)/spacing - i, (y - y0)/spacing - j) in [0, 1)^2;
    its lower triangle, corners (i, j), (i+1, j), (i, j+1), holds s + t <= 1 (its edges and
    diagonal included), the upper triangle, corner (i+1, j+1), the rest."""

    kind: str = "plane"
    normal: np.ndarray = field(default_factory=lambda: np.array([0.0, 0.0, 1.0]))
    offset: float = 0.0
    origin: tuple = (0.0, 0.0)
    spacing: float = 1.0
    heights: np.ndarray = field(default_factory=lambda: np.zeros((2, 2)))

    def __post_init__(self):
        if self.kind not in KINDS:
            raise ValueError(f"unknown terrain kind {self.kind!r}: use one of {sorted(KINDS)}")
        n = np.asarray(self.normal, dtype=float)
        if n.shape != (3,) or not np.all(np.isfinite(n)) or n[2] <= 0:
            raise ValueError(f"terrain normal must be a finite 3-vector with positive z, got {self.normal!r}")
        object.__setattr__(self, "normal", n / np.linalg.norm(n))
        h = np.asarray(self.heights, dtype=float)
        if h.ndim != 2 or min(h.shape) < 2 or not np.all(np.isfinite(h)):
            raise ValueError("terrain heights must be a finite 2-D array of at least 2 x 2 values")
        if not (np.isfinite(self.spacing) and self.spacing > 0):
            raise ValueError(f"terrain spacing must be positive, got {self.spacing!r}")
        object.__setattr__(self, "heights", np.ascontiguousarray(h))

    @classmethod
    def none(cls) -> Terrain:
        return cls(kind="none")

    @classmethod
    def flat(cls, z: float = 0.0) -> Terrain:
        return cls(kind="plane", offset=float(z))

    @classmethod
    def slope(cls, angle_deg: float, azimuth_deg: float = 0.0) -> Terrain:
        """A plane through the origin rising by angle_deg toward the azimuth (deg from +x)."""
        if not -60 < angle_deg < 60:
            raise ValueError(f"slope angle {np.asarray(angle_deg).tolist()!r} deg out of range (-60, 60)")
        a, b = np.radians(angle_deg), np.radians(azimuth_deg)
        n = np.array([-np.sin(a) * np.cos(b), -np.sin(a) * np.sin(b), np.cos(a)])
        return cls(kind="plane", normal=n, offset=0.0)

    @classmethod
    def random(cls, seed: int, size: float = 6.0, spacing: float = 0.25, amplitude: float = 0.03) -> Terrain:
        """A seeded random height field of side `size` m centred at the origin, heights of
        standard deviation about `amplitude` m (smoothed white noise)."""
        rng = np.random.default_rng(seed)
        n = int(round(size / spacing)) + 1
        z = rng.normal(size=(n + 2, n + 2))
        z = (z[:-2, 1:-1] + z[2:, 1:-1] + z[1:-1, :-2] + z[1:-1, 2:] + 2 * z[1:-1, 1:-1]) / 6
        z *= amplitude / max(z.std(), 1e-12)
        return cls(kind="heightfield", origin=(-size / 2, -size / 2), spacing=spacing, heights=z)

    def _cell(self, x: np.ndarray, y: np.ndarray) -> tuple[np.ndarray, ...]:
        """The height-field cell under world points (x, y): inside the field (bool), (s, t) in
        the cell, `low` (the lower triangle: s + t <= 1, class docstring), and the corner
        heights z00, z10, z01, z11 (m); the values off the field are meaningless."""
        z = self.heights
        u, v = (x - self.origin[0]) / self.spacing, (y - self.origin[1]) / self.spacing
        i, j = np.floor(u).astype(int), np.floor(v).astype(int)
        ok = (i >= 0) & (j >= 0) & (i < z.shape[0] - 1) & (j < z.shape[1] - 1)
        i, j = np.minimum(np.maximum(i, 0), z.shape[0] - 2), np.minimum(np.maximum(j, 0), z.shape[1] - 2)
        s, t = u - i, v - j
        k, ny, zf = i * z.shape[1] + j, z.shape[1], z.ravel()  # the cell's corners, each read once
        return ok, s, t, s + t <= 1, zf[k], zf[k + ny], zf[k + 1], zf[k + ny + 1]

    def height(self, x: ArrayLike, y: ArrayLike) -> np.ndarray:
        """Terrain height (m) under world points (x, y); NaN off a height field."""
        x, y = np.asarray(x, float), np.asarray(y, float)
        if self.kind == "none":
            return np.full(np.broadcast(x, y).shape, -np.inf)
        if self.kind == "plane":
            n = self.normal
            return (self.offset - n[0] * x - n[1] * y) / n[2]
        return self._height(*self._cell(x, y))

    @staticmethod
    def _height(ok, s, t, low, z00, z10, z01, z11) -> np.ndarray:
        """`height` in the cells of `_cell`: the plane of the triangle through its corners."""
        h_low = z00 + s * (z10 - z00) + t * (z01 - z00)
        h_up = z11 + (1 - s) * (z01 - z11) + (1 - t) * (z10 - z11)
        return np.where(ok, np.where(low, h_low, h_up), np.nan)

    def normal_at(self, x: ArrayLike, y: ArrayLike) -> np.ndarray:
        """Unit upward normal (..., 3) of the terrain triangle under (x, y)."""
        return self.height_and_normal(x, y, height=False)[1]

    def height_and_normal(
        self, x: ArrayLike, y: ArrayLike, height: bool = True
    ) -> tuple[np.ndarray | None, np.ndarray]:
        """`height` (m; None if not asked for) and `normal_at` (..., 3) under world points
        (x, y), from one query of the cells: on a height field the exact normal of the triangle
        that `height` interpolates in, computed as kernel/contact.py `terrain_contact` does (NaN
        off the field)."""
        x, y = np.asarray(x, float), np.asarray(y, float)
        if self.kind != "heightfield":
            n = np.broadcast_to(self.normal, np.broadcast(x, y).shape + (3,)).copy()
            return (self.height(x, y) if height else None), n
        cell = self._cell(x, y)
        ok, _, _, low, z00, z10, z01, z11 = cell
        h = self.spacing
        z0 = np.where(low, z00, z11)  # the corner of the triangle's right angle
        ax = np.where(low, -h * (z10 - z0), h * (z01 - z0))
        ay = np.where(low, -h * (z01 - z0), h * (z10 - z0))
        az = h * h
        nn = np.sqrt(ax * ax + ay * ay + az * az)
        n = np.stack([ax / nn, ay / nn, np.broadcast_to(az / nn, nn.shape)], axis=-1)
        n[~ok] = np.nan
        return (self._height(*cell) if height else None), n

    def describe(self) -> str:
        """The terrain in words (figure titles): "a 10 deg slope" (a tilted plane), "flat
        ground", "uneven terrain (height field)" or "no ground"."""
        if self.kind == "plane":
            slope = float(np.degrees(np.arccos(min(1.0, abs(float(self.normal[2]))))))
            return f"a {slope:.3g} deg slope" if slope > 0.05 else "flat ground"
        return {"heightfield": "uneven terrain (height field)", "none": "no ground"}.get(
            self.kind, f"{self.kind} ground"
        )

    def incline(self, x: ArrayLike, y: ArrayLike, even: float = 1.0) -> float:
        """Tilt from the horizontal, deg, of the ground under the points (x, y) m, where it is one
        plane there (their normals agree within `even` deg); NaN where it is uneven."""
        n = self.normal_at(x, y).reshape(-1, 3)
        m = n.mean(axis=0) / np.linalg.norm(n.mean(axis=0))
        if np.degrees(np.arccos(np.clip(n @ m, -1.0, 1.0))).max() > even:
            return float("nan")
        return float(np.degrees(np.arccos(np.clip(m[2], -1.0, 1.0))))

    def triangles(self, extent: float = 2.0, centre: ArrayLike = (0.0, 0.0)) -> tuple[np.ndarray, np.ndarray]:
        """Vertices (V, 3) and triangles (T, 3) of the terrain mesh, for drawing. A plane is
        drawn as a square of half-side `extent` m around `centre`."""
        if self.kind == "heightfield":
            nx, ny = self.heights.shape
            gx = self.origin[0] + self.spacing * np.arange(nx)
            gy = self.origin[1] + self.spacing * np.arange(ny)
            X, Y = np.meshgrid(gx, gy, indexing="ij")
            verts = np.stack([X, Y, self.heights], axis=-1).reshape(-1, 3)
        else:
            c = np.asarray(centre, float)
            X, Y = np.meshgrid(c[0] + extent * np.array([-1, 1]), c[1] + extent * np.array([-1, 1]), indexing="ij")
            nx = ny = 2
            verts = np.stack([X, Y, self.height(X, Y) if self.kind == "plane" else np.zeros_like(X)], -1).reshape(-1, 3)
        idx = np.arange(nx * ny).reshape(nx, ny)
        a, b, c_, d = idx[:-1, :-1].ravel(), idx[1:, :-1].ravel(), idx[:-1, 1:].ravel(), idx[1:, 1:].ravel()
        tris = np.concatenate([np.stack([a, b, c_], 1), np.stack([d, c_, b], 1)])
        return verts, tris

    def packed(self) -> tuple[int, np.ndarray, np.ndarray]:
        """(kind code, meta (7,) = n, offset, x0, y0, spacing, heights) for the kernel."""
        meta = np.array([*self.normal, self.offset, self.origin[0], self.origin[1], self.spacing])
        return KINDS[self.kind], meta, self.heights


def from_spec(spec: str) -> Terrain:
    """The one reading of a terrain written as text (command line): `flat`, `none`,
    `slope:ANGLE[:AZIMUTH]` (deg) or `random:SEED[:AMPLITUDE]` (m; a SPEC_FIELD_SIZE m field of
    0.25 m cells). ValueError naming the spec otherwise."""
    kind, _, rest = str(spec).strip().partition(":")
    parts = rest.split(":") if rest else []
    try:
        args = [float(a) for a in parts]
    except ValueError:
        raise ValueError(f"terrain {spec!r}: {rest!r} is not a list of numbers; use {SPEC_HELP}") from None
    if not all(np.isfinite(args)):
        raise ValueError(f"terrain {spec!r}: values must be finite")
    if kind == "flat" and not args:
        return Terrain.flat()
    if kind == "none" and not args:
        return Terrain.none()
    if kind == "slope" and 1 <= len(args) <= 2:
        return Terrain.slope(*args)
    if kind == "random" and 1 <= len(args) <= 2:
        if not args[0].is_integer() or args[0] < 0:
            raise ValueError(f"terrain {spec!r}: the seed must be a whole number >= 0")
        if len(args) == 2 and not args[1] > 0:
            raise ValueError(f"terrain {spec!r}: the amplitude must be positive (m)")
        return Terrain.random(int(args[0]), size=SPEC_FIELD_SIZE, **({"amplitude": args[1]} if len(args) == 2 else {}))
    raise ValueError(f"terrain {spec!r}: use {SPEC_HELP}")
