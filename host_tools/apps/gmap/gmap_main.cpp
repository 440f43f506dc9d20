// ggins gmap: generate an onboard gravity-gradient map tile (firmware gmap.h)
// from EGM96 for a lat/lon box at one altitude, for the map-matching UKF (Gao et al.) and the cold-atom particle filter (Phillips et al.).
#include <CLI/CLI.hpp>

#include "ggins/cli_checks.hpp"

#include <chrono>
#include <cstdio>
#include <fstream>

#include "ggins/gmap_gen.hpp"

#ifndef GGINS_DATA_DIR
#define GGINS_DATA_DIR "data"
#endif

int main(int argc, char** argv) {
  namespace cli = ggins::cli;
  ggins::gmap::TileSpec sp;
  std::string egm = std::string(GGINS_DATA_DIR) + "/egm96_to360.ascii.txt";
  std::string out_bin, out_json;
  CLI::App app{
      "ggins gmap - onboard gravity-gradient map tile (firmware/include/ggins/gmap.h).\n"
      "Gradient tensor Gamma = dG/dx of EGM96 (spherical harmonics to --degree; total = WGS-84 normal\n"
      "gravitation + disturbance, or --anomaly = disturbance only) in the NED frame of each node, six\n"
      "components NN EE DD NE ND ED (s^-2) and their height derivatives, on a lat/lon grid at --alt.\n"
      "The map-matching UKF uses the TOTAL field. --noise-e adds seeded N(0, sigma) database noise.\n\n"
      "Exit status: 0 written; 1 failed (e.g. the coefficient file does not read, an output not written);\n"
      "2 bad arguments (the option, its value and the allowed range are named)."};
  app.add_option("--lat-min", sp.lat_min_deg, "south edge, deg")->required()->check(cli::FiniteRange(-90, 90));
  app.add_option("--lat-max", sp.lat_max_deg, "north edge, deg (rounded up to a whole node)")
      ->required()
      ->check(cli::FiniteRange(-90, 90));
  app.add_option("--lon-min", sp.lon_min_deg, "west edge, deg")->required()->check(cli::FiniteRange(-360, 360));
  app.add_option("--lon-max", sp.lon_max_deg, "east edge, deg (rounded up to a whole node)")
      ->required()
      ->check(cli::FiniteRange(-360, 360));
  app.add_option("--spacing", sp.spacing_deg, "node spacing in lat and lon, deg")
      ->capture_default_str()
      ->check(cli::FiniteRange(0, 10, cli::kOpenLow));
  app.add_option("--alt", sp.alt_m, "grid height above the WGS-84 ellipsoid, m")
      ->capture_default_str()
      ->check(cli::FiniteRange(-1e4, 1e6));
  app.add_option("--h-range", sp.h_range_m, "accepted |h - alt| on board, m")
      ->capture_default_str()
      ->check(cli::FiniteRange(0, 1e6, cli::kOpenLow));
  app.add_option("--degree", sp.nmax, "spherical-harmonic degree (2..360)")->capture_default_str()->check(cli::IntRange(2, 360));
  app.add_flag("--anomaly", sp.anomaly, "store total minus the WGS-84 normal field");
  bool gzz_only = false;
  app.add_flag("--gzz-only", gzz_only,
               "a tile of Gamma_DD alone (its height derivative kept, the other values zero; flag GG_GMAP_GZZ_ONLY): "
               "the map kind of the cold-atom aid");
  app.add_option("--noise-e", sp.noise_e, "database noise sigma, E (1 E = 1e-9 s^-2)")
      ->capture_default_str()
      ->check(cli::FiniteRange(0, 1e6));
  app.add_option("--seed", sp.seed, "noise seed")->capture_default_str()->check(cli::Seed());
  app.add_option("--threads", sp.threads, "worker threads")->capture_default_str()->check(cli::IntRange(1, 1024));
  app.add_option("--egm96", egm, "EGM96 coefficient file (NASA ASCII)")->capture_default_str()->check(CLI::ExistingFile);
  app.add_option("--out", out_bin, "binary tile (format in gmap.h)")->check(cli::OutputFile());
  app.add_option("--json", out_json, "JSON copy of the tile")->check(cli::OutputFile());
  return cli::run("ggins gmap", app, argc, argv, [&] {
    if (out_bin.empty() && out_json.empty()) throw cli::BadArgument("give --out and/or --json");
    if (!(sp.lat_max_deg >= sp.lat_min_deg) || !(sp.lon_max_deg >= sp.lon_min_deg))
      throw cli::BadArgument("the box needs --lat-max >= --lat-min and --lon-max >= --lon-min");
    const auto t0 = std::chrono::steady_clock::now();
    auto field = ggins::gmap::make_egm96_field(egm, sp.nmax, sp.anomaly);
    auto tile = ggins::gmap::make_tile(*field, sp);
    if (gzz_only) {
      tile->flags |= GG_GMAP_GZZ_ONLY;
      for (int n = 0; n < tile->nlat * tile->nlon; ++n)
        for (int k = 0; k < GG_GMAP_NVAL; ++k)
          if (k != GG_GMAP_C_DD && k != GG_GMAP_NCOMP + GG_GMAP_C_DD) tile->node[n][k] = 0.0;
    }
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (!out_bin.empty()) {
      const auto b = ggins::gmap::encode(*tile);
      cli::write_file(out_bin, std::string(reinterpret_cast<const char*>(b.data()), b.size()), true);
    }
    if (!out_json.empty()) cli::write_file(out_json, ggins::gmap::to_json(*tile).dump(1) + "\n");
    std::printf("gmap: %d x %d nodes (%d of %d), %.4f deg, alt %.1f m, degree %d, %s, noise %.4g E, seed %llu, %.1f s\n",
                tile->nlat, tile->nlon, tile->nlat * tile->nlon, GG_GMAP_MAX_NODES, sp.spacing_deg, sp.alt_m, sp.nmax,
                gzz_only ? (sp.anomaly ? "anomaly Gamma_DD" : "total Gamma_DD") : (sp.anomaly ? "anomaly" : "total"), sp.noise_e, static_cast<unsigned long long>(sp.seed), s);
    return 0;
  });
}
