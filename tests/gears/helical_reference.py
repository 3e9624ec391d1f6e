#!/usr/bin/env python3
"""Independent reference values for tests/gears/helical_gear_test.cpp: the ISO 21771:2007
relations of a helical gear evaluated with Python's math module (double precision), written out
from the standard's formulas, not from gearmc's code.

Gear: the issue's example, z 31, m_n 4 mm, alpha_n 20 deg, beta 15 deg, x 0.2, ISO 53 profile A
(h_aP 1, h_fP 1.25, rho_fP 0.38, in modules).
  m_t = m_n / cos(beta)                         (ISO 21771 §4.3, transverse module)
  tan(alpha_t) = tan(alpha_n) / cos(beta)       (transverse pressure angle)
  d = z m_t, d_b = d cos(alpha_t)
  sin(beta_b) = sin(beta) cos(alpha_n)          (base helix angle)
  p_z = pi d / tan(beta)                        (lead)
  d_a = d + 2 m_n (h_aP + x), d_f = d - 2 m_n (h_fP - x)
  s_t = m_t (pi/2 + 2 x tan(alpha_n))           (transverse tooth thickness on d)
  W_k = m_n cos(alpha_n) [(k - 0.5) pi + z inv(alpha_t)] + 2 x m_n sin(alpha_n)
                                                (base tangent length over k teeth, normal)
Run: python3 tests/gears/helical_reference.py
"""
import math

z, m_n, alpha_n_deg, beta_deg, x = 31, 4.0, 20.0, 15.0, 0.2
h_aP, h_fP = 1.0, 1.25
alpha_n, beta = math.radians(alpha_n_deg), math.radians(beta_deg)
m_t = m_n / math.cos(beta)
alpha_t = math.atan(math.tan(alpha_n) / math.cos(beta))
d = z * m_t
d_b = d * math.cos(alpha_t)
beta_b = math.asin(math.sin(beta) * math.cos(alpha_n))
p_z = math.pi * d / math.tan(beta)
d_a = d + 2 * m_n * (h_aP + x)
d_f = d - 2 * m_n * (h_fP - x)
s_t = m_t * (math.pi / 2 + 2 * x * math.tan(alpha_n))
inv = lambda a: math.tan(a) - a
W = {k: m_n * math.cos(alpha_n) * ((k - 0.5) * math.pi + z * inv(alpha_t)) +
     2 * x * m_n * math.sin(alpha_n) for k in (2, 4, 6)}
for name, value in [("m_t", m_t), ("alpha_t_deg", math.degrees(alpha_t)), ("d", d),
                    ("d_b", d_b), ("beta_b_deg", math.degrees(beta_b)), ("p_z", p_z),
                    ("d_a", d_a), ("d_f", d_f), ("s_t", s_t)] + \
                   [("W_%d" % k, w) for k, w in W.items()]:
    print("%-12s %.12f" % (name, value))
