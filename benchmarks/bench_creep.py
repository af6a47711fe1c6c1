"""What `averaging_error` does not see: a level still creeping at the end of its hold (issue 31).

`workspace.nominal.averaging_error` measures the oscillation left in the averaging window (a
drift of r m/s reads r W / 8 over a window of W s). It cannot see how far the CoG still has to
go after the window: a level still moving at its end (the twisted strings at a voltage just
above the gears' friction; before stop 45, every loaded motor, whose friction was linear below
omega_eps and crept toward its frictionless balance G V = f h: docs/benchmarks.md).

Per sweep file of SWEEPS (`results/sweeps/{contact}/pairNN.nc`) and level: `averaging_error` (mm),
the CoG's speed over the window (mm/s, least squares), the path moved over the level's second half
(mm), and the motion left after the window by geometric extrapolation of the window's thirds
(Aitken); for the first --history rows, the speed between the mean CoGs of successive twelfths of
the level, the check of the extrapolation. With m1, m2, m3 the thirds' mean CoGs, d1 = m2 - m1, d2 = m3 - m2 and
q = (d2 . d1) / |d1|^2, left = |d2| q / (1 - q) for 0 < q < 1, "inf" for q >= 1 (not decaying
within the window), "nan" for q <= 0 (the drift reverses: an oscillation). The extrapolation
assumes a geometric decay; its own error is not estimated (the speeds over the whole level are
the check: docs/benchmarks.md, "What averaging_error does not see"). It means something only where
the drift dominates the oscillation: column drift/osc, |m3 - m1| / averaging_error, is 16/3 for a
steady drift (which reads r W / 8); above 4 a level counts as drifting. On the pneumatic sweeps
the extrapolation is noise. Prints figures; asserts nothing."""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np
import xarray as xr

from tensegrity.workspace import nominal

DRIFT = 4.0  # drift/osc above which a level counts as drifting (a steady drift reads 16/3)


def level_creep(t: np.ndarray, level: np.ndarray, cog: np.ndarray, k: int, hold: float, discard: float) -> dict:
    """Figures of level k (module docstring): t (T,) s, level (T,) index, cog (T, 3) m."""
    sel = nominal.window(t, level, k, hold, discard)
    x, tw = cog[sel], t[sel]
    n = x.shape[0] // 3
    m1, m2, m3 = (x[i * n : (i + 1) * n].mean(0) for i in range(3))
    d1, d2 = m2 - m1, m3 - m2
    q = float(d2 @ d1 / (d1 @ d1)) if d1 @ d1 > 0 else np.nan
    left = float(np.linalg.norm(d2)) * q / (1.0 - q) if 0.0 < q < 1.0 else (np.inf if q >= 1.0 else np.nan)
    speed = float(np.linalg.norm(np.polyfit(tw - tw.mean(), x, 1)[0]))
    every = level == k
    tk = t[every] - t[every][0]
    last = tk >= tk.max() / 2.0
    path = float(np.linalg.norm(np.diff(cog[every][last], axis=0), axis=1).sum())
    ae = float(nominal.averaging_error(t, level, cog, int(level.max()) + 1, hold, discard)[k])
    edges = np.linspace(0.0, tk.max(), 13)  # the mean CoG of 12 equal parts of the level
    means = np.array([cog[every][(tk >= a) & (tk <= b)].mean(0) for a, b in zip(edges[:-1], edges[1:])])
    history = np.linalg.norm(np.diff(means, axis=0), axis=1) / (edges[1] - edges[0])
    ratio = float(np.linalg.norm(m3 - m1)) / ae if ae > 0 else np.nan
    return {"history": history, "ae": ae, "speed": speed, "path": path, "left": left, "ratio": ratio}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("sweeps", type=Path, help="folder of the sweep files (results/sweeps)")
    ap.add_argument("--discard", type=float, default=None, help="s (default: discard_s of the nominal files)")
    ap.add_argument("--top", type=int, default=20, help="rows printed, largest extrapolated motion first")
    ap.add_argument("--history", type=int, default=3, help="of these rows, how many print their speeds over the level")
    a = ap.parse_args()
    files = sorted(a.sweeps.glob("*/pair*.nc"))
    if not files:
        raise SystemExit(f"no sweep files (*/pair*.nc) under {a.sweeps}")
    rows = []
    for f in files:
        with xr.open_dataset(f) as ds:
            t, level, cog = ds["time"].values, ds["level"].values, ds["cog"].values
            hold, levels = float(ds.attrs["hold_s"]), ds["levels"].values
            unit = ds["pressure_cmd"].attrs.get("units", "")
            discard = a.discard if a.discard is not None else nominal_discard(a.sweeps, f.parent.name)
        for k, lv in enumerate(levels):
            rows.append((f"{f.parent.name}/{f.stem}", f"{lv:g} {unit}", level_creep(t, level, cog, k, hold, discard)))
    print(f"{len(rows)} levels of {len(files)} sweep files under {a.sweeps}, hold {hold:g} s,", end=" ")
    print(f"window the last {hold - discard:g} s")
    head = ("sweep", "level", "avg err mm", "speed mm/s", "2nd half mm", "drift/osc", "left mm")
    print(f"{head[0]:24s}", " ".join(f"{h:>12s}" for h in head[1:]))
    rows.sort(key=lambda r: (r[2]["ratio"] <= DRIFT, -np.nan_to_num(r[2]["left"], nan=-1.0)))
    for name, lv, r in rows[: a.top]:
        mm = (r["ae"] * 1e3, r["speed"] * 1e3, r["path"] * 1e3, r["ratio"], r["left"] * 1e3)
        print(f"{name:24s} {lv:>12s}", " ".join(f"{v:12.4f}" for v in mm))
    for name, lv, r in rows[: min(a.history, a.top)]:
        print(f"{name} {lv}: speed between successive twelfths of the level, mm/s:", end=" ")
        print(" ".join(f"{v * 1e3:.3f}" for v in r["history"]))
    ae = np.array([r["ae"] for _, _, r in rows])
    left = np.array([r["left"] for _, _, r in rows])
    drift = np.array([r["ratio"] for _, _, r in rows]) > DRIFT
    print(f"averaging_error: largest {np.nanmax(ae) * 1e3:.4f} mm, median {np.nanmedian(ae) * 1e3:.4f} mm")
    print(f"levels whose drift dominates (drift/osc > {DRIFT:g}): {drift.sum()} of {len(rows)}")
    if drift.any():
        fin = left[drift & np.isfinite(left)]
        print(
            f"  extrapolated motion left among them: {np.isinf(left[drift]).sum()} not decaying, "
            f"{np.isnan(left[drift]).sum()} reversing, finite ones "
            + (f"median {np.median(fin) * 1e3:.3f} mm, largest {fin.max() * 1e3:.3f} mm" if fin.size else "none")
        )


def nominal_discard(sweeps: Path, contact: str) -> float:
    """discard_s (s) of the nominal file made from these sweeps (SWEEPS/../nominal/{contact}.nc)."""
    f = sweeps.parent / "nominal" / f"{contact}.nc"
    if not f.is_file():
        raise SystemExit(f"no {f} to read the averaging window from: give --discard")
    with xr.open_dataset(f) as ds:
        return float(ds.attrs["discard_s"])


if __name__ == "__main__":
    main()
