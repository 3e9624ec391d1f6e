#!/usr/bin/env python3
"""Brute-force reference of gearmc's size dimensions (tests/CMakeLists.txt runs it on the output
of size_dimensions_dump): the nominal s_n, W_k, ball position and M_dK of gears/size_dimensions.h
and the first-order size deviations E_sn, E_Wk, E_MdK of engine/evaluation/gear_parameters.h.

Nothing here uses the closed forms under test (no inv(alpha_Kt) relation, no theta_b, no W_k or
M_dK formula). From the definitions only:
  * the transverse section: m_t = m_n / cos(beta), tan(alpha_t) = tan(alpha_n) / cos(beta),
    r = z m_t / 2, r_b = r cos(alpha_t), s_t = m_t (pi/2 + 2 x tan(alpha_n));
  * the involute of the base circle, P(u) = r_b e(phi0 + g u) - g r_b u e'(phi0 + g u), unwinding
    clockwise (g = -1: an external tooth narrows outward) or counter-clockwise (g = +1: an
    internal tooth widens outward); the R flank of tooth 1 is the one through the reference-circle
    point at polar angle +s_t / (2 r): phi0 from a bisection on |P(u)| = r and the polar angle of
    that point; the L flank its mirror image in the X axis; tooth j turned by (j - 1) 2 pi / z;
    the helicoid's section at height h turned by hand h tan(beta) / r (docs: involute_gear.h);
  * a transverse deviation d (+ = material added) of a flank: the involute moved along its normal
    by d, i.e. the same involute turned about the axis by d / r_b (R flank counter-clockwise,
    L flank clockwise, for both kinds of gear);
  * ball: its centre on the space's centre line (polar angle pi / z), at the radius where the
    minimum 3-D distance to the R flank's helicoid (spur: to the involute in the plane) equals
    D_M / 2: a bisection on the radius, the distance by nested golden-section searches (over the
    height h, over the involute parameter u, each started from a dense sample); alpha_Kt =
    acos(r_b / r_K); M = |C_a - C_b| +/- D_M (Euclidean distance of the two centres, spaces 0 and
    z/2 or (z - 1)/2); the contact's roll length both as gearmc defines it (the foot of the
    centre's perpendicular to the flank in the centre's transverse section, on its base tangent)
    and, for information, at the true 3-D contact point of a helical gear;
  * span: W_kt = the distance of the two parallel lines perpendicular to the span's symmetry axis
    that support the L flank of tooth 1 and the R flank of tooth k (maxima of P.u over densely
    sampled flanks from the base circle to the tip, refined by a root of the numerical
    derivative; checks that turning the jaws does not change it); W_k = the distance of the
    jaws' planes, the helicoid's tangent planes at the two contacts: (P_R - P_L).n with n the unit
    normal from a numerical cross product of the partial derivatives (checks that the two
    contacts' normals are antiparallel); the contact's roll length sqrt(|P|^2 - r_b^2);
  * deviations: the flanks turned by +/- d / r_b, re-solved (tooth thickness on the reference
    circle, normal to the flank traces on the developed reference cylinder; the span by the
    supports; each ball's centre in the section z = 0 by Newton's method on its two 3-D distances
    with a numerical Jacobian), first-order values by central differences with the dump's
    deviations themselves (µm -> mm): the second-order terms cancel, the third-order ones are
    (d / rho)^2 ~ 1e-6 relative, the solvers' noise ~1e-10 relative, so 1e-3 relative is a
    safe bound that still catches any wrong factor (cos beta, cos beta_b, cos(pi / 2z)).
    E_MdK is the change of the Euclidean distance of the two centres: on an odd z it includes
    the balls' tangential displacements (printed as a note, split from the radial part).
Checks: nominal lengths to 1e-7 mm (angles 1e-9 rad), deviations to 1e-3 relative. Exit status 1
on any mismatch. Run: size_dimensions_reference.py DUMP [-v]   (-v: every comparison)
"""
import math
import sys

NOMINAL_TOL_MM = 1e-7
ANGLE_TOL_RAD = 1e-9
DEVIATION_REL_TOL = 1e-3
GOLDEN = (math.sqrt(5.0) - 1.0) / 2.0
# Plain Python (no numpy): CMake's Python3_EXECUTABLE need not have it.


def linspace(a, b, n):
    return [a + (b - a) * i / (n - 1) for i in range(n)]


def argbest(values, sign=1.0):
    """Index of the smallest (sign +1) or largest (sign -1) value."""
    best = 0
    for i, v in enumerate(values):
        if sign * v < sign * values[best]:
            best = i
    return best


def sub(a, b):
    return tuple(x - y for x, y in zip(a, b))


def dot(a, b):
    return sum(x * y for x, y in zip(a, b))


def norm(a):
    return math.sqrt(dot(a, a))


def golden_min(f, a, b, tol=1e-10):
    """Minimum of a unimodal f on [a, b]: (x, f(x)). Stopping at a bracket of tol (relative)
    leaves an error in the minimum's value of order f'' tol^2, far below the rounding of f."""
    c, d = b - GOLDEN * (b - a), a + GOLDEN * (b - a)
    fc, fd = f(c), f(d)
    for _ in range(200):
        if b - a < tol * (1.0 + abs(a)):
            break
        if fc < fd:
            b, d, fd = d, c, fc
            c = b - GOLDEN * (b - a)
            fc = f(c)
        else:
            a, c, fc = c, d, fd
            d = a + GOLDEN * (b - a)
            fd = f(d)
    return (c, fc) if fc < fd else (d, fd)


def sampled_min(f, a, b, n):
    """Global minimum of f on [a, b]: the best of n samples refined by golden-section search
    between its neighbours: (x, f(x))."""
    xs = linspace(a, b, n)
    i = argbest([f(x) for x in xs])
    return golden_min(f, xs[max(i - 1, 0)], xs[min(i + 1, n - 1)])


def derivative(f, x, e):
    """f'(x) by the five-point central difference (error ~e^4 f^(5) / 30, rounding ~eps f / e)."""
    return (8.0 * (f(x + e) - f(x - e)) - (f(x + 2 * e) - f(x - 2 * e))) / (12.0 * e)


def stationary_point(f, a, b):
    """Where f' = 0 in [a, b] (f' changes sign there): locates the extremum to ~1e-11 relative,
    where the golden-section search only reaches sqrt(eps) (f is flat there)."""
    return bisect(lambda x: derivative(f, x, 1e-4 * (1.0 + abs(x))), a, b, tol=1e-15)


def bisect(f, a, b, tol=1e-15, iterations=200):
    fa, fb = f(a), f(b)
    if fa == 0.0:
        return a
    if fb == 0.0:
        return b
    if (fa > 0) == (fb > 0):
        raise ValueError("no sign change in [%g, %g]: %g, %g" % (a, b, fa, fb))
    for _ in range(iterations):
        m = 0.5 * (a + b)
        fm = f(m)
        if fm == 0.0:
            return m
        if (fm > 0) == (fa > 0):
            a, fa = m, fm
        else:
            b = m
        if b - a < tol * (1.0 + abs(a)):
            break
    return 0.5 * (a + b)


class Gear:
    def __init__(self, f):
        self.internal = int(f["internal"]) == 1
        self.z = int(f["z"])
        self.m_n = float(f["m_n"])
        self.alpha_n = math.radians(float(f["alpha_n_deg"]))
        self.beta = math.radians(float(f["beta_deg"]))
        self.hand = int(f["hand"])
        self.x = float(f["x"])
        self.sigma = -1.0 if self.internal else 1.0
        self.g = 1.0 if self.internal else -1.0  # unwinding direction of the R flank's involute
        self.m_t = self.m_n / math.cos(self.beta)
        self.alpha_t = math.atan(math.tan(self.alpha_n) / math.cos(self.beta))
        self.r = self.z * self.m_t / 2.0
        self.r_b = self.r * math.cos(self.alpha_t)
        self.r_a = self.r + self.sigma * self.m_n * (1.0 + self.x)  # ISO 53 A rack, h_aP = m
        self.r_f = self.r - self.sigma * self.m_n * (1.25 - self.x)
        self.tau = 2.0 * math.pi / self.z
        self.turn = self.hand * math.tan(self.beta) / self.r  # rad per mm of height
        self.s_t = self.m_t * (math.pi / 2.0 + 2.0 * self.x * math.tan(self.alpha_n))
        # phi0: the involute with phi0 = 0 meets the reference circle at polar angle psi; the R
        # flank of tooth 1 passes there at +s_t / (2 r).
        self.phi0 = 0.0
        u_r = bisect(lambda u: math.hypot(*self.involute(u)) - self.r, 0.0, 10.0)
        psi = math.atan2(self.involute(u_r)[1], self.involute(u_r)[0])
        self.phi0 = self.s_t / (2.0 * self.r) - psi
        self.u_tip = math.sqrt((self.r_a / self.r_b) ** 2 - 1.0)

    def involute(self, u):
        a = self.phi0 + self.g * u
        ca, sa = math.cos(a), math.sin(a)
        k = -self.g * self.r_b * u
        return (self.r_b * ca - k * sa, self.r_b * sa + k * ca)

    def flank_xy(self, side, tooth, u, h=0.0, d_mm=0.0):
        """The transverse section at height h of the flank `side` of `tooth`, turned by its
        deviation d_mm / r_b (material added: R counter-clockwise, L clockwise)."""
        px, py = self.involute(u)
        if side == "L":
            py = -py
        a = ((tooth - 1) * self.tau + self.turn * h +
             d_mm / self.r_b * (1.0 if side == "R" else -1.0))
        c, s = math.cos(a), math.sin(a)
        return (c * px - s * py, s * px + c * py)

    # --- distances -------------------------------------------------------------------------
    def section_min(self, C, side, tooth, h, d_mm, u_max):
        """min over u of |C - S(u, h)|^2, C in the section z = 0: (u*, value)."""
        cx, cy = C

        def f(u):
            px, py = self.flank_xy(side, tooth, u, h, d_mm)
            return (px - cx) ** 2 + (py - cy) ** 2

        u, v = sampled_min(f, 0.0, u_max, 161)
        return u, v + h * h

    def section_foot(self, C, side, tooth, u_max):
        """The foot of C's perpendicular to the flank in the section z = 0 (parameter u)."""
        cx, cy = C

        def f(u):
            px, py = self.flank_xy(side, tooth, u)
            return (px - cx) ** 2 + (py - cy) ** 2

        us = linspace(0.0, u_max, 2001)
        i = argbest([f(u) for u in us])
        return stationary_point(f, us[max(i - 1, 0)], us[min(i + 1, len(us) - 1)])

    def distance(self, C, side, tooth, d_mm, D):
        """Minimum 3-D distance from C (section z = 0) to a flank (over the whole involute and
        heights within +/- D): (distance, u*, h*)."""
        u_max = math.sqrt((max(self.r_a, self.r_f, math.hypot(*C) + D) * 1.2 / self.r_b) ** 2 - 1)
        if self.beta == 0.0:
            u, v = self.section_min(C, side, tooth, 0.0, d_mm, u_max)
            return math.sqrt(v), u, 0.0
        h, v = sampled_min(lambda h: self.section_min(C, side, tooth, h, d_mm, u_max)[1],
                           -D, D, 21)
        if abs(h) > 0.95 * D:
            raise RuntimeError("3-D distance: minimum at the end of the height range")
        u = self.section_min(C, side, tooth, h, d_mm, u_max)[0]
        return math.sqrt(v), u, h

    def roll_length(self, P):
        return math.sqrt(P[0] ** 2 + P[1] ** 2 - self.r_b ** 2)

    # --- ball --------------------------------------------------------------------------------
    def ball_nominal(self, D):
        """The radius of the centre on space 1's centre line: a scan from the base circle
        outward for the first sign change of distance - D/2, then bisection."""
        e = (math.cos(math.pi / self.z), math.sin(math.pi / self.z))

        def f(R):
            return self.distance((R * e[0], R * e[1]), "R", 1, 0.0, D)[0] - D / 2.0

        Rs = linspace(self.r_b * 1.0001, max(self.r_a, self.r_f) + D, 40)
        vals = [f(R) for R in Rs]
        for i in range(len(Rs) - 1):
            if (vals[i] > 0) != (vals[i + 1] > 0):
                return bisect(f, Rs[i], Rs[i + 1], tol=1e-16)
        raise RuntimeError("ball: no centre radius found")

    def ball_solve(self, space, D, d_right_mm, d_left_mm, start):
        """Centre (section z = 0) at distance D/2 from the R flank of tooth space+1 and the L
        flank of tooth space+2, both deviated: Newton with a central-difference Jacobian."""
        t_r = space + 1
        t_l = (space + 1) % self.z + 1

        def F(C):
            return (self.distance(C, "R", t_r, d_right_mm, D)[0] - D / 2.0,
                    self.distance(C, "L", t_l, d_left_mm, D)[0] - D / 2.0)

        C = tuple(start)
        e = 1e-6
        for _ in range(12):
            r = F(C)
            Fx = sub(F((C[0] + e, C[1])), F((C[0] - e, C[1])))
            Fy = sub(F((C[0], C[1] + e)), F((C[0], C[1] - e)))
            a, b, c, d = Fx[0] / (2 * e), Fy[0] / (2 * e), Fx[1] / (2 * e), Fy[1] / (2 * e)
            det = a * d - b * c
            step = ((-r[0] * d + r[1] * b) / det, (-r[1] * a + r[0] * c) / det)
            C = (C[0] + step[0], C[1] + step[1])
            if max(abs(step[0]), abs(step[1])) < 1e-14:
                break
        residual = max(abs(v) for v in F(C))
        if residual > 1e-13:
            raise RuntimeError("ball: Newton did not converge (residual %g)" % residual)
        return C

    # --- span --------------------------------------------------------------------------------
    def support(self, side, tooth, direction, d_mm, sign):
        """max over the flank (base circle ... tip) of sign * P.direction: (value, u*)."""
        n = 2001

        def f(u):
            return -sign * dot(self.flank_xy(side, tooth, u, 0.0, d_mm), direction)

        us = linspace(0.0, self.u_tip, n)
        i = argbest([f(u) for u in us])
        if i == 0 or i == n - 1:
            raise RuntimeError("span: the jaw's contact is at the end of the flank (k unsuitable)")
        u = stationary_point(f, us[i - 1], us[i + 1])
        return -f(u), u

    def span_transverse(self, k, d_first_mm=0.0, d_last_mm=0.0, extra_turn=0.0):
        """W_kt: jaws perpendicular to the span's symmetry axis (turned by extra_turn)."""
        psi = (k - 1) * self.tau / 2.0 + extra_turn
        direction = (-math.sin(psi), math.cos(psi))
        top, u_r = self.support("R", k, direction, d_last_mm, +1.0)
        bottom, u_l = self.support("L", 1, direction, d_first_mm, -1.0)
        return top + bottom, u_r, u_l

    def helicoid_normal(self, side, tooth, u, h=0.0):
        """Unit normal of the flank's helicoid at (u, h): the cross product of the partial
        derivatives (five-point differences)."""
        e = 1e-3
        Su = [derivative(lambda t: self.flank_xy(side, tooth, t, h)[i], u, e) for i in (0, 1)]
        Su.append(0.0)
        Sh = [derivative(lambda t: self.flank_xy(side, tooth, u, t)[i], h, e) for i in (0, 1)]
        Sh.append(1.0)
        n = (Su[1] * Sh[2] - Su[2] * Sh[1], Su[2] * Sh[0] - Su[0] * Sh[2],
             Su[0] * Sh[1] - Su[1] * Sh[0])
        return tuple(v / norm(n) for v in n)

    # --- tooth thickness ---------------------------------------------------------------------
    def polar_angle_at(self, side, tooth, radius, h, d_mm):
        u = bisect(lambda u: math.hypot(*self.flank_xy(side, tooth, u, h, d_mm)) - radius,
                   0.0, 10.0)
        x, y = self.flank_xy(side, tooth, u, h, d_mm)
        return math.atan2(y, x)

    def normal_thickness(self, d_left_mm=0.0, d_right_mm=0.0):
        """Tooth 1's thickness on the developed reference cylinder, normal to the flank traces
        (the traces are the flanks' helices: (arc r phi, h) for h = 0 and 1)."""
        r = self.r
        aR0 = r * self.polar_angle_at("R", 1, r, 0.0, d_right_mm)
        aL0 = r * self.polar_angle_at("L", 1, r, 0.0, d_left_mm)
        aR1 = r * self.polar_angle_at("R", 1, r, 1.0, d_right_mm)
        aL1 = r * self.polar_angle_at("L", 1, r, 1.0, d_left_mm)
        vR = (aR1 - aR0, 1.0)
        vL = (aL1 - aL0, 1.0)
        if abs(vR[0] * vL[1] - vR[1] * vL[0]) > 1e-12:
            raise RuntimeError("thickness: the flank traces are not parallel")
        n = (vR[1] / norm(vR), -vR[0] / norm(vR))
        return abs((aR0 - aL0) * n[0])


class Checker:
    def __init__(self):
        self.failures = []

    verbose = False

    def nominal(self, case, name, got, want, tol=NOMINAL_TOL_MM):
        if self.verbose:
            print("    %s %s: %.15g vs %.15g (%.2e)" % (case, name, got, want, got - want))
        if not abs(got - want) <= tol:
            self.failures.append("%s: %s = %.12g, brute force %.12g (difference %.3g > %.1g)"
                                 % (case, name, got, want, got - want, tol))
        return abs(got - want)

    def deviation(self, case, name, got, want, tol=DEVIATION_REL_TOL):
        if self.verbose:
            print("    %s %s: %.12g vs %.12g (rel %.2e)" % (case, name, got, want,
                                                           abs(got - want) / abs(want)))
        rel = abs(got - want) / max(abs(want), 1e-12)
        if not rel <= tol:
            self.failures.append("%s: %s = %.12g µm, brute force %.12g µm (relative %.3g > %.1g)"
                                 % (case, name, got, want, rel, tol))
        return rel


def parse(path):
    cases = []
    with open(path) as fh:
        for line in fh:
            t = line.split()
            if not t or t[0] != "case":
                continue
            f = {"id": t[1]}
            for kv in t[2:]:
                key, value = kv.split("=", 1)
                f[key] = value
            cases.append(f)
    return cases


def check_case(f, chk):
    cid = f["id"]
    gear = Gear(f)
    info = []
    nom, dev = [0.0], [0.0]
    um = 1e-3  # µm -> mm

    def nominal(name, got, want, tol=NOMINAL_TOL_MM):
        nom[0] = max(nom[0], chk.nominal(cid, name, got, want, tol))

    def deviation(name, got, want):
        dev[0] = max(dev[0], chk.deviation(cid, name, got, want))

    nominal("d_a", float(f["d_a"]), 2 * gear.r_a)

    # Tooth thickness and E_sn (d_L, d_R) = (0.3, 0.5) µm.
    nominal("s_n", float(f["s_n"]), gear.normal_thickness())
    dL, dR = 0.3 * um, 0.5 * um
    E_sn = (gear.normal_thickness(dL, dR) - gear.normal_thickness(-dL, -dR)) / (2 * um)
    deviation("E_sn", float(f["E_sn"]), E_sn)

    # Span and E_Wk (d_first, d_last) = (0.3, 0.5) µm.
    k = int(f["k"])
    if k > 0:
        W_t, u_r, u_l = gear.span_transverse(k)
        P_r = gear.flank_xy("R", k, u_r)
        P_l = gear.flank_xy("L", 1, u_l)
        n_r = gear.helicoid_normal("R", k, u_r)
        n_l = gear.helicoid_normal("L", 1, u_l)
        if abs(abs(dot(n_r, n_l)) - 1.0) > 1e-9:
            chk.failures.append("%s: the span's contact normals are not parallel" % cid)
        W_n = abs(dot(sub(P_r, P_l) + (0.0,), n_r))  # the tangent planes' distance
        cos_bb = math.hypot(n_r[0], n_r[1])  # W_n / W_t
        nominal("W_k", float(f["W_k"]), W_n)
        # The width does not depend on the jaws' direction (both flanks are involutes).
        nominal("W_kt (jaws turned 0.01 rad)", gear.span_transverse(k, extra_turn=0.01)[0], W_t,
                1e-9)
        nominal("span_L (R flank of tooth k)", float(f["span_L"]), gear.roll_length(P_r))
        nominal("span_L (L flank of tooth 1)", float(f["span_L"]), gear.roll_length(P_l))
        d1, d2 = 0.3 * um, 0.5 * um
        Wp = gear.span_transverse(k, d1, d2)[0] * cos_bb
        Wm = gear.span_transverse(k, -d1, -d2)[0] * cos_bb
        deviation("E_Wk", float(f["E_Wk"]), (Wp - Wm) / (2 * um))

    # Balls.
    D = float(f["D"])
    if D > 0:
        R = gear.ball_nominal(D)
        e_a = (math.cos(math.pi / gear.z), math.sin(math.pi / gear.z))
        C_a = (R * e_a[0], R * e_a[1])
        dist, u3, h3 = gear.distance(C_a, "R", 1, 0.0, D)
        L3 = gear.roll_length(gear.flank_xy("R", 1, u3, h3))  # the true 3-D contact
        # The foot of C's perpendicular to the flank in C's own section (on C's base tangent: the
        # normals of an involute are the base circle's tangents).
        u0 = gear.section_foot(C_a, "R", 1, 2.0 * gear.u_tip + 1.0)
        L0 = gear.roll_length(gear.flank_xy("R", 1, u0))
        nominal("ball symmetry (distance to L of tooth 2)",
                gear.distance(C_a, "L", 2, 0.0, D)[0], D / 2, 1e-10)
        nominal("r_K", float(f["r_K"]), R)
        nominal("alpha_Kt", float(f["alpha_Kt"]), math.acos(gear.r_b / R), ANGLE_TOL_RAD)
        # The 3-D contact comes from nested golden-section searches, resolved to ~1e-7 mm.
        nominal("ball_L (the 3-D contact's roll length)", float(f["ball_L"]), L3, 1e-6)
        if gear.beta != 0.0:
            info.append("the 3-D contact lies at L %.9f mm, h %+.6f mm (the centre's section's "
                        "foot on the same contact line: L %.9f mm)" % (L3, h3, L0))
        space_b = int(f["space_b"])
        e_b = (math.cos(math.pi / gear.z + space_b * gear.tau),
               math.sin(math.pi / gear.z + space_b * gear.tau))
        C_b = (R * e_b[0], R * e_b[1])
        nominal("M", float(f["M"]), norm(sub(C_a, C_b)) + gear.sigma * D)

        dRa, dLa = float(f["dRa"]) * um, float(f["dLa"]) * um
        dRb, dLb = float(f["dRb"]) * um, float(f["dLb"]) * um
        Ca_p = gear.ball_solve(0, D, dRa, dLa, C_a)
        Ca_m = gear.ball_solve(0, D, -dRa, -dLa, C_a)
        Cb_p = gear.ball_solve(space_b, D, dRb, dLb, C_b)
        Cb_m = gear.ball_solve(space_b, D, -dRb, -dLb, C_b)
        Da = tuple(v / (2 * um) for v in sub(Ca_p, Ca_m))  # first-order displacements, µm
        Db = tuple(v / (2 * um) for v in sub(Cb_p, Cb_m))
        deviation("radial_a", float(f["radial_a"]), dot(Da, e_a))
        deviation("radial_b", float(f["radial_b"]), dot(Db, e_b))
        Mp = norm(sub(Ca_p, Cb_p)) + gear.sigma * D
        Mm = norm(sub(Ca_m, Cb_m)) + gear.sigma * D
        E_MdK = (Mp - Mm) / (2 * um)
        if gear.z % 2 == 1:
            # The balls' displacements along the line of centres: radial and tangential parts.
            ab = sub(C_a, C_b)
            uab = (ab[0] / norm(ab), ab[1] / norm(ab))
            radial = dot(Da, e_a) * dot(e_a, uab) - dot(Db, e_b) * dot(e_b, uab)
            info.append("odd z: E_MdK %.9g µm = %.9g from the balls' radial displacements + "
                        "%.9g from their tangential ones" % (E_MdK, radial, E_MdK - radial))
        deviation("E_MdK", float(f["E_MdK"]), E_MdK)

    return nom[0], dev[0], info


def main(argv):
    verbose = len(argv) == 3 and argv[2] == "-v"
    if len(argv) != 2 and not verbose:
        print(__doc__)
        return 2
    Checker.verbose = verbose
    cases = parse(argv[1])
    if not cases:
        print("size_dimensions_reference: no cases in %s" % argv[1])
        return 1
    chk = Checker()
    for f in cases:
        before = len(chk.failures)
        try:
            nom, dev, info = check_case(f, chk)
        except (RuntimeError, ValueError, ZeroDivisionError) as e:
            chk.failures.append("%s: brute force failed: %s" % (f["id"], e))
            print("%-14s FAILED (%s)" % (f["id"], e))
            continue
        status = "ok" if len(chk.failures) == before else "MISMATCH"
        print("%-14s %-8s nominal max |diff| %.2e mm, deviations max rel %.2e" %
              (f["id"], status, nom, dev))
        for line in info:
            print("               note: " + line)
    if chk.failures:
        print("size_dimensions_reference: %d mismatch(es):" % len(chk.failures))
        for m in chk.failures:
            print("  " + m)
        return 1
    print("size_dimensions_reference: %d cases agree" % len(cases))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
