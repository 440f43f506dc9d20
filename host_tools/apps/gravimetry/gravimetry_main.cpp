// ggins gravimetry: the survey product of a flight flown by ggins run3d (its
// gravimetry_raw.csv), made after the flight from the whole of it
// (host_tools/lib/gravimetry/include/ggins/gravimetry/survey.hpp states the models).
#include <CLI/CLI.hpp>

#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "ggins/cli_checks.hpp"
#include "ggins/gravimetry/survey.hpp"

namespace fs = std::filesystem;
namespace gv = ggins::gravimetry;
using json = nlohmann::json;

namespace {

// chi-square band (two-sided 95 %) by Wilson-Hilferty
void chi2_band(double dof, double& lo, double& hi) {
  const double z = 1.959964, c = 2.0 / (9.0 * dof);
  lo = dof * std::pow(1 - c - z * std::sqrt(c), 3);
  hi = dof * std::pow(1 - c + z * std::sqrt(c), 3);
}

json stats_json(const gv::LineStats& s) {
  return {{"line", s.number},
          {"type", s.number == 0 ? "all" : (s.tie ? "tie" : "line")},
          {"samples", s.n},
          {"rms_dg_mgal", s.rms_mgal},
          {"max_dg_mgal", s.max_mgal},
          {"rms_horizontal_mgal", s.rms_h_mgal},
          {"rms_xi_arcsec", s.rms_xi_arcsec},
          {"rms_eta_arcsec", s.rms_eta_arcsec},
          {"rms_dg_at_nav_position_mgal", s.rms_true_pos_mgal},
          {"rms_sigma_mgal", s.rms_sigma_mgal},
          {"normalised_mse", s.nmse},
          {"signal_rms_dg_mgal", s.signal_rms_mgal},
          {"position_error_rms_m", s.pos_err_rms_m}};
}

std::vector<double> parse_list(const std::string& s) {
  std::vector<double> v;
  std::stringstream is(s);
  std::string x;
  while (std::getline(is, x, ',')) v.push_back(std::stod(x));
  return v;
}

}  // namespace

int main(int argc, char** argv) {
  std::string run_dir, out_dir, wl_list = "2,4,6,10";
  double wavelength_km = 6;
  gv::LineOptions lo;
  gv::ClosingOptions co;
  bool no_crossovers = false, no_plots = false, quiet = false;
  double position_sigma_m = 100, grid_m = 0, grid_radius_m = 0;
  std::string python = GGINS_PLOT_PYTHON;
  CLI::App app{
      "ggins gravimetry - the survey product of a flight: the gravity disturbance (scalar, mGal) and\n"
      "the deflections of the vertical (xi, eta, arcsec) along the flight's lines, at the positions the\n"
      "navigation knew, with a one-sigma at every sample; made after the flight from all of it.\n\n"
      "Input: a ggins run3d output folder (its gravimetry_raw.csv and summary.json). No GNSS anywhere:\n"
      "the estimate is the navigation's own (gradiometer mode: gravitation dead-reckoned from the\n"
      "measured gradient; model mode: Rubenstein & Winter's barometer-loop gravimeter, scalar only).\n\n"
      "Processing: lines and ties are found as straight level stretches of the track; the error model\n"
      "(a random walk in the integrated gradient noise + a constant gradient error) is adjusted to the\n"
      "closing measurement (the track back over its start, the zero point) and to every line crossover,\n"
      "as one least-squares (Gaussian-process) estimate; each line is then low-passed (zero-phase\n"
      "Butterworth, amplitude 1/2 at the full wavelength) and compared with the truth from the\n"
      "scenario's field filtered the same way.\n\n"
      "Writes to --out (default RUN/gravimetry/):\n"
      "  survey.csv        line, type, fid, time, lat, lon, height, dg, xi, eta, sigmas, truth (along\n"
      "                    the true path), errors; the truth at the nav's positions\n"
      "  survey.xyz        the same lines in the XYZ line layout of survey packages (Line N / Tie N)\n"
      "  grid.csv          the gridded map: estimate, truth and error at regular nodes\n"
      "  gravimetry.json   per line and pooled: rms and max error, the one-sigma's rms, the chi-square\n"
      "                    check over the lines; the table at --wavelengths-km; the error against\n"
      "                    wavelength; the observations and their residuals\n"
      "  profiles.png, spectrum.png, map.png (the lines and the gridded map beside the truth;\n"
      "                    with Python + matplotlib)\n\n"
      "Exit status: 0 written; 1 failed (input unreadable, no lines found); 2 bad arguments."};
  app.add_option("run", run_dir, "ggins run3d output folder")->required()->check(CLI::ExistingDirectory);
  app.add_option("-o,--out", out_dir, "output folder (default RUN/gravimetry)");
  app.add_option("--wavelength-km", wavelength_km, "full wavelength of the product's filter, km")
      ->capture_default_str()
      ->check(ggins::cli::FiniteRange(0.2, 1000));
  app.add_option("--wavelengths-km", wl_list, "wavelengths of the error table, km (comma-separated)")
      ->capture_default_str();
  app.add_option("--min-line-km", lo.min_length_m, "shortest straight level stretch taken as a line, m")
      ->capture_default_str()
      ->check(ggins::cli::FiniteRange(100, 1e7));
  app.add_option("--max-turn-dps", lo.max_turn_dps, "a line's largest track heading rate, deg/s")
      ->capture_default_str()
      ->check(ggins::cli::FiniteRange(1e-4, 10));
  bool no_closing = false;
  app.add_flag("--no-closing", no_closing, "do not use the closing measurement at the zero point");
  app.add_option("--closing-radius-m", co.radius_m, "the nav track back within this of its start: the closing point")
      ->capture_default_str()
      ->check(ggins::cli::FiniteRange(1, 1e5));
  app.add_flag("--no-crossovers", no_crossovers, "do not adjust to the line crossovers");
  bool loop_as_flown = false;
  app.add_flag("--loop-as-flown", loop_as_flown,
               "model mode: take the barometer loop's output as flown (lagged), not inverted after the flight");
  app.add_option("--position-sigma-m", position_sigma_m,
                 "the navigation's horizontal position one-sigma (no GNSS: the INS's own; weighs the crossovers)")
      ->capture_default_str()
      ->check(ggins::cli::FiniteRange(0, 1e5));
  app.add_option("--grid-m", grid_m, "node spacing of grid.csv, m (default: a quarter of the wavelength)")
      ->check(ggins::cli::FiniteRange(10, 1e6));
  app.add_option("--grid-radius-m", grid_radius_m,
                 "samples within this of a node make it, m (default: half the wavelength)")
      ->check(ggins::cli::FiniteRange(10, 1e6));
  app.add_flag("--no-plots", no_plots, "no PNG plots");
  app.add_option("--python", python, "Python with matplotlib for the plots")->capture_default_str();
  app.add_flag("-q,--quiet", quiet, "no summary on stdout");
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 2;
  }
  co.enable = !no_closing;
  std::vector<double> wls;
  try {
    wls = parse_list(wl_list);
    for (double w : wls)
      if (!(w > 0.1 && w < 1000)) throw std::invalid_argument("range");
  } catch (const std::exception&) {
    std::fprintf(stderr, "ggins gravimetry: --wavelengths-km '%s': give km values in (0.1, 1000), comma-separated\n",
                 wl_list.c_str());
    return 2;
  }
  const fs::path out = out_dir.empty() ? fs::path(run_dir) / "gravimetry" : fs::path(out_dir);
  try {
    fs::create_directories(out);
    gv::Record rec = gv::read_record(run_dir);
    if (loop_as_flown) rec.loop_poles.clear();
    const auto lines = gv::find_lines(rec, lo);
    if (lines.empty())
      throw std::runtime_error("no straight level stretch of " + std::to_string(lo.min_length_m / 1000) +
                               " km or more in the flight (--min-line-km, --max-turn-dps)");
    std::vector<gv::Observation> obs;
    gv::Observation cl;
    const bool have_closing = gv::closing(rec, co, cl);
    if (have_closing) obs.push_back(cl);
    if (!no_crossovers) {
      const auto xo = gv::crossovers(rec, lines, position_sigma_m);
      obs.insert(obs.end(), xo.begin(), xo.end());
    }
    const gv::Adjusted adj = gv::adjust(rec, obs);
    const gv::Product pr = gv::make_product(rec, lines, adj, wavelength_km * 1000);
    gv::write_csv(out / "survey.csv", rec, pr);
    // the gridded map: nodes every wavelength / 4, each from the samples within half the
    // wavelength (at least 1.5 node spacings)
    const double gsp = grid_m > 0 ? grid_m : wavelength_km * 1000 / 4;
    const gv::Grid grid = gv::make_grid(rec, pr, gsp, grid_radius_m > 0 ? grid_radius_m : std::max(1.5 * gsp, wavelength_km * 500));
    gv::write_grid_csv(out / "grid.csv", grid);
    gv::write_xyz(out / "survey.xyz", rec, pr,
                  "ggins gravimetry of " + fs::absolute(run_dir).string() + " (" + rec.mode + " mode)");
    json j;
    j["run"] = fs::absolute(run_dir).string();
    j["mode"] = rec.mode;
    j["field"] = rec.field;
    j["error_model"] = rec.mode == "gradiometer";
    j["loop_inverted"] = rec.mode == "model" && rec.loop_poles.size() == 3;
    j["wavelength_m"] = wavelength_km * 1000;
    j["closing"] = have_closing ? json{{"lat_deg", cl.lat_deg}, {"lon_deg", cl.lon_deg},
                                       {"misclosure_mgal", {cl.y[0] / gv::kMgal, cl.y[1] / gv::kMgal, cl.y[2] / gv::kMgal}}}
                                : json(nullptr);
    size_t nxo = 0;
    json ob = json::array();
    for (size_t k = 0; k < obs.size(); ++k) {
      nxo += obs[k].kind == "crossover";
      ob.push_back({{"kind", obs[k].kind}, {"lines", {obs[k].line_a, obs[k].line_b}}, {"lat_deg", obs[k].lat_deg},
                    {"lon_deg", obs[k].lon_deg},
                    {"value_mgal", {obs[k].y[0] / gv::kMgal, obs[k].y[1] / gv::kMgal, obs[k].y[2] / gv::kMgal}},
                    {"residual_mgal",
                     {adj.residual[k][0] / gv::kMgal, adj.residual[k][1] / gv::kMgal, adj.residual[k][2] / gv::kMgal}}});
    }
    j["crossovers"] = nxo;
    j["observations"] = ob;
    json ls = json::array();
    for (size_t i = 0; i < lines.size(); ++i) {
      json s = stats_json(pr.stats[i]);
      s["length_m"] = lines[i].length_m;
      s["heading_deg"] = lines[i].heading_deg;
      s["speed_mps"] = lines[i].speed_mps;
      ls.push_back(s);
    }
    j["lines"] = ls;
    j["all"] = stats_json(pr.all);
    if (rec.mode == "gradiometer") {  // chi-square over the lines: one degree of freedom per line and component
      double chi2 = 0;
      for (const auto& s : pr.stats) chi2 += 3 * s.nmse;
      const double dof = 3.0 * static_cast<double>(pr.stats.size());
      double lo95 = 0, hi95 = 0;
      chi2_band(dof, lo95, hi95);
      j["chi2"] = {{"value", chi2}, {"dof", dof}, {"band95", {lo95, hi95}}, {"in_band", chi2 >= lo95 && chi2 <= hi95}};
    }
    json tab = json::array();
    for (double w : wls) {
      const gv::Product q = gv::make_product(rec, lines, adj, w * 1000);
      tab.push_back({{"wavelength_km", w}, {"rms_dg_mgal", q.all.rms_mgal}, {"rms_horizontal_mgal", q.all.rms_h_mgal},
                     {"rms_deflection_arcsec", q.all.rms_xi_arcsec}, {"signal_rms_dg_mgal", q.all.signal_rms_mgal},
                     {"rms_sigma_mgal", q.all.rms_sigma_mgal}});
    }
    j["table"] = tab;
    json sp = json::array();  // the error against wavelength (log-spaced sweep)
    for (double w = 1.0; w <= 64.01; w *= std::sqrt(2.0)) {
      const gv::Product q = gv::make_product(rec, lines, adj, w * 1000);
      sp.push_back({{"wavelength_km", w}, {"rms_dg_mgal", q.all.rms_mgal}, {"rms_horizontal_mgal", q.all.rms_h_mgal},
                    {"signal_rms_dg_mgal", q.all.signal_rms_mgal}});
    }
    j["spectrum"] = sp;
    {  // the raw (unadjusted) estimate at the product's wavelength, for comparison
      gv::Adjusted raw = gv::adjust(rec, {});
      const gv::Product q = gv::make_product(rec, lines, raw, wavelength_km * 1000);
      j["unadjusted"] = stats_json(q.all);
    }
    std::ofstream jf(out / "gravimetry.json");
    jf << j.dump(2) << "\n";
    if (!jf) throw std::runtime_error("cannot write " + (out / "gravimetry.json").string());
    if (!quiet) {
      std::printf("ggins gravimetry: %s mode, %zu lines + ties, %zu crossovers, closing %s\n", rec.mode.c_str(),
                  lines.size(), nxo, have_closing ? "used" : "none");
      std::printf("  at %.1f km full wavelength: dg rms %.3f mGal (max %.3f), horizontal rms %.3f mGal, "
                  "deflection rms %.3f arcsec",
                  wavelength_km, pr.all.rms_mgal, pr.all.max_mgal, pr.all.rms_h_mgal, pr.all.rms_xi_arcsec);
      if (rec.mode == "gradiometer")
        std::printf("; stated one-sigma rms %.3f mGal\n", pr.all.rms_sigma_mgal);
      else
        std::printf(" (model mode: the barometer loop's gravimeter%s, scalar only, no error model)\n",
                    rec.loop_poles.size() == 3 ? " inverted after the flight" : " as flown");
      if (j.contains("chi2"))
        std::printf("  chi-square over the lines %.1f for %g dof (95 %% band %.1f..%.1f)%s\n",
                    j["chi2"]["value"].get<double>(), j["chi2"]["dof"].get<double>(), j["chi2"]["band95"][0].get<double>(),
                    j["chi2"]["band95"][1].get<double>(), j["chi2"]["in_band"].get<bool>() ? "" : " OUT OF BAND");
      std::printf("  output: %s\n", out.c_str());
    }
    if (!no_plots && !python.empty()) {
      const std::string cmd = "'" + python + "' '" + std::string(GGINS_GRAVIMETRY_PLOT) + "' '" + out.string() +
                              "' > '" + (out / "plot.log").string() + "' 2>&1";
      if (std::system(cmd.c_str()) != 0)
        std::fprintf(stderr, "ggins gravimetry: plotting failed; see %s\n", (out / "plot.log").c_str());
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "ggins gravimetry: %s\n", e.what());
    return 1;
  }
  return 0;
}
