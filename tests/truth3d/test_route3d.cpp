// Route trajectory (host_tools/lib/truth3d route3d.hpp) against independent truth:
//  * derivatives: v, a, omega_b, omega_b' from the jets against central finite
//    differences of r, v, C_b_i, omega_b (in turns, speed changes, climbs);
//  * geodesy: each leg against the WGS-84 geodesic between its waypoints by
//    Vincenty's formulas (independent: T. Vincenty, Survey Review 23 (176),
//    1975), length, start azimuth and the footprint along the leg; the
//    footprint in the plane through the Earth's centre and both waypoints;
//  * the start, the end and turn-free waypoints passed through, the waypoint
//    heights held; ground speed, climb rate and turn rate as specified, the bank
//    coordinated (tan phi = V psi' / g0);
//  * the scenario parser's errors (line-numbered) for bad routes.
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <type_traits>

#include "ggins/gravity/wgs84.hpp"
#include "ggins/truth3d/generator3d.hpp"
#include "ggins/truth3d/route3d.hpp"

using namespace ggins;
using namespace ggins::truth3d;
namespace wgs = gravity::wgs84;

namespace {

int g_fail = 0;
void check(bool ok, const std::string& what, double value, double bound) {
  std::printf("%s %s: %.3e (bound %.1e)\n", ok ? "ok  " : "FAIL", what.c_str(), value, bound);
  if (!ok) ++g_fail;
}
void check_below(double v, double bound, const std::string& what) { check(std::isfinite(v) && v < bound, what, v, bound); }

constexpr double kDeg = M_PI / 180.0;

// ---- Vincenty (1975) on WGS-84, in double ----
struct Vin {
  double a = 6378137.0, f = 1 / 298.257223563, b = a * (1 - f);
};
void vincenty_inverse(double lat1, double lon1, double lat2, double lon2, double& s, double& az1) {
  const Vin e;
  const double L = lon2 - lon1, U1 = std::atan((1 - e.f) * std::tan(lat1)), U2 = std::atan((1 - e.f) * std::tan(lat2));
  const double sU1 = std::sin(U1), cU1 = std::cos(U1), sU2 = std::sin(U2), cU2 = std::cos(U2);
  double lam = L, sig = 0, ss = 0, cs = 0, c2a = 0, c2m = 0;
  for (int it = 0; it < 200; ++it) {
    const double sl = std::sin(lam), cl = std::cos(lam);
    ss = std::hypot(cU2 * sl, cU1 * sU2 - sU1 * cU2 * cl);
    cs = sU1 * sU2 + cU1 * cU2 * cl;
    sig = std::atan2(ss, cs);
    const double sa = cU1 * cU2 * sl / ss;
    c2a = 1 - sa * sa;
    c2m = cs - 2 * sU1 * sU2 / c2a;
    const double C = e.f / 16 * c2a * (4 + e.f * (4 - 3 * c2a));
    const double prev = lam;
    lam = L + (1 - C) * e.f * sa * (sig + C * ss * (c2m + C * cs * (-1 + 2 * c2m * c2m)));
    if (std::fabs(lam - prev) < 1e-14) break;
  }
  const double u2 = c2a * (e.a * e.a - e.b * e.b) / (e.b * e.b);
  const double A = 1 + u2 / 16384 * (4096 + u2 * (-768 + u2 * (320 - 175 * u2)));
  const double B = u2 / 1024 * (256 + u2 * (-128 + u2 * (74 - 47 * u2)));
  const double ds = B * ss * (c2m + B / 4 * (cs * (-1 + 2 * c2m * c2m) - B / 6 * c2m * (-3 + 4 * ss * ss) * (-3 + 4 * c2m * c2m)));
  s = e.b * A * (sig - ds);
  az1 = std::atan2(cU2 * std::sin(lam), cU1 * sU2 - sU1 * cU2 * std::cos(lam));
}
void vincenty_direct(double lat1, double lon1, double az1, double s, double& lat2, double& lon2) {
  const Vin e;
  const double U1 = std::atan((1 - e.f) * std::tan(lat1)), sU1 = std::sin(U1), cU1 = std::cos(U1);
  const double sa1 = std::sin(az1), ca1 = std::cos(az1);
  const double sig1 = std::atan2(std::tan(U1), ca1), sa = cU1 * sa1, c2a = 1 - sa * sa;
  const double u2 = c2a * (e.a * e.a - e.b * e.b) / (e.b * e.b);
  const double A = 1 + u2 / 16384 * (4096 + u2 * (-768 + u2 * (320 - 175 * u2)));
  const double B = u2 / 1024 * (256 + u2 * (-128 + u2 * (74 - 47 * u2)));
  double sig = s / (e.b * A), c2m = 0, ss = 0, cs = 0;
  for (int it = 0; it < 200; ++it) {
    c2m = std::cos(2 * sig1 + sig);
    ss = std::sin(sig);
    cs = std::cos(sig);
    const double ds = B * ss * (c2m + B / 4 * (cs * (-1 + 2 * c2m * c2m) - B / 6 * c2m * (-3 + 4 * ss * ss) * (-3 + 4 * c2m * c2m)));
    const double prev = sig;
    sig = s / (e.b * A) + ds;
    if (std::fabs(sig - prev) < 1e-14) break;
  }
  ss = std::sin(sig);
  cs = std::cos(sig);
  c2m = std::cos(2 * sig1 + sig);
  lat2 = std::atan2(sU1 * cs + cU1 * ss * ca1, (1 - e.f) * std::hypot(sa, sU1 * ss - cU1 * cs * ca1));
  const double lam = std::atan2(ss * sa1, cU1 * cs - sU1 * ss * ca1);
  const double C = e.f / 16 * c2a * (4 + e.f * (4 - 3 * c2a));
  lon2 = lon1 + lam - (1 - C) * e.f * sa * (sig + C * ss * (c2m + C * cs * (-1 + 2 * c2m * c2m)));
}

Vec3 surface(Real lat, Real lon) { return wgs::geodetic_to_ecef(lat, lon, 0); }
Vec3 footprint_of(const Vec3& r) {
  Real lat, lon, h;
  wgs::ecef_to_geodetic(r, lat, lon, h);
  return surface(lat, lon);
}
Real height_of(const Vec3& r) {
  Real lat, lon, h;
  wgs::ecef_to_geodetic(r, lat, lon, h);
  return h;
}
Vec3 vee(const Mat3& w) { return Vec3(w(2, 1), w(0, 2), w(1, 0)); }
// track azimuth of the Earth-relative velocity, rad
Real track(const State3& s) {
  const Vec3 n = ned_to_ecef(s.lat, s.lon).transpose() * s.v_e;
  return std::atan2(n(1), n(0));
}

// ---- derivatives by finite differences ----
void derivative_checks(const Route3& r, const std::string& tag, Real t) {
  const Real h = 1e-3L;
  const State3 s = r.at(t), sp = r.at(t + h), sm = r.at(t - h);
  const State3 sp2 = r.at(t + 2 * h), sm2 = r.at(t - 2 * h);
  // 4th-order central differences
  auto d1 = [&](auto f) {
    using T = std::decay_t<decltype(f(s))>;
    return T((8 * (f(sp) - f(sm)) - (f(sp2) - f(sm2))) / (12 * h));
  };
  const Vec3 v_fd = d1([](const State3& x) -> Vec3 { return x.r_e; });
  const Vec3 a_fd = d1([](const State3& x) -> Vec3 { return x.v_e; });
  const Mat3 Cd_fd = d1([](const State3& x) -> Mat3 { return x.C_b_i; });
  const Vec3 w_fd = vee(s.C_b_i.transpose() * Cd_fd);
  const Vec3 wd_fd = d1([](const State3& x) -> Vec3 { return x.omega_b; });
  const Vec3 ai_fd = d1([](const State3& x) -> Vec3 { return x.v_i; });
  check_below(static_cast<double>((s.v_e - v_fd).norm()), 1e-8, tag + ": |v_e - dr_e/dt| (m/s)");
  check_below(static_cast<double>((s.a_e - a_fd).norm()), 1e-8, tag + ": |a_e - dv_e/dt| (m/s^2)");
  check_below(static_cast<double>((s.a_i - ai_fd).norm()), 1e-8, tag + ": |a_i - dv_i/dt| (m/s^2)");
  check_below(static_cast<double>((s.omega_b - w_fd).norm()), 1e-10, tag + ": |omega_b - vee(C^T dC/dt)| (rad/s)");
  check_below(static_cast<double>((s.omega_dot_b - wd_fd).norm()), 1e-9, tag + ": |omega_b' - d omega_b/dt| (rad/s^2)");
}

Scenario3 scen(const char* name) { return load_scenario3(name, {}); }
std::unique_ptr<Route3> route_of(const Scenario3& s) {
  return std::make_unique<Route3>(route_params(s.trajectory), s.strapdown() ? Attitude::Coordinated : Attitude::Stabilized);
}

// footprint ground speed and geodetic height rate by central differences (0.01 s)
Real ground_speed(const Route3& r, Real t) {
  const Real h = 0.01L;
  return (footprint_of(r.at(t + h).r_e) - footprint_of(r.at(t - h).r_e)).norm() / (2 * h);
}
Real climb_rate(const Route3& r, Real t) {
  const Real h = 0.01L;
  return (height_of(r.at(t + h).r_e) - height_of(r.at(t - h).r_e)) / (2 * h);
}

// Each leg against the geodesic. The great ellipse's plane holds the
// geocentric radius, the geodesic's osculating plane the ellipsoid normal:
// they differ by the angle e^2 sin(2 lat)/2 (<= e^2/2) about the chord, so the
// great ellipse leaves the geodesic by at most (e^2/2) L^2/(8 R) at mid-leg
// (the chord's sagitta times that angle) and starts off its azimuth by at most
// (e^2/2) L/(2 R); R >= 6.33e6 m (the smallest radius of curvature); 2 % margin
// for the approximations and Vincenty's own 0.1 mm.
void leg_geodesy(const Route3& r, const std::string& tag) {
  const auto& W = r.params().waypoints;
  const double e2 = static_cast<double>(wgs::kE2), R = 6.33e6;
  for (size_t k = 0; k + 1 < W.size(); ++k) {
    const auto& g = r.legs()[k];
    double sg, az;
    vincenty_inverse(static_cast<double>(W[k].lat), static_cast<double>(W[k].lon), static_cast<double>(W[k + 1].lat),
                     static_cast<double>(W[k + 1].lon), sg, az);
    const std::string lt = tag + " leg " + std::to_string(k + 1);
    // the length: the great ellipse is longer by second order in the deviation
    check_below(std::fabs(static_cast<double>(g.length) - sg), 1e-6 * sg + 1e-3, lt + ": |length - geodesic| (m)");
    double dev = 0, dplane = 0;
    const Vec3 A = surface(W[k].lat, W[k].lon), B = surface(W[k + 1].lat, W[k + 1].lon);
    const Vec3 nrm = A.cross(B).normalized();
    for (int q = 0; q <= 10; ++q) {
      const double frac = q / 10.0;
      double la, lo;
      vincenty_direct(static_cast<double>(W[k].lat), static_cast<double>(W[k].lon), az, frac * sg, la, lo);
      const Vec3 pr = r.leg_point(k, g.length * frac);
      dev = std::max(dev, static_cast<double>((pr - surface(la, lo)).norm()));
      dplane = std::max(dplane, static_cast<double>(std::fabs(pr.dot(nrm))));
    }
    check_below(dev, 1.02 * e2 / 2 * sg * sg / (8 * R) + 1e-3, lt + ": footprint vs Vincenty geodesic, max distance (m)");
    check_below(dplane, 1e-6, lt + ": footprint out of the plane of centre and waypoints (m)");
    const Vec3 p0 = r.leg_point(k, 0), p1 = r.leg_point(k, 1.0L);
    const Vec3 ned = ned_to_ecef(W[k].lat, W[k].lon).transpose() * (p1 - p0);
    const double az_r = static_cast<double>(std::atan2(ned(1), ned(0)));
    check_below(std::fabs(std::remainder(az_r - az, 2 * M_PI)), 1.02 * e2 / 2 * sg / (2 * R) + 1e-7,
                lt + ": start azimuth - geodesic's (rad)");
  }
}

// The flown track holds the leg's: at time t on leg k (outside turns), the
// footprint's velocity (central differences of the truth's footprint) has the
// azimuth of the plane section's tangent p x n (p the normal of the plane
// through the centre and both waypoints, n the ellipsoid normal there),
// computed here from the waypoints alone. (The velocity at altitude turns off
// it by h times the geodesic torsion of the ellipsoid, < 1e-6 rad at 3 km.)
void track_hold(const Route3& r, size_t k, Real t, const std::string& what) {
  const auto& W = r.params().waypoints;
  const Vec3 p = surface(W[k].lat, W[k].lon).cross(surface(W[k + 1].lat, W[k + 1].lon)).normalized();
  const State3 s = r.at(t);
  const Vec3 fp = footprint_of(s.r_e);
  Real lat, lon, h;
  wgs::ecef_to_geodetic(fp, lat, lon, h);
  const Mat3 Cne = ned_to_ecef(lat, lon);
  const Vec3 n = -Cne.col(2);
  const Vec3 tg = Cne.transpose() * p.cross(n);
  const Real dt = 0.01L;
  const Vec3 vf = Cne.transpose() * (footprint_of(r.at(t + dt).r_e) - footprint_of(r.at(t - dt).r_e));
  check_below(static_cast<double>(std::fabs(std::remainder(std::atan2(vf(1), vf(0)) - std::atan2(tg(1), tg(0)), 2 * kPi))),
              1e-9, what + ": footprint track - the leg plane's tangent azimuth (rad)");
}

}  // namespace

int main() {
  // ---------------- the hand-written route: 45 N eastbound, two turns, climb, speed-up
  {
    const Scenario3 sc = scen("3d-route-45n");
    const auto rp = route_of(sc);
    const Route3& r = *rp;
    const auto& W = r.params().waypoints;
    std::printf("3d-route-45n: waypoint times");
    for (size_t k = 0; k < W.size(); ++k) std::printf(" %.1f", static_cast<double>(r.waypoint_time(k)));
    std::printf(" s\n");
    // derivatives: cruise, in each turn, in the climb, in the speed change
    derivative_checks(r, "45n t=50 (leg 1)", 50);
    derivative_checks(r, "45n turn 1 centre", r.waypoint_time(1));
    derivative_checks(r, "45n turn 1 entry", r.waypoint_time(1) - 4);
    derivative_checks(r, "45n climb", 0.5L * (r.legs()[1].t_climb0 + r.legs()[1].t_climb1));
    derivative_checks(r, "45n climb start", r.legs()[1].t_climb0);
    derivative_checks(r, "45n turn 2 exit", r.waypoint_time(2) + 5);
    derivative_checks(r, "45n end", 640);
    // start and waypoint heights
    check_below(static_cast<double>((r.at(0).r_e - wgs::geodetic_to_ecef(W[0].lat, W[0].lon, W[0].h)).norm()), 1e-6,
                "45n: r_e(0) - start waypoint (m)");
    for (size_t k = 1; k < W.size(); ++k)
      check_below(static_cast<double>(std::fabs(height_of(r.at(r.waypoint_time(k)).r_e) - W[k].h)), 1e-6,
                  "45n: height at waypoint " + std::to_string(k) + " - its height (m)");
    // the end waypoint (no turn) is passed through
    const size_t n = W.size() - 1;
    check_below(static_cast<double>((r.at(r.waypoint_time(n)).r_e - wgs::geodetic_to_ecef(W[n].lat, W[n].lon, W[n].h)).norm()),
                1e-6, "45n: position at the end waypoint's time - end waypoint (m)");
    // fly-by turns: the closest approach to a turn waypoint is well inside the turn's size
    for (size_t k = 1; k < n; ++k) {
      const Vec3 wp = surface(W[k].lat, W[k].lon);
      double dmin = 1e30;
      for (Real t = r.waypoint_time(k) - 60; t <= r.waypoint_time(k) + 60; t += 0.05L)
        dmin = std::min(dmin, static_cast<double>((footprint_of(r.at(t).r_e) - wp).norm()));
      const double size = static_cast<double>(r.turns()[k].lambda);
      check(dmin > 0.01 * size && dmin < 1.5 * size, "45n: fly-by closest approach to turn waypoint " + std::to_string(k) +
                                                          " (m; within (0.01, 1.5) x lambda " + std::to_string(size) + ")",
            dmin, 1.5 * size);
    }
    // ground speed on the legs (footprint, by differences), climb rate, level flight
    check_below(static_cast<double>(std::fabs(ground_speed(r, 60) - 150)), 1e-6, "45n: ground speed leg 1 - 150 (m/s)");
    check_below(static_cast<double>(std::fabs(ground_speed(r, r.waypoint_time(3) - 10) - 180)), 1e-6,
                "45n: ground speed leg 3 after the speed change - 180 (m/s)");
    const auto& g2 = r.legs()[1];
    check_below(static_cast<double>(std::fabs(climb_rate(r, 0.5L * (g2.t_climb0 + g2.t_climb1)) - 5)), 1e-6,
                "45n: climb rate mid-climb - 5 (m/s)");
    check_below(static_cast<double>(std::fabs(climb_rate(r, 100))), 1e-9, "45n: vertical rate on leg 1 (level) (m/s)");
    // turn rate: the track's rate peaks at turn_rate (3 deg/s) at the turn centre; the track turns by dpsi
    for (size_t k = 1; k < n; ++k) {
      const Real tc = r.waypoint_time(k), dt = 0.01L;
      Real peak = 0;
      for (Real t = tc - 30; t <= tc + 30; t += 0.25L)
        peak = std::max(peak, std::fabs(std::remainder(track(r.at(t + dt)) - track(r.at(t - dt)), 2 * kPi) / (2 * dt)));
      check_below(std::fabs(static_cast<double>(peak) / (3 * kDeg) - 1), 2e-3,
                  "45n turn " + std::to_string(k) + ": peak track rate / 3 deg/s - 1");
      // the track turns by the angle between the two legs' planes' tangents at the waypoint
      const Vec3 wk = surface(W[k].lat, W[k].lon);
      const Mat3 Cne = ned_to_ecef(W[k].lat, W[k].lon);
      const Vec3 nk = -Cne.col(2);
      const Vec3 pa = surface(W[k - 1].lat, W[k - 1].lon).cross(wk).normalized();
      const Vec3 pb = wk.cross(surface(W[k + 1].lat, W[k + 1].lon)).normalized();
      const Vec3 ta = Cne.transpose() * pa.cross(nk), tb = Cne.transpose() * pb.cross(nk);
      const Real want_turn = std::remainder(std::atan2(tb(1), tb(0)) - std::atan2(ta(1), ta(0)), 2 * kPi);
      check_below(static_cast<double>(std::fabs(r.turns()[k].dpsi - want_turn)), 1e-12,
                  "45n turn " + std::to_string(k) + ": turn angle - the leg planes' (rad)");
      // coordinated bank at the centre: tan(phi) = V psi' / g0 (flat-Earth relation, 1e-3)
      const State3 s = r.at(tc);
      const Real V = std::hypot(s.v_e.norm(), 0.0L);
      const Real want = std::atan(V * peak / kG0);
      check_below(static_cast<double>(std::fabs(std::fabs(s.roll) - want)), 2e-3,
                  "45n turn " + std::to_string(k) + ": |bank| - atan(V psi'/g0) (rad)");
    }
    leg_geodesy(r, "45n");
    track_hold(r, 0, 60, "45n leg 1");
    track_hold(r, 1, 0.5L * (r.waypoint_time(1) + r.waypoint_time(2)), "45n leg 2 (climbing)");
    track_hold(r, 2, r.waypoint_time(3) - 10, "45n leg 3");
  }
  // ---------------- Liverpool -> Toulouse: one leg, 3000 m, 100 m/s
  {
    const Scenario3 sc = scen("3d-liverpool-toulouse");
    const auto rp = route_of(sc);
    const Route3& r = *rp;
    const auto& W = r.params().waypoints;
    std::printf("3d-liverpool-toulouse: leg %.3f m, Toulouse at %.2f s\n", static_cast<double>(r.legs()[0].length),
                static_cast<double>(r.waypoint_time(1)));
    derivative_checks(r, "LT t=5000", 5000);
    check_below(static_cast<double>(std::fabs(ground_speed(r, 5000) - 100)), 1e-6, "LT: ground speed - 100 (m/s)");
    check_below(static_cast<double>(std::fabs(height_of(r.at(5000).r_e) - 3000)), 1e-6, "LT: height - 3000 (m)");
    check_below(static_cast<double>((r.at(r.waypoint_time(1)).r_e - wgs::geodetic_to_ecef(W[1].lat, W[1].lon, 3000)).norm()),
                1e-6, "LT: passes through Toulouse (m)");
    leg_geodesy(r, "LT");
    track_hold(r, 0, 9000, "LT");
  }
  // ---------------- Gao's voyage: accelerations, 90 and 2 x 90 deg turns
  {
    const Scenario3 sc = scen("3d-gao-voyage-10h");
    const auto rp = route_of(sc);
    const Route3& r = *rp;
    std::printf("3d-gao-voyage-10h: waypoint times");
    for (size_t k = 0; k < r.params().waypoints.size(); ++k) std::printf(" %.0f", static_cast<double>(r.waypoint_time(k)));
    std::printf(" s\n");
    check(r.waypoint_time(r.params().waypoints.size() - 1) > 35000 && r.waypoint_time(r.params().waypoints.size() - 1) < 37000,
          "Gao: the route lasts ~10 h (s)", static_cast<double>(r.waypoint_time(r.params().waypoints.size() - 1)), 37000);
    derivative_checks(r, "Gao departure", 300);
    derivative_checks(r, "Gao turn 1", r.waypoint_time(1));
    derivative_checks(r, "Gao 180 turn, 2nd half", r.waypoint_time(6) - 50);
    check_below(static_cast<double>(std::fabs(ground_speed(r, 5000) - 10)), 1e-7, "Gao: cruise speed - 10 (m/s)");
    check_below(static_cast<double>(std::fabs(ground_speed(r, r.waypoint_time(3) - 600) - 5)), 1e-7, "Gao: slow leg - 5 (m/s)");
    check_below(static_cast<double>(std::fabs(height_of(r.at(20000).r_e) + 100)), 1e-6, "Gao: depth 100 m held (m)");
    leg_geodesy(r, "Gao");
    track_hold(r, 1, 10000, "Gao leg 2");
    track_hold(r, 3, 19000, "Gao leg 4 (slow)");
  }
  // ---------------- parser: clear, line-numbered errors
  {
    const std::string head = "[trajectory]\ntype = \"route\"\nlat_deg = 45.0\nlon_deg = 10.0\nspeed_mps = 150.0\n";
    auto expect_error = [&](const std::string& body, const std::string& want, const std::string& what) {
      std::string msg;
      try {
        parse_scenario3(head + body, "t", "test");
      } catch (const std::exception& e) {
        msg = e.what();
      }
      const bool ok = msg.find(want) != std::string::npos;
      std::printf("%s parser: %s -> \"%s\"\n", ok ? "ok  " : "FAIL", what.c_str(), msg.c_str());
      if (!ok) ++g_fail;
    };
    expect_error("", "needs at least one [[trajectory.waypoint]]", "no waypoint");
    expect_error("[[trajectory.waypoint]]\nlat_deg = 45.0\nlon_deg = 10.5\nspeed_mps = 0.5\n",
                 "test:9: trajectory.waypoint[1].speed_mps = 0.5: out of range (allowed: [1, 3000] m/s)", "speed below 1 m/s");
    expect_error("[[trajectory.waypoint]]\nlat_deg = 45.0\n", "test:6: trajectory.waypoint[1]: lat_deg and lon_deg are required",
                 "missing lon");
    expect_error("[[trajectory.waypoint]]\nlat_deg = 45.0\nlon_deg = 10.5\nspeed = 3.0\n",
                 "test:9: unknown key 'trajectory.waypoint[1].speed'", "unknown key");
    expect_error("[[trajectory.waypoint]]\nlat_deg = 45.0\nlon_deg = 10.5\n[[trajectory.waypoint]]\nlat_deg = 45.0\nlon_deg = 10.0\n",
                 "trajectory.waypoint[1] (line 6): route: the turn at this waypoint is", "180 deg turn");
    expect_error("[[trajectory.waypoint]]\nlat_deg = 45.0\nlon_deg = 10.01\n[[trajectory.waypoint]]\nlat_deg = 45.01\nlon_deg = 10.01\n",
                 "trajectory.waypoint[1] (line 6): route: leg of", "leg too short for its turns");
    expect_error("[[trajectory.waypoint]]\nlat_deg = 45.0\nlon_deg = 10.1\nheight_m = 9000.0\n",
                 "trajectory.waypoint[1] (line 6): route: the height change of", "climb does not fit");
    expect_error("[[trajectory.waypoint]]\nlat_deg = 45.0\nlon_deg = 10.0\n", "waypoint[1] (line 6): route: waypoint coincides",
                 "coincident waypoints");
    expect_error("[[trajectory.waypoint]]\nlat_deg = 95.0\nlon_deg = 10.0\n", "test:7: trajectory.waypoint[1].lat_deg = 95.0: out of range (allowed: [-85, 85] deg)",
                 "latitude out of range");
    std::string msg;
    try {
      parse_scenario3("[trajectory]\ntype = \"flight\"\n[[trajectory.waypoint]]\nlat_deg = 1.0\nlon_deg = 2.0\n", "t", "test");
    } catch (const std::exception& e) {
      msg = e.what();
    }
    const bool ok = msg.find("is a key of type = \"route\"") != std::string::npos;
    std::printf("%s parser: waypoint on a flight -> \"%s\"\n", ok ? "ok  " : "FAIL", msg.c_str());
    if (!ok) ++g_fail;
  }
  std::printf(g_fail ? "FAILED (%d)\n" : "PASSED\n", g_fail);
  return g_fail ? 1 : 0;
}
