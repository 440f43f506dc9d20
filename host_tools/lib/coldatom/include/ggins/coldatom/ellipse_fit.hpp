// Standard ellipse-fitting estimator of the differential phase from a batch of
// pairs (the baseline of Phillips et al., section II, after Foster et al. 2002,
// their ref. 44): fit the conic A x^2 + B x y + C y^2 + D x + E y + F = 0 to the
// pairs by direct least squares with the ellipse constraint 4AC - B^2 = 1
// (Fitzgibbon, Pilu & Fisher 1999, in the numerically stable form of Halir &
// Flusser 1998), then
//   dphi = acos( -B / (2 sqrt(A C)) )        (Foster et al. 2002, from eq. 3 of Phillips)
// since x = x0 + a cos(theta), y = y0 + b cos(theta + dphi) satisfies
//   (x-x0)^2/a^2 - 2 (x-x0)(y-y0) cos(dphi)/(a b) + (y-y0)^2/b^2 = sin^2(dphi).
// dphi is returned in [0, pi] (the fit cannot tell the sign).
#pragma once

#include <vector>

namespace ggins::coldatom {

struct Conic {
  double A = 0, B = 0, C = 0, D = 0, E = 0, F = 0;
};

struct EllipseFit {
  bool ok = false;
  Conic conic;          // in the caller's coordinates, scaled so that 4AC - B^2 = 1
  double dphi = 0;      // rad, [0, pi]
  double x0 = 0, y0 = 0;  // centre
};

// Needs at least 6 pairs; ok = false when the fit is not an ellipse or degenerate.
EllipseFit fit_ellipse(const std::vector<double>& x, const std::vector<double>& y);

}  // namespace ggins::coldatom
