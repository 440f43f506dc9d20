// The cold-atom gradiometer of a 3-D scenario (host_tools/lib/truth3d coldatom3d.hpp):
//  * shots at the configured rate only (ca_status ABSENT between them, ca_utime the shot's);
//  * without noise every pair lies on the ellipse x^2 - 2 x y cos(dphi) + y^2 = sin^2(dphi)
//    (paper eq. 3 form, x = (1/2 - s_0)/(eta/2), y likewise) whose dphi = k_eff dz T^2 Gamma_zz
//    is the map's Gamma_zz at the TRUE position of the step; Gamma_zz of the normal map within
//    5 E of the free-air value -d gamma/dh of WGS-84 normal gravity (finite differences of the
//    firmware's Somigliana series; the map holds the gravitation, normal gravity adds the
//    centrifugal term: measured 1.9 E);
//  * frame k is a pure function of k (any order of calls);
//  * failed shots: the fraction with p_fail = 0.3 within 4 sigma of the binomial;
//  * the parser: [aid_pf] needs [coldatom]; unknown keys are refused; the onboard map is
//    map_dir or map_from_field (a route map only), one of them.
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>

extern "C" {
#include "ggins/geo.h"
}
#include "ggins/truth3d/generator3d.hpp"
#include "ggins/truth3d/scenario3d.hpp"
#include "checks.hpp"

using namespace ggins;
using namespace ggins::truth3d;

namespace {

using ggins_test::check;
using ggins_test::g_fail;

std::string scenario(const std::string& coldatom_extra, double duration) {
  return R"(
[trajectory]
type = "route"
lat_deg = 53.407579
lon_deg = -2.967853
height_m = 3000.0
speed_mps = 100.0
[[trajectory.waypoint]]
lat_deg = 43.604652
lon_deg = 1.444209
[platform]
kind = "strapdown"
[time]
duration_s = )" + std::to_string(duration) + R"(
rate_hz = 100.0
[coldatom]
enabled = true
gzz_map = "phillips-route-normal"
)" + coldatom_extra;
}

}  // namespace

int main() {
  {
    const Scenario3 s = parse_scenario3(scenario("shot_noise = false\nphase_noise_mrad = 0.0\n", 60.0), "t", "t");
    const Generator3 g(s);
    check(g.coldatom() != nullptr, "the scenario's [coldatom] makes the sensor");
    const double scale = s.coldatom.grad.scale(), amp = 0.5 * s.coldatom.grad.contrast;
    int shots = 0, wrong_absent = 0, off_map = 0;
    double worst_ellipse = 0, worst_dphi = 0, worst_normal_E = 0;
    gg_frame_t f;
    Truth3 t;
    for (int64_t k = 0; k < g.n_steps(); ++k) {
      g.frame(k, f, &t);
      const bool due = k >= 100 && k % 100 == 0;
      if (!due) {
        wrong_absent += f.ca_status != GG_SENSOR_ABSENT;
        continue;
      }
      ++shots;
      if (f.ca_status != GG_SENSOR_OK || f.ca_utime != f.utime) {
        ++wrong_absent;
        continue;
      }
      double gzz = 0;
      const bool on = g.coldatom()->map().gzz(static_cast<double>(t.s.lat), static_cast<double>(t.s.lon),
                                              static_cast<double>(t.s.h), &gzz);
      off_map += !on;
      const double dphi = scale * gzz;
      const double x = (0.5 - f.ca_s[0]) / amp, y = (0.5 - f.ca_s[1]) / amp;
      worst_ellipse = std::fmax(worst_ellipse, std::fabs(x * x - 2 * x * y * std::cos(dphi) + y * y -
                                                         std::sin(dphi) * std::sin(dphi)));
      // dphi recovered from the pair: cos(phi_L) = x, cos(phi_L + dphi) = y
      const double pl = std::acos(std::fmax(-1.0, std::fmin(1.0, x)));
      double best = 1e9;
      for (double sgn : {1.0, -1.0}) {
        const double c = std::cos(sgn * pl + dphi);
        best = std::fmin(best, std::fabs(c - y));
      }
      worst_dphi = std::fmax(worst_dphi, best);
      double gp = 0, gm = 0;
      gg_geo_normal_gravity(static_cast<double>(t.s.lat), static_cast<double>(t.s.h) + 1.0, &gp);
      gg_geo_normal_gravity(static_cast<double>(t.s.lat), static_cast<double>(t.s.h) - 1.0, &gm);
      worst_normal_E = std::fmax(worst_normal_E, std::fabs(gzz - (gm - gp) / 2.0) * 1e9);
    }
    std::printf("%d shots in 60 s; ellipse residual %.2e; cos(phi_L + dphi) residual %.2e; |Gamma_zz - normal "
                "free-air| <= %.2f E\n",
                shots, worst_ellipse, worst_dphi, worst_normal_E);
    const int64_t expect = (g.n_steps() - 1) / 100;  // steps 100, 200, ... below n_steps
    check(shots == expect && wrong_absent == 0 && off_map == 0,
          "a shot at each whole second from 1 s (" + std::to_string(expect) + "), ABSENT between, all on the map");
    check(worst_ellipse < 1e-12, "noise-free pairs on the ellipse of the map's Gamma_zz at the true position");
    check(worst_dphi < 1e-9, "the pair's phase difference is k_eff dz T^2 Gamma_zz");
    check(worst_normal_E < 5.0, "the normal map's Gamma_zz is the free-air gradient of normal gravity (5 E: the map holds the gravitation, normal gravity adds the centrifugal term)");
    // pure function of k
    gg_frame_t a, b;
    g.frame(3000, a);
    g.frame(500, b);
    g.frame(3000, b);
    check(std::memcmp(&a, &b, sizeof a) == 0, "frame k is a pure function of k");
  }
  {
    const Scenario3 s = parse_scenario3(scenario("p_fail = 0.3\nseed = 7\n", 600.0), "t", "t");
    const Generator3 g(s);
    int shots = 0, failed = 0;
    gg_frame_t f;
    for (int64_t k = 100; k < g.n_steps(); k += 100) {
      g.frame(k, f);
      ++shots;
      failed += f.ca_status == GG_SENSOR_BAD;
    }
    const double p = static_cast<double>(failed) / shots, sd = std::sqrt(0.3 * 0.7 / shots);
    std::printf("failed shots: %d of %d (%.3f, expected 0.3 +- %.3f)\n", failed, shots, p, sd);
    check(std::fabs(p - 0.3) < 4 * sd, "failed-shot fraction within 4 sigma of p_fail");
  }
  {
    bool threw = false;
    try {
      parse_scenario3(scenario("", 10.0) + "[aid_pf]\nenabled = true\nmap_dir = \"x\"\n", "t", "t");
    } catch (const std::exception&) {
      threw = true;
    }
    check(!threw, "[aid_pf] with [coldatom] parses");
    threw = false;
    try {
      parse_scenario3(R"([trajectory]
type = "route"
lat_deg = 45.0
lon_deg = 10.0
height_m = 3000.0
speed_mps = 150.0
[[trajectory.waypoint]]
lat_deg = 45.0
lon_deg = 11.0
[aid_pf]
enabled = true
map_dir = "x"
)",
                      "t", "t");
    } catch (const std::exception&) {
      threw = true;
    }
    check(threw, "[aid_pf] without [coldatom] is refused");
    threw = false;
    try {
      parse_scenario3(scenario("dz = 2.0\n", 10.0), "t", "t");
    } catch (const std::exception& e) {
      threw = std::string(e.what()).find("dz") != std::string::npos;
    }
    check(threw, "an unknown [coldatom] key is refused, named");
    // the onboard map: map_dir or map_from_field, one of them
    const auto refusal = [](const std::string& text) {
      try {
        parse_scenario3(text, "t", "t");
      } catch (const std::exception& e) {
        return std::string(e.what());
      }
      return std::string();
    };
    check(refusal(scenario("", 10.0) + "[aid_pf]\nenabled = true\nmap_from_field = true\n").empty(),
          "[aid_pf] map_from_field on the route map parses");
    check(refusal(scenario("", 10.0) + "[aid_pf]\nenabled = true\n").find("map_from_field = true") !=
              std::string::npos,
          "[aid_pf] with neither map_dir nor map_from_field is refused, both named");
    check(refusal(scenario("", 10.0) + "[aid_pf]\nenabled = true\nmap_dir = \"x\"\nmap_from_field = true\n")
                  .find("exclude each other") != std::string::npos,
          "[aid_pf] map_dir with map_from_field is refused");
    std::string field = scenario("", 10.0);
    field.replace(field.find("\"phillips-route-normal\""), 23, "\"field\"");
    check(refusal(field + "[aid_pf]\nenabled = true\nmap_from_field = true\n").empty(),
          "[aid_pf] map_from_field with the sensor on the [gravity] field parses (tiles of the field)");
    check(refusal(field + "[aid_pf]\nenabled = true\nmap_from_field = true\nmap_spacing_deg = 2\n")
                  .find("map_spacing_deg") != std::string::npos,
          "[aid_pf] map_spacing_deg above 1 deg is refused, named");
    check(refusal(scenario("", 10.0) + "[aid_pf]\nenabled = true\nmap_from_field = true\nmap_step_m = 5\n")
                  .find("map_step_m") != std::string::npos,
          "[aid_pf] map_step_m below 10 m is refused, named");
  }
  std::printf("%d failure(s)\n", g_fail);
  return g_fail == 0 ? 0 : 1;
}
