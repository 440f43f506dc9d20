// The computer's map storage as a 3-D run records it for its replay
// (lcmtypes/nav3d_config_t: map_source_*). hal_sim loads the tiles (--map, in
// this order) from up to kMaxSources sources, each one gmap tile file (any
// name) or a directory (its *.gmap files in name order: the storage of an
// aid's tiles along a route). A source is recorded by its path and kind, the
// number of its tiles, their bytes and one unkeyed BLAKE2b-256 (libsodium
// crypto_generichash) over them: for each tile in load order the length of its
// file name (u32, little-endian), the name, the file's size (u64,
// little-endian) and its contents. The name is part of the digest because the
// order of the tiles decides among overlapping ones (hal_sim/hal_map.c); the
// directory is not, so a storage moved elsewhere is the same storage.
#pragma once

#include <sodium.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <system_error>
#include <vector>

namespace ggins::run3d {

constexpr int kMaxSources = 16;   // sources a configuration records
constexpr int kMaxTiles = 256;    // tiles of the storage (hal_sim/hal_map.h HAL_MAP_MAX_TILES)

enum class SourceKind : int8_t { kFile = 0, kDir = 1 };

struct MapSource {
  std::string path;
  SourceKind kind = SourceKind::kFile;
};

// A source as read from the file system: its tile files in load order and its record.
struct SourceRecord {
  std::vector<std::string> files;
  int32_t tiles = 0;
  int64_t bytes = 0;
  std::array<uint8_t, 32> blake2b{};
};

// The tile files of a source in load order; "" and the files, or why they cannot be listed.
inline std::string source_files(const MapSource& s, std::vector<std::string>& files) {
  namespace fs = std::filesystem;
  files.clear();
  std::error_code ec;
  if (s.kind == SourceKind::kFile) {
    if (!fs::is_regular_file(s.path, ec)) return "not a readable file";
    files.push_back(s.path);
    return "";
  }
  if (!fs::is_directory(s.path, ec)) return "not a directory";
  for (const auto& e : fs::directory_iterator(s.path, ec))
    if (e.is_regular_file() && e.path().extension() == ".gmap") files.push_back(e.path().string());
  if (ec) return ec.message();
  std::sort(files.begin(), files.end());
  if (files.empty()) return "no *.gmap tile in it";
  return "";
}

// Read a source: "" and its record, or why it cannot be read.
inline std::string read_source(const MapSource& s, SourceRecord& r) {
  r = SourceRecord{};
  if (const std::string why = source_files(s, r.files); !why.empty()) return why;
  crypto_generichash_state h;
  if (crypto_generichash_init(&h, nullptr, 0, r.blake2b.size()) != 0) return "BLAKE2b init failed";
  auto put_le = [&](uint64_t v, int n) {
    unsigned char b[8];
    for (int i = 0; i < n; ++i) b[i] = static_cast<unsigned char>(v >> (8 * i));
    crypto_generichash_update(&h, b, static_cast<unsigned long long>(n));
  };
  for (const auto& f : r.files) {
    std::ifstream in(f, std::ios::binary);
    if (!in) return f + ": cannot be read";
    const std::vector<char> data((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (in.bad()) return f + ": cannot be read";
    const std::string name = std::filesystem::path(f).filename().string();
    put_le(name.size(), 4);
    crypto_generichash_update(&h, reinterpret_cast<const unsigned char*>(name.data()), name.size());
    put_le(data.size(), 8);
    crypto_generichash_update(&h, reinterpret_cast<const unsigned char*>(data.data()), data.size());
    r.bytes += static_cast<int64_t>(data.size());
    ++r.tiles;
  }
  if (crypto_generichash_final(&h, r.blake2b.data(), r.blake2b.size()) != 0) return "BLAKE2b failed";
  return "";
}

inline std::string hex(const std::array<uint8_t, 32>& b) {
  static const char* k = "0123456789abcdef";
  std::string s;
  for (uint8_t c : b) {
    s.push_back(k[c >> 4]);
    s.push_back(k[c & 15]);
  }
  return s;
}

inline const char* kind_name(SourceKind k) { return k == SourceKind::kDir ? "directory" : "file"; }

}  // namespace ggins::run3d
