#include "ggins/gravity/spherical_harmonic.hpp"

#include "ggins/gravity/wgs84.hpp"
#include "sh_engine.hpp"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdlib>
#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace ggins::gravity {
namespace {

// One line of a coefficient file split into whitespace-separated tokens,
// with errors that name the file and line.
struct Line {
  const std::string* path;
  int no;
  std::vector<std::string> tok;
  [[noreturn]] void fail(const std::string& what) const {
    throw std::runtime_error(*path + ":" + std::to_string(no) + ": " + what);
  }
  Real real(std::size_t i, const char* what) const {
    std::string t = tok[i];
    for (char& ch : t)
      if (ch == 'D' || ch == 'd') ch = 'e';  // Fortran exponents
    char* end = nullptr;
    errno = 0;
    const Real v = std::strtold(t.c_str(), &end);
    if (end == t.c_str() || *end != '\0' || errno == ERANGE || !std::isfinite(v))
      fail(std::string("bad ") + what + " '" + tok[i] + "'");
    return v;
  }
  int integer(std::size_t i, const char* what) const {
    char* end = nullptr;
    errno = 0;
    const long v = std::strtol(tok[i].c_str(), &end, 10);
    if (end == tok[i].c_str() || *end != '\0' || errno == ERANGE || v < 0 || v > 100000)
      fail(std::string("bad ") + what + " '" + tok[i] + "'");
    return static_cast<int>(v);
  }
};

void split(const std::string& s, std::vector<std::string>& tok) {
  tok.clear();
  std::size_t i = 0;
  const std::size_t n = s.size();
  while (i < n) {
    while (i < n && std::isspace(static_cast<unsigned char>(s[i]))) ++i;
    const std::size_t j = i;
    while (i < n && !std::isspace(static_cast<unsigned char>(s[i]))) ++i;
    if (i > j) tok.emplace_back(s, j, i - j);
  }
}

// p!/q! for nearby p, q.
Real fact_ratio(int p, int q) {
  Real r = 1;
  if (p >= q) for (int i = q + 1; i <= p; ++i) r *= i;
  else for (int i = p + 1; i <= q; ++i) r /= i;
  return r;
}

// N_nm * G(np, mp), N_nm^2 = (2-delta_m0)(2n+1)(n-m)!/(n+m)! (the full
// normalisation, Heiskanen & Moritz 1967 eq. (1-73)); G(np, mp) = 1/N_{np,mp}
// for mp >= 0, and for mp = -k < 0 the factor of Phi_{np,-k} =
// (-1)^k (np-k)!/(np+k)! conj(Phi_{np,k}) divided by N_{np,k}.
Real norm_ratio(int n, int m, int np, int mp) {
  if (mp > np || -mp > np) return 0;
  const Real dm = (m == 0) ? 1 : 2;
  if (mp >= 0) {
    const Real dk = (mp == 0) ? 1 : 2;
    const Real r2 = dm * (2 * n + 1) / (dk * (2 * np + 1)) * fact_ratio(n - m, np - mp) * fact_ratio(np + mp, n + m);
    return std::sqrt(r2);
  }
  const int k = -mp;
  const Real r2 = dm * (2 * n + 1) / (2.0L * (2 * np + 1)) * fact_ratio(n - m, np + k) * fact_ratio(np - k, n + m);
  return ((k % 2) ? -1.0L : 1.0L) * std::sqrt(r2);
}

Real binom(int n, int k) {
  Real r = 1;
  for (int i = 1; i <= k; ++i) r = r * (n - k + i) / i;
  return r;
}

}  // namespace

void ShCoefficients::resize(int n) {
  nmax = n;
  const std::size_t sz = idx(n, n) + 1;
  c.assign(sz, 0); s.assign(sz, 0); sigma_c.assign(sz, 0); sigma_s.assign(sz, 0);
}

ShCoefficients ShCoefficients::truncated(int n) const {
  if (n > nmax) throw std::invalid_argument("ShCoefficients::truncated: degree above nmax");
  ShCoefficients t = *this;
  const std::size_t sz = idx(n, n) + 1;
  t.nmax = n;
  t.c.resize(sz); t.s.resize(sz); t.sigma_c.resize(sz); t.sigma_s.resize(sz);
  return t;
}

ShCoefficients read_nasa_ascii(const std::string& path, Real gm, Real a, int nmax) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("read_nasa_ascii: cannot open " + path);
  struct Row { int n, m; Real c, s, sc, ss; };
  std::vector<Row> rows;
  int nfound = 0;
  std::string text;
  Line L{&path, 0, {}};
  while (std::getline(in, text)) {
    ++L.no;
    split(text, L.tok);
    if (L.tok.empty()) continue;
    if (L.tok.size() < 4 || L.tok.size() > 6) L.fail("expected 'n m C S [sigmaC sigmaS]', got " + std::to_string(L.tok.size()) + " fields");
    Row r{};
    r.n = L.integer(0, "degree"); r.m = L.integer(1, "order");
    if (r.m > r.n) L.fail("order " + std::to_string(r.m) + " above degree " + std::to_string(r.n));
    r.c = L.real(2, "C"); r.s = L.real(3, "S");
    r.sc = L.tok.size() > 4 ? L.real(4, "sigma C") : 0; r.ss = L.tok.size() > 5 ? L.real(5, "sigma S") : 0;
    if (nmax >= 0 && r.n > nmax) continue;
    nfound = std::max(nfound, r.n);
    rows.push_back(r);
  }
  if (rows.empty()) throw std::runtime_error("read_nasa_ascii: no coefficients in " + path);
  if (nmax >= 0 && nfound < nmax) throw std::runtime_error("read_nasa_ascii: " + path + " has degree " + std::to_string(nfound) + " < requested " + std::to_string(nmax));
  ShCoefficients k;
  k.gm = gm; k.a = a; k.source = path;
  k.resize(nmax >= 0 ? nmax : nfound);
  k.c[0] = 1;  // C00 = 1 unless the file says otherwise
  for (const Row& r : rows) {
    const auto i = ShCoefficients::idx(r.n, r.m);
    k.c[i] = r.c; k.s[i] = r.s; k.sigma_c[i] = r.sc; k.sigma_s[i] = r.ss;
  }
  return k;
}

ShCoefficients read_icgem_gfc(const std::string& path, int nmax) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("read_icgem_gfc: cannot open " + path);
  ShCoefficients k;
  k.source = path;
  int file_nmax = -1;
  bool have_gm = false, have_a = false, head_done = false, errors = true;
  std::string text;
  Line L{&path, 0, {}};
  while (std::getline(in, text)) {
    ++L.no;
    split(text, L.tok);
    if (L.tok.empty()) continue;
    const std::string& key = L.tok[0];
    if (!head_done) {
      if (key == "end_of_head") {
        head_done = true;
        if (!have_gm) L.fail("header lacks earth_gravity_constant");
        if (!have_a) L.fail("header lacks radius");
        if (file_nmax < 0) L.fail("header lacks max_degree");
        if (nmax > file_nmax) L.fail("requested degree " + std::to_string(nmax) + " above max_degree " + std::to_string(file_nmax));
        k.resize(nmax >= 0 ? nmax : file_nmax);
        k.c[0] = 1;
        continue;
      }
      const bool has_val = L.tok.size() >= 2;
      if (key == "earth_gravity_constant" || key == "radius" || key == "max_degree" || key == "norm" ||
          key == "errors" || key == "tide_system") {
        if (!has_val) L.fail("header keyword " + key + " without a value");
      }
      if (key == "earth_gravity_constant") {
        k.gm = L.real(1, "earth_gravity_constant"); have_gm = true;
        if (!(k.gm > 0)) L.fail("earth_gravity_constant must be positive");
      } else if (key == "radius") {
        k.a = L.real(1, "radius"); have_a = true;
        if (!(k.a > 0)) L.fail("radius must be positive");
      } else if (key == "max_degree") file_nmax = L.integer(1, "max_degree");
      else if (key == "norm" && L.tok[1] != "fully_normalized") L.fail("norm '" + L.tok[1] + "': only fully_normalized models are supported");
      else if (key == "errors") errors = (L.tok[1] != "no");
      else if (key == "tide_system") {
        k.tide_system = L.tok[1] == "unknown" ? "" : L.tok[1];
        if (!k.tide_system.empty() && k.tide_system != "tide_free" && k.tide_system != "zero_tide" && k.tide_system != "mean_tide")
          L.fail("unknown tide_system '" + k.tide_system + "' (tide_free, zero_tide, mean_tide)");
      }
      continue;
    }
    if (key == "gfct" || key == "trnd" || key == "acos" || key == "asin" || key == "dot")
      L.fail("time-variable models (" + key + " records) are not supported");
    if (key != "gfc") L.fail("unknown record '" + key + "' (expected gfc)");
    const std::size_t nt = L.tok.size() - 1;
    if (nt < 4 || (errors && nt < 6)) L.fail(errors ? "expected 'gfc n m C S sigmaC sigmaS'" : "expected 'gfc n m C S'");
    const int n = L.integer(1, "degree"), m = L.integer(2, "order");
    if (m > n) L.fail("order " + std::to_string(m) + " above degree " + std::to_string(n));
    if (n > file_nmax) L.fail("degree " + std::to_string(n) + " above max_degree " + std::to_string(file_nmax));
    if (n > k.nmax) continue;
    const auto i = ShCoefficients::idx(n, m);
    k.c[i] = L.real(3, "C"); k.s[i] = L.real(4, "S");
    if (nt >= 6) { k.sigma_c[i] = L.real(5, "sigma C"); k.sigma_s[i] = L.real(6, "sigma S"); }
  }
  if (!head_done) throw std::runtime_error("read_icgem_gfc: no end_of_head in " + path);
  return k;
}

ShCoefficients read_model(const std::string& path, int nmax, Real gm, Real a) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot open model file " + path);
  std::string text;
  std::vector<std::string> tok;
  for (int i = 0; i < 200 && std::getline(in, text); ++i) {
    split(text, tok);
    if (tok.empty()) continue;
    if (tok[0] == "end_of_head" || tok[0] == "earth_gravity_constant" || tok[0] == "product_type" || tok[0] == "modelname")
      return read_icgem_gfc(path, nmax);
    if (std::isdigit(static_cast<unsigned char>(tok[0][0]))) break;
  }
  return read_nasa_ascii(path, gm, a, nmax);
}

// IERS Conventions (2010), IERS TN 36, sec. 6.2.2: the permanent-tide part of
// C20, <dC20> = A0 H0 k20 = -4.1736e-9 (zero tide minus tide free), and the
// direct part A0 H0 = <dC20>/k20, k20 = 0.30190 (mean tide minus zero tide).
constexpr Real kDc20ZeroMinusFree = -4.1736e-9L;
constexpr Real kDc20MeanMinusZero = -4.1736e-9L / 0.30190L;

ShCoefficients to_tide_system(const ShCoefficients& k, const std::string& target) {
  auto level = [](const std::string& t) -> Real {  // C20 offset relative to tide free
    if (t == "tide_free") return 0;
    if (t == "zero_tide") return kDc20ZeroMinusFree;
    if (t == "mean_tide") return kDc20ZeroMinusFree + kDc20MeanMinusZero;
    throw std::invalid_argument("unknown tide system '" + t + "' (tide_free, zero_tide, mean_tide)");
  };
  if (k.tide_system.empty()) throw std::invalid_argument("to_tide_system: the model's tide system is not known (" + k.source + ")");
  ShCoefficients t = k;
  if (k.nmax >= 2) t.c[ShCoefficients::idx(2, 0)] += level(target) - level(k.tide_system);
  else (void)level(target);
  t.tide_system = target;
  return t;
}

ShCoefficients synthetic_kaula(int nmax, std::uint64_t seed) {
  if (nmax < 0) throw std::invalid_argument("synthetic_kaula: negative degree");
  std::uint64_t state = seed;
  auto uniform = [&state] {  // splitmix64 (Steele, Lea & Flood 2014), (0, 1]
    std::uint64_t z = (state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    z ^= z >> 31;
    return (static_cast<double>(z >> 11) + 1.0) * 0x1.0p-53;
  };
  auto normal = [&] {  // Box-Muller
    const double u1 = uniform(), u2 = uniform();
    return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * M_PI * u2);
  };
  ShCoefficients k;
  k.gm = 3.986004415e14L; k.a = 6378136.3L;  // EGM2008 (Pavlis et al. 2012)
  k.source = "kaula(seed " + std::to_string(seed) + ")";
  k.resize(nmax);
  k.c[0] = 1;
  for (int n = 2; n <= nmax; ++n) {
    const double sig = 1e-5 / (static_cast<double>(n) * n);
    for (int m = 0; m <= n; ++m) {
      const auto i = ShCoefficients::idx(n, m);
      k.c[i] = sig * normal();
      k.s[i] = (m == 0) ? 0.0 : sig * normal();
    }
  }
  return k;
}

Real ShDerivatives::at(int ax, int ay, int az) const {
  for (std::size_t i = 0; i < index.size(); ++i)
    if (index[i][0] == ax && index[i][1] == ay && index[i][2] == az) return value[i];
  throw std::out_of_range("ShDerivatives::at");
}

SphericalHarmonicField::SphericalHarmonicField(ShCoefficients coeffs, int nmax, int max_order, ShPrecision precision)
    : k_(std::move(coeffs)), nmax_(nmax < 0 ? k_.nmax : nmax), jmax_(std::max(2, max_order)), prec_(precision) {
  if (nmax_ > k_.nmax) throw std::invalid_argument("SphericalHarmonicField: nmax above the coefficients' degree");
  if (!(k_.gm > 0) || !(k_.a > 0)) throw std::invalid_argument("SphericalHarmonicField: GM and a must be positive");
  const int N = nmax_;
  switch (prec_) {
    case ShPrecision::LongDouble: el_ = std::make_shared<detail::ShEngine<long double>>(k_, N); break;
    case ShPrecision::Double: ed_ = std::make_shared<detail::ShEngine<double>>(k_, N); break;
    case ShPrecision::Mixed:
      el_ = std::make_shared<detail::ShEngine<long double>>(k_, std::min(N, kMixedSplit));
      if (N > kMixedSplit) ed_ = std::make_shared<detail::ShEngine<double>>(k_, N, kMixedSplit + 1);
      break;
  }
}

template <class T>
void SphericalHarmonicField::fill(Tables<T>& t) const {
  const int L = nmax_ + jmax_;
  const std::size_t nl = ShCoefficients::idx(L, L) + 1;
  t.sec.assign(L + 1, 0); t.anm.assign(nl, 0); t.bnm.assign(nl, 0);
  for (int m = 1; m <= L; ++m) t.sec[m] = static_cast<T>((m == 1) ? std::sqrt(3.0L) : std::sqrt((2.0L * m + 1) / (2.0L * m)));
  for (int m = 0; m <= L; ++m)
    for (int n = m + 1; n <= L; ++n) {
      const auto i = ShCoefficients::idx(n, m);
      const Real nn = n, mm = m;
      t.anm[i] = static_cast<T>(std::sqrt((2 * nn - 1) * (2 * nn + 1) / ((nn - mm) * (nn + mm))));
      t.bnm[i] = static_cast<T>((n >= m + 2) ? std::sqrt((2 * nn + 1) * (nn + mm - 1) * (nn - mm - 1) / ((2 * nn - 3) * (nn + mm) * (nn - mm))) : 0);
    }
  const std::size_t nk = ShCoefficients::idx(nmax_, nmax_) + 1;
  t.ratio.resize(jmax_ + 1);
  for (int j = 0; j <= jmax_; ++j) {
    t.ratio[j].assign(nk * (2 * j + 1), 0);
    for (int n = 0; n <= nmax_; ++n)
      for (int m = 0; m <= n; ++m)
        for (int s = -j; s <= j; ++s)
          t.ratio[j][ShCoefficients::idx(n, m) * (2 * j + 1) + (s + j)] = static_cast<T>(norm_ratio(n, m, n + j, m + s));
  }
  const int tw = 2 * jmax_ + 1;
  t.fact.assign(static_cast<std::size_t>(nmax_ + 1) * tw, 0);
  for (int l = 0; l <= nmax_; ++l)
    for (int q = 0; q < tw; ++q) t.fact[l * tw + q] = static_cast<T>(fact_ratio(l + q, l));
  t.c.assign(nk, 0); t.s.assign(nk, 0);
  for (std::size_t i = 0; i < nk; ++i) { t.c[i] = static_cast<T>(k_.c[i]); t.s[i] = static_cast<T>(k_.s[i]); }
}

std::string SphericalHarmonicField::name() const {
  return "sh(" + k_.source + ", n<=" + std::to_string(nmax_) + (prec_ == ShPrecision::Double ? ", double" : prec_ == ShPrecision::Mixed ? ", mixed" : "") + ")";
}

std::vector<ShDerivatives> SphericalHarmonicField::derivatives(const Vec3& r, int order) const {
  if (order < 0 || order > jmax_) throw std::invalid_argument("SphericalHarmonicField::derivatives: order above max_order");
  std::call_once(tables_once_, [this] {
    if (prec_ == ShPrecision::LongDouble) fill(tl_);
    else fill(td_);
  });
  return prec_ == ShPrecision::Double ? derivatives_impl(td_, r, order) : derivatives_impl(tl_, r, order);
}

template <class T>
std::vector<ShDerivatives> SphericalHarmonicField::derivatives_impl(const Tables<T>& tb, const Vec3& r, int order) const {
  // Solid harmonics Phi_nm, n <= nmax + order (M&G eqs. (3.29)-(3.31), normalised).
  const int L = nmax_ + order;
  const std::size_t nl = ShCoefficients::idx(L, L) + 1;
  thread_local std::vector<T> re, im;
  if (re.size() < nl) { re.resize(nl); im.resize(nl); }
  const Real r2l = r.squaredNorm();
  if (!(r2l > 0) || !std::isfinite(r2l)) throw std::domain_error("SphericalHarmonicField: position at the centre or not finite");
  {
    const Real a = k_.a;
    const T X = static_cast<T>(r.x() * a / r2l), Y = static_cast<T>(r.y() * a / r2l), Z = static_cast<T>(r.z() * a / r2l),
            Q = static_cast<T>(a * a / r2l);
    re[0] = static_cast<T>(a / std::sqrt(r2l));
    im[0] = 0;
    for (int m = 0; m <= L; ++m) {
      const auto imm = ShCoefficients::idx(m, m);
      if (m > 0) {  // M&G eq. (3.30)
        const auto ip = ShCoefficients::idx(m - 1, m - 1);
        re[imm] = tb.sec[m] * (X * re[ip] - Y * im[ip]);
        im[imm] = tb.sec[m] * (X * im[ip] + Y * re[ip]);
      }
      if (m + 1 <= L) {  // M&G eq. (3.31), n = m+1
        const auto i1 = ShCoefficients::idx(m + 1, m);
        re[i1] = tb.anm[i1] * Z * re[imm];
        im[i1] = tb.anm[i1] * Z * im[imm];
      }
      for (int n = m + 2; n <= L; ++n) {  // M&G eq. (3.31)
        const auto i = ShCoefficients::idx(n, m), i1 = ShCoefficients::idx(n - 1, m), i2 = ShCoefficients::idx(n - 2, m);
        re[i] = tb.anm[i] * Z * re[i1] - tb.bnm[i] * Q * re[i2];
        im[i] = tb.anm[i] * Z * im[i1] - tb.bnm[i] * Q * im[i2];
      }
    }
  }
  // Ladder terms: for each (j, s) the pairs (a, b) with a - b = s, a + b <= j,
  // c = j - a - b, sign (-1)^(a+c), factorial offset t = 2b + c.
  // Sums live in one flat array: order j at offset off[j], slot a*(j+1)+b.
  struct Term { int j, s, slot, t; T sign; };
  std::vector<Term> terms;
  std::vector<int> off(order + 2, 0);
  for (int j = 0; j <= order; ++j) off[j + 1] = off[j] + (j + 1) * (j + 1);
  for (int j = 0; j <= order; ++j)
    for (int s = -j; s <= j; ++s)
      for (int b = std::max(0, -s); 2 * b + s <= j; ++b) {
        const int a = b + s, c = j - a - b;
        terms.push_back({j, s, off[j] + a * (j + 1) + b, 2 * b + c, static_cast<T>(((a + c) % 2) ? -1 : 1)});
      }
  const int J = order, tw = 2 * jmax_ + 1;
  std::vector<T> sr(off[J + 1], 0), si(off[J + 1], 0);
  T* const srp = sr.data();
  T* const sip = si.data();
  const Term* const tb0 = terms.data();
  const std::size_t nterms = terms.size();
  for (int n = nmax_; n >= 0; --n) {  // high degrees first: small terms summed before large ones
    for (int m = n; m >= 0; --m) {
      const auto inm = ShCoefficients::idx(n, m);
      const T C = tb.c[inm], S = tb.s[inm];
      if (C == 0 && S == 0) continue;
      const T* fl = &tb.fact[(n - m) * tw];
      int cur_j = -1, cur_s = -100;
      T pr = 0, pi = 0;
      for (std::size_t iq = 0; iq < nterms; ++iq) {
        const Term& q = tb0[iq];
        if (q.j != cur_j || q.s != cur_s) {
          cur_j = q.j; cur_s = q.s;
          const T R = tb.ratio[q.j][inm * (2 * q.j + 1) + (q.s + q.j)];
          const int mp = m + q.s;
          if (R == 0) { pr = pi = 0; continue; }
          const auto ip = ShCoefficients::idx(n + q.j, mp < 0 ? -mp : mp);
          const T fr = re[ip], fi = (mp < 0) ? -im[ip] : im[ip];
          pr = R * (C * fr + S * fi);  // R (C - iS)(fr + i fi)
          pi = R * (C * fi - S * fr);
        }
        const T f = q.sign * fl[q.t];
        srp[q.slot] += f * pr;
        sip[q.slot] += f * pi;
      }
    }
  }
  std::vector<ShDerivatives> out(J + 1);
  Real scale = k_.gm / k_.a;
  for (int j = 0; j <= J; ++j, scale /= k_.a) {
    ShDerivatives& d = out[j];
    d.order = j;
    for (int ax = j; ax >= 0; --ax)
      for (int ay = j - ax; ay >= 0; --ay) {
        const int az = j - ax - ay;
        Real accr = 0, acci = 0;
        for (int p = 0; p <= ax; ++p)
          for (int q = 0; q <= ay; ++q) {
            const int a = p + q, b = (ax - p) + (ay - q);
            const Real w = binom(ax, p) * binom(ay, q) * (((ay - q) % 2) ? -1.0L : 1.0L);
            accr += w * sr[off[j] + a * (j + 1) + b];
            acci += w * si[off[j] + a * (j + 1) + b];
          }
        // multiply by (-i)^ay / 2^(ax+ay) and take the real part
        Real v = 0;
        switch (ay % 4) {
          case 0: v = accr; break;
          case 1: v = acci; break;
          case 2: v = -accr; break;
          default: v = -acci; break;
        }
        v = std::ldexp(v, -(ax + ay));
        d.index.push_back({ax, ay, az});
        d.value.push_back(scale * v);
      }
  }
  return out;
}

bool SphericalHarmonicField::third(const Vec3& r, Tensor3& t) const {
  if (jmax_ < 3) return false;
  const auto d = derivatives(r, 3);
  for (int k = 0; k < 3; ++k)
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        int ix[3] = {0, 0, 0};
        ++ix[i]; ++ix[j]; ++ix[k];
        t[k](i, j) = d[3].at(ix[0], ix[1], ix[2]);
      }
  return true;
}

// Column sums at the reference point (rho, 0, z), shared by all longitudes.
class ShCircle final : public FieldCircle {
 public:
  ShCircle(const SphericalHarmonicField& f, Real rho, Real z, Real e_rho, Real e_z) : f_(f), rho_(rho) {
    const Vec3 p0(rho, 0, z);
    if (f.el_) {
      gl_ = detail::sh_geometry<long double>(p0, f.el_->a());
      sl_.resize(f.el_->nmax() + 1);
      f.el_->column_sums(gl_, true, sl_.data());
    }
    if (f.ed_) {
      gd_ = detail::sh_geometry<double>(p0, f.ed_->a());
      sd_.resize(f.ed_->nmax() + 1);
      f.ed_->column_sums(gd_, true, sd_.data());
    }
    if (e_rho != 0 || e_z != 0) {
      std::call_once(f.dual_once_, [&f] { f.edd_ = std::make_shared<detail::ShEngine<detail::Dd>>(f.k_, f.nmax_); });
      er_ = static_cast<double>(e_rho);
      gx_ = detail::sh_geometry(p0, Vec3(e_rho, 0, e_z), f.edd_->a().x);
      sx_.resize(f.edd_->nmax() + 1);
      f.edd_->column_sums(gx_, true, sx_.data());
    }
  }
  FieldSample eval(Real lon, Mat3* dgamma) const override {
    const Real c = std::cos(lon), s = std::sin(lon), x = rho_ * c, y = rho_ * s;
    Real v = 0, g[3] = {0, 0, 0}, G[6] = {0, 0, 0, 0, 0, 0};
    auto add = [&](const auto& o) {
      v += o.v;
      for (int i = 0; i < 3; ++i) g[i] += o.g[i];
      for (int i = 0; i < 6; ++i) G[i] += o.gamma[i];
    };
    if (f_.el_) {
      detail::ShGeom<long double> h = gl_;
      h.s1 = x * h.ir; h.s2 = y * h.ir;
      add(f_.el_->assemble(sl_.data(), h, true));
    }
    if (f_.ed_) {
      detail::ShGeom<double> h = gd_;
      h.s1 = static_cast<double>(x) * h.ir; h.s2 = static_cast<double>(y) * h.ir;
      add(f_.ed_->assemble(sd_.data(), h, true));
    }
    if (dgamma) {
      dgamma->setZero();
      if (!sx_.empty()) {
        // s(lon) and its derivative along e(lon) = e_rho (cos, sin, 0) + e_z z^:
        // ds/de = (e - s dr)/r with dr/de the same on the whole circle.
        detail::ShGeom<detail::Dd> h = gx_;
        const double ir = h.ir.x, dr = h.r.d, s1 = static_cast<double>(x) * ir, s2 = static_cast<double>(y) * ir;
        h.s1 = detail::Dd(s1, (er_ * static_cast<double>(c) - s1 * dr) * ir);
        h.s2 = detail::Dd(s2, (er_ * static_cast<double>(s) - s2 * dr) * ir);
        const auto o = f_.edd_->assemble(sx_.data(), h, true);
        *dgamma << o.gamma[0].d, o.gamma[1].d, o.gamma[2].d, o.gamma[1].d, o.gamma[3].d, o.gamma[4].d, o.gamma[2].d,
            o.gamma[4].d, o.gamma[5].d;
      }
    }
    FieldSample out;
    out.potential = v;
    out.g = Vec3(g[0], g[1], g[2]);
    out.gamma << G[0], G[1], G[2], G[1], G[3], G[4], G[2], G[4], G[5];
    return out;
  }

 private:
  const SphericalHarmonicField& f_;
  Real rho_;
  double er_ = 0;
  detail::ShGeom<long double> gl_{};
  detail::ShGeom<double> gd_{};
  detail::ShGeom<detail::Dd> gx_{};
  std::vector<detail::ColSums<long double>> sl_;
  std::vector<detail::ColSums<double>> sd_;
  std::vector<detail::ColSums<detail::Dd>> sx_;
};

std::unique_ptr<FieldCircle> SphericalHarmonicField::circle(Real rho, Real z, Real e_rho, Real e_z) const {
  return std::make_unique<ShCircle>(*this, rho, z, e_rho, e_z);
}

Vec3 SphericalHarmonicField::gravitation(const Vec3& r) const {
  Real g[3] = {0, 0, 0};
  if (el_) {
    const auto o = el_->eval(r, false);
    for (int i = 0; i < 3; ++i) g[i] += o.g[i];
  }
  if (ed_) {
    const auto o = ed_->eval(r, false);
    for (int i = 0; i < 3; ++i) g[i] += o.g[i];
  }
  return Vec3(g[0], g[1], g[2]);
}

FieldSample SphericalHarmonicField::eval(const Vec3& r) const {
  Real v = 0, g[3] = {0, 0, 0}, G[6] = {0, 0, 0, 0, 0, 0};
  if (el_) {
    const auto o = el_->eval(r);
    v += o.v;
    for (int i = 0; i < 3; ++i) g[i] += o.g[i];
    for (int i = 0; i < 6; ++i) G[i] += o.gamma[i];
  }
  if (ed_) {
    const auto o = ed_->eval(r);
    v += o.v;
    for (int i = 0; i < 3; ++i) g[i] += o.g[i];
    for (int i = 0; i < 6; ++i) G[i] += o.gamma[i];
  }
  FieldSample s;
  s.potential = v;
  s.g = Vec3(g[0], g[1], g[2]);
  s.gamma << G[0], G[1], G[2], G[1], G[3], G[4], G[2], G[4], G[5];
  return s;
}

}  // namespace ggins::gravity

namespace ggins::gravity {

Real normal_j2n(int n) {
  // H&M (2-90) for J2 from the defining constants, (2-92) for J2n.
  const Real a = wgs84::kA, b = wgs84::kB, gm = wgs84::kGm, w = wgs84::kOmega;
  const Real e2 = wgs84::kE2, ep = std::sqrt(a * a - b * b) / b;
  // q0 = q(b) by its series in t = E/b = e' (see normal.cpp)
  Real q0 = 0, p = ep * ep * ep;
  for (int k = 1; k < 60; ++k, p *= ep * ep) q0 += ((k % 2) ? 2.0L : -2.0L) * k * p / ((2.0L * k + 1) * (2.0L * k + 3));
  const Real m = w * w * a * a * b / gm;
  const Real j2 = e2 / 3 * (1 - 2 * m * ep / (15 * q0));
  if (n == 1) return j2;
  return ((n % 2) ? 1 : -1) * 3 * std::pow(e2, static_cast<Real>(n)) / ((2 * n + 1) * (2 * n + 3)) * (1 - n + 5 * n * j2 / e2);
}

ShCoefficients subtract_normal(const ShCoefficients& k) {
  ShCoefficients t = k;
  t.source = k.source + " - normal";
  const Real gr = wgs84::kGm / k.gm, ar = wgs84::kA / k.a;
  t.c[0] -= gr;
  for (int n = 1; 2 * n <= std::min(k.nmax, 40); ++n)
    t.c[ShCoefficients::idx(2 * n, 0)] -= gr * std::pow(ar, static_cast<Real>(2 * n)) * (-normal_j2n(n) / std::sqrt(4.0L * n + 1));
  return t;
}

}  // namespace ggins::gravity
