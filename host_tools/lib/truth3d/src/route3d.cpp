// Route trajectory: great-ellipse legs, fly-by turns, climbs, speed changes
// (see ggins/truth3d/route3d.hpp for the construction).
#include "ggins/truth3d/route3d.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <sstream>

#include "ggins/gravity/wgs84.hpp"

namespace ggins::truth3d {

namespace wgs = gravity::wgs84;

namespace {

using C = std::complex<Real>;
constexpr int kGTerms = 48;                // power series of G: truncation < (5/6 pi)^48 / 48! ~ 1e-38
constexpr Real kSkipWeight = 1e-40L;       // legs whose blend weight is below this are left out
constexpr Real kTurnSkipU = 120;           // |u| beyond which a turn is left out: its step is 0 or 1 to e^-120
constexpr Real kMaxTurn = 150.0L * kPi / 180.0L;

std::string deg(Real rad) {
  std::ostringstream os;
  os.precision(4);
  os << static_cast<double>(rad * 180 / kPi) << " deg";
  return os.str();
}
std::string num(Real x) {
  std::ostringstream os;
  os.precision(6);
  os << static_cast<double>(x);
  return os.str();
}

Vec3 unit(const Vec3& v) { return v / v.norm(); }

// Karney (2013) eqs. 17, 18, 21: A1, C1_l, C1'_l to eps^6.
void karney_series(Real eps, Real& A1, Real c1[7], Real c1p[7]) {
  const Real e2 = eps * eps, e3 = e2 * eps, e4 = e2 * e2, e5 = e4 * eps, e6 = e3 * e3;
  A1 = (1 + e2 / 4 + e4 / 64 + e6 / 256) / (1 - eps);
  c1[0] = 0;
  c1[1] = -eps / 2 + 3 * e3 / 16 - e5 / 32;
  c1[2] = -e2 / 16 + e4 / 32 - 9 * e6 / 2048;
  c1[3] = -e3 / 48 + 3 * e5 / 256;
  c1[4] = -5 * e4 / 512 + 3 * e6 / 512;
  c1[5] = -7 * e5 / 1280;
  c1[6] = -7 * e6 / 2048;
  c1p[0] = 0;
  c1p[1] = eps / 2 - 9 * e3 / 32 + 205 * e5 / 1536;
  c1p[2] = 5 * e2 / 16 - 37 * e4 / 96 + 1335 * e6 / 4096;
  c1p[3] = 29 * e3 / 96 - 75 * e5 / 128;
  c1p[4] = 539 * e4 / 1536 - 2391 * e6 / 2560;
  c1p[5] = 3467 * e5 / 7680;
  c1p[6] = 38081 * e6 / 61440;
}

Real arc(const Route3::Leg& g, Real beta) {
  Real s = beta;
  for (int l = 1; l <= 6; ++l) s += g.c1[l] * std::sin(2 * l * beta);
  return g.A1b * s;
}

// Central projection onto the ellipsoid.
JV to_surface(const JV& x) {
  const Real ia2 = 1 / (wgs::kA * wgs::kA), ib2 = 1 / (wgs::kB * wgs::kB);
  const J q = (x[0] * x[0] + x[1] * x[1]) * ia2 + x[2] * x[2] * ib2;
  return scale(x, 1 / sqrt(q));
}

J horner(const std::vector<Real>& c, const J& w) {  // sum_k c[k] w^k
  J r(0);
  for (size_t k = c.size(); k-- > 0;) r = r * w + c[k];
  return r;
}

}  // namespace

Route3::Route3(const RouteParams& p, Attitude att) : p_(p), att_(att) {
  const auto& W = p_.waypoints;
  if (W.size() < 2) throw RouteError(0, "route: at least two waypoints (the start and one more) are needed");
  const size_t n = W.size() - 1;  // legs
  for (size_t k = 0; k < W.size(); ++k) {
    const auto& w = W[k];
    const int ik = static_cast<int>(k);
    if (!std::isfinite(w.lat) || !std::isfinite(w.lon) || !std::isfinite(w.h))
      throw RouteError(ik, "route: waypoint position must be finite");
    if (std::fabs(w.lat) > 85.0L * kPi / 180.0L) throw RouteError(ik, "route: waypoint latitude must be within +-85 deg");
    if (k == 0) continue;
    if (!(w.speed_mps >= 1)) throw RouteError(ik, "route: speed_mps must be >= 1 m/s (attitude along the velocity)");
    if (!(w.climb_rate_mps > 0)) throw RouteError(ik, "route: climb_rate_mps must be > 0");
    if (!(w.accel_mps2 > 0)) throw RouteError(ik, "route: accel_mps2 must be > 0");
    if (!(w.vertical_accel_mps2 > 0)) throw RouteError(ik, "route: vertical_accel_mps2 must be > 0");
    if (!(w.turn_rate_radps > 0)) throw RouteError(ik, "route: turn_rate_dps must be > 0");
  }
  if (p_.initial_speed_mps >= 0 && !(p_.initial_speed_mps >= 1))
    throw RouteError(0, "route: the initial speed must be >= 1 m/s (attitude along the velocity)");

  // ---- legs: great ellipses through the footprints
  std::vector<Vec3> P(W.size());
  for (size_t k = 0; k < W.size(); ++k) P[k] = wgs::geodetic_to_ecef(W[k].lat, W[k].lon, 0);
  legs_.resize(n);
  for (size_t k = 0; k < n; ++k) {
    Leg& g = legs_[k];
    const Vec3 a = P[k], b = P[k + 1];
    const Vec3 cr = a.cross(b);
    if (cr.norm() < 1e-6L * a.norm() * b.norm())
      throw RouteError(static_cast<int>(k + 1), "route: waypoint coincides with (or is antipodal to) the one before");
    g.p = unit(cr);
    const Vec3 zc = Vec3(0, 0, 1).cross(g.p);
    g.e1 = zc.norm() > 1e-12L ? unit(zc) : unit(Vec3(a(0), a(1), 0));
    g.e2 = g.p.cross(g.e1);
    const Real sz = g.e2(2);
    g.b = 1 / std::sqrt((1 - sz * sz) / (wgs::kA * wgs::kA) + sz * sz / (wgs::kB * wgs::kB));
    Real A1;
    karney_series((wgs::kA - g.b) / (wgs::kA + g.b), A1, g.c1, g.c1p);
    g.A1b = A1 * g.b;
    const Real b0 = std::atan2(a.dot(g.e2) / g.b, a.dot(g.e1) / wgs::kA);
    Real b1 = std::atan2(b.dot(g.e2) / g.b, b.dot(g.e1) / wgs::kA);
    while (b1 <= b0) b1 += 2 * kPi;  // counter-clockwise about p: the short way (< pi)
    g.s0 = arc(g, b0);
    g.length = arc(g, b1) - g.s0;
    g.speed = W[k + 1].speed_mps;
  }

  // ---- turns at the interior waypoints
  turns_.resize(W.size());
  for (size_t k = 1; k < n; ++k) {
    Turn& tr = turns_[k];
    tr.on = true;
    // track directions (N, E) of leg k-1 at its end and of leg k at its start
    auto track = [&](const Leg& g, Real a_along, Real out[2]) {
      const Real tau = (g.s0 + a_along) / g.A1b;
      Real beta = tau;
      for (int l = 1; l <= 6; ++l) beta += g.c1p[l] * std::sin(2 * l * tau);
      const Vec3 dx = -wgs::kA * std::sin(beta) * g.e1 + g.b * std::cos(beta) * g.e2;
      const Mat3 Cne = ned_to_ecef(W[k].lat, W[k].lon);
      const Vec3 ned = Cne.transpose() * dx;
      const Real hn = std::hypot(ned(0), ned(1));
      out[0] = ned(0) / hn;
      out[1] = ned(1) / hn;
    };
    track(legs_[k - 1], legs_[k - 1].length, tr.d1);
    track(legs_[k], 0, tr.d2);
    const Real cr = tr.d1[0] * tr.d2[1] - tr.d1[1] * tr.d2[0], dt = tr.d1[0] * tr.d2[0] + tr.d1[1] * tr.d2[1];
    tr.dpsi = std::atan2(cr, dt);
    if (std::fabs(tr.dpsi) > kMaxTurn)
      throw RouteError(static_cast<int>(k), "route: the turn at this waypoint is " + deg(tr.dpsi) +
                                                " (at most +-150 deg: split a sharper turn with another waypoint)");
    tr.lambda = std::max<Real>(1, legs_[k - 1].speed * std::fabs(tr.dpsi) / (4 * W[k].turn_rate_radps));
    // exp(i a w) = 1 + (e^(ia) - 1) w + w (1 - w) Q(w): Q = sum q_m w^m, q_m = sum_{j=1..m+1} f_j
    const C ia(0, tr.dpsi), eia = std::exp(ia);
    std::vector<C> f(kGTerms + 2);
    C term(1, 0);
    for (int j = 1; j <= kGTerms + 1; ++j) {
      term *= ia / static_cast<Real>(j);
      f[static_cast<size_t>(j)] = term;
    }
    f[1] -= eia - C(1, 0);
    tr.g_re.assign(kGTerms + 1, 0);
    tr.g_im.assign(kGTerms + 1, 0);
    C q(0, 0), g1(0, 0);
    for (int m = 0; m < kGTerms; ++m) {
      q += f[static_cast<size_t>(m + 1)];
      const C gm = q / static_cast<Real>(m + 1);  // G = sum q_m w^(m+1) / (m+1)
      tr.g_re[static_cast<size_t>(m + 1)] = gm.real();
      tr.g_im[static_cast<size_t>(m + 1)] = gm.imag();
      g1 += gm;
    }
    const C emia = std::conj(eia);
    const Real sd = std::sin(tr.dpsi);
    const Real alpha = std::fabs(sd) > 1e-15L ? tr.lambda * (emia * g1).imag() / sd : 0;
    tr.P0[0] = alpha * tr.d1[0];
    tr.P0[1] = alpha * tr.d1[1];
    tr.c1 = alpha;
    tr.g1_re = g1.real();
    tr.g1_im = g1.imag();
    tr.c2 = alpha * std::cos(tr.dpsi) + tr.lambda * (emia * g1).real();
  }

  // ---- path length of each waypoint (turn centre)
  s_wp_.assign(W.size(), 0);
  for (size_t k = 1; k <= n; ++k) {
    const Real c2 = turns_[k - 1].on ? turns_[k - 1].c2 : 0, c1 = turns_[k].on ? turns_[k].c1 : 0;
    s_wp_[k] = s_wp_[k - 1] - c2 + c1 + legs_[k - 1].length;
    const Real need = 4 * ((turns_[k - 1].on ? turns_[k - 1].lambda : 0) + (turns_[k].on ? turns_[k].lambda : 0));
    if (!(s_wp_[k] - s_wp_[k - 1] > need))
      throw RouteError(static_cast<int>(k), "route: leg of " + num(legs_[k - 1].length) +
                                                " m is too short for the turns at its ends (their centres " +
                                                num(s_wp_[k] - s_wp_[k - 1]) + " m apart along the path, needs > " +
                                                num(need) + " m: lower the speed or raise turn_rate_dps)");
  }

  // ---- speed changes (sequential: each placed with the ones before it)
  v0_ = p_.initial_speed_mps >= 0 ? p_.initial_speed_mps : legs_[0].speed;
  Real cur = v0_;
  for (size_t k = 0; k < n; ++k) {
    const Real target = legs_[k].speed;
    if (target == cur) continue;
    SpeedChange c;
    c.dv = target - cur;
    c.tau = std::fabs(c.dv) / (4 * W[k + 1].accel_mps2);
    const Real s_ref = s_wp_[k] + (turns_[k].on ? 6 * turns_[k].lambda : 0);
    c.t = time_of_path(s_ref) + 10 * c.tau;
    dv_.push_back(c);
    cur = target;
    const Real s_end = s_wp_[k + 1] - (turns_[k + 1].on ? 6 * turns_[k + 1].lambda : 0);
    if (k + 1 < n && !(time_of_path(s_end) > c.t + 10 * c.tau))
      throw RouteError(static_cast<int>(k + 1), "route: the speed change to " + num(target) +
                                                    " m/s does not fit in the leg (raise accel_mps2 or lengthen it)");
  }
  for (size_t k = 1; k < n; ++k) turns_[k].s_w = s_wp_[k];
  t_wp_.assign(W.size(), 0);
  for (size_t k = 1; k <= n; ++k) t_wp_[k] = time_of_path(s_wp_[k]);

  // ---- climbs and descents
  for (size_t k = 0; k < n; ++k) {
    Leg& g = legs_[k];
    const Real dh = W[k + 1].h - W[k].h;
    if (dh == 0) continue;
    const Real rate = W[k + 1].climb_rate_mps;
    g.climb_rate = dh > 0 ? rate : -rate;
    g.tau_h = rate / (4 * W[k + 1].vertical_accel_mps2);
    g.t_climb0 = t_wp_[k] + 20 * g.tau_h;
    g.t_climb1 = g.t_climb0 + dh / g.climb_rate;
    if (!(g.t_climb1 + 20 * g.tau_h <= t_wp_[k + 1]))
      throw RouteError(static_cast<int>(k + 1),
                       "route: the height change of " + num(dh) + " m at " + num(rate) + " m/s needs " +
                           num(std::fabs(dh) / rate + 40 * g.tau_h) + " s but the leg lasts " +
                           num(t_wp_[k + 1] - t_wp_[k]) + " s (raise climb_rate_mps or lengthen the leg)");
  }

  if (att_ == Attitude::Stabilized) {
    att_ = Attitude::Coordinated;
    JV r;
    JM Cm;
    jets(0, r, Cm);
    att_ = Attitude::Stabilized;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) c0_[i][j] = J(Cm[i][j].val());
  }
}

J Route3::path_length(Real t) const {
  const J T = J::variable(t);
  J s = T * v0_;
  for (const auto& c : dv_) {
    const J sp = softplus((T - c.t) / c.tau) - softplus(J(-c.t / c.tau)).val();
    s += sp * (c.dv * c.tau);
  }
  return s;
}

Real Route3::time_of_path(Real s) const {
  Real t = s / v0_;
  for (int it = 0; it < 200; ++it) {
    const J sj = path_length(t);
    const Real dt = (sj.val() - s) / sj.d(1);
    t -= dt;
    if (std::fabs(dt) < 1e-15L * (1 + std::fabs(t))) break;
  }
  return t;
}

J Route3::height(Real t) const {
  const J T = J::variable(t);
  J h(p_.waypoints[0].h);
  for (const auto& g : legs_) {
    if (g.climb_rate == 0) continue;
    const Real th = g.tau_h;
    const J x = softplus((T - g.t_climb0) / th) - softplus((T - g.t_climb1) / th);
    const Real x0 = softplus(J(-g.t_climb0 / th)).val() - softplus(J(-g.t_climb1 / th)).val();
    h += (x - x0) * (g.climb_rate * th);
  }
  return h;
}

JV Route3::leg_point_j(size_t k, const J& a, const J& e) const {
  const Leg& g = legs_[k];
  const J tau = (a + g.s0) / g.A1b;
  J beta = tau;
  for (int l = 1; l <= 6; ++l) beta += sin(tau * static_cast<Real>(2 * l)) * g.c1p[l];
  J sb, cb;
  sincos(beta, sb, cb);
  JV x;
  for (int i = 0; i < 3; ++i) x[static_cast<size_t>(i)] = cb * (wgs::kA * g.e1(i)) + sb * (g.b * g.e2(i)) - e * g.p(i);
  return x;
}

Vec3 Route3::leg_point(size_t k, Real a) const { return value(to_surface(leg_point_j(k, J(a), J(0)))); }

// Coordinates of a turn's curve: w (blend step), and its deviation from the
// incoming leg's asymptote (r1 along, e1 to the right) and from the outgoing
// leg's (r2, e2). r1, e1 decay as u -> -inf, r2, e2 as u -> +inf.
void Route3::turn_coords(const Turn& tr, const J& s, J& w, J& r1, J& e1, J& r2, J& e2) const {
  const J u = (s - tr.s_w) / tr.lambda;
  r1 = e1 = r2 = e2 = J(0);
  const Real uv = u.val();
  // far from the turn: the step is 0 or 1 and the corrections of the side in
  // use are below e^-120 of lambda (the other side's leg carries no weight)
  if (uv < -kTurnSkipU) {
    w = J(0);
    return;
  }
  if (uv > kTurnSkipU) {
    w = J(1);
    return;
  }
  w = logistic(u);
  const Real cd = std::cos(tr.dpsi), sd = std::sin(tr.dpsi);
  const J gr = horner(tr.g_re, w), gi = horner(tr.g_im, w);
  r1 = (softplus(u) * (cd - 1) + gr) * tr.lambda;
  e1 = (softplus(u) * sd + gi) * tr.lambda;
  // H = G(w) - G(1), rotated by e^{-i dpsi}
  const J hr = gr - tr.g1_re, hi = gi - tr.g1_im;
  const J rr = hr * cd + hi * sd, ri = hi * cd - hr * sd;
  const J spm = softplus(-u);
  r2 = (spm * (1 - cd) + rr) * tr.lambda;
  e2 = (spm * sd + ri) * tr.lambda;
}

JV Route3::footprint(const J& s) const {
  const size_t n = legs_.size();
  // blend steps of the turns at waypoints 1..n-1 and their coordinates
  std::vector<J> w(n + 1), r1(n + 1), e1(n + 1), r2(n + 1), e2(n + 1);
  w[0] = J(1);
  w[n] = J(0);
  for (size_t k = 1; k < n; ++k) {
    turn_coords(turns_[k], s, w[k], r1[k], e1[k], r2[k], e2[k]);
  }
  JV x{J(0), J(0), J(0)};
  for (size_t k = 1; k <= n; ++k) {  // leg k (index k-1): from waypoint k-1 to k
    const J wt = (k == 1 ? J(1) : w[k - 1]) * (k == n ? J(1) : 1 - w[k]);
    if (!(std::fabs(wt.val()) >= kSkipWeight)) continue;
    const Real c2 = turns_[k - 1].on ? turns_[k - 1].c2 : 0;
    J a = s - s_wp_[k - 1] + c2, e(0);
    if (k > 1) {
      a += r2[k - 1];
      e += e2[k - 1];
    }
    if (k < n) {
      a += r1[k];
      e += e1[k];
    }
    x = x + scale(leg_point_j(k - 1, a, e), wt);
  }
  return to_surface(x);
}

void Route3::geodetic(Real t, J& lat, J& lon, J& h) const {
  const JV x = footprint(path_length(t));
  const J rho = sqrt(x[0] * x[0] + x[1] * x[1]);
  lat = atan2(x[2], rho * (1 - wgs::kE2));
  lon = atan2(x[1], x[0]);
  h = height(t);
}

void Route3::jets(Real t, JV& r_e, JM& C_b_i) const {
  J lat, lon, h;
  geodetic(t, lat, lon, h);
  r_e = geodetic_to_ecef(lat, lon, h);
  if (att_ == Attitude::Stabilized) {
    C_b_i = c0_;
    return;
  }
  const JV v = deriv(r_e), a = deriv(v);
  C_b_i = matmul(earth_rotation(t), coordinated_attitude_e(lat, lon, v, a));
}

RouteParams route_params(const Trajectory3Params& t) {
  constexpr Real kDeg = kPi / 180.0L;
  RouteParams p;
  p.initial_speed_mps = t.initial_speed_mps >= 0 ? t.initial_speed_mps : t.speed_mps;
  RouteWaypoint w0;
  w0.lat = static_cast<Real>(t.lat_deg) * kDeg;
  w0.lon = static_cast<Real>(t.lon_deg) * kDeg;
  w0.h = t.height_m;
  p.waypoints.push_back(w0);
  for (const auto& w : t.waypoints) {
    RouteWaypoint r;
    r.lat = static_cast<Real>(w.lat_deg) * kDeg;
    r.lon = static_cast<Real>(w.lon_deg) * kDeg;
    r.h = w.height_m;
    r.speed_mps = w.speed_mps;
    r.climb_rate_mps = w.climb_rate_mps;
    r.accel_mps2 = w.accel_mps2;
    r.vertical_accel_mps2 = w.vertical_accel_mps2;
    r.turn_rate_radps = static_cast<Real>(w.turn_rate_dps) * kDeg;
    p.waypoints.push_back(r);
  }
  return p;
}

std::unique_ptr<Trajectory3> make_route3(const Scenario3& s) {
  return std::make_unique<Route3>(route_params(s.trajectory),
                                  s.strapdown() ? Attitude::Coordinated : Attitude::Stabilized);
}

}  // namespace ggins::truth3d
