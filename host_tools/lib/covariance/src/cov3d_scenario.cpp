// The great-circle scenario of the 3-D error analysis as a file: the schema of
// Cov3DScenario (truth/scenario_schema.hpp), read and written by the same rows.
#include <sstream>
#include <stdexcept>

#include "ggins/covariance/cov3d.hpp"
#include "ggins/truth/scenario_keys.hpp"
#include "ggins/truth/scenario_schema.hpp"

namespace ggins::covariance {

namespace {

namespace sch = truth::sch;
using S = Cov3DScenario;

sch::Schema<S> build() {
  sch::Schema<S> sc;
  sc.title = "3-D great-circle scenario (ggins covariance3d, montecarlo3d: the gc3d-* built-ins)";
  {
    sch::Table<S> t("", "Name and description.");
    t.custom(truth::keys::name_key<S>());
    sc.secs.push_back(sch::section<S>(t));
  }
  {
    sch::Table<S> t("great_circle",
                    "A great circle at constant height and speed over a spherical or normal Earth (trajectory3d.hpp).");
    sch::Key<S> plat = sch::mk<S>("platform", "string", "", "\"stabilized\", \"strapdown\"",
                                  "stabilized (locally level) or strapdown (coordinated attitude, gyros) platform", "");
    plat.read = [](S& s, const toml::node& n, const sch::Ctx& c, const std::string& p) {
      s.platform = sch::read_str(n, c, p, {"stabilized", "strapdown"}) == "strapdown" ? Platform::kStrapdown
                                                                                        : Platform::kStabilized;
    };
    plat.write = [](const S& s) -> std::optional<std::string> {
      return sch::str_text(s.platform == Platform::kStrapdown ? "strapdown" : "stabilized");
    };
    t.custom(plat)
        .str("field", &S::field, {"normal", "point-mass"}, "gravitation: WGS-84 normal field or a point mass")
        .num("omega_ie_radps", &S::omega_ie, "rad/s", sch::in(0, 1e-3), "Earth rate (0: non-rotating)")
        .num("radius_m", &S::radius_m, "m", sch::in(6e6, 7e6), "sphere radius of the circle (plus height_m)")
        .num("height_m", &S::height_m, "m", sch::in(-1e4, 1e6), "height above the sphere")
        .num("lat0_deg", &S::lat0_deg, "deg", sch::in(-89, 89), "start geocentric latitude")
        .num("lon0_deg", &S::lon0_deg, "deg", sch::in(-360, 360), "start longitude")
        .num("heading_deg", &S::heading_deg, "deg", sch::in(-360, 360), "initial heading from north")
        .num("speed_mps", &S::speed_mps, "m/s", sch::in(0, 2e4), "ground speed (0: at rest)");
    sc.secs.push_back(sch::section<S>(t));
  }
  {
    sch::Table<S> t("time", "Duration and firmware step rate.");
    t.num("duration_s", &S::duration_s, "s", sch::in_lopen(0, 1e9), "flight duration");
    sch::Key<S> rate = sch::mk<S>("rate_hz", "number", "Hz", sch::in_lopen(0, 1e4).text(),
                                  "step rate (white-noise densities: sigma^2 / rate_hz)", "");
    const sch::Range rr = sch::in_lopen(0, 1e4);
    rate.read = [rr](S& s, const toml::node& n, const sch::Ctx& c, const std::string& p) {
      s.model.rate_hz = sch::read_num(n, c, p, rr, "Hz");
    };
    rate.write = [](const S& s) -> std::optional<std::string> { return sch::num_text(s.model.rate_hz); };
    t.custom(rate);
    sc.secs.push_back(sch::section<S>(t));
  }
  {
    sch::Table<Nav3DModelConfig> t("instrument", "The gradiometer's geometry.");
    t.vec<3>("half_base_m", &Nav3DModelConfig::half_base_m, "m", sch::in_lopen(0, 100),
             "half-baselines a, b, c of the accelerometer pairs");
    sc.secs.push_back(sch::section<S, Nav3DModelConfig>(t, &S::model));
  }
  {
    sch::Table<S> t("errors", "Sensor errors (each drawn per run, zero mean) and initial-state errors, one sigma.");
    sch::Key<S> an = sch::mk<S>("acc_noise_sigma_mps2", "number", "m/s^2", sch::in(0, 1e3).text(),
                                "white noise per reading per sample", "");
    an.read = [](S& s, const toml::node& n, const sch::Ctx& c, const std::string& p) {
      s.model.acc_noise_sigma_mps2 = sch::read_num(n, c, p, sch::in(0, 1e3), "m/s^2");
    };
    an.write = [](const S& s) -> std::optional<std::string> { return sch::num_text(s.model.acc_noise_sigma_mps2); };
    sch::Key<S> gn = sch::mk<S>("gyro_noise_sigma_radps", "number", "rad/s", sch::in(0, 10).text(),
                                "white gyro noise per axis per sample (strapdown)", "");
    gn.read = [](S& s, const toml::node& n, const sch::Ctx& c, const std::string& p) {
      s.model.gyro_noise_sigma_radps = sch::read_num(n, c, p, sch::in(0, 10), "rad/s");
    };
    gn.write = [](const S& s) -> std::optional<std::string> { return sch::num_text(s.model.gyro_noise_sigma_radps); };
    t.num("acc_bias_sigma_mps2", &S::acc_bias_sigma_mps2, "m/s^2", sch::in(0, 1e3), "constant bias of each of the 18 readings")
        .num("gyro_bias_sigma_radps", &S::gyro_bias_sigma_radps, "rad/s", sch::in(0, 10), "constant gyro bias per axis (strapdown)")
        .custom(an)
        .custom(gn)
        .num("g0_sigma_mps2", &S::g0_sigma_mps2, "m/s^2", sch::in(0, 1e3), "initial gravity error per ECEF axis")
        .num("r0_sigma_m", &S::r0_sigma_m, "m", sch::in(0, 1e7), "initial position error per ECEF axis")
        .num("v0_sigma_mps", &S::v0_sigma_mps, "m/s", sch::in(0, 1e4), "initial velocity error per ECEF axis")
        .num("psi0_sigma_rad", &S::psi0_sigma_rad, "rad", sch::in(0, 1), "initial attitude error per axis (strapdown)")
        .num("baro_bias_sigma_m", &S::baro_bias_sigma_m, "m", sch::in(0, 1e5), "constant barometer bias ([baro] enable)");
    sc.secs.push_back(sch::section<S>(t));
  }
  {
    sch::Table<Nav3DBaro> t("baro", "The barometric vertical loop and the barometer's errors (nav3d_model.hpp).");
    t.boolean("enable", &Nav3DBaro::on, "the loop on")
        .vec<3>("poles_radps", &Nav3DBaro::poles_radps, "rad/s", sch::in_lopen(0, 10), "the loop's three real poles")
        .num("omega_s2", &Nav3DBaro::omega_s2, "1/s^2", sch::in(0, 1e-3), "w_s^2 of the loop gain k2 (0: |G(r0)|/|r0|)")
        .num("period_s", &Nav3DBaro::period_s, "s", sch::in_lopen(0, 1e4), "barometer sample period")
        .num("gm_sigma_m", &Nav3DBaro::gm_sigma_m, "m", sch::in(0, 1e4), "Gauss-Markov error, stationary sigma")
        .num("gm_tau_s", &Nav3DBaro::gm_tau_s, "s", sch::in_lopen(0, 1e7), "Gauss-Markov correlation time")
        .num("noise_sigma_m", &Nav3DBaro::noise_sigma_m, "m", sch::in(0, 1e4), "white noise per sample");
    sc.secs.push_back(sch::section<S, Nav3DBaro>(t, [](S& s) -> Nav3DBaro& { return s.model.baro; }));
  }
  return sc;
}

const sch::Schema<S>& schema() {
  static const sch::Schema<S> s = build();
  return s;
}

}  // namespace

bool is_great_circle_text(const std::string& text) {
  try {
    const toml::table root = toml::parse(text);
    return root.contains("great_circle");
  } catch (const toml::parse_error&) {
    return false;
  }
}

Cov3DScenario parse_great_circle_scenario(const std::string& text, const std::string& fallback_name,
                                          const std::string& source) {
  const sch::Ctx c{source};
  const toml::table root = sch::parse_toml(text, source);
  Cov3DScenario s;
  s.name = fallback_name;
  schema().read(s, root, c);
  s.source = source;
  return s;
}

std::string great_circle_scenario_to_toml(const Cov3DScenario& s, bool template_comments) {
  const std::string head =
      template_comments ? "# 3-D great-circle scenario: every key with its default (docs/scenario-reference.md)\n"
                        : "# scenario " + s.name + " as flown (defaults filled in, overrides applied)\n";
  return head + schema().to_toml(s, template_comments);
}

std::string great_circle_reference_markdown() { return schema().reference_markdown(); }

}  // namespace ggins::covariance
