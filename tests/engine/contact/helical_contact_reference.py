#!/usr/bin/env python3
"""Independent reference of gearmc's stylus contact on helical flanks (tests/CMakeLists.txt runs
it on the output of helical_contact_dump, a few hundred points with steep modifications).

Written from the formulas, not from gearmc's code:
  * the gear from ISO 21771:2007 (m_t = m_n / cos(beta), tan(alpha_t) = tan(alpha_n) / cos(beta),
    d = z m_t, r_b = d cos(alpha_t) / 2, s_t = m_t (pi/2 + 2 x tan(alpha_n)), half tooth angle at
    the base circle theta_b = s_t / d + inv(alpha_t));
  * the flank as docs/scenarios.md and docs/formats.md define it: the R flank of tooth k unwinds
    from the base circle at phi_b = (k - 1) 2 pi / z + s (theta_b - L / r_b) + z tan(beta) / r
    (s = +1 R, -1 L; a right-hand section turns counter-clockwise with z, a left-hand one
    clockwise), its point r_b e(phi_b) + L s e'(phi_b) + z e_z, the deviation (µm) along the
    transverse normal s e'(phi_b); an internal gear's flank (DIN 3960's internal tooth, half angle
    s_t / d - inv(alpha_t) + inv(alpha_y)) the concave involute r_b e(phi_b) - L s e'(phi_b),
    phi_b = (k - 1) 2 pi / z + s (theta_b + L / r_b) + z tan(beta) / r, theta_b = s_t / d -
    inv(alpha_t);
  * the normal of the nominal helicoid as the cross product of the point's partial derivatives
    (mpmath's numerical differentiation), oriented outward (positive along s e'(phi_b));
  * the first contact as the highest point of the contact height f(L, z) = w.n + sqrt(R^2 -
    |w - (w.n) n|^2), w = S(L, z) - p, over the stylus's footprint: a 41 x 41 grid in double
    precision over a box that holds the footprint, then Newton's method on grad f = 0 with the
    gradient and Hessian from mpmath.diff at 40 digits, from the best few grid nodes; the
    highest converged maximum. C = S(L*, z*), O = p + f* n.
Checks: p and n of the dump equal the nominal helicoid's to 1e-9 mm; C and O equal the
reference's to 1e-6 mm (1 nm). Exit status 1 otherwise.
Run: helical_contact_reference.py DUMP  (DUMP from helical_contact_dump)
"""
import math
import re
import sys

import mpmath as mp

mp.mp.dps = 40


class Gear:
    def __init__(self, teeth, m_n, alpha_deg, beta_deg, hand, x, kind="external"):
        self.z = teeth
        # An internal (ring) gear: the material on the involute's concave side, sigma = -1. Its
        # flank is the involute of the same base circle on the other side of the base point:
        # r_b e(phi_b) - s L e'(phi_b), phi_b = (k - 1) 2 pi / z + s (theta_b + L / r_b) + z
        # tan(beta) / r, with the internal tooth's half angle at the base circle theta_b = s_t / d
        # - inv(alpha_t) (DIN 3960: the half tooth angle at r_y is s_t / d - inv(alpha_t) +
        # inv(alpha_y)); the outward normal stays s e'(phi_b).
        self.sigma = -1 if kind == "internal" else 1
        beta = math.radians(beta_deg)
        alpha_n = math.radians(alpha_deg)
        mb, man = mp.radians(beta_deg), mp.radians(alpha_deg)
        m_t = mp.mpf(m_n) / mp.cos(mb)
        alpha_t = mp.atan(mp.tan(man) / mp.cos(mb))
        self.d = teeth * m_t
        self.r = self.d / 2
        self.r_b = self.d * mp.cos(alpha_t) / 2
        s_t = m_t * (mp.pi / 2 + 2 * x * mp.tan(man))
        self.theta_b = s_t / self.d + self.sigma * (mp.tan(alpha_t) - alpha_t)
        self.turn = (1 if hand == "right" else -1) * mp.tan(mb) / self.r
        self.tan_beta_b = math.tan(math.asin(math.sin(beta) * math.cos(alpha_n)))

    def point(self, tooth, s, L, z, dev):
        phi = self.base_angle(tooth, s, L, z)
        c, sn = mp.cos(phi), mp.sin(phi)
        n_t = (s * -sn, s * c)  # s e'(phi)
        d = dev(L, z) / 1000 if dev else 0
        a = self.sigma * L + d
        return mp.matrix([self.r_b * c + a * n_t[0], self.r_b * sn + a * n_t[1], z])

    def base_angle(self, tooth, s, L, z):
        return ((tooth - 1) * 2 * mp.pi / self.z + s * (self.theta_b - self.sigma * L / self.r_b)
                + z * self.turn)

    def point_float(self, tooth, s, L, z, dev):
        """The same in double precision (the coarse search)."""
        phi = ((tooth - 1) * 2 * math.pi / self.z
               + s * (float(self.theta_b) - self.sigma * L / float(self.r_b)) + z * float(self.turn))
        c, sn = math.cos(phi), math.sin(phi)
        d = dev(L, z) / 1000 if dev else 0.0
        r_b = float(self.r_b)
        a = self.sigma * L + d
        return (r_b * c + a * s * -sn, r_b * sn + a * s * c, z)

    def normal(self, tooth, s, L, z):
        P = lambda l, zz: self.point(tooth, s, l, zz, None)
        d_L = mp.matrix([mp.diff(lambda l: P(l, z)[i], L) for i in range(3)])
        d_z = mp.matrix([mp.diff(lambda zz: P(L, zz)[i], z) for i in range(3)])
        n = mp.matrix([d_L[1] * d_z[2] - d_L[2] * d_z[1], d_L[2] * d_z[0] - d_L[0] * d_z[2],
                       d_L[0] * d_z[1] - d_L[1] * d_z[0]])
        n = n / mp.norm(n)
        phi = self.base_angle(tooth, s, L, z)
        if n[0] * (s * -mp.sin(phi)) + n[1] * (s * mp.cos(phi)) < 0:
            n = -n
        return n


def expression(text):
    """A muParser expression of L, z (µm) as a Python function (the dump writes only +, -, *,
    /, ^, parentheses, numbers, L, z, sin, cos, exp, max)."""
    py = text.replace("^", "**")
    if re.search(r"[^0-9A-Za-z_+\-*/(). ,]", py):
        raise ValueError("unexpected character in " + text)
    code = compile(py, "<expr>", "eval")
    mp_env = {"sin": mp.sin, "cos": mp.cos, "exp": mp.exp, "max": max}
    float_env = {"sin": math.sin, "cos": math.cos, "exp": math.exp, "max": max}

    def value(L, z):
        env = float_env if isinstance(L, float) else mp_env
        return eval(code, {"__builtins__": {}}, dict(env, L=L, z=z))
    return value


def contact(gear, tooth, s, dev, p, n, R, L0, z0):
    def f(L, z):
        w = gear.point(tooth, s, L, z, dev) - p
        wn = sum(w[i] * n[i] for i in range(3))
        q2 = R * R - sum((w[i] - wn * n[i]) ** 2 for i in range(3))
        return wn + mp.sqrt(q2) if q2 > 0 else mp.mpf("-inf")

    # The box: the footprint's roll-length half-width about 1.3 R r_b / L0 plus the helicoid's
    # shear over z +/- R (tan(beta_b) R), and z +/- R.
    half_L = 1.3 * R * float(gear.r_b) / L0 + 0.05 + gear.tan_beta_b * R
    pf, nf = [float(v) for v in p], [float(v) for v in n]

    def f_float(L, z):
        S = gear.point_float(tooth, s, L, z, dev)
        w = [S[i] - pf[i] for i in range(3)]
        wn = sum(w[i] * nf[i] for i in range(3))
        q2 = R * R - sum((w[i] - wn * nf[i]) ** 2 for i in range(3))
        return wn + math.sqrt(q2) if q2 > 0 else -math.inf

    N = 40
    grid = []
    for i in range(N + 1):
        for j in range(N + 1):
            L = L0 - half_L + 2 * half_L * i / N
            z = z0 - R + 2 * R * j / N
            grid.append((f_float(L, z), L, z))
    grid.sort(reverse=True)
    best = None
    for _, L, z in grid[:3]:
        x = mp.matrix([L, z])
        for _ in range(30):
            g = mp.matrix([mp.diff(f, (x[0], x[1]), (1, 0)), mp.diff(f, (x[0], x[1]), (0, 1))])
            H = mp.matrix([[mp.diff(f, (x[0], x[1]), (2, 0)), mp.diff(f, (x[0], x[1]), (1, 1))],
                           [mp.diff(f, (x[0], x[1]), (1, 1)), mp.diff(f, (x[0], x[1]), (0, 2))]])
            step = mp.lu_solve(H, -g)
            # Keep uphill: halve the step while f would drop by more than its rounding.
            for _ in range(30):
                if f(x[0] + step[0], x[1] + step[1]) >= f(x[0], x[1]) - mp.mpf("1e-30"):
                    break
                step = step / 2
            x = x + step
            if mp.norm(step) < mp.mpf("1e-25"):
                break
        height = f(x[0], x[1])
        if best is None or height > best[0]:
            best = (height, x)
    height, x = best
    C = gear.point(tooth, s, x[0], x[1], dev)
    O = p + height * n
    return C, O


def main():
    gears, exprs = {}, {}
    worst_pn = worst_C = worst_O = 0.0
    points = bad = 0
    for line in open(sys.argv[1]):
        t = line.split()
        if not t:
            continue
        if t[0] == "gear":
            gears[t[1]] = Gear(int(t[2]), float(t[3]), float(t[4]), float(t[5]), t[6], float(t[7]),
                               t[8] if len(t) > 8 else "external")
        elif t[0] == "expr":
            exprs[t[1]] = expression(line.split(None, 2)[2].strip())
        elif t[0] == "point":
            g = gears[t[1]]
            dev = exprs[t[2]]
            tooth, s = int(t[3]), (1 if t[4] == "R" else -1)
            L0, z0, R = float(t[5]), float(t[6]), float(t[7])
            vals = [mp.mpf(v) for v in t[8:14]]
            status = t[14]
            C_g = mp.matrix([mp.mpf(v) for v in t[15:18]])
            O_g = mp.matrix([mp.mpf(v) for v in t[18:21]])
            p = g.point(tooth, s, mp.mpf(L0), mp.mpf(z0), None)
            n = g.normal(tooth, s, mp.mpf(L0), mp.mpf(z0))
            worst_pn = max(worst_pn, float(mp.norm(p - mp.matrix(vals[0:3]))),
                           float(mp.norm(n - mp.matrix(vals[3:6]))))
            points += 1
            if status != "ok":
                print("not ok:", line.strip())
                bad += 1
                continue
            C, O = contact(g, tooth, s, dev, p, n, R, L0, z0)
            dC, dO = float(mp.norm(C - C_g)), float(mp.norm(O - O_g))
            if dC > 1e-6 or dO > 1e-6:
                print("differs: |dC| %.3g mm |dO| %.3g mm: %s" % (dC, dO, line.strip()))
                bad += 1
            worst_C, worst_O = max(worst_C, dC), max(worst_O, dO)
    print("%d points: worst |p, n - reference| %.3g; worst |C - C_ref| %.3g nm, |O - O_ref| %.3g nm"
          % (points, worst_pn, 1e6 * worst_C, 1e6 * worst_O))
    ok = points >= 500 and bad == 0 and worst_pn < 1e-9
    print("PASS" if ok else "FAIL")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
