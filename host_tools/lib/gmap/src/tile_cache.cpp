// Map tiles built once (see tile_cache.hpp).
#include "ggins/tile_cache.hpp"

#include <fcntl.h>
#include <sodium.h>
#include <sys/file.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <stdexcept>

namespace ggins::gmap {

namespace fs = std::filesystem;

namespace {

std::string hex(const unsigned char* b, size_t n) {
  static const char* d = "0123456789abcdef";
  std::string s;
  for (size_t i = 0; i < n; ++i) {
    s += d[b[i] >> 4];
    s += d[b[i] & 15];
  }
  return s;
}

std::string blake2b_hex(const unsigned char* data, size_t n) {
  std::array<unsigned char, 32> h{};
  if (crypto_generichash(h.data(), h.size(), data, n, nullptr, 0) != 0) throw std::runtime_error("BLAKE2b failed");
  return hex(h.data(), h.size());
}

std::string hexfloat(double v) {
  char b[64];
  std::snprintf(b, sizeof b, "%a", v);
  return b;
}

// Reads a file whole; false when it is absent or unreadable.
bool read_all(const fs::path& p, std::vector<std::uint8_t>& out) {
  std::ifstream in(p, std::ios::binary);
  if (!in) return false;
  out.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  return !in.bad();
}

bool loads(const std::vector<std::uint8_t>& b) {
  auto st = std::make_unique<gg_gmap_t>();
  return !b.empty() && gg_gmap_load(st.get(), b.data(), b.size()) == GG_OK;
}

// An exclusive flock held for the scope.
struct Lock {
  int fd = -1;
  explicit Lock(const fs::path& p) {
    fd = ::open(p.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    if (fd < 0) throw std::runtime_error("map cache: cannot open the lock " + p.string());
    while (::flock(fd, LOCK_EX) != 0) {
      if (errno != EINTR) {
        ::close(fd);
        throw std::runtime_error("map cache: cannot lock " + p.string());
      }
    }
  }
  ~Lock() {
    if (fd >= 0) ::close(fd);  // closing releases the lock
  }
  Lock(const Lock&) = delete;
  Lock& operator=(const Lock&) = delete;
};

}  // namespace

fs::path default_cache_dir() {
  if (const char* e = std::getenv("GGINS_MAP_CACHE")) {
    const std::string v = e;
    if (v.empty() || v == "off") return {};
    return fs::path(v);
  }
  if (const char* x = std::getenv("XDG_CACHE_HOME"); x != nullptr && *x != '\0') return fs::path(x) / "ggins" / "maps";
  if (const char* h = std::getenv("HOME"); h != nullptr && *h != '\0') return fs::path(h) / ".cache" / "ggins" / "maps";
  return {};
}

std::string file_digest(const std::string& path) {
  if (sodium_init() < 0) throw std::runtime_error("libsodium failed to initialise");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot read " + path);
  crypto_generichash_state st;
  std::array<unsigned char, 32> h{};
  crypto_generichash_init(&st, nullptr, 0, h.size());
  std::vector<char> buf(1 << 16);
  while (in) {
    in.read(buf.data(), static_cast<std::streamsize>(buf.size()));
    const std::streamsize n = in.gcount();
    if (n > 0) crypto_generichash_update(&st, reinterpret_cast<const unsigned char*>(buf.data()), static_cast<unsigned long long>(n));
  }
  if (in.bad()) throw std::runtime_error("cannot read " + path);
  crypto_generichash_final(&st, h.data(), h.size());
  return hex(h.data(), h.size());
}

std::string egm96_field_id(const std::string& path, int nmax, bool anomaly) {
  return std::string("egm96 blake2b=") + file_digest(path) + " nmax=" + std::to_string(nmax) +
         (anomaly ? " disturbance" : " normal+disturbance") + " double";
}

std::string tile_key(const std::string& field_id, const TileSpec& sp, bool gzz_only) {
  if (sodium_init() < 0) throw std::runtime_error("libsodium failed to initialise");
  std::string t = std::string(kTileCacheFormat) + "\nfield " + field_id;
  for (double v : {sp.lat_min_deg, sp.lat_max_deg, sp.lon_min_deg, sp.lon_max_deg, sp.spacing_deg, sp.alt_m,
                   sp.h_range_m, sp.noise_e})
    t += " " + hexfloat(v);
  t += " nmax=" + std::to_string(sp.nmax) + " anomaly=" + std::to_string(sp.anomaly ? 1 : 0) +
       " seed=" + std::to_string(sp.seed) + " gzz_only=" + std::to_string(gzz_only ? 1 : 0);
  return blake2b_hex(reinterpret_cast<const unsigned char*>(t.data()), t.size());
}

std::vector<std::uint8_t> cached_tile(const fs::path& dir, const std::string& key,
                                      const std::function<std::vector<std::uint8_t>()>& make, bool* hit) {
  if (hit) *hit = false;
  if (dir.empty()) return make();
  const fs::path entry = dir / (key + ".gmap");
  std::vector<std::uint8_t> b;
  if (read_all(entry, b) && loads(b)) {  // the common case: no lock needed (entries appear whole)
    if (hit) *hit = true;
    return b;
  }
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw std::runtime_error("map cache: cannot create " + dir.string() + ": " + ec.message());
  const Lock lock(dir / (key + ".lock"));
  if (read_all(entry, b) && loads(b)) {  // built by another while this one waited
    if (hit) *hit = true;
    return b;
  }
  b = make();
  const fs::path tmp = dir / (key + ".tmp." + std::to_string(::getpid()));
  {
    std::ofstream f(tmp, std::ios::binary | std::ios::trunc);
    f.write(reinterpret_cast<const char*>(b.data()), static_cast<std::streamsize>(b.size()));
    if (!f) throw std::runtime_error("map cache: cannot write " + tmp.string());
  }
  fs::rename(tmp, entry, ec);
  if (ec) {
    fs::remove(tmp, ec);
    throw std::runtime_error("map cache: cannot store " + entry.string());
  }
  return b;
}

}  // namespace ggins::gmap
