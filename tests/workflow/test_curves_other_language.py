"""results/curves/curves.json is evaluable in another language, as docs/datasets.md promises.

A JavaScript program (node) reads curves.json itself and evaluates every pair and axis of both
contact cases with the rule the document states (largest i with breaks[i] <= p clamped to the
pieces, Horner in p - breaks[i]); a C program (cc) does the same from the numbers of the file
written as plain text (C has no JSON reader). Both must agree with the Python evaluator
(`tensegrity.workspace.fit.evaluate`) to 1e-12 m at many pressures across each valid range,
including the breaks themselves and the ends.
"""

import json
import shutil
import subprocess

import numpy as np
import pytest

from tensegrity.workspace import fit

TOL_M = 1e-12
N_PRESSURES = 97

JS = r"""
const fs = require("fs");
const doc = JSON.parse(fs.readFileSync(process.argv[2], "utf8"));
const evaluate = (c, p) => {
  const b = c.breaks, m = b.length - 1;
  let i = 0;
  while (i + 1 < m && b[i + 1] <= p) i++;          // largest i with b[i] <= p, clamped to 0..m-1
  let y = 0;
  for (const a of c.coefs[i]) y = y * (p - b[i]) + a; // Horner, highest power first
  return y;
};
const out = [];
for (const [contact, cs] of Object.entries(doc.contacts))
  for (const [pair, axes] of Object.entries(cs.pairs))
    for (const [axis, c] of Object.entries(axes)) {
      const n = %(n)d, ps = [];
      for (let k = 0; k < n; k++) ps.push(c.pmin + (c.pmax - c.pmin) * k / (n - 1));
      ps.push(...c.breaks);
      out.push({contact, pair, axis, p: ps, v: ps.map(p => evaluate(c, p))});
    }
process.stdout.write(JSON.stringify(out));
"""

C = r"""
#include <stdio.h>
/* stdin: per curve "m d" then m+1 breaks, m*(d+1) coefs, then "n" pressures; prints the values */
int main(void) {
  int m, d, n;
  while (scanf("%d %d", &m, &d) == 2) {
    double b[64], c[64][8], p, y;
    for (int i = 0; i <= m; i++) scanf("%lf", &b[i]);
    for (int i = 0; i < m; i++) for (int k = 0; k <= d; k++) scanf("%lf", &c[i][k]);
    scanf("%d", &n);
    for (int j = 0; j < n; j++) {
      scanf("%lf", &p);
      int i = 0;
      while (i + 1 < m && b[i + 1] <= p) i++;
      y = 0;
      for (int k = 0; k <= d; k++) y = y * (p - b[i]) + c[i][k];
      printf("%.17g\n", y);
    }
  }
  return 0;
}
"""


def pressures(c: dict) -> list[float]:
    """The pressures every evaluator uses for curve `c`: an even grid over pmin..pmax and the breaks."""
    k = np.arange(N_PRESSURES)
    return [c["pmin"] + (c["pmax"] - c["pmin"]) * kk / (N_PRESSURES - 1) for kk in k] + list(c["breaks"])


def curves(doc: dict):
    for contact, cs in doc["contacts"].items():
        for pair, axes in cs["pairs"].items():
            for axis, c in axes.items():
                yield contact, pair, axis, c


@pytest.fixture(scope="module")
def doc_path(tiny):
    path = tiny / "results" / "curves" / "curves.json"
    doc = json.loads(path.read_text())
    assert set(doc["contacts"]) == {"equilateral", "isosceles"}
    return path


def compare(doc: dict, results: list[tuple[str, str, str, list, list]]) -> None:
    seen = set()
    for contact, pair, axis, ps, vs in results:
        c = doc["contacts"][contact]["pairs"][pair][axis]
        np.testing.assert_array_equal(ps, pressures(c))  # same pressures, to the last bit
        want = fit.evaluate(c, np.asarray(ps))
        err = np.max(np.abs(np.asarray(vs) - want))
        assert err <= TOL_M, f"{contact} pair {pair} axis {axis}: {err:.3g} m"
        seen.add((contact, pair, axis))
    assert seen == {(a, b, c) for a, b, c, _ in curves(doc)}
    assert len(seen) >= 2 * 3 * 2


@pytest.mark.skipif(
    shutil.which("node") is None and shutil.which("cc") is None,
    reason="neither node nor cc is installed: no second language to evaluate curves.json with",
)
@pytest.mark.parametrize("language", ["javascript", "c"])
def test_curves_json_in_another_language(doc_path, tmp_path, language):
    doc = json.loads(doc_path.read_text())
    if language == "javascript":
        if shutil.which("node") is None:
            pytest.skip("node is not installed (the C evaluator runs instead)")
        prog = tmp_path / "evaluate.js"
        prog.write_text(JS % {"n": N_PRESSURES})
        r = subprocess.run(["node", str(prog), str(doc_path)], capture_output=True, text=True, timeout=60)
        assert r.returncode == 0, r.stderr
        out = [(o["contact"], o["pair"], o["axis"], o["p"], o["v"]) for o in json.loads(r.stdout)]
    else:
        if shutil.which("cc") is None:
            pytest.skip("cc is not installed (the JavaScript evaluator runs instead)")
        src, exe = tmp_path / "evaluate.c", tmp_path / "evaluate"
        src.write_text(C)
        subprocess.run(["cc", "-O0", "-o", str(exe), str(src)], check=True, timeout=60)
        items = list(curves(doc))
        lines = []
        for _, _, _, c in items:
            ps = pressures(c)
            lines.append(f"{len(c['breaks']) - 1} {len(c['coefs'][0]) - 1}")
            lines += [repr(float(x)) for x in c["breaks"]]
            lines += [repr(float(x)) for row in c["coefs"] for x in row]
            lines += [str(len(ps))] + [repr(float(p)) for p in ps]
        r = subprocess.run([str(exe)], input="\n".join(lines) + "\n", capture_output=True, text=True, timeout=60)
        assert r.returncode == 0, r.stderr
        vals = [float(v) for v in r.stdout.split()]
        out, k = [], 0
        for contact, pair, axis, c in items:
            n = len(pressures(c))
            out.append((contact, pair, axis, pressures(c), vals[k : k + n]))
            k += n
        assert k == len(vals)
    compare(doc, out)
