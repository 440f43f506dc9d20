// Host side of the onboard gradient map: generates a
// firmware tile (firmware/include/ggins/gmap.h) from a gravitation model,
// writes and reads the binary tile format and a JSON copy.
//
// Node values: the gradient tensor Gamma = dG/dx of the model, rotated into
// the node's NED frame, Gamma_n = C_n_e Gamma_e C_n_e^T, with
//   C_n_e rows: north = (-sin(lat) cos(lon), -sin(lat) sin(lon), cos(lat)),
//               east  = (-sin(lon), cos(lon), 0),
//               down  = (-cos(lat) cos(lon), -cos(lat) sin(lon), -sin(lat)),
// and its height derivative d Gamma_n/dh = C_n_e (sum_k T_k up_k) C_n_e^T,
// T_k = dGamma_e/dx_k (up = -down; the NED frame is constant along the normal
// at fixed lat/lon). Each row of nodes is one circle of latitude
// (Field::circle): spherical harmonics share the Legendre part along it and
// give sum_k T_k up_k by dual numbers through the synthesis; other models
// (the normal field) evaluate node by node with third().
// Database noise: independent N(0, sigma) added to each of the six values at
// every node (std::mt19937_64 seeded; the height derivatives get none).
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "ggins/gravity/field.hpp"

extern "C" {
#include "ggins/gmap.h"
}

namespace ggins::gmap {

struct TileSpec {
  double lat_min_deg = 0, lat_max_deg = 0;  // node rows span [lat_min, lat_min + (nlat-1) d] >= lat_max
  double lon_min_deg = 0, lon_max_deg = 0;
  double spacing_deg = 0.05;                // node spacing in lat and lon, deg
  double alt_m = 0;                         // grid height above the ellipsoid, m
  double h_range_m = 300;                   // accepted |h - alt| on board
  int nmax = 360;                           // SH degree (metadata; the field is built with it)
  bool anomaly = false;                     // total minus WGS-84 normal
  double noise_e = 0;                       // database noise sigma, E
  std::uint64_t seed = 1;
  int threads = 2;
};

// EGM96 (NASA ASCII file) to degree nmax with third derivatives:
// total = WGS-84 normal (closed form) + SH disturbance (double synthesis),
// or the disturbance alone when anomaly is true.
std::shared_ptr<const gravity::Field> make_egm96_field(const std::string& path, int nmax, bool anomaly);

// Node values at geodetic (lat, lon) rad, height h: 6 components + 6 height derivatives.
void node_values(const gravity::Field& f, double lat, double lon, double h, double out[GG_GMAP_NVAL]);

// Height layers over [h_lo, h_hi] m: n = ceil((h_hi - h_lo) / max_m) layers (at least 1) of
// equal thickness t <= max_m centred at h_lo + (k + 1/2) t, each accepting |h - h0| <= t/2 +
// margin_m. The first-order height term of a tile errs by ~(h - h0)^2/2 d2Gamma/dh2 (EGM96-360
// at 0.05 deg: 3.8e-3 E at 1000 m, docs/map-matching.md), so max_m = 600 m keeps it <= 3.4e-4 E
// where the storage serves the nearest layer (hal.h). Returns (h0, band) pairs.
constexpr double kLayerMaxM = 600.0;    // thickest layer of map_from_field and ggins gmap --alt-to
constexpr double kLayerMarginM = 300.0;  // band beyond the half thickness (an epoch's climb)
struct Layer {
  double h0_m, h_range_m;
};
std::vector<Layer> height_layers(double h_lo, double h_hi, double max_m = kLayerMaxM,
                                 double margin_m = kLayerMarginM);

// Builds a tile (heap-allocated: 240 kB). Throws std::invalid_argument on a
// spec the firmware would reject (too many nodes, spacing <= 0, ...).
std::unique_ptr<gg_gmap_tile_t> make_tile(const gravity::Field& f, const TileSpec& spec);

// A tile of Gamma_DD alone (the particle filter's kind, GG_GMAP_GZZ_ONLY): every other
// value and its height derivative set to zero, the flag set.
void keep_gzz_only(gg_gmap_tile_t& t);

std::vector<std::uint8_t> encode(const gg_gmap_tile_t& t);   // binary format of gmap.h
nlohmann::json to_json(const gg_gmap_tile_t& t);
std::unique_ptr<gg_gmap_tile_t> from_json(const nlohmann::json& j);
// Reads a .bin tile (through the firmware's gg_gmap_load) or a .json tile.
std::unique_ptr<gg_gmap_t> read_tile_file(const std::string& path);

}  // namespace ggins::gmap
