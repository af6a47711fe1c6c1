"""Errors of the two-pair surfaces (issue 34): the largest residual against the swept data of the
cross-validated polynomial alone (the surfaces before issue 34) and of the surface
results/curves/two_pair.json now holds (`workspace.surfaces.fit_surface`), and, with
`--statics N`, both against the independent static equilibrium (`physics.statics`) at the centres
of the grid cells (inside the swept range, between the points) of the N combinations whose
polynomials miss their data most. Prints figures; asserts nothing.

Usage: python benchmarks/bench_surfaces.py results/two_pair/isosceles.nc [more contact files]
       [--statics 10] [--max-degree 3] [--folds 5]
"""

from __future__ import annotations

import argparse

import numpy as np

from tensegrity.io.formats import two_pair as tpf
from tensegrity.physics import frames, statics
from tensegrity.physics import topology as topo
from tensegrity.physics.params import Params
from tensegrity.workspace import surfaces


def statics_cog(params: Params, face: int, pairs, pa: np.ndarray, pb: np.ndarray) -> np.ndarray:
    """Static CoG (n, n, 3) m in the support frame of `face` with pairs[0] at pa, pairs[1] at pb."""
    out = np.empty(pa.shape + (3,))
    for i in range(pa.shape[0]):
        start = None  # each row from the previous solution
        for j in range(pa.shape[1]):
            prs = np.zeros(topo.N_PAIRS)
            prs[pairs[0] - 1], prs[pairs[1] - 1] = pa[i, j], pb[i, j]
            start = statics.equilibrium(params, prs, start=start)
            out[i, j] = frames.in_support_frame(start, face)[0]
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("contacts", nargs="+", help="results/two_pair/{contact}.nc files")
    ap.add_argument("--statics", type=int, default=0, help="combinations compared with statics per contact")
    ap.add_argument("--max-degree", type=int, default=3)
    ap.add_argument("--folds", type=int, default=5)
    a = ap.parse_args()
    levels, src = tpf.read_contacts(a.contacts)
    pa, pb = np.meshgrid(levels, levels, indexing="ij")
    mid = 0.5 * (levels[1:] + levels[:-1])
    qa, qb = np.meshgrid(mid, mid, indexing="ij")
    for contact, ds in sorted(src.items()):
        cog, combos = ds["cog"].values, ds["combo_pairs"].values
        rows = [c for c in range(cog.shape[0]) if np.isfinite(cog[c]).all()]
        fits = {c: [(surfaces.fit_polynomial(pa, pb, cog[c, ..., x], a.max_degree, a.folds),
                     surfaces.fit_surface(pa, pb, cog[c, ..., x], a.max_degree, a.folds)) for x in range(3)]
                for c in rows}  # fmt: skip
        old = np.array([[p["max_residual"] for p, _ in fits[c]] for c in rows]) * 1e3
        new = np.array([[s["max_residual"] for _, s in fits[c]] for c in rows]) * 1e3
        n_spline = sum(s["kind"] == "spline" for c in rows for _, s in fits[c])
        print(
            f"{contact}: {len(rows)} combinations x 3 axes, {levels.size}x{levels.size} levels; largest residual "
            f"against the swept points: polynomial max {old.max():.4f} mm (median {np.median(old):.4f}, "
            f"{int((old > 0.1).sum())} over 0.1 mm) -> now max {new.max():.4f} mm ({n_spline} splines)"
        )
        worst = sorted(rows, key=lambda c: -old[rows.index(c)].max())[: a.statics]
        if not worst:
            continue
        e_old, e_new = [], []
        for c in worst:
            truth = statics_cog(Params(), int(ds.attrs["face"]), combos[c], qa, qb)
            for x, (p, s) in enumerate(fits[c]):
                e_old.append(np.abs(surfaces.evaluate(p, qa, qb) - truth[..., x]).ravel())
                e_new.append(np.abs(surfaces.evaluate(s, qa, qb) - truth[..., x]).ravel())
        e_old, e_new = np.concatenate(e_old) * 1e3, np.concatenate(e_new) * 1e3
        print(
            f"  against statics at {mid.size**2} cell centres of the {len(worst)} combinations with the worst "
            f"polynomials: polynomial max {e_old.max():.4f} mm (median {np.median(e_old):.4f}) -> now max "
            f"{e_new.max():.4f} mm (median {np.median(e_new):.4f})"
        )


if __name__ == "__main__":
    main()
