// ggins field: potential, gravitation and its gradient of a chosen model at
// points (command line, CSV file or a 3-D scenario's route), in ECEF and NED.
#include <CLI/CLI.hpp>

#include "ggins/cli_checks.hpp"
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "ggins/gravity/composite.hpp"
#include "ggins/gravity/normal.hpp"
#include "ggins/gravity/point_anomaly.hpp"
#include "ggins/gravity/spherical_harmonic.hpp"
#include "ggins/gravity/wgs84.hpp"
#include "ggins/truth3d/generator3d.hpp"
#include "ggins/truth3d/scenario3d.hpp"

namespace {

using namespace ggins::gravity;
constexpr Real kDeg = 3.14159265358979323846264338327950288L / 180;

const char* kHelp = R"(Potential V, gravitation G and its gradient Gamma of a gravity model at points.

Conventions (docs/gravity.md):
  G is the gravitation (no centrifugal term), G = grad V, pointing toward the
  masses (down); V > 0 (GM/r for a point mass). Gamma_jk = dG_j/dx_k, symmetric,
  trace 0 outside the masses. Units: V m^2/s^2, G m/s^2, Gamma in Eotvos
  (1 E = 1e-9 s^-2).
Frames: ECEF (x to lon 0 on the equator, z to the north pole, metres) and the
  local north-east-down frame at the point's geodetic (WGS-84) latitude and
  longitude; in NED a downward gravitation has G_D > 0, and Gamma_DD > 0
  (gravitation grows downward, ~ +3086 E).
Points: --at LAT,LON,H (geodetic degrees, degrees, metres above the WGS-84
  ellipsoid), --ecef X,Y,Z (metres), --csv FILE (header with lat_deg,lon_deg,h_m
  or x_m,y_m,z_m), or --route SCENARIO (a 3-D scenario's trajectory, every
  --step seconds).
Models (--model):
  normal       WGS-84 normal gravitation (closed form, long double)
  point-mass   GM/r with WGS-84 GM (--gm to change)
  sh           spherical harmonics from --file (ICGEM .gfc or NASA/NGA ASCII;
               default data/egm96_to360.ascii.txt) to --nmax (default: all)
  sh-anomaly   the same minus the WGS-84 normal field
  rw           Rubenstein & Winter point-mass anomalies (35 N, 80 W region)
  kaula        synthetic Kaula-rule model to --nmax (seed --seed)

Exit status: 0 written; 1 failed (a model or CSV file that does not read, an output not
written); 2 bad arguments (the option or point, its value and the allowed range are named).
)";

struct Point { Vec3 r; Real lat, lon, h; std::string label; };

std::vector<Real> parse_triple(const std::string& s, const char* what) {
  std::vector<Real> v;
  std::stringstream ss(s);
  std::string t;
  while (std::getline(ss, t, ',')) {
    char* end = nullptr;
    const Real x = std::strtold(t.c_str(), &end);
    if (end == t.c_str() || *end != '\0' || !std::isfinite(x)) throw ggins::cli::BadArgument(std::string(what) + " '" + s + "': '" + t + "' is not a finite number (allowed: three finite numbers)");
    v.push_back(x);
  }
  if (v.size() != 3) throw ggins::cli::BadArgument(std::string(what) + " '" + s + "': not three numbers (allowed: three comma-separated finite numbers)");
  return v;
}

Point geodetic(Real lat_deg, Real lon_deg, Real h, const std::string& label) {
  if (!(lat_deg >= -90 && lat_deg <= 90)) throw ggins::cli::BadArgument(label + ": latitude " + std::to_string(static_cast<double>(lat_deg)) + " not in [-90, 90] deg");
  if (!(lon_deg >= -360 && lon_deg <= 360)) throw ggins::cli::BadArgument(label + ": longitude not in [-360, 360] deg");
  if (!(h > -1e5L && h < 1e8L)) throw ggins::cli::BadArgument(label + ": height not in (-100 km, 100000 km)");
  return {wgs84::geodetic_to_ecef(lat_deg * kDeg, lon_deg * kDeg, h), lat_deg * kDeg, lon_deg * kDeg, h, label};
}

Point ecef(Real x, Real y, Real z, const std::string& label) {
  const Vec3 r(x, y, z);
  if (!(r.norm() > 1e6L)) throw ggins::cli::BadArgument(label + ": |r| below 1000 km (the models hold outside the Earth's masses)");
  Point p{r, 0, 0, 0, label};
  wgs84::ecef_to_geodetic(r, p.lat, p.lon, p.h);
  return p;
}

std::vector<Point> read_csv(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot open CSV " + path);
  std::string line;
  int no = 0;
  std::vector<std::string> head;
  std::vector<Point> pts;
  int ia = -1, ib = -1, ic = -1;
  bool geo = true;
  while (std::getline(in, line)) {
    ++no;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty() || line[0] == '#') continue;
    std::vector<std::string> f;
    std::stringstream ss(line);
    for (std::string t; std::getline(ss, t, ',');) {
      const auto b = t.find_first_not_of(" \t"), e = t.find_last_not_of(" \t");
      f.push_back(b == std::string::npos ? "" : t.substr(b, e - b + 1));
    }
    const std::string where = path + ":" + std::to_string(no);
    if (head.empty()) {
      head = f;
      auto find = [&](const char* n) { for (std::size_t i = 0; i < f.size(); ++i) if (f[i] == n) return static_cast<int>(i); return -1; };
      ia = find("lat_deg"); ib = find("lon_deg"); ic = find("h_m");
      if (ia < 0 || ib < 0 || ic < 0) {
        geo = false;
        ia = find("x_m"); ib = find("y_m"); ic = find("z_m");
      }
      if (ia < 0 || ib < 0 || ic < 0) throw std::runtime_error(where + ": header needs lat_deg,lon_deg,h_m or x_m,y_m,z_m");
      continue;
    }
    const int need = std::max(ia, std::max(ib, ic));
    if (static_cast<int>(f.size()) <= need) throw std::runtime_error(where + ": " + std::to_string(f.size()) + " fields, header has " + std::to_string(head.size()));
    Real v[3];
    const int col[3] = {ia, ib, ic};
    for (int k = 0; k < 3; ++k) {
      char* end = nullptr;
      const std::string& t = f[static_cast<std::size_t>(col[k])];
      v[k] = std::strtold(t.c_str(), &end);
      if (end == t.c_str() || *end != '\0' || !std::isfinite(v[k])) throw std::runtime_error(where + ": '" + t + "' (" + head[static_cast<std::size_t>(col[k])] + ") is not a finite number");
    }
    pts.push_back(geo ? geodetic(v[0], v[1], v[2], where) : ecef(v[0], v[1], v[2], where));
  }
  if (pts.empty()) throw std::runtime_error(path + ": no points");
  return pts;
}

Mat3 c_n_e(Real lat, Real lon) {  // rows: north, east, down in ECEF
  const Real sl = std::sin(lat), cl = std::cos(lat), so = std::sin(lon), co = std::cos(lon);
  Mat3 c;
  c << -sl * co, -sl * so, cl, -so, co, 0, -cl * co, -cl * so, -sl;
  return c;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{kHelp, "ggins field"};
  std::string model = "sh", file, precision = "mixed", tide, csv, route, format = "csv", frame = "both", out;
  int nmax = -1;
  unsigned long long seed = 1;
  double gm = static_cast<double>(wgs84::kGm), step = 60;
  std::vector<std::string> at, ecef_pts;
  app.add_option("--model", model, "normal | point-mass | sh | sh-anomaly | rw | kaula")
      ->check(CLI::IsMember({"normal", "point-mass", "sh", "sh-anomaly", "rw", "kaula"}))->capture_default_str();
  app.add_option("--file", file, "coefficient file for sh, sh-anomaly (ICGEM .gfc or NASA/NGA ASCII)");
  app.add_option("--nmax", nmax, "highest degree (sh, sh-anomaly: default all; kaula: required)")->check(ggins::cli::IntRange(0, 5400));
  app.add_option("--precision", precision, "synthesis: mixed (degrees <= 8 long double, rest double), ld, double")
      ->check(CLI::IsMember({"mixed", "ld", "double"}))->capture_default_str();
  app.add_option("--tide", tide, "convert the model's C20 to tide_free | zero_tide | mean_tide (ICGEM files name theirs)")
      ->check(CLI::IsMember({"tide_free", "zero_tide", "mean_tide"}));
  app.add_option("--gm", gm, "GM of point-mass, m^3/s^2")->check(ggins::cli::FiniteRange(1e10, 1e18))->capture_default_str();
  app.add_option("--seed", seed, "seed of the kaula model")->capture_default_str()->check(ggins::cli::Seed());
  app.add_option("--at", at, "LAT,LON,H: geodetic deg, deg, m (repeatable)");
  app.add_option("--ecef", ecef_pts, "X,Y,Z: ECEF metres (repeatable)");
  app.add_option("--csv", csv, "CSV of points: header lat_deg,lon_deg,h_m or x_m,y_m,z_m")->check(CLI::ExistingFile);
  app.add_option("--route", route, "3-D scenario (name or .toml) whose route is sampled");
  app.add_option("--step", step, "route sampling interval, s")->check(ggins::cli::FiniteRange(1e-3, 1e6))->capture_default_str();
  app.add_option("--format", format, "csv | json")->check(CLI::IsMember({"csv", "json"}))->capture_default_str();
  app.add_option("--frame", frame, "ecef | ned | both")->check(CLI::IsMember({"ecef", "ned", "both"}))->capture_default_str();
  app.add_option("-o,--out", out, "output file (default stdout)")->check(ggins::cli::OutputFile());
  return ggins::cli::run("ggins field", app, argc, argv, [&] {
    std::vector<Point> pts;
    for (const std::string& s : at) {
      const auto v = parse_triple(s, "--at");
      pts.push_back(geodetic(v[0], v[1], v[2], "--at " + s));
    }
    for (const std::string& s : ecef_pts) {
      const auto v = parse_triple(s, "--ecef");
      pts.push_back(ecef(v[0], v[1], v[2], "--ecef " + s));
    }
    if (!csv.empty()) for (Point& p : read_csv(csv)) pts.push_back(p);
    if (!route.empty()) {
      const auto sc = ggins::truth3d::load_scenario3(route, {GGINS_SCENARIO_DIR});
      const auto traj = ggins::truth3d::make_trajectory3(sc);
      for (Real t = 0; t <= static_cast<Real>(sc.duration_s) + 1e-9L; t += static_cast<Real>(step)) {
        const auto st = traj->at(t);
        pts.push_back({st.r_e, st.lat, st.lon, st.h, "t=" + std::to_string(static_cast<double>(t))});
      }
    }
    if (pts.empty()) throw ggins::cli::BadArgument("no points (allowed: one or more of --at, --ecef, --csv, --route; see --help)");

    const ShPrecision prec = precision == "ld" ? ShPrecision::LongDouble : precision == "double" ? ShPrecision::Double : ShPrecision::Mixed;
    std::shared_ptr<const Field> f;
    std::string desc;
    if (model == "normal") f = std::make_shared<NormalField>();
    else if (model == "point-mass") f = std::make_shared<PointMassField>(gm);
    else if (model == "rw") f = std::make_shared<PointMassAnomalyField>(make_rubenstein_winter_field(RwAnomalyConfig{}));
    else {
      ShCoefficients k;
      if (model == "kaula") {
        if (nmax < 0) throw ggins::cli::BadArgument("--model kaula needs --nmax");
        k = synthetic_kaula(nmax, seed);
      } else {
        const std::string path = file.empty() ? std::string(GGINS_DATA_DIR) + "/egm96_to360.ascii.txt" : file;
        k = read_model(path, nmax);
        if (file.empty()) k.tide_system = "tide_free";  // EGM96 (Lemoine et al. 1998)
      }
      if (!tide.empty()) k = to_tide_system(k, tide);
      desc = "GM " + std::to_string(static_cast<double>(k.gm)) + " a " + std::to_string(static_cast<double>(k.a)) +
             (k.tide_system.empty() ? "" : " " + k.tide_system);
      if (model == "sh-anomaly") k = subtract_normal(k);
      f = std::make_shared<SphericalHarmonicField>(std::move(k), nmax, 2, prec);
    }
    std::FILE* o = stdout;
    if (!out.empty() && !(o = std::fopen(out.c_str(), "w"))) throw std::runtime_error("cannot write " + out);
    const bool e = frame != "ned", n = frame != "ecef";
    nlohmann::json js = nlohmann::json::array();
    if (format == "csv") {
      std::fprintf(o, "# ggins field: model %s%s%s; V m^2/s^2, G m/s^2, Gamma E\n", f->name().c_str(), desc.empty() ? "" : ", ", desc.c_str());
      std::fprintf(o, "lat_deg,lon_deg,h_m,x_m,y_m,z_m,V,G_norm");
      if (e) std::fprintf(o, ",Gx,Gy,Gz,Gam_xx,Gam_xy,Gam_xz,Gam_yy,Gam_yz,Gam_zz");
      if (n) std::fprintf(o, ",G_N,G_E,G_D,Gam_NN,Gam_NE,Gam_ND,Gam_EE,Gam_ED,Gam_DD");
      std::fprintf(o, "\n");
    }
    const int ij[6][2] = {{0, 0}, {0, 1}, {0, 2}, {1, 1}, {1, 2}, {2, 2}};
    for (const Point& p : pts) {
      const FieldSample s = f->eval(p.r);
      const Mat3 C = c_n_e(p.lat, p.lon);
      const Vec3 gn = C * s.g;
      const Mat3 Gn = C * s.gamma * C.transpose();
      if (format == "csv") {
        std::fprintf(o, "%.12Lf,%.12Lf,%.6Lf,%.6Lf,%.6Lf,%.6Lf,%.10Le,%.15Le", p.lat / kDeg, p.lon / kDeg, p.h, p.r.x(), p.r.y(), p.r.z(),
                     s.potential, s.g.norm());
        if (e) {
          for (int i = 0; i < 3; ++i) std::fprintf(o, ",%.15Le", s.g[i]);
          for (const auto& q : ij) std::fprintf(o, ",%.12Le", s.gamma(q[0], q[1]) * 1e9L);
        }
        if (n) {
          for (int i = 0; i < 3; ++i) std::fprintf(o, ",%.15Le", gn[i]);
          for (const auto& q : ij) std::fprintf(o, ",%.12Le", Gn(q[0], q[1]) * 1e9L);
        }
        std::fprintf(o, "\n");
      } else {
        nlohmann::json j;
        j["point"] = p.label.empty() ? nlohmann::json() : nlohmann::json(p.label);
        j["lat_deg"] = static_cast<double>(p.lat / kDeg); j["lon_deg"] = static_cast<double>(p.lon / kDeg); j["h_m"] = static_cast<double>(p.h);
        j["ecef_m"] = {static_cast<double>(p.r.x()), static_cast<double>(p.r.y()), static_cast<double>(p.r.z())};
        j["V_m2ps2"] = static_cast<double>(s.potential);
        j["G_norm_mps2"] = static_cast<double>(s.g.norm());
        if (e) {
          j["G_ecef_mps2"] = {static_cast<double>(s.g.x()), static_cast<double>(s.g.y()), static_cast<double>(s.g.z())};
          nlohmann::json g6 = nlohmann::json::array();
          for (const auto& q : ij) g6.push_back(static_cast<double>(s.gamma(q[0], q[1]) * 1e9L));
          j["Gamma_ecef_E_xx_xy_xz_yy_yz_zz"] = g6;
        }
        if (n) {
          j["G_ned_mps2"] = {static_cast<double>(gn.x()), static_cast<double>(gn.y()), static_cast<double>(gn.z())};
          nlohmann::json g6 = nlohmann::json::array();
          for (const auto& q : ij) g6.push_back(static_cast<double>(Gn(q[0], q[1]) * 1e9L));
          j["Gamma_ned_E_NN_NE_ND_EE_ED_DD"] = g6;
        }
        js.push_back(j);
      }
    }
    if (format == "json") {
      nlohmann::json doc;
      doc["model"] = f->name();
      doc["model_constants"] = desc;
      doc["conventions"] = "G = grad V toward the masses, no centrifugal term; Gamma_jk = dG_j/dx_k in Eotvos; NED at the geodetic (WGS-84) latitude/longitude";
      doc["points"] = js;
      std::fprintf(o, "%s\n", doc.dump(1).c_str());
    }
    if (std::fflush(o) != 0 || std::ferror(o) || (o != stdout && std::fclose(o) != 0))
      throw std::runtime_error("cannot write " + (out.empty() ? std::string("standard output") : out));
    return 0;
  });
}
