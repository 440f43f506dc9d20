// The tile cache (host_tools/lib/gmap/tile_cache.hpp) against what it promises:
//   - keys: equal for equal specifications (whatever the thread count), different when any
//     one value of the specification, the field's identity or the Gamma_DD-only flag changes
//     by the smallest step (one ulp of a double, one of an integer);
//   - the field's identity follows the coefficient file's bytes (one byte changed: another id);
//   - an entry is built once: the second request returns the same bytes without building;
//     a damaged entry (truncated, or bytes the firmware refuses) is built again;
//   - two threads asking for one absent entry at once build it once (the lock), and both
//     get the whole tile;
//   - no folder: built every time, nothing stored.
// The tiles are of the normal field (closed form, fast), through the same make_tile as any.
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>
#include <thread>

#include "ggins/gmap_gen.hpp"
#include "ggins/gravity/normal.hpp"
#include "ggins/tile_cache.hpp"

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
extern "C" {
#include <cmocka.h>
}

namespace fs = std::filesystem;
namespace gm = ggins::gmap;

static gm::TileSpec spec() {
  gm::TileSpec s;
  s.lat_min_deg = 44.0;
  s.lat_max_deg = 44.5;
  s.lon_min_deg = 7.0;
  s.lon_max_deg = 7.5;
  s.spacing_deg = 0.05;
  s.alt_m = 3000;
  s.h_range_m = 600;
  s.nmax = 0;
  s.noise_e = 0.001;
  s.seed = 7;
  return s;
}

static fs::path temp_dir(const char* what) {
  const fs::path d = fs::temp_directory_path() / ("ggins-tile-cache-" + std::string(what) + "-" + std::to_string(::getpid()));
  std::error_code ec;
  fs::remove_all(d, ec);
  return d;
}

static void test_keys(void** state) {
  (void)state;
  const gm::TileSpec s0 = spec();
  const std::string id = "field A";
  const std::string k0 = gm::tile_key(id, s0, false);
  assert_int_equal(k0.size(), 64);
  gm::TileSpec t = s0;
  t.threads = 1;
  assert_string_equal(gm::tile_key(id, t, false).c_str(), k0.c_str());  // threads: not part of it
  std::set<std::string> keys{k0};
  double gm::TileSpec::*doubles[] = {&gm::TileSpec::lat_min_deg, &gm::TileSpec::lat_max_deg, &gm::TileSpec::lon_min_deg,
                                     &gm::TileSpec::lon_max_deg, &gm::TileSpec::spacing_deg, &gm::TileSpec::alt_m,
                                     &gm::TileSpec::h_range_m,   &gm::TileSpec::noise_e};
  for (auto m : doubles) {
    gm::TileSpec u = s0;
    u.*m = std::nextafter(u.*m, 1e300);
    keys.insert(gm::tile_key(id, u, false));
  }
  gm::TileSpec u = s0;
  u.nmax += 1;
  keys.insert(gm::tile_key(id, u, false));
  u = s0;
  u.seed += 1;
  keys.insert(gm::tile_key(id, u, false));
  u = s0;
  u.anomaly = true;
  keys.insert(gm::tile_key(id, u, false));
  keys.insert(gm::tile_key(id, s0, true));
  keys.insert(gm::tile_key("field B", s0, false));
  assert_int_equal(keys.size(), 1 + 8 + 5);  // every change its own key
}

static void test_field_id_follows_the_file(void** state) {
  (void)state;
  const fs::path d = temp_dir("id");
  fs::create_directories(d);
  const fs::path a = d / "a.txt";
  std::ofstream(a) << "2 0 -0.484165371736E-03 0.0\n";
  const std::string ia = gm::egm96_field_id(a.string(), 2, false);
  std::ofstream(a) << "2 0 -0.484165371737E-03 0.0\n";  // one digit
  const std::string ib = gm::egm96_field_id(a.string(), 2, false);
  assert_true(ia != ib);
  assert_true(gm::egm96_field_id(a.string(), 2, true) != ib);
  assert_true(gm::egm96_field_id(a.string(), 3, false) != ib);
  std::error_code ec;
  fs::remove_all(d, ec);
}

static void test_built_once_and_rebuilt_when_damaged(void** state) {
  (void)state;
  const ggins::gravity::NormalField f;
  const gm::TileSpec s = spec();
  const fs::path d = temp_dir("once");
  int builds = 0;
  const auto make = [&] {
    ++builds;
    return gm::encode(*gm::make_tile(f, s));
  };
  const std::string key = gm::tile_key("normal", s, false);
  bool hit = true;
  const auto b1 = gm::cached_tile(d, key, make, &hit);
  assert_false(hit);
  assert_int_equal(builds, 1);
  const auto b2 = gm::cached_tile(d, key, make, &hit);
  assert_true(hit);
  assert_int_equal(builds, 1);
  assert_true(b1 == b2);
  assert_true(b1 == gm::encode(*gm::make_tile(f, s)));  // the entry is the tile
  // truncated: refused by the firmware's loader, built again
  fs::resize_file(d / (key + ".gmap"), 100);
  const auto b3 = gm::cached_tile(d, key, make, &hit);
  assert_false(hit);
  assert_int_equal(builds, 2);
  assert_true(b3 == b1);
  // the right length, a bad magic
  {
    std::fstream io(d / (key + ".gmap"), std::ios::in | std::ios::out | std::ios::binary);
    io.seekp(0);
    io.write("XXXX", 4);
  }
  (void)gm::cached_tile(d, key, make, &hit);
  assert_false(hit);
  assert_int_equal(builds, 3);
  // no folder: built each time, nothing stored
  const auto b4 = gm::cached_tile(fs::path(), key, make, &hit);
  assert_false(hit);
  assert_int_equal(builds, 4);
  assert_true(b4 == b1);
  std::error_code ec;
  fs::remove_all(d, ec);
}

static void test_concurrent_build_once(void** state) {
  (void)state;
  const ggins::gravity::NormalField f;
  const gm::TileSpec s = spec();
  const fs::path d = temp_dir("conc");
  std::atomic<int> builds{0};
  const auto make = [&] {
    ++builds;
    std::this_thread::sleep_for(std::chrono::milliseconds(300));  // the other asks meanwhile
    return gm::encode(*gm::make_tile(f, s));
  };
  const std::string key = gm::tile_key("normal", s, false);
  std::vector<std::uint8_t> r[2];
  bool hit[2] = {false, false};
  std::thread t0([&] { r[0] = gm::cached_tile(d, key, make, &hit[0]); });
  std::thread t1([&] { r[1] = gm::cached_tile(d, key, make, &hit[1]); });
  t0.join();
  t1.join();
  assert_int_equal(builds.load(), 1);
  assert_true(hit[0] != hit[1]);  // one built, the other waited and read
  assert_true(r[0] == r[1]);
  assert_true(r[0] == gm::encode(*gm::make_tile(f, s)));
  std::error_code ec;
  fs::remove_all(d, ec);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_keys),
      cmocka_unit_test(test_field_id_follows_the_file),
      cmocka_unit_test(test_built_once_and_rebuilt_when_damaged),
      cmocka_unit_test(test_concurrent_build_once),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
