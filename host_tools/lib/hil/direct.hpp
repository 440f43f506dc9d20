// --direct: the flight stepped in this process, through exactly what hal_sim
// does with the messages (hal_sim/hal_lcm.c, hal_lcm3d.c): the configuration
// and every frame as encoded LCM messages, decoded, converted to the
// firmware's structs, one gg_nav2d_task_cycle / gg_nav3d_task_cycle per frame
// through an in-process HAL (CLOCK_MONOTONIC cycle counter, as hal_sim's), the
// output converted to its message. Only the bus is missing, so the numbers are
// those of a run over LCM, bit for bit: the reference for the transport's cost.
#pragma once

#include <cstdint>
#include <memory>
#include <string>

#include "link.hpp"

namespace ggins::hil {

class DirectImpl;

template <class Task>
class Direct {
 public:
  // Throws Fail if the firmware refuses the configuration. timed: the HAL's cycle counter is
  // CLOCK_MONOTONIC (as hal_sim's), so each step's cycles are measured and a step longer than the
  // frame period sets GG_HEALTH_DEADLINE; untimed: no cycle counter (cycles 0, never DEADLINE),
  // for a computer stepped beside the flight only for its numbers (the unaided reference), whose
  // wall time is the host's scheduling, not the flight's.
  explicit Direct(const typename Task::Config& cfg, bool timed = true);
  ~Direct();
  Direct(const Direct&) = delete;
  Direct& operator=(const Direct&) = delete;
  // One firmware step on frame message m; its output message (republished 0, mac zero).
  typename Task::Out step(const ggins::sensor_frame_t& m);
  // A gradient map tile file (gmap format) into the computer's map storage, as
  // hal_sim --map FILE (hal_sim/hal_map.h); throws Fail naming the file.
  void add_map(const std::string& path);

 private:
  std::unique_ptr<DirectImpl> impl_;
};

template <>
Direct<Task2D>::Direct(const ggins::nav2d_config_t& cfg, bool timed);
template <>
Direct<Task3D>::Direct(const ggins::nav3d_config_t& cfg, bool timed);
template <>
ggins::nav_output_t Direct<Task2D>::step(const ggins::sensor_frame_t& m);
template <>
ggins::nav3d_output_t Direct<Task3D>::step(const ggins::sensor_frame_t& m);
template <>
void Direct<Task2D>::add_map(const std::string& path);
template <>
void Direct<Task3D>::add_map(const std::string& path);
template <>
Direct<Task2D>::~Direct();
template <>
Direct<Task3D>::~Direct();

}  // namespace ggins::hil
