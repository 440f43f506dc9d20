// Tile generation and file formats for the onboard gradient map (see gmap_gen.hpp).
#include "ggins/gmap_gen.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <random>
#include <stdexcept>
#include <exception>
#include <thread>

#include "ggins/gravity/composite.hpp"
#include "ggins/gravity/normal.hpp"
#include "ggins/gravity/spherical_harmonic.hpp"
#include "ggins/gravity/wgs84.hpp"

namespace ggins::gmap {

using gravity::Mat3;
using gravity::Real;
using gravity::Vec3;

std::shared_ptr<const gravity::Field> make_egm96_field(const std::string& path, int nmax, bool anomaly) {
  auto egm = gravity::read_nasa_ascii(path, gravity::kEgm96Gm, gravity::kEgm96A, nmax);
  auto dist = std::make_shared<gravity::SphericalHarmonicField>(gravity::subtract_normal(egm), nmax, 3,
                                                                gravity::ShPrecision::Double);
  if (anomaly) return dist;
  auto normal = std::make_shared<gravity::NormalField>();
  return std::make_shared<gravity::SumField>(
      std::vector<std::pair<Real, std::shared_ptr<const gravity::Field>>>{{1.0L, normal}, {1.0L, dist}},
      "egm96-" + std::to_string(nmax));
}

namespace {

// The node's values from Gamma_e and d Gamma_e / dh (along the ellipsoid normal).
void ned_values(const Mat3& gamma, const Mat3& dgh, double lat, double lon, double out[GG_GMAP_NVAL]) {
  const Real sl = std::sin(static_cast<Real>(lat)), cl = std::cos(static_cast<Real>(lat));
  const Real so = std::sin(static_cast<Real>(lon)), co = std::cos(static_cast<Real>(lon));
  Mat3 c;  // C_n_e
  c << -sl * co, -sl * so, cl, -so, co, 0, -cl * co, -cl * so, -sl;
  const Mat3 gn = c * gamma * c.transpose();
  const Mat3 dn = c * dgh * c.transpose();
  const int ij[6][2] = {{0, 0}, {1, 1}, {2, 2}, {0, 1}, {0, 2}, {1, 2}};
  for (int k = 0; k < 6; ++k) {
    out[k] = static_cast<double>(gn(ij[k][0], ij[k][1]));
    out[k + 6] = static_cast<double>(dn(ij[k][0], ij[k][1]));
  }
}

// The circle of latitude lat at height h, with the ellipsoid normal
// up = (cos lat cos lon, cos lat sin lon, sin lat) as the derivative direction.
std::unique_ptr<gravity::FieldCircle> row(const gravity::Field& f, double lat, double h) {
  const Vec3 p0 = gravity::wgs84::geodetic_to_ecef(lat, 0.0, h);
  return f.circle(p0.x(), p0.z(), std::cos(static_cast<Real>(lat)), std::sin(static_cast<Real>(lat)));
}

}  // namespace

void node_values(const gravity::Field& f, double lat, double lon, double h, double out[GG_GMAP_NVAL]) {
  Mat3 dgh;
  const gravity::FieldSample s = row(f, lat, h)->eval(lon, &dgh);
  ned_values(s.gamma, dgh, lat, lon, out);
}

std::vector<Layer> height_layers(double h_lo, double h_hi, double max_m, double margin_m) {
  if (!(h_hi >= h_lo) || !(max_m > 0) || !(margin_m >= 0))
    throw std::invalid_argument("gmap: height layers need h_hi >= h_lo, a thickness > 0 and a margin >= 0");
  const int n = std::max(1, static_cast<int>(std::ceil((h_hi - h_lo) / max_m - 1e-9)));
  const double t = (h_hi - h_lo) / n;
  std::vector<Layer> out;
  for (int k = 0; k < n; ++k) out.push_back({h_lo + (k + 0.5) * t, 0.5 * t + margin_m});
  return out;
}

void keep_gzz_only(gg_gmap_tile_t& t) {
  t.flags |= GG_GMAP_GZZ_ONLY;
  for (int n = 0; n < t.nlat * t.nlon; ++n)
    for (int c = 0; c < GG_GMAP_NVAL; ++c)
      if (c != GG_GMAP_C_DD && c != GG_GMAP_NCOMP + GG_GMAP_C_DD) t.node[n][c] = 0.0;
}

std::unique_ptr<gg_gmap_tile_t> make_tile(const gravity::Field& f, const TileSpec& sp) {
  if (!(sp.spacing_deg > 0) || !(sp.lat_max_deg > sp.lat_min_deg) || !(sp.lon_max_deg > sp.lon_min_deg))
    throw std::invalid_argument("gmap: need lat_max > lat_min, lon_max > lon_min, spacing > 0");
  const int nlat = static_cast<int>(std::ceil((sp.lat_max_deg - sp.lat_min_deg) / sp.spacing_deg - 1e-9)) + 1;
  const int nlon = static_cast<int>(std::ceil((sp.lon_max_deg - sp.lon_min_deg) / sp.spacing_deg - 1e-9)) + 1;
  if (nlat < 4 || nlon < 4 || static_cast<long>(nlat) * nlon > GG_GMAP_MAX_NODES)
    throw std::invalid_argument("gmap: " + std::to_string(nlat) + " x " + std::to_string(nlon) +
                                " nodes; need >= 4 x 4 and <= " + std::to_string(GG_GMAP_MAX_NODES));
  auto tile = std::make_unique<gg_gmap_tile_t>();
  std::memset(tile.get(), 0, sizeof(gg_gmap_tile_t));
  const double d2r = M_PI / 180.0;
  tile->nlat = nlat;
  tile->nlon = nlon;
  tile->flags = sp.anomaly ? GG_GMAP_ANOMALY : 0u;
  tile->nmax = sp.nmax;
  tile->lat0_rad = sp.lat_min_deg * d2r;
  double lon0 = sp.lon_min_deg;  // a tile across the antimeridian: its west edge within [-180, 180)
  while (lon0 >= 180.0) lon0 -= 360.0;
  while (lon0 < -180.0) lon0 += 360.0;
  if (!((nlon - 1) * sp.spacing_deg < 360.0))
    throw std::invalid_argument("gmap: a tile spans less than 360 deg of longitude");
  tile->lon0_rad = lon0 * d2r;
  tile->dlat_rad = sp.spacing_deg * d2r;
  tile->dlon_rad = sp.spacing_deg * d2r;
  tile->h0_m = sp.alt_m;
  tile->h_range_m = sp.h_range_m;
  tile->noise_s2 = sp.noise_e * 1e-9;
  tile->seed = sp.seed;
  const int nth = std::max(1, sp.threads);
  std::vector<std::thread> pool;
  std::vector<std::exception_ptr> failed(static_cast<size_t>(nth));  // a worker's exception, for the caller
  for (int w = 0; w < nth; ++w) {
    pool.emplace_back([&, w] {
      try {
        for (int i = w; i < nlat; i += nth) {  // one circle of latitude per row
          const double lat = tile->lat0_rad + i * tile->dlat_rad;
          const auto c = row(f, lat, sp.alt_m);
          for (int j = 0; j < nlon; ++j) {
            const double lon = tile->lon0_rad + j * tile->dlon_rad;
            Mat3 dgh;
            const gravity::FieldSample s = c->eval(lon, &dgh);
            ned_values(s.gamma, dgh, lat, lon, tile->node[i * nlon + j]);
          }
        }
      } catch (...) {
        failed[static_cast<size_t>(w)] = std::current_exception();
      }
    });
  }
  for (auto& th : pool) th.join();
  for (const auto& e : failed)
    if (e) std::rethrow_exception(e);
  if (sp.noise_e > 0) {
    std::mt19937_64 rng(sp.seed);
    std::normal_distribution<double> nd(0.0, tile->noise_s2);
    for (int n = 0; n < nlat * nlon; ++n)
      for (int k = 0; k < 6; ++k) tile->node[n][k] += nd(rng);
  }
  auto check = std::make_unique<gg_gmap_t>();  // the firmware's own validation
  if (gg_gmap_init(check.get(), tile.get()) != GG_OK)
    throw std::invalid_argument("gmap: the firmware rejects this tile (latitude beyond 89 deg, longitude across "
                                "+-180 deg, height or range out of limits)");
  return tile;
}

static void put(std::vector<std::uint8_t>& b, const void* p, std::size_t n) {
  const auto* c = static_cast<const std::uint8_t*>(p);
  b.insert(b.end(), c, c + n);  // x86-64 and the M7 are little-endian, as the format
}

std::vector<std::uint8_t> encode(const gg_gmap_tile_t& t) {
  std::vector<std::uint8_t> b;
  b.reserve(GG_GMAP_HEADER_BYTES + 96u * static_cast<std::size_t>(t.nlat * t.nlon));
  put(b, "GGMAP001", 8);
  put(b, &t.nlat, 4);
  put(b, &t.nlon, 4);
  put(b, &t.flags, 4);
  put(b, &t.nmax, 4);
  for (double d : {t.lat0_rad, t.lon0_rad, t.dlat_rad, t.dlon_rad, t.h0_m, t.h_range_m, t.noise_s2}) put(b, &d, 8);
  put(b, &t.seed, 8);
  put(b, t.node, 96u * static_cast<std::size_t>(t.nlat * t.nlon));
  return b;
}

nlohmann::json to_json(const gg_gmap_tile_t& t) {
  nlohmann::json j;
  j["format"] = "ggins-gmap-1";
  j["components"] = {"NN", "EE", "DD", "NE", "ND", "ED"};
  j["units"] = "node[i*nlon+j] = 6 components (s^-2, NED) then their d/dh (s^-2/m)";
  j["nlat"] = t.nlat;
  j["nlon"] = t.nlon;
  j["anomaly"] = (t.flags & GG_GMAP_ANOMALY) != 0;
  j["gzz_only"] = (t.flags & GG_GMAP_GZZ_ONLY) != 0;
  j["nmax"] = t.nmax;
  j["lat0_rad"] = t.lat0_rad;
  j["lon0_rad"] = t.lon0_rad;
  j["dlat_rad"] = t.dlat_rad;
  j["dlon_rad"] = t.dlon_rad;
  j["h0_m"] = t.h0_m;
  j["h_range_m"] = t.h_range_m;
  j["noise_s2"] = t.noise_s2;
  j["seed"] = t.seed;
  nlohmann::json nodes = nlohmann::json::array();
  for (int n = 0; n < t.nlat * t.nlon; ++n) nodes.push_back(std::vector<double>(t.node[n], t.node[n] + GG_GMAP_NVAL));
  j["nodes"] = std::move(nodes);
  return j;
}

std::unique_ptr<gg_gmap_tile_t> from_json(const nlohmann::json& j) {
  auto t = std::make_unique<gg_gmap_tile_t>();
  std::memset(t.get(), 0, sizeof(gg_gmap_tile_t));
  t->nlat = j.at("nlat").get<int>();
  t->nlon = j.at("nlon").get<int>();
  t->flags = (j.at("anomaly").get<bool>() ? GG_GMAP_ANOMALY : 0u) | (j.value("gzz_only", false) ? GG_GMAP_GZZ_ONLY : 0u);
  t->nmax = j.at("nmax").get<int>();
  t->lat0_rad = j.at("lat0_rad").get<double>();
  t->lon0_rad = j.at("lon0_rad").get<double>();
  t->dlat_rad = j.at("dlat_rad").get<double>();
  t->dlon_rad = j.at("dlon_rad").get<double>();
  t->h0_m = j.at("h0_m").get<double>();
  t->h_range_m = j.at("h_range_m").get<double>();
  t->noise_s2 = j.at("noise_s2").get<double>();
  t->seed = j.at("seed").get<std::uint64_t>();
  const auto& nodes = j.at("nodes");
  if (t->nlat < 4 || t->nlon < 4 || static_cast<long>(t->nlat) * t->nlon > GG_GMAP_MAX_NODES ||
      nodes.size() != static_cast<std::size_t>(t->nlat * t->nlon))
    throw std::invalid_argument("gmap json: bad node count");
  for (int n = 0; n < t->nlat * t->nlon; ++n)
    for (int k = 0; k < GG_GMAP_NVAL; ++k) t->node[n][k] = nodes.at(n).at(k).get<double>();
  return t;
}

std::unique_ptr<gg_gmap_t> read_tile_file(const std::string& path) {
  auto st = std::make_unique<gg_gmap_t>();
  std::memset(st.get(), 0, sizeof(gg_gmap_t));
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("gmap: cannot open " + path);
  if (path.size() > 5 && path.substr(path.size() - 5) == ".json") {
    nlohmann::json j;
    in >> j;
    auto t = from_json(j);
    if (gg_gmap_init(st.get(), t.get()) != GG_OK) throw std::runtime_error("gmap: tile rejected: " + path);
  } else {
    std::vector<std::uint8_t> b((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (gg_gmap_load(st.get(), b.data(), b.size()) != GG_OK) throw std::runtime_error("gmap: tile rejected: " + path);
  }
  return st;
}

}  // namespace ggins::gmap
