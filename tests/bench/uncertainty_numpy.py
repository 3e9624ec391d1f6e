#!/usr/bin/python3
"""The two models of tests/bench/uncertainty_speed.sh in NumPy, vectorised as suncal does, for
the speed comparison with `gearmc uncertainty` (same work: draws, model, mean, u, both 95 % /
99.73 % coverage intervals of JCGM 101 §7.7).

  uncertainty_numpy.py mass M          JCGM 101 §9.3 with M trials (p = 0.95)
  uncertainty_numpy.py adaptive P      JCGM 101 §9.2 normal inputs, adaptive §7.9 at p = P
"""
import math
import sys

import numpy as np


def intervals(y, p):
    y = np.sort(y)
    M = y.size
    pm = p * M
    q = int(pm) if pm == int(pm) else int(math.floor(pm + 0.5))
    r = (M - q) // 2 if (M - q) % 2 == 0 else (M - q + 1) // 2
    best = int(np.argmin(y[q:] - y[: M - q]))
    return (y[r - 1], y[r + q - 1]), (y[best], y[best + q])


def mass(M, rng):
    m_Rc = rng.normal(100000.000, 0.050, M)
    dm_Rc = rng.normal(1.234, 0.020, M)
    rho_a = rng.uniform(1.10, 1.30, M)
    rho_W = rng.uniform(7000, 9000, M)
    rho_R = rng.uniform(7950, 8050, M)
    return (m_Rc + dm_Rc) * (1 + (rho_a - 1.2) * (1 / rho_W - 1 / rho_R)) - 100000


def additive(M, rng):
    return rng.normal(0, 1, M) + rng.normal(0, 1, M) + rng.normal(0, 1, M) + rng.normal(0, 1, M)


def tolerance(u, ndig=2):
    l = math.floor(math.log10(u)) - (ndig - 1)
    if round(u / 10**l) >= 10**ndig:
        l += 1
    return 0.5 * 10**l


def adaptive(p, rng):
    B = max(math.ceil(100 / (1 - p)), 10000)
    blocks, values = [], []
    while True:
        y = additive(B, rng)
        values.append(y)
        sym, short = intervals(y, p)
        blocks.append((y.mean(), y.std(ddof=1), sym[0], sym[1], short[0], short[1]))
        h = len(blocks)
        if h < 2:
            continue
        a = np.array(blocks)
        s = a.std(axis=0, ddof=1) / math.sqrt(h)
        delta = tolerance(np.concatenate(values).std(ddof=1))
        if np.all(2 * s <= delta):
            break
    y = np.concatenate(values)
    return y, h


def main():
    rng = np.random.default_rng(1)
    if sys.argv[1] == "mass":
        y = mass(int(sys.argv[2]), rng)
        p = 0.95
    else:
        p = float(sys.argv[2])
        y, h = adaptive(p, rng)
    sym, short = intervals(y, p)
    print(f"M {y.size} y {y.mean():.6f} u {y.std(ddof=1):.6f} symmetric [{sym[0]:.6f}, {sym[1]:.6f}]"
          f" shortest [{short[0]:.6f}, {short[1]:.6f}]")


if __name__ == "__main__":
    main()
