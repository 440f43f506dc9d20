// Shared helpers for the gravity tests (CMocka from C++).
#pragma once

#include <cmath>
#include <cstdarg>
#include <cstddef>
#include <cstdio>
#include <fstream>
#include <setjmp.h>
#include <string>
#include <type_traits>

extern "C" {
#include <cmocka.h>
}

#include "ggins/gravity/field.hpp"

namespace gt {

using ggins::gravity::Field;
using ggins::gravity::FieldSample;
using ggins::gravity::Mat3;
using ggins::gravity::Real;
using ggins::gravity::Vec3;

constexpr int kSkip = 77;  // CTest SKIP_RETURN_CODE

inline std::string egm96_path() { return std::string(GGINS_DATA_DIR) + "/egm96_to360.ascii.txt"; }
inline bool have_file(const std::string& p) { std::ifstream f(p); return static_cast<bool>(f); }

// Fourth-order central differences (error h^4/30 f^(5)), independent of any model code.
template <class F>
auto fd4(F f, const Vec3& r, int axis, Real h) {
  using T = std::decay_t<decltype(f(r))>;  // evaluate (no Eigen expression templates)
  Vec3 d = Vec3::Zero();
  d[axis] = h;
  const T a = f(r - 2 * d), b = f(r - d), c = f(r + d), e = f(r + 2 * d);
  const T out = (a - 8 * b + 8 * c - e) / (12 * h);
  return out;
}

struct FdErrors {
  Real g = 0;      // max |dV/dx_k - g_k|, m/s^2
  Real gamma = 0;  // max |dG_j/dx_k - Gamma_jk|, s^-2
  Real trace = 0;  // |trace Gamma|, s^-2
  Real asym = 0;   // max |Gamma - Gamma^T|, s^-2
};

inline FdErrors fd_check(const Field& f, const Vec3& r, Real hv, Real hg) {
  const FieldSample s = f.eval(r);
  FdErrors e;
  for (int k = 0; k < 3; ++k) {
    const Real dv = fd4([&](const Vec3& x) { return f.eval(x).potential; }, r, k, hv);
    e.g = std::max(e.g, std::fabs(dv - s.g[k]));
    const Vec3 dg = fd4([&](const Vec3& x) -> Vec3 { return f.eval(x).g; }, r, k, hg);
    e.gamma = std::max(e.gamma, (dg - s.gamma.col(k)).cwiseAbs().maxCoeff());
  }
  e.trace = std::fabs(s.gamma.trace());
  e.asym = (s.gamma - s.gamma.transpose()).cwiseAbs().maxCoeff();
  return e;
}

}  // namespace gt
