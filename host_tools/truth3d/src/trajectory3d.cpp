#include "ggins/truth3d/trajectory3d.hpp"

#include <cmath>
#include <stdexcept>

#include "ggins/gravity/wgs84.hpp"

namespace ggins::truth3d {

namespace wgs = gravity::wgs84;

namespace {

JM rot3(const J& a) {  // [[c,-s,0],[s,c,0],[0,0,1]]
  J s, c;
  sincos(a, s, c);
  JM m;
  m[0] = {c, -s, J(0)};
  m[1] = {s, c, J(0)};
  m[2] = {J(0), J(0), J(1)};
  return m;
}
JM rot1(const J& a) {  // [[1,0,0],[0,c,-s],[0,s,c]]
  J s, c;
  sincos(a, s, c);
  JM m;
  m[0] = {J(1), J(0), J(0)};
  m[1] = {J(0), c, -s};
  m[2] = {J(0), s, c};
  return m;
}
JM constant(const JM& m) {
  JM r;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) r[i][j] = J(m[i][j].val());
  return r;
}
void radii(Real lat, Real& M, Real& N) {
  const Real s = std::sin(lat), w = 1 - wgs::kE2 * s * s;
  N = wgs::kA / std::sqrt(w);
  M = wgs::kA * (1 - wgs::kE2) / (w * std::sqrt(w));
}
Vec3 vee(const Mat3& w) { return Vec3(w(2, 1), w(0, 2), w(1, 0)); }

}  // namespace

JV geodetic_to_ecef(const J& lat, const J& lon, const J& h) {
  J sl, cl, so, co;
  sincos(lat, sl, cl);
  sincos(lon, so, co);
  const J N = wgs::kA / sqrt(1 - wgs::kE2 * sl * sl);
  const J nh = N + h;
  return {nh * cl * co, nh * cl * so, (N * (1 - wgs::kE2) + h) * sl};
}

void ned_axes(const J& lat, const J& lon, JV& north, JV& east, JV& down) {
  J sl, cl, so, co;
  sincos(lat, sl, cl);
  sincos(lon, so, co);
  north = {-sl * co, -sl * so, cl};
  east = {-so, co, J(0)};
  down = {-cl * co, -cl * so, -sl};
}

JM earth_rotation(Real t) { return rot3(kOmegaIe * J::variable(t)); }

JM coordinated_attitude_e(const J& lat, const J& lon, const JV& v_e, const JV& a_e) {
  JV n, e, d;
  ned_axes(lat, lon, n, e, d);
  const JV x = normalized(v_e);
  const JV y0 = normalized(cross(d, x));
  const JV z0 = cross(x, y0);
  const J q = dot(a_e, y0) / kG0;  // tan(bank)
  const J ic = 1 / sqrt(1 + q * q);
  const J c = ic, s = q * ic;
  const JV y = scale(y0, c) + scale(z0, s);
  const JV z = scale(z0, c) - scale(y0, s);
  JM C;
  for (int i = 0; i < 3; ++i) C[i] = {x[i], y[i], z[i]};
  return C;
}

State3 Trajectory3::at(Real t) const {
  JV rj;
  JM Cj;
  jets(t, rj, Cj);
  const JM R = earth_rotation(t);
  const JV ri = matvec(R, rj);
  State3 s;
  s.t = t;
  s.r_i = value(ri);
  s.v_i = deriv_value(ri, 1);
  s.a_i = deriv_value(ri, 2);
  s.r_e = value(rj);
  s.v_e = deriv_value(rj, 1);
  s.a_e = deriv_value(rj, 2);
  wgs::ecef_to_geodetic(s.r_e, s.lat, s.lon, s.h);
  s.C_b_i = value(Cj);
  s.C_b_i_dot = deriv_value(Cj, 1);
  s.C_b_i_ddot = deriv_value(Cj, 2);
  s.C_e_i = value(R);
  s.C_b_e = s.C_e_i.transpose() * s.C_b_i;
  const Mat3 W = s.C_b_i.transpose() * s.C_b_i_dot;                       // [omega x]
  const Mat3 Wd = s.C_b_i_dot.transpose() * s.C_b_i_dot + s.C_b_i.transpose() * s.C_b_i_ddot;  // [omega' x]
  s.omega_b = 0.5L * (vee(W) - vee(W.transpose()));
  s.omega_dot_b = 0.5L * (vee(Wd) - vee(Wd.transpose()));
  const Mat3 C_b_n = ned_to_ecef(s.lat, s.lon).transpose() * s.C_b_e;
  euler_zyx(C_b_n, s.roll, s.pitch, s.yaw);
  return s;
}

// ---- Flight ----------------------------------------------------------------

Flight3::Flight3(const FlightParams& p, Attitude att) : p_(p), att_(att) {
  if (!std::isfinite(p.lat0) || std::fabs(p.lat0) > 1.5L) throw std::invalid_argument("flight: |lat0| must be < 86 deg");
  Real M, N;
  radii(p.lat0, M, N);
  rate_scale_[0] = 1 / (M + p.h0);
  rate_scale_[1] = 1 / ((N + p.h0) * std::cos(p.lat0));
  rate_scale_[2] = -1;
  for (const auto& m : p.maneuvers)
    if (!(m.duration_s > 0)) throw std::invalid_argument("flight: maneuver duration must be > 0");
  const Real v2 = p.v_ned0[0] * p.v_ned0[0] + p.v_ned0[1] * p.v_ned0[1] + p.v_ned0[2] * p.v_ned0[2];
  if (!(v2 > 1)) throw std::invalid_argument("flight: initial speed must be > 1 m/s (attitude along the velocity)");
  J lat, lon, h;
  geodetic(0, lat, lon, h);
  const JV r = geodetic_to_ecef(lat, lon, h);
  c0_ = constant(attitude(0, lat, lon, r));
}

void Flight3::geodetic(Real t, J& lat, J& lon, J& h) const {
  const J T = J::variable(t);
  J pos[3];
  for (int i = 0; i < 3; ++i) pos[i] = T * p_.v_ned0[i];
  for (const auto& m : p_.maneuvers) {
    const Real tau = m.duration_s / 8;
    const J sp = softplus((T - m.t_s) / tau) - softplus(J(-m.t_s / tau)).val();
    for (int i = 0; i < 3; ++i)
      if (m.dv_ned[i] != 0) pos[i] += sp * (m.dv_ned[i] * tau);
  }
  lat = p_.lat0 + pos[0] * rate_scale_[0];
  lon = p_.lon0 + pos[1] * rate_scale_[1];
  h = p_.h0 + pos[2] * rate_scale_[2];
}

JM Flight3::attitude(Real t, const J& lat, const J& lon, const JV& r_e) const {
  const JV v = deriv(r_e), a = deriv(v);
  return matmul(earth_rotation(t), coordinated_attitude_e(lat, lon, v, a));
}

void Flight3::jets(Real t, JV& r_e, JM& C_b_i) const {
  J lat, lon, h;
  geodetic(t, lat, lon, h);
  r_e = geodetic_to_ecef(lat, lon, h);
  C_b_i = att_ == Attitude::Stabilized ? c0_ : attitude(t, lat, lon, r_e);
}

// ---- Circle ----------------------------------------------------------------

Circle3::Circle3(const CircleParams& p, Attitude att) : p_(p), att_(att) {
  if (!(p.radius_m > 0) || !(std::fabs(p.speed_mps) > 1)) throw std::invalid_argument("circle: radius > 0, |speed| > 1");
  Real M, N;
  radii(p.lat_c, M, N);
  alat_ = p.radius_m / (M + p.h);
  alon_ = p.radius_m / ((N + p.h) * std::cos(p.lat_c));
  w_ = p.speed_mps / p.radius_m;
  JV r;
  JM C;
  att_ = Attitude::Coordinated;
  jets(0, r, C);
  att_ = att;
  c0_ = constant(C);
}

void Circle3::jets(Real t, JV& r_e, JM& C_b_i) const {
  const J T = J::variable(t);
  J s, c;
  sincos(T * w_, s, c);
  const J lat = p_.lat_c + s * alat_, lon = p_.lon_c - c * alon_, h(p_.h);
  r_e = geodetic_to_ecef(lat, lon, h);
  if (att_ == Attitude::Stabilized) {
    C_b_i = c0_;
    return;
  }
  const JV v = deriv(r_e), a = deriv(v);
  C_b_i = matmul(earth_rotation(t), coordinated_attitude_e(lat, lon, v, a));
}

// ---- Tumble ----------------------------------------------------------------

Tumble3::Tumble3(const TumbleParams& p) : p_(p) { r_e_ = wgs::geodetic_to_ecef(p.lat, p.lon, p.h); }

void Tumble3::jets(Real t, JV& r_e, JM& C_b_i) const {
  const J T = J::variable(t);
  r_e = {J(r_e_(0)), J(r_e_(1)), J(r_e_(2))};
  const J psi = p_.psi0 + T * p_.precession_radps;
  const J nu = p_.nutation0 + sin(T * p_.nutation_radps) * p_.nutation_amp;
  const J phi = p_.phi0 + T * p_.spin_radps;
  C_b_i = matmul(matmul(rot3(psi), rot1(nu)), rot3(phi));
}

// ---- helpers ---------------------------------------------------------------

Mat3 value(const JM& m) { return deriv_value(m, 0); }
Vec3 value(const JV& v) { return deriv_value(v, 0); }
Mat3 deriv_value(const JM& m, int k) {
  Mat3 r;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) r(i, j) = m[i][j].d(k);
  return r;
}
Vec3 deriv_value(const JV& v, int k) { return Vec3(v[0].d(k), v[1].d(k), v[2].d(k)); }

Mat3 ned_to_ecef(Real lat, Real lon) {
  const Real sl = std::sin(lat), cl = std::cos(lat), so = std::sin(lon), co = std::cos(lon);
  Mat3 C;
  C << -sl * co, -so, -cl * co,  //
      -sl * so, co, -cl * so,    //
      cl, 0, -sl;
  return C;
}

void euler_zyx(const Mat3& C, Real& roll, Real& pitch, Real& yaw) {
  pitch = -std::asin(std::max(-1.0L, std::min(1.0L, C(2, 0))));
  roll = std::atan2(C(2, 1), C(2, 2));
  yaw = std::atan2(C(1, 0), C(0, 0));
}

}  // namespace ggins::truth3d
