// WGS-84 constants and geodetic <-> Earth-fixed conversions.
// Defining constants: NIMA TR8350.2 (3rd ed., 2000), Table 3.1, as the firmware
// defines them (firmware/include/ggins/geo.h: one copy for the host and the target);
// derived constants quoted for checks: the tables of derived geometric and
// physical constants of TR8350.2 ch. 3 (table numbers not re-checked here).
#pragma once

#include "ggins/gravity/field.hpp"
extern "C" {
#include "ggins/geo.h"
}

namespace ggins::gravity::wgs84 {

constexpr Real kA = GG_WGS84_A_M;                  // semi-major axis, m (Table 3.1)
constexpr Real kInvF = GG_WGS84_INV_F;             // 1/f (Table 3.1)
constexpr Real kF = 1.0L / kInvF;
constexpr Real kGm = GG_WGS84_GM_M3PS2;            // m^3/s^2 incl. atmosphere (Table 3.1)
constexpr Real kOmega = GG_WGS84_OMEGA_IE;         // rad/s (Table 3.1)
constexpr Real kB = kA * (1.0L - kF);              // semi-minor axis, m
constexpr Real kE2 = kF * (2.0L - kF);             // first eccentricity squared

// Derived constants as published (TR8350.2 ch. 3), used by tests as independent truth.
constexpr Real kPubC20 = -0.484166774985e-3L;      // normalised C20 of the ellipsoid
constexpr Real kPubU0 = 62636851.7146L;            // normal potential on the ellipsoid, m^2/s^2
constexpr Real kPubGammaE = 9.7803253359L;         // normal gravity at the equator, m/s^2
constexpr Real kPubGammaP = 9.8321849378L;         // normal gravity at the poles, m/s^2
constexpr Real kPubK = 0.00193185265241L;          // Somigliana constant k
constexpr Real kPubE2 = 6.69437999014e-3L;         // e^2

// Geodetic latitude/longitude (rad), ellipsoidal height (m) -> Earth-fixed (m).
Vec3 geodetic_to_ecef(Real lat, Real lon, Real h);
// Earth-fixed -> geodetic (iterative, converged to long-double precision).
void ecef_to_geodetic(const Vec3& r, Real& lat, Real& lon, Real& h);
// Meridian (m) and prime-vertical (n) radii of curvature at geodetic latitude lat (rad), m:
// n = a / sqrt(1 - e^2 sin^2 lat), m = a (1 - e^2) / (1 - e^2 sin^2 lat)^(3/2).
void radii(Real lat, Real& m, Real& n);
// Rotation whose columns are the local east, north, up unit vectors at (lat, lon),
// i.e. C_n_e^T: r_e = C * r_enu.
Mat3 enu_to_ecef(Real lat, Real lon);

}  // namespace ggins::gravity::wgs84
