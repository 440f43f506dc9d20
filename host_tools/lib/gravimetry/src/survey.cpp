// Post-mission airborne gravimetry (survey.hpp states the models).
#include "ggins/gravimetry/survey.hpp"

#include "ggins/gravity/wgs84.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdio>
#include <fstream>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>

namespace ggins::gravimetry {
namespace {

constexpr double kPi = 3.14159265358979323846;
namespace w84 = ggins::gravity::wgs84;
using gravity::Real;

// Normal gravity magnitude: Somigliana on the ellipsoid (WGS-84) with the free-air term.
double normal_gravity(double lat_deg, double h) {
  const double s2 = std::pow(std::sin(lat_deg * kPi / 180), 2);
  return static_cast<double>(w84::kPubGammaE * (1 + w84::kPubK * s2) / std::sqrt(1 - w84::kPubE2 * s2)) -
         3.086e-6 * h;
}

std::vector<std::string> split(const std::string& s) {
  std::vector<std::string> out;
  std::string cur;
  std::istringstream is(s);
  while (std::getline(is, cur, ',')) out.push_back(cur);
  return out;
}

double wrap180(double a) {
  while (a > 180) a -= 360;
  while (a <= -180) a += 360;
  return a;
}

// The measured gradient's disturbance (NED, s^-2) applied to a NED offset.
V3 gam_times(const std::array<double, 6>& g, const V3& d) {
  const double nn = g[0] * 1e-9, ee = g[1] * 1e-9, dd = g[2] * 1e-9, ne = g[3] * 1e-9, nd = g[4] * 1e-9,
               ed = g[5] * 1e-9;
  return {nn * d[0] + ne * d[1] + nd * d[2], ne * d[0] + ee * d[1] + ed * d[2], nd * d[0] + ed * d[1] + dd * d[2]};
}

V3 enu_to_ned(const V3& a) { return {a[1], a[0], -a[2]}; }
double norm3(const V3& a) { return std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]); }

}  // namespace

Record read_record(const std::filesystem::path& dir) {
  Record r;
  const auto csv = dir / "gravimetry_raw.csv";
  std::ifstream f(csv);
  if (!f) throw std::runtime_error("cannot read " + csv.string() + " (a ggins run3d output folder holds it)");
  std::string line;
  if (!std::getline(f, line)) throw std::runtime_error(csv.string() + ": empty");
  const auto head = split(line);
  std::map<std::string, size_t> col;
  for (size_t i = 0; i < head.size(); ++i) col[head[i]] = i;
  const char* need[] = {"t_s", "seq", "nav_lat_deg", "nav_lon_deg", "nav_h_m", "true_lat_deg", "true_lon_deg",
                        "true_h_m", "speed_mps", "est_dg_n_mps2", "est_dg_e_mps2", "est_dg_d_mps2",
                        "truth_nav_dg_n_mps2", "truth_nav_dg_e_mps2", "truth_nav_dg_d_mps2", "truth_true_dg_n_mps2",
                        "truth_true_dg_e_mps2", "truth_true_dg_d_mps2", "loop_a_c_mps2", "var_rw_n_mps2sq",
                        "var_rw_e_mps2sq", "var_rw_d_mps2sq", "est_gam_nn_E", "est_gam_ee_E", "est_gam_dd_E", "est_gam_ne_E",
                        "est_gam_nd_E", "est_gam_ed_E", "health"};
  for (const char* c : need)
    if (!col.count(c)) throw std::runtime_error(csv.string() + ": no column '" + c + "'");
  size_t ln = 1;
  while (std::getline(f, line)) {
    ++ln;
    if (line.empty()) continue;
    const auto v = split(line);
    if (v.size() != head.size())
      throw std::runtime_error(csv.string() + ":" + std::to_string(ln) + ": " + std::to_string(v.size()) +
                               " values for " + std::to_string(head.size()) + " columns");
    auto num = [&](const char* c) {
      const std::string& s = v[col[c]];
      char* end = nullptr;
      const double x = std::strtod(s.c_str(), &end);
      if (end == s.c_str()) throw std::runtime_error(csv.string() + ":" + std::to_string(ln) + ": '" + s + "' in " + c);
      return x;
    };
    Sample s;
    s.t = num("t_s");
    s.seq = static_cast<int64_t>(num("seq"));
    s.lat_deg = num("nav_lat_deg");
    s.lon_deg = num("nav_lon_deg");
    s.h_m = num("nav_h_m");
    s.true_lat_deg = num("true_lat_deg");
    s.true_lon_deg = num("true_lon_deg");
    s.true_h_m = num("true_h_m");
    s.speed_mps = num("speed_mps");
    const char* e[3] = {"est_dg_n_mps2", "est_dg_e_mps2", "est_dg_d_mps2"};
    const char* tn[3] = {"truth_nav_dg_n_mps2", "truth_nav_dg_e_mps2", "truth_nav_dg_d_mps2"};
    const char* tt[3] = {"truth_true_dg_n_mps2", "truth_true_dg_e_mps2", "truth_true_dg_d_mps2"};
    for (int j = 0; j < 3; ++j) {
      s.est[static_cast<size_t>(j)] = num(e[j]);
      s.truth_nav[static_cast<size_t>(j)] = num(tn[j]);
      s.truth_true[static_cast<size_t>(j)] = num(tt[j]);
    }
    s.a_c = num("loop_a_c_mps2");
    s.var_rw = {num("var_rw_n_mps2sq"), num("var_rw_e_mps2sq"), num("var_rw_d_mps2sq")};
    const char* g[6] = {"est_gam_nn_E", "est_gam_ee_E", "est_gam_dd_E", "est_gam_ne_E", "est_gam_nd_E", "est_gam_ed_E"};
    for (int j = 0; j < 6; ++j) s.gam_E[static_cast<size_t>(j)] = num(g[j]);
    s.health = static_cast<uint32_t>(num("health"));
    {  // the body-axis bias coefficients (absent: no constant gradient error in the model)
      const char* jn[3] = {"n", "e", "d"};
      const char* kl[9] = {"xx", "xy", "xz", "yx", "yy", "yz", "zx", "zy", "zz"};
      for (size_t j = 0; j < 3; ++j)
        for (size_t q = 0; q < 9; ++q) {
          const std::string c = std::string("bias_") + jn[j] + "_" + kl[q] + "_m";
          if (col.count(c)) s.bias_coef[j][q] = num(c.c_str());
        }
    }
    r.s.push_back(s);
  }
  if (r.s.size() < 10) throw std::runtime_error(csv.string() + ": fewer than 10 samples");
  // local plane (east, north, up) at the first nav sample
  auto rad = [](double deg) { return static_cast<Real>(deg) * static_cast<Real>(kPi) / 180; };
  const gravity::Vec3 o = w84::geodetic_to_ecef(rad(r.s[0].lat_deg), rad(r.s[0].lon_deg), r.s[0].h_m);
  const gravity::Mat3 C_e_enu = w84::enu_to_ecef(rad(r.s[0].lat_deg), rad(r.s[0].lon_deg)).transpose();
  auto plane = [&](double lat, double lon, double h) {
    const gravity::Vec3 d = C_e_enu * (w84::geodetic_to_ecef(rad(lat), rad(lon), h) - o);
    return V3{static_cast<double>(d(0)), static_cast<double>(d(1)), static_cast<double>(d(2))};
  };
  for (auto& s : r.s) {
    s.enu = plane(s.lat_deg, s.lon_deg, s.h_m);
    s.true_enu = plane(s.true_lat_deg, s.true_lon_deg, s.true_h_m);
    s.g_abs = normal_gravity(s.lat_deg, s.h_m);
  }
  const double dt = (r.s.back().t - r.s.front().t) / static_cast<double>(r.s.size() - 1);
  if (!(dt > 0)) throw std::runtime_error(csv.string() + ": time does not advance");
  r.rate_hz = 1.0 / dt;
  const auto sum = dir / "summary.json";
  std::ifstream js(sum);
  if (js) {
    try {
      const auto j = nlohmann::json::parse(js);
      if (j.contains("gravimetry")) {
        const auto& g = j["gravimetry"];
        r.mode = g.value("mode", r.mode);
        r.field = g.value("field", std::string());
        r.sigma_gamma_bias_ps2 = g.value("sigma_gamma_bias_ps2", 0.0);
        if (g.contains("loop_poles_radps") && g["loop_poles_radps"].is_array())
          r.loop_poles = g["loop_poles_radps"].get<std::vector<double>>();
      }
    } catch (const std::exception& e) {
      throw std::runtime_error(sum.string() + ": " + e.what());
    }
  }
  return r;
}

std::vector<Line> find_lines(const Record& r, const LineOptions& o) {
  const size_t n = r.s.size();
  const double dt = 1.0 / r.rate_hz;
  const size_t w = std::max<size_t>(1, static_cast<size_t>(std::lround(o.smooth_s / 2 / dt)));
  std::vector<double> psi(n, 0.0);
  for (size_t i = 0; i < n; ++i) {
    const size_t a = i > 0 ? i - 1 : 0, b = std::min(n - 1, i + 1);
    psi[i] = std::atan2(r.s[b].enu[0] - r.s[a].enu[0], r.s[b].enu[1] - r.s[a].enu[1]) * 180 / kPi;
  }
  std::vector<char> ok(n, 0);
  for (size_t i = w; i + w < n; ++i) {
    const double rate = wrap180(psi[i + w] - psi[i - w]) / (2 * static_cast<double>(w) * dt);
    const double climb = (r.s[i + w].h_m - r.s[i - w].h_m) / (2 * static_cast<double>(w) * dt);
    ok[i] = std::fabs(rate) < o.max_turn_dps && std::fabs(climb) < o.max_climb_mps && r.s[i].speed_mps > 1;
  }
  std::vector<Line> runs;
  for (size_t i = 0; i < n;) {
    if (!ok[i]) {
      ++i;
      continue;
    }
    size_t j = i;
    double len = 0;
    while (j + 1 < n && ok[j + 1]) {
      len += std::hypot(r.s[j + 1].enu[0] - r.s[j].enu[0], r.s[j + 1].enu[1] - r.s[j].enu[1]);
      ++j;
    }
    if (len >= o.min_length_m) {
      Line l;
      l.begin = i;
      l.end = j + 1;
      l.length_m = len;
      l.heading_deg = std::atan2(r.s[j].enu[0] - r.s[i].enu[0], r.s[j].enu[1] - r.s[i].enu[1]) * 180 / kPi;
      double v = 0;
      for (size_t k = i; k <= j; ++k) v += r.s[k].speed_mps;
      l.speed_mps = v / static_cast<double>(j + 1 - i);
      runs.push_back(l);
    }
    i = j + 1;
  }
  // the commonest direction (mod 180) by length: the lines
  std::array<double, 18> bins{};
  for (const auto& l : runs) {
    double a = std::fmod(l.heading_deg + 360.0, 180.0);
    bins[static_cast<size_t>(std::min(17.0, std::floor(a / 10)))] += l.length_m;
  }
  const size_t best = static_cast<size_t>(std::max_element(bins.begin(), bins.end()) - bins.begin());
  const double dir = 10.0 * static_cast<double>(best) + 5;
  int nl = 0, nt = 0;
  for (auto& l : runs) {
    const double a = std::fmod(l.heading_deg + 360.0, 180.0);
    double d = std::fabs(a - dir);
    d = std::min(d, 180 - d);
    l.tie = d > 20;
    l.number = l.tie ? 1000 + 10 * nt++ : 10 * ++nl;
  }
  return runs;
}

bool closing(const Record& r, const ClosingOptions& o, Observation& out) {
  if (!o.enable) return false;
  const V3& z = r.s[0].true_enu;  // the zero point: the start, where G is surveyed
  bool away = false;
  size_t best = 0;
  double bd = std::numeric_limits<double>::infinity();
  for (size_t i = 1; i < r.s.size(); ++i) {
    const double d = std::hypot(r.s[i].true_enu[0] - z[0], r.s[i].true_enu[1] - z[1], r.s[i].true_enu[2] - z[2]);
    if (d > 10 * o.radius_m) {
      if (best != 0) break;  // the pass is over
      away = true;
    }
    if (away && d <= o.radius_m && d < bd) {
      bd = d;
      best = i;
    }
  }
  if (best == 0) return false;
  const Sample& s = r.s[best];
  const V3 off = enu_to_ned({s.true_enu[0] - z[0], s.true_enu[1] - z[1], s.true_enu[2] - z[2]});
  const V3 carry = gam_times(s.gam_E, off);  // the disturbance from the zero point to the nav's point
  out = Observation{};
  out.kind = "closing";
  out.coef = {{best, 1.0}};
  for (int j = 0; j < 3; ++j) {
    const size_t u = static_cast<size_t>(j);
    out.y[u] = s.est[u] - r.s[0].est[u] - carry[u];
  }
  // the carry's own errors: 1 E of gradient noise over the offset, 10 % for the field's curvature
  out.var = 1e-16 + std::pow(1e-9 * norm3(off), 2) + std::pow(0.1 * norm3(carry), 2);
  out.lat_deg = s.lat_deg;
  out.lon_deg = s.lon_deg;
  return true;
}

std::vector<Observation> crossovers(const Record& r, const std::vector<Line>& lines, double position_sigma_m) {
  std::vector<Observation> out;
  for (size_t a = 0; a < lines.size(); ++a)
    for (size_t b = a + 1; b < lines.size(); ++b) {
      const Line &A = lines[a], &B = lines[b];
      for (size_t i = A.begin; i + 1 < A.end; ++i) {
        const V3 &p = r.s[i].enu, &p1 = r.s[i + 1].enu;
        for (size_t j = B.begin; j + 1 < B.end; ++j) {
          const V3 &q = r.s[j].enu, &q1 = r.s[j + 1].enu;
          if (std::max(p[0], p1[0]) < std::min(q[0], q1[0]) || std::max(q[0], q1[0]) < std::min(p[0], p1[0]) ||
              std::max(p[1], p1[1]) < std::min(q[1], q1[1]) || std::max(q[1], q1[1]) < std::min(p[1], p1[1]))
            continue;
          const double d1x = p1[0] - p[0], d1y = p1[1] - p[1], d2x = q1[0] - q[0], d2y = q1[1] - q[1];
          const double den = d1x * d2y - d1y * d2x;
          if (std::fabs(den) < 1e-9) continue;
          const double al = ((q[0] - p[0]) * d2y - (q[1] - p[1]) * d2x) / den;
          const double be = ((q[0] - p[0]) * d1y - (q[1] - p[1]) * d1x) / den;
          if (al < 0 || al >= 1 || be < 0 || be >= 1) continue;
          Observation ob;
          ob.kind = "crossover";
          ob.line_a = A.number;
          ob.line_b = B.number;
          ob.coef = {{i, 1 - al}, {i + 1, al}, {j, -(1 - be)}, {j + 1, -be}};
          const double ha = r.s[i].h_m * (1 - al) + r.s[i + 1].h_m * al;
          const double hb = r.s[j].h_m * (1 - be) + r.s[j + 1].h_m * be;
          std::array<double, 6> g{};
          for (size_t k = 0; k < 6; ++k) g[k] = (r.s[i].gam_E[k] + r.s[j].gam_E[k]) / 2;
          const V3 carry = gam_times(g, {0, 0, -(ha - hb)});  // A's point against B's, NED
          for (size_t u = 0; u < 3; ++u) {
            const double ea = r.s[i].est[u] * (1 - al) + r.s[i + 1].est[u] * al;
            const double eb = r.s[j].est[u] * (1 - be) + r.s[j + 1].est[u] * be;
            ob.y[u] = ea - eb - carry[u];
          }
          // the two passes' true points differ by their nav errors: |Gamma| sqrt(2) sigma_pos
          double g2 = 0;
          for (size_t k = 0; k < 6; ++k) g2 += (k < 3 ? 1.0 : 2.0) * g[k] * g[k] * 1e-18;
          ob.var = 2e-16 + std::pow(1e-9 * (ha - hb), 2) + std::pow(0.1 * norm3(carry), 2) +
                   2 * g2 / 3 * position_sigma_m * position_sigma_m;
          ob.lat_deg = r.s[i].lat_deg * (1 - al) + r.s[i + 1].lat_deg * al;
          ob.lon_deg = r.s[i].lon_deg * (1 - al) + r.s[i + 1].lon_deg * al;
          out.push_back(ob);
        }
      }
    }
  return out;
}

Adjusted adjust(const Record& r, const std::vector<Observation>& obs) {
  const size_t n = r.s.size(), m = obs.size();
  Adjusted a;
  a.value.resize(n);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  a.sigma.assign(n, V3{nan, nan, nan});
  a.residual.assign(m, V3{});
  for (size_t i = 0; i < n; ++i) a.value[i] = r.s[i].est;
  if (r.mode != "gradiometer") {
    // the R&W loop has no error model here: the closing measurement takes out its mean error
    for (const auto& o : obs)
      if (o.kind == "closing")
        for (auto& v : a.value)
          for (size_t u = 0; u < 3; ++u) v[u] -= o.y[u];
    return a;
  }
  const double sb2 = r.sigma_gamma_bias_ps2 * r.sigma_gamma_bias_ps2;
  for (size_t u = 0; u < 3; ++u) {  // each component with its own random walk
    auto K = [&](size_t i, size_t j) {
      const auto &p = r.s[i].bias_coef[u], &q = r.s[j].bias_coef[u];
      double dot = 0;
      for (size_t k = 0; k < 9; ++k) dot += p[k] * q[k];
      return std::min(r.s[i].var_rw[u], r.s[j].var_rw[u]) + sb2 * dot;
    };
    for (size_t i = 0; i < n; ++i) a.sigma[i][u] = std::sqrt(std::max(0.0, K(i, i)));
    if (m == 0) continue;
    Eigen::MatrixXd KA(n, static_cast<Eigen::Index>(m));  // K A^T
    for (size_t t = 0; t < n; ++t)
      for (size_t k = 0; k < m; ++k) {
        double sum = 0;
        for (const auto& c : obs[k].coef) sum += c.second * K(t, c.first);
        KA(static_cast<Eigen::Index>(t), static_cast<Eigen::Index>(k)) = sum;
      }
    Eigen::MatrixXd S(static_cast<Eigen::Index>(m), static_cast<Eigen::Index>(m));
    for (size_t k = 0; k < m; ++k)
      for (size_t l = 0; l < m; ++l) {
        double sum = 0;
        for (const auto& c : obs[k].coef)
          sum += c.second * KA(static_cast<Eigen::Index>(c.first), static_cast<Eigen::Index>(l));
        S(static_cast<Eigen::Index>(k), static_cast<Eigen::Index>(l)) = sum + (k == l ? obs[k].var : 0.0);
      }
    const Eigen::LDLT<Eigen::MatrixXd> ldlt(S);
    if (ldlt.info() != Eigen::Success) throw std::runtime_error("gravimetry: the observations' covariance is singular");
    Eigen::VectorXd y(static_cast<Eigen::Index>(m));
    for (size_t k = 0; k < m; ++k) y(static_cast<Eigen::Index>(k)) = obs[k].y[u];
    const Eigen::VectorXd e = KA * ldlt.solve(y);
    for (size_t t = 0; t < n; ++t) a.value[t][u] -= e(static_cast<Eigen::Index>(t));
    for (size_t k = 0; k < m; ++k) {
      double sum = 0;
      for (const auto& c : obs[k].coef) sum += c.second * e(static_cast<Eigen::Index>(c.first));
      a.residual[k][u] = obs[k].y[u] - sum;
    }
    const Eigen::MatrixXd SiKt = ldlt.solve(KA.transpose());  // m x n
    for (size_t t = 0; t < n; ++t) {
      const double red = KA.row(static_cast<Eigen::Index>(t)).dot(SiKt.col(static_cast<Eigen::Index>(t)));
      a.sigma[t][u] = std::sqrt(std::max(0.0, K(t, t) - red));
    }
  }
  return a;
}

std::vector<double> lowpass(const std::vector<double>& x, double dt, double fc, int order) {
  if (order < 2 || order > 8 || order % 2) throw std::invalid_argument("lowpass: order must be 2, 4, 6 or 8");
  if (!(fc > 0) || !(fc * dt < 0.5)) throw std::invalid_argument("lowpass: cut-off must be in (0, Nyquist)");
  const size_t n = x.size();
  if (n < 2) return x;
  const double K = std::tan(kPi * fc * dt);
  struct Bq {
    double b0, b1, b2, a1, a2;
  };
  std::vector<Bq> sec;
  for (int k = 0; k < order / 2; ++k) {
    const double th = kPi * (2.0 * k + 1) / (2.0 * order);  // pole pair at -sin(th) +- i cos(th)
    const double q = 2 * std::sin(th);
    const double D = 1 + q * K + K * K;
    sec.push_back({K * K / D, 2 * K * K / D, K * K / D, 2 * (K * K - 1) / D, (1 - q * K + K * K) / D});
  }
  const size_t pad = std::min(n - 1, static_cast<size_t>(std::ceil(3.0 / (fc * dt))));
  std::vector<double> y;
  y.reserve(n + 2 * pad);
  for (size_t i = pad; i >= 1; --i) y.push_back(2 * x[0] - x[i]);
  y.insert(y.end(), x.begin(), x.end());
  for (size_t i = 1; i <= pad; ++i) y.push_back(2 * x[n - 1] - x[n - 1 - i]);
  auto pass = [&](std::vector<double>& v) {
    for (const auto& s : sec) {
      double z2 = (s.b2 - s.a2) * v[0], z1 = (s.b1 - s.a1) * v[0] + z2;  // steady state of v[0]
      for (double& xv : v) {
        const double out = s.b0 * xv + z1;
        z1 = s.b1 * xv - s.a1 * out + z2;
        z2 = s.b2 * xv - s.a2 * out;
        xv = out;
      }
    }
  };
  pass(y);
  std::reverse(y.begin(), y.end());
  pass(y);
  std::reverse(y.begin(), y.end());
  return std::vector<double>(y.begin() + static_cast<std::ptrdiff_t>(pad), y.begin() + static_cast<std::ptrdiff_t>(pad + n));
}

double lowpass_gain(double f, double fc, int order) { return 1.0 / (1.0 + std::pow(f / fc, 2.0 * order)); }

Product make_product(const Record& r, const std::vector<Line>& lines, const Adjusted& a, double wavelength_m) {
  Product p;
  p.wavelength_m = wavelength_m;
  p.lines = lines;
  const double dt = 1.0 / r.rate_hz;
  double se = 0, seh = 0, sxi = 0, set_ = 0, ss = 0, sn = 0, sig = 0, spos = 0, maxe = 0;
  size_t ntot = 0;
  // the whole flight filtered once (the lines are parts of one continuous record: no edges at
  // the lines' ends), cut-off from the lines' mean ground speed
  double vs = 0, nv = 0;
  for (const Line& l : lines) {
    vs += l.speed_mps * static_cast<double>(l.end - l.begin);
    nv += static_cast<double>(l.end - l.begin);
  }
  const double fc = std::min(0.45 / dt, (nv > 0 ? vs / nv : 1.0) / wavelength_m);
  const size_t N = r.s.size();
  std::array<std::vector<double>, 3> ev, tv, ttv;
  for (size_t u = 0; u < 3; ++u) {
    std::vector<double> e(N), t(N), tt(N);
    for (size_t i = 0; i < N; ++i) {
      e[i] = a.value[i][u];
      t[i] = r.s[i].truth_nav[u];
      tt[i] = r.s[i].truth_true[u];
    }
    ev[u] = lowpass(e, dt, fc);
    tv[u] = lowpass(t, dt, fc);
    ttv[u] = lowpass(tt, dt, fc);
  }
  if (r.mode == "model" && r.loop_poles.size() == 3) {
    // Rubenstein & Winter's loop output is -a_c = H_g(s) dg, H_g = p1 p2 p3 / ((s+p1)(s+p2)(s+p3))
    // (vchan.h, docs/vertical.md): after the flight its lag and attenuation are undone inside
    // the product's band, dg = H_g^-1 y = y + c1 dy/dt + c2 d2y/dt2 + c3 d3y/dt3 on the filtered
    // y, c1 = sum 1/p_i, c2 = sum_(i<j) 1/(p_i p_j), c3 = 1/(p1 p2 p3) (central differences of
    // the low-passed series, which the filter makes smooth on the sample scale)
    const double p1 = r.loop_poles[0], p2 = r.loop_poles[1], p3 = r.loop_poles[2];
    const double c1 = 1 / p1 + 1 / p2 + 1 / p3, c2 = 1 / (p1 * p2) + 1 / (p1 * p3) + 1 / (p2 * p3),
                 c3 = 1 / (p1 * p2 * p3);
    const std::vector<double>& y = ev[2];
    std::vector<double> out(y);
    for (size_t i = 2; i + 2 < N; ++i) {
      const double d1 = (y[i + 1] - y[i - 1]) / (2 * dt);
      const double d2 = (y[i + 1] - 2 * y[i] + y[i - 1]) / (dt * dt);
      const double d3 = (y[i + 2] - 2 * y[i + 1] + 2 * y[i - 1] - y[i - 2]) / (2 * dt * dt * dt);
      out[i] = y[i] + c1 * d1 + c2 * d2 + c3 * d3;
    }
    ev[2] = out;
  }
  for (const Line& l : lines) {
    const size_t n = l.end - l.begin;
    LineStats st;
    st.number = l.number;
    st.tie = l.tie;
    st.n = n;
    double le = 0, leh = 0, let = 0, lt = 0, lnm = 0, lsig = 0, lpos = 0, lmax = 0;
    double lxi2 = 0, leta2 = 0;
    for (size_t i = 0; i < n; ++i) {
      const size_t k = l.begin + i;
      const Sample& s = r.s[k];
      V3 e{}, t{}, tt{};
      for (size_t u = 0; u < 3; ++u) {
        e[u] = ev[u][k];
        t[u] = tv[u][k];
        tt[u] = ttv[u][k];
      }
      p.idx.push_back(k);
      p.line_of.push_back(l.number);
      p.est.push_back(e);
      p.truth.push_back(t);
      p.truth_true.push_back(tt);
      p.sigma.push_back(a.sigma[k]);
      const double sd = a.sigma[k][2];
      const double d = e[2] - tt[2];
      le += d * d;
      lmax = std::max(lmax, std::fabs(d));
      leh += ((e[0] - tt[0]) * (e[0] - tt[0]) + (e[1] - tt[1]) * (e[1] - tt[1])) / 2;
      lxi2 += std::pow((e[0] - tt[0]) / s.g_abs, 2);
      leta2 += std::pow((e[1] - tt[1]) / s.g_abs, 2);
      let += (e[2] - t[2]) * (e[2] - t[2]);
      lt += tt[2] * tt[2];
      lsig += sd * sd;
      for (size_t u = 0; u < 3; ++u)
        if (std::isfinite(a.sigma[k][u]) && a.sigma[k][u] > 0) lnm += std::pow((e[u] - tt[u]) / a.sigma[k][u], 2) / 3;
      lpos += std::pow(s.enu[0] - s.true_enu[0], 2) + std::pow(s.enu[1] - s.true_enu[1], 2);
    }
    const double dn = static_cast<double>(n);
    st.rms_mgal = std::sqrt(le / dn) / kMgal;
    st.max_mgal = lmax / kMgal;
    st.rms_h_mgal = std::sqrt(leh / dn) / kMgal;
    st.rms_xi_arcsec = std::sqrt(lxi2 / dn) / kArcsec;
    st.rms_eta_arcsec = std::sqrt(leta2 / dn) / kArcsec;
    st.rms_true_pos_mgal = std::sqrt(let / dn) / kMgal;
    st.signal_rms_mgal = std::sqrt(lt / dn) / kMgal;
    st.rms_sigma_mgal = std::sqrt(lsig / dn) / kMgal;
    st.nmse = lnm / dn;
    st.pos_err_rms_m = std::sqrt(lpos / dn);
    p.stats.push_back(st);
    se += le;
    seh += leh;
    sxi += lxi2 + leta2;
    set_ += let;
    ss += lt;
    sn += lnm;
    sig += lsig;
    spos += lpos;
    maxe = std::max(maxe, lmax);
    ntot += n;
  }
  if (ntot) {
    const double dn = static_cast<double>(ntot);
    p.all.n = ntot;
    p.all.rms_mgal = std::sqrt(se / dn) / kMgal;
    p.all.max_mgal = maxe / kMgal;
    p.all.rms_h_mgal = std::sqrt(seh / dn) / kMgal;
    p.all.rms_xi_arcsec = std::sqrt(sxi / 2 / dn) / kArcsec;
    p.all.rms_eta_arcsec = p.all.rms_xi_arcsec;
    p.all.rms_true_pos_mgal = std::sqrt(set_ / dn) / kMgal;
    p.all.signal_rms_mgal = std::sqrt(ss / dn) / kMgal;
    p.all.rms_sigma_mgal = std::sqrt(sig / dn) / kMgal;
    p.all.nmse = sn / dn;
    p.all.pos_err_rms_m = std::sqrt(spos / dn);
  }
  return p;
}

Grid make_grid(const Record& r, const Product& p, double spacing_m, double radius_m) {
  Grid g;
  g.spacing_m = spacing_m;
  g.radius_m = radius_m;
  if (p.idx.empty() || !(spacing_m > 0) || !(radius_m > 0)) return g;
  double x0 = 1e300, x1 = -1e300, y0 = 1e300, y1 = -1e300;
  for (size_t k : p.idx) {
    x0 = std::min(x0, r.s[k].enu[0]);
    x1 = std::max(x1, r.s[k].enu[0]);
    y0 = std::min(y0, r.s[k].enu[1]);
    y1 = std::max(y1, r.s[k].enu[1]);
  }
  g.nx = static_cast<size_t>(std::floor((x1 - x0) / spacing_m)) + 1;
  g.ny = static_cast<size_t>(std::floor((y1 - y0) / spacing_m)) + 1;
  if (g.nx * g.ny > 4000000) throw std::runtime_error("gravimetry: grid of over 4e6 nodes (raise the spacing)");
  std::vector<double> w(g.nx * g.ny, 0.0), se(g.nx * g.ny, 0.0), st(g.nx * g.ny, 0.0);
  std::vector<int> cnt(g.nx * g.ny, 0);
  const double s2 = std::pow(radius_m / 2, 2);
  const long reach = static_cast<long>(std::ceil(radius_m / spacing_m));
  for (size_t i = 0; i < p.idx.size(); ++i) {
    const V3& q = r.s[p.idx[i]].enu;
    const long cx = std::lround((q[0] - x0) / spacing_m), cy = std::lround((q[1] - y0) / spacing_m);
    for (long iy = std::max(0L, cy - reach); iy <= std::min(static_cast<long>(g.ny) - 1, cy + reach); ++iy)
      for (long ix = std::max(0L, cx - reach); ix <= std::min(static_cast<long>(g.nx) - 1, cx + reach); ++ix) {
        const double dx = x0 + static_cast<double>(ix) * spacing_m - q[0], dy = y0 + static_cast<double>(iy) * spacing_m - q[1];
        const double d2 = dx * dx + dy * dy;
        if (d2 > radius_m * radius_m) continue;
        const size_t k = static_cast<size_t>(iy) * g.nx + static_cast<size_t>(ix);
        const double wk = std::exp(-d2 / (2 * s2));
        w[k] += wk;
        se[k] += wk * p.est[i][2];
        st[k] += wk * p.truth_true[i][2];
        ++cnt[k];
      }
  }
  // nodes back to latitude and longitude: the local plane's inverse to first order (the plane
  // spans a survey block; the positions are for display and gridding software)
  const Sample& o = r.s[0];
  const double la = o.lat_deg * kPi / 180;
  Real rm = 0, rn = 0;
  w84::radii(static_cast<Real>(la), rm, rn);
  const double m = static_cast<double>(rm) + o.h_m, nrad = (static_cast<double>(rn) + o.h_m) * std::cos(la);
  g.node.resize(g.nx * g.ny);
  for (size_t iy = 0; iy < g.ny; ++iy)
    for (size_t ix = 0; ix < g.nx; ++ix) {
      const size_t k = iy * g.nx + ix;
      GridNode& n = g.node[k];
      n.lat_deg = o.lat_deg + (y0 + static_cast<double>(iy) * spacing_m) / m * 180 / kPi;
      n.lon_deg = o.lon_deg + (x0 + static_cast<double>(ix) * spacing_m) / nrad * 180 / kPi;
      n.n = cnt[k];
      n.dg = cnt[k] ? se[k] / w[k] : std::numeric_limits<double>::quiet_NaN();
      n.truth = cnt[k] ? st[k] / w[k] : std::numeric_limits<double>::quiet_NaN();
    }
  return g;
}

void write_grid_csv(const std::filesystem::path& path, const Grid& g) {
  std::ofstream f(path);
  if (!f) throw std::runtime_error("cannot write " + path.string());
  f << "# nodes " << g.nx << " x " << g.ny << ", spacing " << g.spacing_m << " m, radius " << g.radius_m << " m\n";
  f << "ix,iy,lat_deg,lon_deg,dg_mgal,truth_dg_mgal,err_dg_mgal,samples\n";
  char b[256];
  for (size_t iy = 0; iy < g.ny; ++iy)
    for (size_t ix = 0; ix < g.nx; ++ix) {
      const GridNode& n = g.node[iy * g.nx + ix];
      std::snprintf(b, sizeof b, "%zu,%zu,%.8f,%.8f,%.4f,%.4f,%.4f,%d\n", ix, iy, n.lat_deg, n.lon_deg, n.dg / kMgal,
                    n.truth / kMgal, (n.dg - n.truth) / kMgal, n.n);
      f << b;
    }
}

void write_csv(const std::filesystem::path& path, const Record& r, const Product& p) {
  std::ofstream f(path);
  if (!f) throw std::runtime_error("cannot write " + path.string());
  f << "line,type,fid,time_s,lat_deg,lon_deg,height_m,dg_mgal,xi_arcsec,eta_arcsec,dg_n_mgal,dg_e_mgal,"
       "sigma_dg_mgal,sigma_xi_arcsec,sigma_eta_arcsec,truth_dg_mgal,truth_xi_arcsec,truth_eta_arcsec,"
       "err_dg_mgal,err_xi_arcsec,err_eta_arcsec,truth_at_nav_position_dg_mgal,true_lat_deg,true_lon_deg\n";
  char b[768];
  for (size_t i = 0; i < p.idx.size(); ++i) {
    const Sample& s = r.s[p.idx[i]];
    const V3 &e = p.est[i], &t = p.truth_true[i];  // the truth along the true path
    const double g = s.g_abs;
    const V3& sg = p.sigma[i];
    const bool tie = p.line_of[i] >= 1000;
    std::snprintf(b, sizeof b,
                  "%d,%s,%lld,%.2f,%.8f,%.8f,%.2f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,"
                  "%.4f,%.4f,%.8f,%.8f\n",
                  p.line_of[i], tie ? "tie" : "line", static_cast<long long>(s.seq), s.t, s.lat_deg, s.lon_deg, s.h_m,
                  e[2] / kMgal, -e[0] / g / kArcsec, -e[1] / g / kArcsec, e[0] / kMgal, e[1] / kMgal, sg[2] / kMgal,
                  sg[0] / g / kArcsec, sg[1] / g / kArcsec, t[2] / kMgal, -t[0] / g / kArcsec, -t[1] / g / kArcsec,
                  (e[2] - t[2]) / kMgal, -(e[0] - t[0]) / g / kArcsec, -(e[1] - t[1]) / g / kArcsec,
                  p.truth[i][2] / kMgal, s.true_lat_deg, s.true_lon_deg);
    f << b;
  }
}

void write_xyz(const std::filesystem::path& path, const Record& r, const Product& p, const std::string& title) {
  std::ofstream f(path);
  if (!f) throw std::runtime_error("cannot write " + path.string());
  f << "/ " << title << "\n";
  f << "/ gravity disturbance (mGal, down component of g - gamma), deflections xi, eta (arcsec), one-sigma;\n";
  f << "/ low-passed to a full wavelength of " << p.wavelength_m << " m; positions are the navigation's (WGS-84)\n";
  f << "/ FID TIME LAT LON HEIGHT DG XI ETA SIGMA_DG SIGMA_DEFL\n";
  int cur = -1;
  char b[512];
  for (size_t i = 0; i < p.idx.size(); ++i) {
    if (p.line_of[i] != cur) {
      cur = p.line_of[i];
      f << (cur >= 1000 ? "Tie " : "Line ") << cur << "\n";
    }
    const Sample& s = r.s[p.idx[i]];
    const V3& e = p.est[i];
    std::snprintf(b, sizeof b, "%lld %.2f %.8f %.8f %.2f %.4f %.4f %.4f %.4f %.4f\n", static_cast<long long>(s.seq),
                  s.t, s.lat_deg, s.lon_deg, s.h_m, e[2] / kMgal, -e[0] / s.g_abs / kArcsec,
                  -e[1] / s.g_abs / kArcsec, p.sigma[i][2] / kMgal,
                  std::hypot(p.sigma[i][0], p.sigma[i][1]) / std::sqrt(2.0) / s.g_abs / kArcsec);
    f << b;
  }
}

}  // namespace ggins::gravimetry
