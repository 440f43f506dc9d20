// Map tiles built once: a folder of encoded tiles (the binary format of gmap.h) named by
// the content that defines them, shared by ggins gmap, ggins run3d (map_from_field) and the
// campaigns' workers.
//
// Key: the unkeyed BLAKE2b-256 (libsodium crypto_generichash) of a text that holds the
// cache's format (kTileCacheFormat, changed whenever the tile arithmetic changes), the
// field's identity (egm96_field_id: the coefficient file's digest, the degree, total or
// disturbance) and every value of the tile's specification (area, spacing, height and band,
// degree, noise and its seed, whether it keeps Gamma_DD alone) as exact hexadecimal
// floating point. Two specifications that differ in any bit get different entries; the
// number of build threads is not part of it (rows are computed independently).
//
// Concurrency: an entry is built under an exclusive lock (flock) of <key>.lock, written to a
// temporary file and renamed into place (atomic on POSIX), so that concurrent users build
// it once and a reader never sees a partial tile; an entry the firmware's gg_gmap_load
// refuses (a damaged file) is built again. Entries are never evicted: remove the folder to
// reclaim its space (a 50 x 50 tile takes 240 kB).
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "ggins/gmap_gen.hpp"

namespace ggins::gmap {

inline constexpr const char* kTileCacheFormat = "ggins-tile-cache-1";

// The shared folder: $GGINS_MAP_CACHE when set ("off" or empty: no cache, returns an empty
// path), else $XDG_CACHE_HOME/ggins/maps, else $HOME/.cache/ggins/maps (empty without HOME).
std::filesystem::path default_cache_dir();

// BLAKE2b-256 of a file's bytes, hex. Throws std::runtime_error when it cannot be read.
std::string file_digest(const std::string& path);

// The identity of the EGM96 field make_egm96_field builds (and the truth generator's
// normal + disturbance without its lattice, FastField::exact): the file's digest, degree
// and total/disturbance.
std::string egm96_field_id(const std::string& path, int nmax, bool anomaly);

// The entry's key (64 hex digits) of a tile of `field_id` built as `sp`.
std::string tile_key(const std::string& field_id, const TileSpec& sp, bool gzz_only);

// The encoded tile of `key`: the cached entry when it is present and the firmware loads it
// (*hit = true), else make()'s bytes, stored (*hit = false). An empty dir: make(), no cache.
// Throws std::runtime_error when the folder cannot be created or written.
std::vector<std::uint8_t> cached_tile(const std::filesystem::path& dir, const std::string& key,
                                      const std::function<std::vector<std::uint8_t>()>& make, bool* hit);

}  // namespace ggins::gmap
