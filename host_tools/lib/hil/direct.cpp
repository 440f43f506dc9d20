// See direct.hpp.
#include "direct.hpp"

#include <time.h>

#include <cstring>
#include <vector>

extern "C" {
#include "ggins/hal.h"
#include "ggins/nav2d.h"
#include "ggins/nav3d.h"
}
#include "ggins_nav2d_config_t.h"
#include "ggins_nav3d_config_t.h"
#include "ggins_nav3d_output_t.h"
#include "ggins_nav_output_t.h"
#include "ggins_sensor_frame_t.h"
#include "hal_lcm.h"
#include "hal_lcm3d.h"
#include "hal_map.h"

namespace ggins::hil {

class DirectImpl {
 public:
  gg_nav2d_t nav2{};
  gg_nav3d_t nav3{};
  gg_hal_t hal{};
  gg_frame_t frame{};
  bool have_frame = false;
  ggins_nav_output_t out2{};
  ggins_nav3d_output_t out3{};
  std::vector<uint8_t> buf = std::vector<uint8_t>(1 << 16);
  hal_map_store_t maps{};  // the computer's map storage (hal_sim/hal_map.h)

  explicit DirectImpl(bool timed) {
    hal_map_init(&maps);
    hal.ctx = this;
    hal.read_frame = read_frame;
    hal.write_output = write_output;
    hal.write_output3d = write_output3d;
    if (timed) {
      hal.cycle_count = cycle_count;
      hal.cycles_per_second = 1000000000u;
    }
  }
  ~DirectImpl() { hal_map_free(&maps); }
  DirectImpl(const DirectImpl&) = delete;
  DirectImpl& operator=(const DirectImpl&) = delete;
  void add_map(const std::string& path) {
    char err[512];
    if (hal_map_load(&maps, path.c_str(), err, sizeof err) != 0) throw Fail("map tile " + path + ": " + err);
    hal.map = &maps.ops;
  }
  static gg_status_t read_frame(void* ctx, gg_frame_t* f) {
    auto* d = static_cast<DirectImpl*>(ctx);
    if (!d->have_frame) return GG_ERR_NO_DATA;
    *f = d->frame;
    d->have_frame = false;
    return GG_OK;
  }
  static gg_status_t write_output(void* ctx, const gg_nav_output_t* o) {
    ggins_output_to_lcm(o, 0, &static_cast<DirectImpl*>(ctx)->out2);
    return GG_OK;
  }
  static gg_status_t write_output3d(void* ctx, const struct gg_nav3d_output_s* o) {
    ggins_output3d_to_lcm(o, 0, &static_cast<DirectImpl*>(ctx)->out3);
    return GG_OK;
  }
  static uint32_t cycle_count(void*) {  // as hal_sim's: CLOCK_MONOTONIC ns truncated to uint32
    timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return static_cast<uint32_t>(static_cast<uint64_t>(ts.tv_sec) * 1000000000ull + static_cast<uint64_t>(ts.tv_nsec));
  }
  // The frame message as hal_sim receives it: encoded, decoded, converted.
  void load_frame(const ggins::sensor_frame_t& m, int64_t run_id) {
    ggins::sensor_frame_t c = m;
    c.run_id = run_id;
    const int n = c.encode(buf.data(), 0, static_cast<int>(buf.size()));
    ggins_sensor_frame_t cm;
    if (n < 0 || ggins_sensor_frame_t_decode(buf.data(), 0, n, &cm) != n) throw Fail("--direct: frame encoding failed");
    ggins_frame_from_lcm(&cm, &frame);
    have_frame = true;
  }
  // A C message to its C++ twin (same encoding).
  template <class Cpp, class C, class Enc>
  Cpp to_cpp(const C& c, Enc enc) {
    const int n = enc(buf.data(), 0, static_cast<int>(buf.size()), &c);
    Cpp m{};
    if (n < 0 || m.decode(buf.data(), 0, n) != n) throw Fail("--direct: output encoding failed");
    return m;
  }
};

template <>
Direct<Task2D>::Direct(const ggins::nav2d_config_t& cfg, bool timed) : impl_(std::make_unique<DirectImpl>(timed)) {
  const int n = cfg.encode(impl_->buf.data(), 0, static_cast<int>(impl_->buf.size()));
  ggins_nav2d_config_t cm;
  if (n < 0 || ggins_nav2d_config_t_decode(impl_->buf.data(), 0, n, &cm) != n) throw Fail("--direct: configuration encoding failed");
  gg_nav2d_config_t c;
  ggins_config_from_lcm(&cm, &c);
  ggins_nav2d_config_t_decode_cleanup(&cm);
  const gg_status_t st = gg_nav2d_init(&impl_->nav2, &c);
  if (st != GG_OK) throw Fail("the firmware refused the configuration (2-D init status " + std::to_string(st) + ")");
}

template <>
Direct<Task3D>::Direct(const ggins::nav3d_config_t& cfg, bool timed) : impl_(std::make_unique<DirectImpl>(timed)) {
  const int n = cfg.encode(impl_->buf.data(), 0, static_cast<int>(impl_->buf.size()));
  ggins_nav3d_config_t cm;
  if (n < 0 || ggins_nav3d_config_t_decode(impl_->buf.data(), 0, n, &cm) != n) throw Fail("--direct: configuration encoding failed");
  gg_nav3d_config_t c;
  ggins_config3d_from_lcm(&cm, &c);
  ggins_nav3d_config_t_decode_cleanup(&cm);
  const gg_status_t st = gg_nav3d_init(&impl_->nav3, &c);
  if (st != GG_OK) throw Fail("the firmware refused the configuration (3-D init status " + std::to_string(st) + ")");
}

template <>
void Direct<Task2D>::add_map(const std::string& path) {
  impl_->add_map(path);
}
template <>
void Direct<Task3D>::add_map(const std::string& path) {
  impl_->add_map(path);
}

template <>
Direct<Task2D>::~Direct() = default;
template <>
Direct<Task3D>::~Direct() = default;

template <>
ggins::nav_output_t Direct<Task2D>::step(const ggins::sensor_frame_t& m) {
  impl_->load_frame(m, m.run_id);
  gg_nav2d_task_cycle(&impl_->nav2, &impl_->hal);
  ggins::nav_output_t o = impl_->to_cpp<ggins::nav_output_t>(impl_->out2, ggins_nav_output_t_encode);
  o.run_id = m.run_id;
  return o;
}

template <>
ggins::nav3d_output_t Direct<Task3D>::step(const ggins::sensor_frame_t& m) {
  impl_->load_frame(m, m.run_id);
  gg_nav3d_task_cycle(&impl_->nav3, &impl_->hal);
  ggins::nav3d_output_t o = impl_->to_cpp<ggins::nav3d_output_t>(impl_->out3, ggins_nav3d_output_t_encode);
  o.run_id = m.run_id;
  return o;
}


}  // namespace ggins::hil
