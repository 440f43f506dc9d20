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
#include "ggins/gravity/normal.hpp"
#include "ggins/gravity/wgs84.hpp"

#include <vector>

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

// Field::third against 4th-order finite differences of Gamma: returns the max
// abs error and (in scale) the max |T| seen; supported = false if not provided.
inline Real third_fd_check(const Field& f, const Vec3& r, Real h, Real& scale, bool& supported) {
  ggins::gravity::Tensor3 t;
  supported = f.third(r, t);
  if (!supported) return 0;
  Real worst = 0;
  for (int k = 0; k < 3; ++k) {
    const Mat3 dG = fd4([&](const Vec3& x) -> Mat3 { return f.eval(x).gamma; }, r, k, h);
    worst = std::max(worst, (dG - t[k]).cwiseAbs().maxCoeff());
    scale = std::max(scale, t[k].cwiseAbs().maxCoeff());
    // symmetric in all three indices
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) worst = std::max(worst, std::fabs(t[k](i, j) - t[i](k, j)));
  }
  return worst;
}

// Normalised C20 of the WGS-84 normal field, extracted by Gauss-Legendre
// quadrature of V on the sphere r = a: C_n0 = (r/GM)(r/a)^n 1/2 int V Pbar_n dt.
inline void gauss_legendre(int n, std::vector<Real>& x, std::vector<Real>& w) {
  x.resize(n); w.resize(n);
  for (int i = 0; i < n; ++i) {
    Real z = std::cos(static_cast<Real>(M_PI) * (i + 0.75L) / (n + 0.5L)), dp = 0;
    for (int it = 0; it < 100; ++it) {
      Real p0 = 1, p1 = z;
      for (int k = 2; k <= n; ++k) { const Real p2 = ((2 * k - 1) * z * p1 - (k - 1) * p0) / k; p0 = p1; p1 = p2; }
      dp = n * (z * p1 - p0) / (z * z - 1);
      const Real dz = p1 / dp;
      z -= dz;
      if (std::fabs(dz) < 1e-19L) break;
    }
    x[i] = z; w[i] = 2 / ((1 - z * z) * dp * dp);
  }
}

inline Real normal_c20() {
  const ggins::gravity::NormalField f;
  std::vector<Real> x, w;
  gauss_legendre(48, x, w);
  const Real a = ggins::gravity::wgs84::kA;
  Real acc = 0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    const Real t = x[i];
    const Vec3 r(a * std::sqrt(1 - t * t), 0, a * t);
    acc += w[i] * f.eval(r).potential * std::sqrt(5.0L) * (3 * t * t - 1) / 2;
  }
  return 0.5L * acc * a / ggins::gravity::wgs84::kGm;
}

}  // namespace gt
