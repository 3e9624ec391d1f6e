// The profile and helix filter of gear evaluation: the Gaussian low-pass of ISO 16610-21, whose
// weighting function s(x) = exp(−π (x / (α λc))²) / (α λc), α = √(ln 2 / π), passes a sine of
// wavelength λ with the amplitude ratio exp(−π (α λc / λ)²) — one half at the cut-off λc. A
// gear trace is short (L_α is a few cut-offs), so the filter is the first-order Gaussian
// regression (ISO 16610-31's linear form, Seewig 2005): at each sample the weighted least-squares
// line through its neighbours, weighted by s; in the interior it is the Gaussian filter itself,
// and at the ends it keeps a straight trace straight and loses no samples (the plain Gaussian,
// renormalised at the ends, would bend a slope by 0.15 × slope × λc at an end and bias f_Hα, f_Hβ).
// x in mm (roll length for a profile, face position for a helix), d in µm.
#pragma once

#include <span>
#include <vector>

namespace gearmc {

// √(ln 2 / π): the Gaussian's width factor, so that λc transmits 50 %.
inline constexpr double kGaussianFilterAlpha = 0.46971863934982566689;

// The trace d(x) filtered with cut-off `cutoff_mm` (> 0): the same samples, x ascending (any
// spacing: each neighbour weighs s(x_j − x_i) times the trapezoid width of its sample). Weights
// below 1e-12 of the centre's are left out (|x_j − x_i| > 1.4 λc).
std::vector<double> gaussian_regression_filter(std::span<const double> x_mm,
                                               std::span<const double> d_um, double cutoff_mm);

// The amplitude ratio of a sine of wavelength λ through the filter (ISO 16610-21).
double gaussian_filter_transmission(double wavelength_mm, double cutoff_mm);

}  // namespace gearmc
