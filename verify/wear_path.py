"""The fretting-wear path (spec mdr.md §5; graded: docs/fretting-wear.md) by an independent solver:
a grid uniform in r (the library's is uniform in r²), the MDR integrals as exact cell integrals of
piecewise-linear f and g (incomplete beta and Gauss hypergeometric functions of scipy, not the
library's power sums), and Heun's second-order step in τ (the library steps by explicit Euler).

Normalized variables a0 = d = 1, grading exponent k, amplitude ratio χ, c = sqrt(1 − χ):

    g(x) = x^(1−k) ∫_0^x f'(r) (x² − r²)^((k−1)/2) dr                          (docs/theory-mdr.md#graded-profile-transform, Eq. 20)
    p(r) = (c̃_N/π) ∫_r^a g'(x) (x² − r²)^((k−1)/2) dx,   c̃_N = (1+k)(3+k)/4     (docs/theory-mdr.md#graded-pressure, Eq. 28)
    Δũ(r) = 4 [(f − f∞)/χ + J(r)],  J = 1 − I_{c²/r²}((1+k)/2, (1−k)/2)   for c < r < a
    ∂f/∂τ = p Δũ

with a where the linear interpolant of g beyond the outermost node with g < 1 reaches 1, and f∞ by
the quadrature of verify/graded_wear.py. Cell integrals:
  ∫_{r1}^{r2} (x² − r²)^α dr = (x^k/2) B(1/2, (1+k)/2) [I_{(r2/x)²} − I_{(r1/x)²}](1/2, (1+k)/2),
  ∫_r^X (x² − r²)^α dx = (r^k/(2b)) (1 − t)^b ₂F₁(b, 1 + k/2; b + 1; 1 − t),  t = r²/X², b = (1+k)/2,
(α = (k−1)/2; the second is acosh(X/r) at k = 0).

Case `wear_path/k{k}_chi{chi}`: arrays `tau`, `contact_radius` a/a0, `profile_at_a0` f(a0)/d,
`wear_volume` V/(π a0² d) = 2∫(f − f0) r dr, on the finer grid; `*_coarse` the same on a grid of half
the cells (their difference bounds this solver's own error); attributes `k`, `chi`, `n`, `dtau`.
"""
import numpy as np
from scipy.special import beta, betainc, hyp2f1

from .graded_wear import limiting_profile

# (k, χ, nodes of the finer grid, Δτ, τ of the records)
CASES = [
    (0.0, 0.5, 1201, 5e-4, [0.1, 0.25, 0.5, 1.0, 2.0]),
    (0.5, 0.9, 1201, 5e-4, [0.1, 0.25, 0.5, 1.0, 2.0]),
    (-0.5, 0.5, 801, 5e-5, [0.1, 0.25, 0.5, 1.0]),
]
LENGTH = 1.6


class WearPath:
    def __init__(self, k, chi, nodes, length=LENGTH):
        self.k, self.chi = k, chi
        self.r = np.linspace(0.0, length, nodes)
        self.dr = self.r[1]
        self.c = np.sqrt(1.0 - chi)
        self.modulus = 0.25 * (1.0 + k) * (3.0 + k)
        self.f0 = 0.5 * (1.0 + k) * self.r ** 2
        self.limit = np.array([limiting_profile(x, chi, k) for x in self.r])
        with np.errstate(divide="ignore", invalid="ignore"):
            ratio = np.where(self.r > self.c, (self.c / self.r) ** 2, 1.0)
        self.J = 1.0 - betainc(0.5 * (1.0 + k), 0.5 * (1.0 - k), ratio)
        # g = G @ (cell slopes): G[i, j] = x_i/2 · B(1/2, b) [I((r_{j+1}/x_i)²) − I((r_j/x_i)²)], j < i.
        b = 0.5 * (1.0 + k)
        x = self.r[:, None]
        with np.errstate(divide="ignore", invalid="ignore"):
            u2 = lambda rr: np.clip((rr[None, :] / x) ** 2, 0.0, 1.0)
            G = 0.5 * x * beta(0.5, b) * (betainc(0.5, b, u2(self.r[1:])) - betainc(0.5, b, u2(self.r[:-1])))
        self.G = np.where(np.arange(nodes - 1)[None, :] < np.arange(nodes)[:, None], G, 0.0)
        # Pressure cells: F(X; r) = ∫_r^X (x² − r²)^α dx on the nodes, for r in the annulus only.
        self.rows = np.nonzero(self.r > self.c)[0]
        self.F = self._F(self.r[None, :], self.r[self.rows][:, None])

    def _F(self, X, r):
        b = 0.5 * (1.0 + self.k)
        with np.errstate(divide="ignore", invalid="ignore"):
            z = np.where(X > r, 1.0 - (r / X) ** 2, 0.0)
            out = r ** self.k / (2.0 * b) * z ** b * hyp2f1(b, 1.0 + 0.5 * self.k, b + 1.0, z)
        return np.where(X > r, out, 0.0)

    def state(self, f):
        """g, the edge a, the pressure and the slip of profile f."""
        slopes = np.diff(f) / self.dr
        # einsum, not BLAS: the same sums in the same order for any thread count.
        g = np.einsum("ij,j->i", self.G, slopes, optimize=False)
        last = int(np.nonzero(g < 1.0)[0].max())
        xl = self.r[last]
        a = xl + (1.0 - g[last]) / (g[last + 1] - g[last]) * self.dr
        gs = np.diff(g) / self.dr  # g' on each x-cell
        cells = np.zeros_like(gs)
        cells[:last] = gs[:last]
        # Σ over full cells [x_i, x_{i+1}], i < last, plus the partial cell [x_last, a].
        W = np.diff(self.F, axis=1)  # W[m, i] = F(x_{i+1}; r) − F(x_i; r)
        p_rows = np.einsum("mi,i->m", W, cells, optimize=False)
        edge_slope = (1.0 - g[last]) / (a - xl)
        rr = self.r[self.rows][:, None]
        partial = (self._F(np.array([[a]]), rr) - self._F(np.array([[xl]]), rr))[:, 0]
        p_rows += edge_slope * partial
        p = np.zeros_like(f)
        p[self.rows] = np.maximum(self.modulus / np.pi * p_rows, 0.0)
        p[self.r >= a] = 0.0
        slip = np.zeros_like(f)
        inside = (self.r > self.c) & (self.r < a)
        slip[inside] = np.maximum(4.0 * ((f - self.limit) / self.chi + self.J)[inside], 0.0)
        return a, p, slip

    def rate(self, f):
        a, p, slip = self.state(f)
        return a, p * slip

    def run(self, dtau, taus):
        f = self.f0.copy()
        out = {"tau": [], "contact_radius": [], "profile_at_a0": [], "wear_volume": []}
        step, targets = 0, [int(round(t / dtau)) for t in taus]
        while step < targets[-1]:
            # Heun: f* = f + Δτ R(f), f ← f + Δτ/2 (R(f) + R(f*)).
            _, r1 = self.rate(f)
            _, r2 = self.rate(f + dtau * r1)
            f = f + 0.5 * dtau * (r1 + r2)
            step += 1
            if step in targets:
                a, _ = self.rate(f)
                out["tau"].append(step * dtau)
                out["contact_radius"].append(a)
                out["profile_at_a0"].append(np.interp(1.0, self.r, f))
                out["wear_volume"].append(np.trapezoid(2.0 * (f - self.f0) * self.r, self.r))
        return {k: np.array(v) for k, v in out.items()}


def generate():
    cases = []
    for k, chi, nodes, dtau, taus in CASES:
        fine = WearPath(k, chi, nodes).run(dtau, taus)
        coarse = WearPath(k, chi, (nodes - 1) // 2 + 1).run(dtau, taus)
        arrays = dict(fine)
        arrays.update({f"{key}_coarse": v for key, v in coarse.items() if key != "tau"})
        cases.append({
            "case": f"wear_path/k{k:+.2f}_chi{chi:.1f}",
            "arrays": arrays,
            "attrs": {"k": k, "chi": chi, "n": nodes, "dtau": dtau, "length": LENGTH},
        })
    return cases


if __name__ == "__main__":
    import sys
    import time
    k, chi, nodes, dtau = (float(sys.argv[1]), float(sys.argv[2]), int(sys.argv[3]), float(sys.argv[4]))
    taus = [float(t) for t in sys.argv[5].split(",")]
    t = time.time()
    w = WearPath(k, chi, nodes)
    # The paraboloid's g is x² exactly: a check of the cell integrals.
    print("max |g0 − x²| =", np.abs(w.G @ (np.diff(w.f0) / w.dr) - w.r ** 2).max())
    out = w.run(dtau, taus)
    for i, tau in enumerate(out["tau"]):
        print(f"tau={tau:g} a={out['contact_radius'][i]:.5f} f(a0)={out['profile_at_a0'][i]:.5f} "
              f"V={out['wear_volume'][i]:.6f}")
    print(f"{time.time() - t:.1f} s")
