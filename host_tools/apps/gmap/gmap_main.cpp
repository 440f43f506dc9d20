// ggins gmap: generate an onboard gravity-gradient map tile (firmware gmap.h)
// from EGM96 for a lat/lon box at one altitude (or height layers over a span), for the map-matching UKF (Gao et al.) and the cold-atom particle filter (Phillips et al.).
#include <CLI/CLI.hpp>

#include "ggins/cli_checks.hpp"

#include <chrono>
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>
#include <cstdio>
#include <fstream>

#include "ggins/gmap_gen.hpp"
#include "ggins/tile_cache.hpp"

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
      "The map-matching UKF uses the TOTAL field. --noise-e adds seeded N(0, sigma) database noise.\n"
      "Height layers for a flight that climbs: --alt-to H writes the layers between --alt and H\n"
      "(at most --layer-m thick, each accepting half its thickness + --h-range), one file per layer,\n"
      "named after --out/--json with _h<height> before the extension; the map storage serves the layer\n"
      "holding the aid's height.\n\n"
      "Exit status: 0 written; 1 failed (e.g. the coefficient file does not read, an output not written);\n"
      "2 bad arguments (the option, its value and the allowed range are named)."};
  app.add_option("--lat-min", sp.lat_min_deg, "south edge, deg")->required()->check(cli::FiniteRange(-90, 90));
  app.add_option("--lat-max", sp.lat_max_deg, "north edge, deg (rounded up to a whole node)")
      ->required()
      ->check(cli::FiniteRange(-90, 90));
  app.add_option("--lon-min", sp.lon_min_deg,
                 "west edge, deg (a tile may cross the antimeridian: e.g. --lon-min 175 --lon-max 185)")->required()->check(cli::FiniteRange(-360, 360));
  app.add_option("--lon-max", sp.lon_max_deg, "east edge, deg (rounded up to a whole node)")
      ->required()
      ->check(cli::FiniteRange(-360, 360));
  app.add_option("--spacing", sp.spacing_deg, "node spacing in lat and lon, deg")
      ->capture_default_str()
      ->check(cli::FiniteRange(0, 10, cli::kOpenLow));
  app.add_option("--alt", sp.alt_m, "grid height above the WGS-84 ellipsoid, m")
      ->capture_default_str()
      ->check(cli::FiniteRange(-1e4, 1e6));
  double alt_to = NAN, layer_m = ggins::gmap::kLayerMaxM;
  app.add_option("--alt-to", alt_to, "top of the height span: height layers from --alt to this, m")
      ->check(cli::FiniteRange(-1e4, 1e6));
  app.add_option("--layer-m", layer_m, "thickest height layer with --alt-to, m")
      ->capture_default_str()
      ->check(cli::FiniteRange(0, 1e5, cli::kOpenLow));
  app.add_option("--h-range", sp.h_range_m, "accepted |h - alt| on board, m (with --alt-to: beyond each layer's half thickness)")
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
  std::string cache = ggins::gmap::default_cache_dir().string();
  bool no_cache = false;
  app.add_option("--cache", cache,
                 "tile cache folder: a tile is built once, named by its content (the coefficient file's digest, "
                 "degree, area, spacing, height, band, noise, seed, kind), shared with ggins run3d (default: "
                 "$GGINS_MAP_CACHE, else $XDG_CACHE_HOME/ggins/maps, else ~/.cache/ggins/maps)")
      ->capture_default_str();
  app.add_flag("--no-cache", no_cache, "build the tile afresh and keep no copy");
  app.add_option("--out", out_bin, "binary tile (format in gmap.h)")->check(cli::OutputFile());
  app.add_option("--json", out_json, "JSON copy of the tile")->check(cli::OutputFile());
  return cli::run("ggins gmap", app, argc, argv, [&] {
    if (out_bin.empty() && out_json.empty()) throw cli::BadArgument("give --out and/or --json");
    if (!(sp.lat_max_deg >= sp.lat_min_deg) || !(sp.lon_max_deg >= sp.lon_min_deg))
      throw cli::BadArgument("the box needs --lat-max >= --lat-min and --lon-max >= --lon-min");
    std::vector<ggins::gmap::Layer> layers{{sp.alt_m, sp.h_range_m}};
    const bool layered = !std::isnan(alt_to);
    if (layered) {
      if (!(alt_to > sp.alt_m)) throw cli::BadArgument("--alt-to must be above --alt");
      layers = ggins::gmap::height_layers(sp.alt_m, alt_to, layer_m, sp.h_range_m);
    }
    // with layers: tile.bin -> tile_h03150.bin
    auto named = [&](const std::string& path, double h0) {
      if (!layered || path.empty()) return path;
      const std::filesystem::path p(path);
      char tag[32];
      std::snprintf(tag, sizeof tag, "_h%05.0f", h0);
      return (p.parent_path() / (p.stem().string() + tag + p.extension().string())).string();
    };
    std::shared_ptr<const ggins::gravity::Field> field;  // read when a tile is to be built
    const std::filesystem::path cache_dir = no_cache ? std::filesystem::path() : std::filesystem::path(cache);
    const std::string field_id = cache_dir.empty() ? std::string() : ggins::gmap::egm96_field_id(egm, sp.nmax, sp.anomaly);
    const std::uint64_t seed0 = sp.seed;
    for (std::size_t k = 0; k < layers.size(); ++k) {
      const auto t0 = std::chrono::steady_clock::now();
      sp.alt_m = layers[k].h0_m;
      sp.h_range_m = layers[k].h_range_m;
      sp.seed = seed0 + k;  // each layer its own noise
      const auto make = [&] {
        if (!field) field = ggins::gmap::make_egm96_field(egm, sp.nmax, sp.anomaly);
        auto t = ggins::gmap::make_tile(*field, sp);
        if (gzz_only) ggins::gmap::keep_gzz_only(*t);
        return ggins::gmap::encode(*t);
      };
      bool hit = false;
      const std::vector<std::uint8_t> b =
          ggins::gmap::cached_tile(cache_dir, ggins::gmap::tile_key(field_id, sp, gzz_only), make, &hit);
      auto st = std::make_unique<gg_gmap_t>();
      if (gg_gmap_load(st.get(), b.data(), b.size()) != GG_OK) throw std::runtime_error("gmap: the tile does not load");
      const gg_gmap_tile_t* tile = &st->tile;
      const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      if (!out_bin.empty()) {
        cli::write_file(named(out_bin, sp.alt_m), std::string(reinterpret_cast<const char*>(b.data()), b.size()),
                        true);
      }
      if (!out_json.empty()) cli::write_file(named(out_json, sp.alt_m), ggins::gmap::to_json(*tile).dump(1) + "\n");
      std::printf("gmap: %d x %d nodes (%d of %d), %.4f deg, alt %.1f m +- %.1f m, degree %d, %s, noise %.4g E, seed %llu, "
                  "%.1f s%s%s\n",
                  tile->nlat, tile->nlon, tile->nlat * tile->nlon, GG_GMAP_MAX_NODES, sp.spacing_deg, sp.alt_m,
                  sp.h_range_m, sp.nmax,
                  gzz_only ? (sp.anomaly ? "anomaly Gamma_DD" : "total Gamma_DD") : (sp.anomaly ? "anomaly" : "total"),
                  sp.noise_e, static_cast<unsigned long long>(sp.seed), s, hit ? " (from the cache)" : "",
                  layered ? (" -> " + named(out_bin.empty() ? out_json : out_bin, sp.alt_m)).c_str() : "");
      std::fflush(stdout);
    }
    return 0;
  });
}
