#!/usr/bin/python3
"""Independent reference values for the `gearmc uncertainty` tests (NumPy, not gearmc's code).

1. The exact 95 % limits of Y = X1 + X2 + X3 + X4, X_i ~ R(-sqrt3, sqrt3) (JCGM 101 §9.2.3):
   the sum of four U(0, 1) has the Irwin-Hall CDF F(s) = (1/4!) sum_k (-1)^k C(4,k) (s-k)^4_+,
   Y = 2 sqrt3 (S - 2); the 0.975 quantile is found by bisection to 1e-12.
2. The mass calibration of JCGM 101 §9.3 by Monte Carlo with 10^7 trials (NumPy's PCG64,
   seed 20261122), vectorised as suncal does: estimate, u(y), probabilistically symmetric and
   shortest 95 % intervals (JCGM 101 §7.7), with the Monte-Carlo standard errors of the
   endpoints from sqrt(p(1-p)/M)/f(q) (f by a kernel-free histogram estimate).

Run:  /usr/bin/python3 tests/bench/uncertainty_reference.py
"""
import math
import sys

import numpy as np


def irwin_hall_cdf(s, n=4):
    return sum((-1) ** k * math.comb(n, k) * max(s - k, 0.0) ** n for k in range(n + 1)) / math.factorial(n)


def irwin_hall_975():
    lo, hi = 2.0, 4.0
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if irwin_hall_cdf(mid) < 0.975:
            lo = mid
        else:
            hi = mid
    return 2.0 * math.sqrt(3.0) * (0.5 * (lo + hi) - 2.0)


def intervals(y, p):
    y = np.sort(y)
    M = y.size
    pm = p * M
    q = int(pm) if pm == int(pm) else int(math.floor(pm + 0.5))
    r = (M - q) // 2 if (M - q) % 2 == 0 else (M - q + 1) // 2
    sym = (y[r - 1], y[r + q - 1])
    widths = y[q:] - y[: M - q]
    best = int(np.argmin(widths))
    return sym, (y[best], y[best + q]), y


def mass_calibration(M=10_000_000, seed=20261122, chunk=2_000_000):
    rng = np.random.default_rng(seed)
    parts = []
    for start in range(0, M, chunk):
        n = min(chunk, M - start)
        m_Rc = rng.normal(100000.000, 0.050, n)
        dm_Rc = rng.normal(1.234, 0.020, n)
        rho_a = rng.uniform(1.10, 1.30, n)
        rho_W = rng.uniform(7000, 9000, n)
        rho_R = rng.uniform(7950, 8050, n)
        parts.append((m_Rc + dm_Rc) * (1 + (rho_a - 1.2) * (1 / rho_W - 1 / rho_R)) - 100000)
    return np.concatenate(parts)


def main():
    print(f"Irwin-Hall 95 % limit of the rectangular additive model: +/-{irwin_hall_975():.6f}")
    y = mass_calibration()
    M = y.size
    sym, short, ys = intervals(y, 0.95)
    print(f"mass calibration, M = {M}: y = {y.mean():.6f} mg, u(y) = {y.std(ddof=1):.6f} mg")
    print(f"  symmetric 95 %: [{sym[0]:.6f}, {sym[1]:.6f}] mg")
    print(f"  shortest  95 %: [{short[0]:.6f}, {short[1]:.6f}] mg")
    # Density at the endpoints from the count within +/- 0.005 mg; se of a quantile.
    for name, x, pp in (("low", short[0], 0.025), ("high", short[1], 0.975)):
        h = 0.005
        f = (np.searchsorted(ys, x + h) - np.searchsorted(ys, x - h)) / (2 * h * M)
        se = math.sqrt(pp * (1 - pp) / M) / f
        print(f"  shortest {name}: density {f:.4f} /mg, MC standard error ~ {se:.6f} mg")
    return 0


if __name__ == "__main__":
    sys.exit(main())
