#include "ggins/coldatom/route_map.hpp"

#include <unsupported/Eigen/FFT>

#include <cmath>
#include <complex>
#include <cstdio>
#include <fstream>
#include <memory>
#include <random>
#include <sstream>
#include <stdexcept>

#include "ggins/gravity/normal.hpp"
#include "ggins/gravity/spherical_harmonic.hpp"
#include "ggins/gravity/wgs84.hpp"

namespace ggins::coldatom {

namespace {
constexpr double kDeg = 3.14159265358979323846 / 180.0;
constexpr double kG = 6.674e-11;
void unit(double lat, double lon, double* p) {
  p[0] = std::cos(lat) * std::cos(lon); p[1] = std::cos(lat) * std::sin(lon); p[2] = std::sin(lat);
}
double dot(const double* a, const double* b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
void cross(const double* a, const double* b, double* c) {
  c[0] = a[1] * b[2] - a[2] * b[1]; c[1] = a[2] * b[0] - a[0] * b[2]; c[2] = a[0] * b[1] - a[1] * b[0];
}
void normalize(double* a) { const double n = std::sqrt(dot(a, a)); a[0] /= n; a[1] /= n; a[2] /= n; }
// Catmull-Rom weights
void cr(double t, double w[4]) {
  const double t2 = t * t, t3 = t2 * t;
  w[0] = 0.5 * (-t3 + 2 * t2 - t); w[1] = 0.5 * (3 * t3 - 5 * t2 + 2);
  w[2] = 0.5 * (-3 * t3 + 4 * t2 + t); w[3] = 0.5 * (t3 - t2);
}
}  // namespace

RouteMap::RouteMap(const RouteMapParams& p, const std::string& egm96_path, const std::string& cache_dir) : p_(p) {
  R_ = 6371000.0 + p.h;
  double p1[3];
  unit(p.lat0_deg * kDeg, p.lon0_deg * kDeg, p0_);
  unit(p.lat1_deg * kDeg, p.lon1_deg * kDeg, p1);
  cross(p0_, p1, n_);
  normalize(n_);
  cross(n_, p0_, e2_);
  L_ = R_ * std::acos(dot(p0_, p1));

  // --- EGM96 (+ normal) grid ---
  egm_ns_ = static_cast<int>(std::ceil((L_ + 2 * p.margin) / p.egm_step)) + 1;
  egm_nc_ = static_cast<int>(std::ceil(2 * p.half_width / p.egm_step)) + 1;
  egm_.assign(static_cast<std::size_t>(egm_ns_) * egm_nc_, 0.0);
  std::ostringstream key;
  key << cache_dir << "/egm96_gzz_" << static_cast<long>(p.h) << "_" << static_cast<long>(p.egm_step) << "_"
      << static_cast<long>(p.half_width) << "_" << static_cast<long>(p.margin) << "_" << (p.with_egm96 ? 1 : 0)
      << ".bin";
  bool loaded = false;
  if (!cache_dir.empty()) {
    std::ifstream f(key.str(), std::ios::binary);
    if (f) {
      f.read(reinterpret_cast<char*>(egm_.data()), static_cast<std::streamsize>(egm_.size() * sizeof(double)));
      loaded = static_cast<bool>(f);
    }
  }
  if (!loaded) {
    using namespace ggins::gravity;
    auto normal = std::make_shared<NormalField>();
    std::unique_ptr<SphericalHarmonicField> dist;
    if (p.with_egm96) {
      auto egm = read_nasa_ascii(egm96_path);
      dist = std::make_unique<SphericalHarmonicField>(subtract_normal(egm), 360, 2, ShPrecision::Double);
    }
    for (int is = 0; is < egm_ns_; ++is) {
      for (int ic = 0; ic < egm_nc_; ++ic) {
        double lat, lon;
        route_point(-p.margin + is * p.egm_step, -p.half_width + ic * p.egm_step, &lat, &lon);
        const Vec3 r = wgs84::geodetic_to_ecef(lat, lon, p.h);
        const Mat3 enu = wgs84::enu_to_ecef(lat, lon);
        const Vec3 down = -enu.col(2);
        Mat3 gam = normal->eval(r).gamma;
        if (dist) gam += dist->eval(r).gamma;
        egm_[static_cast<std::size_t>(is) * egm_nc_ + ic] = static_cast<double>(down.dot(gam * down));
      }
    }
    if (!cache_dir.empty()) {
      std::ofstream f(key.str(), std::ios::binary);
      f.write(reinterpret_cast<const char*>(egm_.data()), static_cast<std::streamsize>(egm_.size() * sizeof(double)));
    }
  }

  // --- synthetic topography, forward-modelled ---
  if (p.with_topo) {
    const double ext = 20e3;
    topo_s0_ = -p.margin - ext;
    topo_c0_ = -p.half_width - ext;
    int ns = static_cast<int>(std::ceil((L_ + 2 * p.margin + 2 * ext) / p.topo_step));
    ns = (ns + 63) / 64 * 64;
    int nc = static_cast<int>(std::ceil((2 * p.half_width + 2 * ext) / p.topo_step));
    nc = (nc + 15) / 16 * 16;
    topo_ns_ = ns; topo_nc_ = nc;
    using cd = std::complex<double>;
    std::vector<cd> H(static_cast<std::size_t>(ns) * nc);
    std::mt19937_64 rng(p.seed);
    std::normal_distribution<double> n01(0, 1);
    for (auto& v : H) v = n01(rng);
    Eigen::FFT<double> fft;
    auto fft2 = [&](std::vector<cd>& a, bool inv) {
      std::vector<cd> in(static_cast<std::size_t>(std::max(ns, nc))), out;
      for (int i = 0; i < ns; ++i) {  // rows (c)
        in.assign(a.begin() + static_cast<long>(i) * nc, a.begin() + static_cast<long>(i + 1) * nc);
        if (inv) fft.inv(out, in); else fft.fwd(out, in);
        std::copy(out.begin(), out.end(), a.begin() + static_cast<long>(i) * nc);
      }
      in.resize(static_cast<std::size_t>(ns));
      for (int j = 0; j < nc; ++j) {  // columns (s)
        for (int i = 0; i < ns; ++i) in[static_cast<std::size_t>(i)] = a[static_cast<std::size_t>(i) * nc + j];
        if (inv) fft.inv(out, in); else fft.fwd(out, in);
        for (int i = 0; i < ns; ++i) a[static_cast<std::size_t>(i) * nc + j] = out[static_cast<std::size_t>(i)];
      }
    };
    fft2(H, false);
    std::vector<cd> Gm(H.size());
    const double kmin = 2 * M_PI / p.topo_highpass, d = p.h - p.topo_mean;
    for (int i = 0; i < ns; ++i) {
      const int fi = (i <= ns / 2) ? i : i - ns;
      const double ks = 2 * M_PI * fi / (ns * p.topo_step);
      for (int j = 0; j < nc; ++j) {
        const int fj = (j <= nc / 2) ? j : j - nc;
        const double kc = 2 * M_PI * fj / (nc * p.topo_step);
        const double k = std::hypot(ks, kc);
        const std::size_t id = static_cast<std::size_t>(i) * nc + j;
        if (k == 0) { H[id] = 0; Gm[id] = 0; continue; }
        const double x4 = std::pow(k / kmin, 4);
        const double amp = std::pow(k, -1.5) * std::sqrt(x4 / (1 + x4));  // sqrt of PSD k^-3, high-passed
        H[id] *= amp;
        Gm[id] = H[id] * (2 * M_PI * kG * p.rho * k * std::exp(-k * d));
      }
    }
    fft2(H, true);
    fft2(Gm, true);
    double s2 = 0;
    for (const auto& v : H) s2 += v.real() * v.real();
    const double scale = p.topo_rms / std::sqrt(s2 / static_cast<double>(H.size()));
    topo_.resize(H.size());
    double g2 = 0;
    for (std::size_t i = 0; i < H.size(); ++i) {
      const double g = Gm[i].real() * scale;
      topo_[i] = static_cast<float>(g);
      g2 += g * g;
    }
    topo_h_rms_ = p.topo_rms;
    topo_g_rms_ = std::sqrt(g2 / static_cast<double>(H.size()));
  }
}

void RouteMap::route_point(double s, double c, double* lat, double* lon) const {
  const double a = s / R_, b = c / R_;
  double q[3];
  for (int i = 0; i < 3; ++i) q[i] = std::cos(b) * (std::cos(a) * p0_[i] + std::sin(a) * e2_[i]) + std::sin(b) * n_[i];
  *lat = std::asin(q[2]);
  *lon = std::atan2(q[1], q[0]);
}

void RouteMap::route_coords(double lat, double lon, double* s, double* c) const {
  double q[3];
  unit(lat, lon, q);
  *c = R_ * std::asin(dot(q, n_));
  *s = R_ * std::atan2(dot(q, e2_), dot(q, p0_));
}

double RouteMap::heading(double s) const {
  double lat, lon, lat2, lon2;
  route_point(s, 0, &lat, &lon);
  route_point(s + 1.0, 0, &lat2, &lon2);
  return std::atan2((lon2 - lon) * std::cos(lat), lat2 - lat);
}

bool RouteMap::land(double lat) const {
  const double d = lat / kDeg;
  return !(d > p_.sea_lat_s && d < p_.sea_lat_n);
}

double RouteMap::egm(double s, double c) const {
  const double fs = (s + p_.margin) / p_.egm_step, fc = (c + p_.half_width) / p_.egm_step;
  int is = static_cast<int>(std::floor(fs)), ic = static_cast<int>(std::floor(fc));
  is = std::min(std::max(is, 1), egm_ns_ - 3);
  ic = std::min(std::max(ic, 1), egm_nc_ - 3);
  double ws[4], wc[4];
  cr(fs - is, ws);
  cr(fc - ic, wc);
  double v = 0;
  for (int a = 0; a < 4; ++a)
    for (int b = 0; b < 4; ++b) v += ws[a] * wc[b] * egm_[static_cast<std::size_t>(is - 1 + a) * egm_nc_ + (ic - 1 + b)];
  return v;
}

double RouteMap::topo(double s, double c) const {
  if (topo_.empty()) return 0;
  const double fs = (s - topo_s0_) / p_.topo_step, fc = (c - topo_c0_) / p_.topo_step;
  const int is = static_cast<int>(std::floor(fs)), ic = static_cast<int>(std::floor(fc));
  if (is < 0 || ic < 0 || is + 1 >= topo_ns_ || ic + 1 >= topo_nc_) return 0;
  const double a = fs - is, b = fc - ic;
  auto at = [&](int i, int j) { return static_cast<double>(topo_[static_cast<std::size_t>(i) * topo_nc_ + j]); };
  return (1 - a) * ((1 - b) * at(is, ic) + b * at(is, ic + 1)) + a * ((1 - b) * at(is + 1, ic) + b * at(is + 1, ic + 1));
}

bool RouteMap::gzz(double lat, double lon, double h, double* out) const {
  double s, c;
  route_coords(lat, lon, &s, &c);
  if (std::fabs(c) > p_.half_width - 2 * p_.egm_step || s < -p_.margin + 2 * p_.egm_step ||
      s > L_ + p_.margin - 2 * p_.egm_step)
    return false;
  // land weight with a 2 km taper at both coasts (latitude as the along-track coordinate)
  const double d = lat / kDeg, taper = 2000.0 / 111e3;
  auto ramp = [](double x) { return x <= 0 ? 0.0 : (x >= 1 ? 1.0 : x * x * (3 - 2 * x)); };
  const double wl = std::max(ramp((d - p_.sea_lat_n) / taper), ramp((p_.sea_lat_s - d) / taper));
  const double g0 = egm(s, c);
  *out = g0 + wl * topo(s, c) - 3.0 * g0 / (6371000.0 + p_.h) * (h - p_.h);
  return true;
}

}  // namespace ggins::coldatom
