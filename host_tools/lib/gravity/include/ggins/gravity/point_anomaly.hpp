// Anomaly fields made of buried point masses (Rubenstein & Winter 1964,
// "Point mass simulation"), seeded, with statistics set to the measured ones
// of Rubenstein & Winter eq. (5): rms deflection of the vertical 4.5 arcsec,
// correlation exp(-|d| / 33 n.mi.).
//
// Statistical design (derivation in docs/gravity.md). Masses of one layer lie
// at depth D below the ellipsoid, one per cell of a grid of spacing s
// (stratified-uniform position in the cell, so the layer is a homogeneous
// random field with area density n = 1/s^2), with independent zero-mean
// Gaussian GM values of variance sigma^2. Seen from height h, with
// p = 2(D + h), the covariance of the deflection component PERPENDICULAR to
// the line joining two points a distance d apart is (planar approximation,
// by the Hankel transforms of e^{-pk}: Gradshteyn & Ryzhik 6.611.1 and the
// Bessel recurrence J2 = 2J1/z - J0)
//   C_perp(d) = pi n sigma^2 / g^2 * 2 (R - p) / (d^2 R),       R = sqrt(p^2 + d^2),
// and of the component ALONG that line
//   C_par(d)  = pi n sigma^2 / g^2 * [2p / R^3 - 2 (R - p) / (d^2 R)],
// both with variance C(0) = pi n sigma^2 / (g^2 p^2).
// A harmonic field cannot give an exponential C_par: its along-line spectrum
// vanishes at zero wavenumber, so the integral of C_par over d is zero. The
// exponential is therefore imposed on C_perp (the deflection across the line
// of stations, which along R&W's E-W line on the 35th parallel is the
// meridian component). Layers at effective depths D + h = c_j L (c_j from
// RwAnomalyConfig) get variance weights w_j >= 0 fitted by non-negative least
// squares so that sum_j w_j c_perp_j(d) matches exp(-d/L) on [0, 4L]; the
// weights are scaled to sum to one (rms exactly delta at d = 0).
#pragma once

#include "ggins/gravity/field.hpp"

#include <cstdint>
#include <vector>

namespace ggins::gravity {

struct PointMass {
  Vec3 r_e = Vec3::Zero();  // position, Earth-fixed, m
  Real gm = 0;              // G * mass, m^3/s^2 (negative: mass deficit)
};

class PointMassAnomalyField final : public Field {
 public:
  explicit PointMassAnomalyField(std::vector<PointMass> masses, std::string label = "point-mass-anomaly");
  FieldSample eval(const Vec3& r_e) const override;
  std::string name() const override { return label_; }
  bool third(const Vec3& r_e, Tensor3& t) const override;
  Vec3 gravitation(const Vec3& r_e) const override;  // G only, in double (cheaper; anomaly-sized values)
  const std::vector<PointMass>& masses() const { return masses_; }

 private:
  std::vector<PointMass> masses_;
  std::string label_;
};

struct RwAnomalyConfig {
  Real lat0 = 0.6108652381980153L;      // region centre, geodetic latitude, rad (35 deg N)
  Real lon0 = -1.3962634015954636L;     // region centre, longitude, rad (80 deg W)
  Real half_size = 600e3L;              // region half-width (N-S and E-W), m
  Real ref_height = 0;                  // height at which the statistics hold, m
  Real rms_deflection = 4.5L / 206264.80624709636L;  // rad (R&W eq. 5)
  Real corr_length = 33.0L * 1852.0L;                 // m (R&W eq. 5)
  Real g_ref = 9.80L;                   // |g| converting deflection <-> horizontal gravitation, m/s^2
  std::vector<Real> depth_factors = {0.05L, 0.1L, 0.2L, 0.4L, 0.8L, 1.6L};  // (D + h)/L candidates
  Real spacing_factor = 1.5L;           // cell size s = spacing_factor * (D + h)
  Real min_depth = 500.0L;              // candidate layers shallower than this are dropped, m
  std::uint64_t seed = 1;
};

struct RwLayer {
  Real depth;      // below the ellipsoid, m
  Real spacing;    // cell size, m
  Real sigma_gm;   // std of G*m per mass, m^3/s^2
  Real weight;     // share of the deflection variance
  Real p;          // 2 (depth + ref_height), m
};

struct RwDesign {
  std::vector<RwLayer> layers;
  Real fit_max_error = 0;  // max |sum w c(d) - exp(-d/L)| on [0, 4L]
};

// Normalised (C(0) = 1) single-layer covariances, p = 2(D+h).
Real rw_corr_perp(Real d, Real p);
Real rw_corr_par(Real d, Real p);

RwDesign design_rubenstein_winter(const RwAnomalyConfig& cfg);
// The design's model covariance (rad^2) of the perpendicular/parallel deflection component at lag d.
Real rw_model_cov_perp(const RwDesign& design, Real rms_deflection, Real d);
Real rw_model_cov_par(const RwDesign& design, Real rms_deflection, Real d);
PointMassAnomalyField make_rubenstein_winter_field(const RwAnomalyConfig& cfg, RwDesign* design_out = nullptr);

}  // namespace ggins::gravity
