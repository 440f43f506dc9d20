// The record of an onboard map tile file (gmap format) kept in the 3-D
// configuration message (lcmtypes/nav3d_config_t: aid_mm_tile_*): its path,
// size and unkeyed BLAKE2b-256 digest (libsodium crypto_generichash), so that
// a replay loads the same tiles as the flight did and refuses other bytes.
#pragma once

#include <sodium.h>

#include <array>
#include <cstdint>
#include <fstream>
#include <iterator>
#include <optional>
#include <string>
#include <vector>

namespace ggins::run3d {

struct TileDigest {
  int64_t bytes = 0;
  std::array<uint8_t, 32> blake2b{};
};

// Size and digest of a file; nullopt if it cannot be read.
inline std::optional<TileDigest> tile_digest(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  if (!f) return std::nullopt;
  const std::vector<unsigned char> data((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  if (f.bad()) return std::nullopt;
  TileDigest d;
  d.bytes = static_cast<int64_t>(data.size());
  if (crypto_generichash(d.blake2b.data(), d.blake2b.size(), data.data(), data.size(), nullptr, 0) != 0)
    return std::nullopt;
  return d;
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

}  // namespace ggins::run3d
