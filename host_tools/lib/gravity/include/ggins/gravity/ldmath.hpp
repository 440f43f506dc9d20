// sin and cos in long double with a cheap exact argument reduction near pi/2.
//
// glibc's sinl/cosl (x87 80-bit) reduce every |x| > pi/4 with the
// multi-precision Payne-Hanek routine, ~10x the cost of the kernel; latitudes
// above 45 deg hit it on every call. For pi/4 < |x| < 3 pi/4 this uses
//   sin x = sign(x) cos r,  cos x = sin r,  r = pi/2 - |x| = (P_hi - |x|) + P_lo,
// where P_hi + P_lo is pi/2 to 128 bits. P_hi - |x| is exact (Sterbenz: P_hi/2 <=
// |x| <= 2 P_hi) and adding P_lo (|P_lo| < 2^-64 P_hi) rounds once, so r is
// correct to half an ulp of r and the results to about one ulp, as
// sinl/cosl; outside that range it calls them.
#pragma once

#include <cmath>

namespace ggins::gravity {

inline void sincos_ld(long double x, long double& s, long double& c) {
  constexpr long double kPio2Hi = 1.570796326794896619256404479703093102216L;  // pi/2 rounded to 64 bits (exact)
  constexpr long double kPio2Lo = -2.508278806334166011778664e-20L;            // pi/2 - kPio2Hi
  constexpr long double kPio4 = 0.78539816339744830961566084581987572L;
  const long double ax = std::fabs(x);
  if (ax <= kPio4 || !(ax < 3 * kPio4)) {
    s = std::sin(x);
    c = std::cos(x);
    return;
  }
  const long double r = (kPio2Hi - ax) + kPio2Lo;
  const long double sr = std::sin(r), cr = std::cos(r);
  s = x < 0 ? -cr : cr;
  c = sr;
}

}  // namespace ggins::gravity
