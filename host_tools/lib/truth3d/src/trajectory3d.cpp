#include "ggins/truth3d/trajectory3d.hpp"

#include <cmath>
#include <stdexcept>

#include "ggins/gravity/wgs84.hpp"

namespace ggins::truth3d {

namespace wgs = gravity::wgs84;

namespace {

template <int N>
JMat3<N> rot3(const Jet<N>& a) {  // [[c,-s,0],[s,c,0],[0,0,1]]
  using T = Jet<N>;
  T s, c;
  sincos(a, s, c);
  JMat3<N> m;
  m[0] = {c, -s, T(0)};
  m[1] = {s, c, T(0)};
  m[2] = {T(0), T(0), T(1)};
  return m;
}
template <int N>
JMat3<N> rot1(const Jet<N>& a) {  // [[1,0,0],[0,c,-s],[0,s,c]]
  using T = Jet<N>;
  T s, c;
  sincos(a, s, c);
  JMat3<N> m;
  m[0] = {T(1), T(0), T(0)};
  m[1] = {T(0), c, -s};
  m[2] = {T(0), s, c};
  return m;
}
JM constant(const JM& m) {
  JM r;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) r[i][j] = J(m[i][j].val());
  return r;
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

namespace {
template <int N>
void ned_axes_n(const Jet<N>& lat, const Jet<N>& lon, JVec3<N>& north, JVec3<N>& east, JVec3<N>& down) {
  Jet<N> sl, cl, so, co;
  sincos(lat, sl, cl);
  sincos(lon, so, co);
  north = {-sl * co, -sl * so, cl};
  east = {-so, co, Jet<N>(0)};
  down = {-cl * co, -cl * so, -sl};
}
}  // namespace

void ned_axes(const J& lat, const J& lon, JV& north, JV& east, JV& down) { ned_axes_n(lat, lon, north, east, down); }

template <int N>
JMat3<N> earth_rotation(Real t, Real omega_ie) {
  return rot3(omega_ie * Jet<N>::variable(t));
}
template JMat3<kJetOrder> earth_rotation<kJetOrder>(Real t, Real omega_ie);
template JMat3<kAttOrder> earth_rotation<kAttOrder>(Real t, Real omega_ie);

JMA coordinated_attitude_e(const JA& lat, const JA& lon, const JVA& v_e, const JVA& a_e) {
  JVA n, e, d;
  ned_axes_n(lat, lon, n, e, d);
  const JVA x = normalized(v_e);
  const JVA y0 = normalized(cross(d, x));
  const JVA z0 = cross(x, y0);
  const JA q = dot(a_e, y0) / kG0;  // tan(bank)
  const JA ic = 1 / sqrt(1 + q * q);
  const JA c = ic, s = q * ic;
  const JVA y = scale(y0, c) + scale(z0, s);
  const JVA z = scale(z0, c) - scale(y0, s);
  JMA C;
  for (int i = 0; i < 3; ++i) C[i] = {x[i], y[i], z[i]};
  return C;
}

JM coordinated_attitude_e(const J& lat, const J& lon, const JV& v_e, const JV& a_e) {
  return resize<kJetOrder>(coordinated_attitude_e(resize<kAttOrder>(lat), resize<kAttOrder>(lon),
                                                  resize<kAttOrder>(v_e), resize<kAttOrder>(a_e)));
}

namespace {
// The coordinated C_b_i = R3(omega_ie t) C_b_e of a trajectory's order-4 jets (order 2, widened).
JM coordinated_attitude_i(Real t, const J& lat, const J& lon, const JV& r_e) {
  const JV v = deriv(r_e), a = deriv(v);
  const JMA C_b_e = coordinated_attitude_e(resize<kAttOrder>(lat), resize<kAttOrder>(lon), resize<kAttOrder>(v),
                                           resize<kAttOrder>(a));
  return resize<kJetOrder>(matmul(earth_rotation<kAttOrder>(t), C_b_e));
}
}  // namespace

State3 Trajectory3::at(Real t) const {
  JV r4;
  JM C4;
  jets(t, r4, C4);
  // State3 needs derivatives up to 2: order-2 jets (same coefficients 0..2)
  const JVA rj = resize<kAttOrder>(r4);
  const JMA Cj = resize<kAttOrder>(C4);
  const JMA R = earth_rotation<kAttOrder>(t, omega_ie());
  const JVA ri = matvec(R, rj);
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
  wgs::radii(p.lat0, M, N);
  rate_scale_[0] = 1 / (M + p.h0);
  rate_scale_[1] = 1 / ((N + p.h0) * std::cos(p.lat0));
  rate_scale_[2] = -1;
  for (const auto& m : p.maneuvers) {
    if (!(m.duration_s > 0)) throw std::invalid_argument("flight: maneuver duration must be > 0");
    const Real tau = m.duration_s / 8;
    sp0_.push_back(softplus(J(-m.t_s / tau)).val());
  }
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
  for (std::size_t k = 0; k < p_.maneuvers.size(); ++k) {
    const Maneuver& m = p_.maneuvers[k];
    const Real tau = m.duration_s / 8;
    const J sp = softplus((T - m.t_s) / tau) - sp0_[k];
    for (int i = 0; i < 3; ++i)
      if (m.dv_ned[i] != 0) pos[i] += sp * (m.dv_ned[i] * tau);
  }
  lat = p_.lat0 + pos[0] * rate_scale_[0];
  lon = p_.lon0 + pos[1] * rate_scale_[1];
  h = p_.h0 + pos[2] * rate_scale_[2];
}

JM Flight3::attitude(Real t, const J& lat, const J& lon, const JV& r_e) const {
  return coordinated_attitude_i(t, lat, lon, r_e);
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
  wgs::radii(p.lat_c, M, N);
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
  C_b_i = coordinated_attitude_i(t, lat, lon, r_e);
}

// ---- Great circle ----------------------------------------------------------

GreatCircle3::GreatCircle3(const GreatCircleParams& p, Attitude att) : p_(p), att_(att), rho_(p.radius_m + p.height_m) {
  if (!(rho_ > 0) || !(p.speed_mps >= 0)) throw std::invalid_argument("great circle: radius > 0, speed >= 0");
  const Real cl = std::cos(p.lat0), sl = std::sin(p.lat0), co = std::cos(p.lon0), so = std::sin(p.lon0);
  u_ = Vec3(cl * co, cl * so, sl);
  const Vec3 north(-sl * co, -sl * so, cl), east(-so, co, 0);
  w_ = std::cos(p.heading) * north + std::sin(p.heading) * east;
  n_ = u_.cross(w_);
}

void GreatCircle3::jets(Real t, JV& r_e, JM& C_b_i) const {
  const J phi = J::variable(t) * (p_.speed_mps / rho_);
  J s, c;
  sincos(phi, s, c);
  JV rh, th;
  for (std::size_t i = 0; i < 3; ++i) {
    const auto ei = static_cast<Eigen::Index>(i);
    rh[i] = c * u_(ei) + s * w_(ei);   // r^
    th[i] = c * w_(ei) - s * u_(ei);   // direction of flight
    r_e[i] = rh[i] * rho_;
  }
  JM C_b_e;
  for (std::size_t i = 0; i < 3; ++i) {
    const auto ei = static_cast<Eigen::Index>(i);
    if (att_ == Attitude::Stabilized) {
      C_b_i[i] = {J(w_(ei)), J(-n_(ei)), J(-u_(ei))};
    } else {
      C_b_e[i] = {th[i], J(-n_(ei)), -rh[i]};
    }
  }
  if (att_ != Attitude::Stabilized) C_b_i = matmul(earth_rotation<kJetOrder>(t, p_.omega_ie), C_b_e);
}

// ---- Tumble ----------------------------------------------------------------

Tumble3::Tumble3(const TumbleParams& p) : p_(p) { r_e_ = wgs::geodetic_to_ecef(p.lat, p.lon, p.h); }

void Tumble3::jets(Real t, JV& r_e, JM& C_b_i) const {
  r_e = {J(r_e_(0)), J(r_e_(1)), J(r_e_(2))};
  const JA T = JA::variable(t);  // the attitude to order 2
  const JA psi = p_.psi0 + T * p_.precession_radps;
  const JA nu = p_.nutation0 + sin(T * p_.nutation_radps) * p_.nutation_amp;
  const JA phi = p_.phi0 + T * p_.spin_radps;
  C_b_i = resize<kJetOrder>(matmul(matmul(rot3(psi), rot1(nu)), rot3(phi)));
}

// ---- helpers ---------------------------------------------------------------


Mat3 ned_to_ecef(Real lat, Real lon) {
  Real sl, cl, so, co;
  gravity::sincos_ld(lat, sl, cl);
  gravity::sincos_ld(lon, so, co);
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
