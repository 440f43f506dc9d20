// Route trajectory: great-ellipse legs between waypoints (lat, lon, h) flown at
// a given ground speed, with fly-by turns at a given rate (coordinated bank),
// climbs and descents at a given rate and smooth speed changes; closed form on
// Taylor jets like every Trajectory3 (trajectory3d.hpp), so r, v, a, the
// attitude and the body rates stay exact derivatives of one another.
//
// Geometry (horizontal), as a function of the path length s along the
// footprint on the WGS-84 ellipsoid (h = 0):
//  * Leg k joins the footprints P_(k-1), P_k of its waypoints along the great
//    ellipse, the ellipsoid's section by the plane through the Earth's centre
//    and both points (normal p_k = unit(P_(k-1) x P_k)). With e1 the node
//    (equator crossing) and e2 = p_k x e1 the ellipse's highest point,
//      X(beta) = a cos(beta) e1 + b_k sin(beta) e2,
//      b_k = 1 / sqrt((1 - s_z^2)/a^2 + s_z^2/b^2),  s_z = e2 . z
//    (a, b the WGS-84 semi-axes). Its arc length from the node is
//      s(beta) = b_k A1 (beta + sum_l C1_l sin 2 l beta)
//    and its inverse beta(s) = tau + sum_l C1'_l sin 2 l tau, tau = s / (b_k A1),
//    with eps = (a - b_k)/(a + b_k) (Karney, "Algorithms for geodesics",
//    J. Geodesy 87, 2013, eqs. 15-21, to eps^6: the omitted terms are below
//    1e-19 of the radius), so the footprint moves at exactly ds/dt along a leg.
//  * Turn at waypoint W_k from track direction d1 to d2 (turn angle dpsi,
//    |dpsi| <= 150 deg, positive to the right): a fly-by curve in W_k's local
//    north-east plane whose heading follows a logistic step,
//      psi(s) = psi_1 + dpsi w(u),  w = 1/(1 + e^-u),  u = (s - s_W)/lambda,
//    at unit speed, P'(s) = d1 exp(i dpsi w) (complex N + iE). Its integral is
//    closed form: with exp(i dpsi w) = 1 + (e^(i dpsi) - 1) w + w (1 - w) Q(w)
//    (Q a power series, summed to 1e-28) and w' = w (1 - w)/lambda,
//      P(s) = P0 + d1 (s - s_W) + (d2 - d1) lambda softplus(u) + lambda d1 G(w),  G' = Q,
//    P0 chosen so that the asymptotes are the two legs' lines. The turn rate
//    V dpsi w (1 - w)/lambda peaks at the centre at V |dpsi| / (4 lambda):
//    lambda = V |dpsi| / (4 turn_rate). The coordinated bank follows from the
//    acceleration (trajectory3d.hpp).
//  * The whole route is one analytic curve: the footprint is the central
//    projection onto the ellipsoid of sum_k W_k(s) L_k(a_k, e_k), where
//    L_k(a, e) = X_k(a) - e p_k is the point at distance a along leg k and e
//    to its right, a_k, e_k the leg's coordinates of the turn curves at both
//    its ends (each turn's deviation from its asymptote decays as e^-|u|), and
//    W_k = w_(k-1) (1 - w_k) (w_0 = 1, w_n = 0). Away from the turns the
//    footprint is on the great ellipse to rounding; in a turn the speed is
//    exact to the flat-plane approximation of the turn (~(turn size / R)^2).
// Timing: s(t) = V_0 t + sum_j dV_j tau_j (softplus((t - t_j)/tau_j) - softplus(-t_j/tau_j)),
// a speed change from one leg's speed to the next's centred 10 tau_j after
// the end of the turn at the leg's start (6 lambda past its centre;
// tau_j = |dV_j| / (4 accel): peak acceleration = accel). Height: h(t) = h_0 + sum_k c_k tau_h (softplus((t - a_k)/tau_h) -
// softplus((t - b_k)/tau_h)) (minus the same at t = 0): on leg k a climb at
// rate c_k from h_(k-1) to h_k (b_k - a_k = (h_k - h_(k-1))/c_k), starting
// 20 tau_h after the time at W_(k-1) and ending at least 20 tau_h before the
// time at W_k (tau_h = |c_k| / (4 vertical_accel)); the geodetic height then
// rises at exactly c_k. Past the last waypoint the route goes on along the
// last leg's great ellipse.
// Waypoints with a turn are flown by (the curve cuts the corner); the start,
// the end and waypoints without a turn are passed through.
#pragma once

#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "ggins/truth3d/scenario3d.hpp"
#include "ggins/truth3d/trajectory3d.hpp"

namespace ggins::truth3d {

struct RouteWaypoint {
  Real lat = 0, lon = 0, h = 0;  // rad, rad, m
  // of the leg that ends at this waypoint (ignored for waypoint 0):
  Real speed_mps = 100;            // ground speed (footprint)
  Real climb_rate_mps = 5;         // |vertical rate| of a height change on the leg
  Real accel_mps2 = 0.5;           // peak along-track acceleration of a speed change onto the leg
  Real vertical_accel_mps2 = 0.5;  // peak vertical acceleration of the climb's start and end
  // of the turn at this waypoint (ignored for the first and the last):
  Real turn_rate_radps = 0.05235987755982988731L;  // 3 deg/s (standard rate)
};

struct RouteParams {
  std::vector<RouteWaypoint> waypoints;  // >= 2; waypoint 0 is the start (t = 0)
  Real initial_speed_mps = -1;           // < 0: the first leg's speed
};

// A route that cannot be flown: `waypoint` is the index of the offending waypoint.
struct RouteError : std::invalid_argument {
  RouteError(int wp, const std::string& what) : std::invalid_argument(what), waypoint(wp) {}
  int waypoint;
};

class Route3 final : public Trajectory3 {
 public:
  Route3(const RouteParams& p, Attitude att);
  void jets(Real t, JV& r_e, JM& C_b_i) const override;
  std::string name() const override { return "route"; }

  // Geodetic lat, lon (footprint) and height as jets.
  void geodetic(Real t, J& lat, J& lon, J& h) const;
  // Path length along the footprint, as a jet in t.
  J path_length(Real t) const;

  // Design quantities (for tests and reports).
  struct Leg {
    Vec3 p = Vec3::Zero(), e1 = Vec3::Zero(), e2 = Vec3::Zero();  // plane normal, node, highest point
    Real b = 0, A1b = 0;             // semi-minor axis of the section; b A1
    Real c1[7] = {}, c1p[7] = {};    // C1_l, C1'_l (l = 1..6)
    Real s0 = 0, length = 0;         // arc length from the node at its start; its length, m
    Real speed = 0, climb_rate = 0;  // signed climb rate (0: level)
    Real t_climb0 = 0, t_climb1 = 0, tau_h = 1;
  };
  struct Turn {
    bool on = false;
    Real dpsi = 0, lambda = 1, s_w = 0;  // angle (rad, right +), length scale, path length at the centre
    Real d1[2] = {1, 0}, d2[2] = {1, 0};  // track directions (N, E) before and after
    Real P0[2] = {0, 0}, c1 = 0, c2 = 0;  // offset of the curve, asymptote shifts along d1, d2
    std::vector<Real> g_re, g_im;        // coefficients of G(w) (G(0) = 0)
    Real g1_re = 0, g1_im = 0;           // G(1)
  };
  const std::vector<Leg>& legs() const { return legs_; }
  const std::vector<Turn>& turns() const { return turns_; }  // turns_[k]: at waypoint k (0 and last: off)
  // Path length at which waypoint k is reached (turn centre for a turn) and the time it is reached.
  Real waypoint_path_length(size_t k) const { return s_wp_[k]; }
  Real waypoint_time(size_t k) const { return t_wp_[k]; }
  const RouteParams& params() const { return p_; }
  // Point at distance a along leg k (from its start), e to its right, on the ellipsoid surface (ECEF).
  Vec3 leg_point(size_t k, Real a) const;

 private:
  JV leg_point_j(size_t k, const J& a, const J& e) const;
  void turn_coords(const Turn& tr, const J& s, J& w, J& r1, J& e1, J& r2, J& e2) const;
  JV footprint(const J& s) const;
  J height(Real t) const;
  Real time_of_path(Real s) const;

  RouteParams p_;
  Attitude att_;
  std::vector<Leg> legs_;
  std::vector<Turn> turns_;
  struct SpeedChange {
    Real t = 0, dv = 0, tau = 1;
  };
  Real v0_ = 0;
  std::vector<SpeedChange> dv_;
  std::vector<Real> s_wp_, t_wp_;
  JM c0_;
};

// The route of a scenario ([trajectory] type = "route", scenario3d.hpp); throws RouteError.
RouteParams route_params(const Trajectory3Params& t);
std::unique_ptr<Trajectory3> make_route3(const Scenario3& s);

}  // namespace ggins::truth3d
