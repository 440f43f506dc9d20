// bus_forger: a local process without the run's key that attacks a running
// host-in-the-loop flight (ggins run or ggins run3d) on its LCM bus, for
// tests/integration/forger_check.py.
//
// It finds the run's hal_sim (the child of --runner-pid), reads the two LCM
// URLs and the channel prefix from hal_sim's command line (public in /proc),
// and the run id from the frames it sees on the bus. When it has seen frame K
// (--start-seq) and output K (alone, or items of the frame and output batches
// of batched lockstep) it publishes, each counted per channel:
//   P+FRAME    frame K copied as K+1..K+3 and as K+100..K+102 (seq patched, the
//              MAC of frame K kept), frame K with a changed reading as K+200 and
//              its MAC zeroed;
//   P+NAV(3D)  output K copied as K+1..K+3 and K+100..K+102, position moved 1 m;
//   P+CONTROL  STOP (twice) and START;
//   P+CONFIG(3D) a configuration for seq 0;
//   P+HAL      hal_sim's status copied with state STOPPED and a later seq;
//   P+REQUEST  RESEND of frame K;
// then a flood (--flood N) of forged frames with random seq and MAC, paced, with
// forged outputs and STOPs mixed in. It prints one JSON line: what it sent per
// channel, the run id, hal_sim's command line and the seqs seen at the start
// and the end of the attack. Exit 0 when the attack was made, 1 otherwise.
#include <dirent.h>
#include <lcm/lcm.h>
#include <poll.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <random>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "ggins/hal_status_t.hpp"
#include "ggins/nav2d_config_t.hpp"
#include "ggins/nav3d_config_t.hpp"
#include "ggins/nav3d_output_t.hpp"
#include "ggins/nav_output_t.hpp"
#include "ggins/run_control_t.hpp"
#include "ggins/sensor_frame_t.hpp"

using json = nlohmann::json;

namespace {

double now_s() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

std::vector<std::string> read_cmdline(const std::string& pid) {
  std::ifstream f("/proc/" + pid + "/cmdline", std::ios::binary);
  std::vector<std::string> a;
  std::string s;
  while (std::getline(f, s, '\0')) a.push_back(s);
  return a;
}

// pid of the hal_sim whose parent is ppid ("" if none yet)
std::string find_hal_sim(long ppid) {
  DIR* d = opendir("/proc");
  if (!d) return "";
  std::string found;
  for (dirent* e; (e = readdir(d)) != nullptr;) {
    const std::string pid = e->d_name;
    if (pid.empty() || pid.find_first_not_of("0123456789") != std::string::npos) continue;
    std::ifstream f("/proc/" + pid + "/stat");
    std::string line;
    if (!std::getline(f, line)) continue;
    const size_t rp = line.rfind(')');
    const size_t lp = line.find('(');
    if (rp == std::string::npos || lp == std::string::npos) continue;
    const std::string comm = line.substr(lp + 1, rp - lp - 1);
    std::istringstream rest(line.substr(rp + 2));
    std::string state;
    long pp = -1;
    rest >> state >> pp;
    if (pp == ppid && comm == "hal_sim") {
      found = pid;
      break;
    }
  }
  closedir(d);
  return found;
}

struct Forger {
  lcm_t* to = nullptr;    // the URL hal_sim listens on (frames, control, configuration)
  lcm_t* from = nullptr;  // the URL the run tool listens on (outputs, status, requests)
  bool mode3d = false;
  std::string prefix = "GGINS_";
  std::optional<int64_t> run_id;
  std::optional<std::vector<uint8_t>> frame_k, out_k;
  int64_t start_seq = 200, last_seen = -1;
  std::map<std::string, int64_t> sent;
  std::vector<uint8_t> buf = std::vector<uint8_t>(65536);
  std::mt19937_64 rng{12345};

  std::string ch(const char* c) const { return prefix + c; }
  std::string ch_nav() const { return prefix + (mode3d ? "NAV3D" : "NAV"); }

  void pub(lcm_t* l, const std::string& c, const uint8_t* d, size_t n) {
    if (lcm_publish(l, c.c_str(), d, static_cast<unsigned>(n)) == 0) ++sent[c];
  }
  template <class M>
  void pub_msg(lcm_t* l, const std::string& c, const M& m) {
    const int n = m.encode(buf.data(), 0, static_cast<int>(buf.size()));
    if (n > 0) pub(l, c, buf.data(), static_cast<size_t>(n));
  }
  void random_mac(uint8_t* mac) {
    for (int i = 0; i < 32; ++i) mac[i] = static_cast<uint8_t>(rng());
  }

  // Frames and outputs are read and forged as bytes (seq, run id, readings and
  // position at fixed offsets of the encoding), so that the forger works
  // whatever the message types' other fields are.
  static int64_t be64(const uint8_t* p) {
    uint64_t v = 0;
    for (int i = 0; i < 8; ++i) v = v << 8 | p[i];
    return static_cast<int64_t>(v);
  }
  static void put_be64(std::vector<uint8_t>& b, size_t off, uint64_t v) {
    for (int i = 0; i < 8; ++i) b[off + static_cast<size_t>(i)] = static_cast<uint8_t>(v >> (56 - 8 * i));
  }
  static void add_double(std::vector<uint8_t>& b, size_t off, double dx) {
    const uint64_t u = static_cast<uint64_t>(be64(b.data() + off));
    double x;
    std::memcpy(&x, &u, sizeof x);
    x += dx;
    uint64_t w;
    std::memcpy(&w, &x, sizeof w);
    put_be64(b, off, w);
  }
  static constexpr size_t kSeq = 16, kRunId = 24;  // after the type hash and utime
  static constexpr size_t kF = 36;                 // sensor_frame_t f[0][0] (after n_acc)
  static constexpr size_t kR = 44;                 // nav_output_t r_i[0], nav3d_output_t r_e[0] (after status, health)

  // A batch (frame_batch_t, nav_output_batch_t, nav3d_output_batch_t: type hash,
  // utime, seq, run_id, n, then n items without type hash, the batch's MAC last):
  // each item as the standalone message it would be (item type hash + item).
  static std::vector<std::vector<uint8_t>> unbatch(const lcm_recv_buf_t* rb, int64_t item_hash) {
    std::vector<std::vector<uint8_t>> out;
    const auto* p = static_cast<const uint8_t*>(rb->data);
    if (rb->data_size < 36 + 32) return out;
    const int64_t n = static_cast<int32_t>(static_cast<uint32_t>(be64(p + 28) & 0xffffffff));
    if (n <= 0) return out;
    const size_t size = (rb->data_size - 36 - 32) / static_cast<size_t>(n);
    for (int64_t i = 0; i < n; ++i) {
      std::vector<uint8_t> m(8);
      put_be64(m, 0, static_cast<uint64_t>(item_hash));
      const uint8_t* it = p + 36 + static_cast<size_t>(i) * size;
      m.insert(m.end(), it, it + size);
      out.push_back(std::move(m));
    }
    return out;
  }
  static void on_frames(const lcm_recv_buf_t* rb, const char*, void* u) {
    for (auto& m : unbatch(rb, ggins::sensor_frame_t::getHash())) take_frame(static_cast<Forger*>(u), m.data(), m.size());
  }
  static void on_navs(const lcm_recv_buf_t* rb, const char*, void* u) {
    auto* f = static_cast<Forger*>(u);
    const int64_t h = f->mode3d ? ggins::nav3d_output_t::getHash() : ggins::nav_output_t::getHash();
    for (auto& m : unbatch(rb, h)) take_nav(f, m.data(), m.size());
  }
  static void on_frame(const lcm_recv_buf_t* rb, const char*, void* u) {
    take_frame(static_cast<Forger*>(u), static_cast<const uint8_t*>(rb->data), rb->data_size);
  }
  static void take_frame(Forger* f, const uint8_t* p, size_t size) {
    if (size < 200) return;
    const int64_t run = be64(p + kRunId);
    if (!f->run_id) f->run_id = run;  // the run id, read from the bus
    if (run != *f->run_id) return;
    const int64_t seq = be64(p + kSeq);
    // progress of the flight (frames come in seq order; our own forged frames come back to us
    // too, and only the rare one that happens to be the next seq moves this)
    if (f->last_seen < 0 || seq == f->last_seen + 1) f->last_seen = seq;
    if (!f->frame_k && seq >= f->start_seq) f->frame_k = std::vector<uint8_t>(p, p + size);
  }
  static void on_nav(const lcm_recv_buf_t* rb, const char*, void* u) {
    take_nav(static_cast<Forger*>(u), static_cast<const uint8_t*>(rb->data), rb->data_size);
  }
  static void take_nav(Forger* f, const uint8_t* p, size_t size) {
    if (f->out_k || !f->frame_k) return;
    if (size < 200 || be64(p + kRunId) != *f->run_id) return;
    if (be64(p + kSeq) >= f->start_seq) f->out_k = std::vector<uint8_t>(p, p + size);
  }

  void pump(double seconds) {
    const double end = now_s() + seconds;
    do {
      pollfd p[2] = {{lcm_get_fileno(to), POLLIN, 0}, {lcm_get_fileno(from), POLLIN, 0}};
      if (poll(p, 2, 1) > 0) {
        if (p[0].revents & POLLIN) lcm_handle(to);
        if (p[1].revents & POLLIN) lcm_handle(from);
      }
    } while (now_s() < end);
  }

  static void patch_seq(std::vector<uint8_t>& b, int64_t seq) { put_be64(b, kSeq, static_cast<uint64_t>(seq)); }

  void attack_frames() {
    const int64_t k = be64(frame_k->data() + kSeq);
    for (int64_t d : {1, 2, 3, 100, 101, 102}) {  // copies of frame K as later frames (its MAC kept)
      std::vector<uint8_t> b = *frame_k;
      patch_seq(b, k + d);
      pub(to, ch("FRAME"), b.data(), b.size());
    }
    std::vector<uint8_t> b = *frame_k;  // a frame with a changed reading, last 32 bytes (the MAC) zeroed
    patch_seq(b, k + 200);
    add_double(b, kF, 1e-3);
    std::fill(b.end() - 32, b.end(), 0);
    pub(to, ch("FRAME"), b.data(), b.size());
  }
  void attack_outputs() {  // output K as later outputs, the position moved 1 m (its MAC kept)
    const int64_t k = be64(out_k->data() + kSeq);
    for (int64_t d : {1, 2, 3, 100, 101, 102}) {
      std::vector<uint8_t> b = *out_k;
      patch_seq(b, k + d);
      add_double(b, kR, 1.0);
      pub(from, ch_nav(), b.data(), b.size());
    }
  }
  void attack_control() {
    ggins::run_control_t c{};
    c.run_id = *run_id;
    c.resend_seq = -1;
    c.utime = 1;
    for (int32_t cmd : {int32_t{ggins::run_control_t::STOP}, int32_t{ggins::run_control_t::START}, int32_t{ggins::run_control_t::STOP}}) {
      c.command = cmd;
      c.seq = 1000 + cmd;
      random_mac(c.mac);
      pub_msg(to, ch("CONTROL"), c);
      pump(0.002);
    }
    if (mode3d) {
      ggins::nav3d_config_t m{};
      m.run_id = *run_id;
      m.dt_us = 10000;
      m.q0_hi[0] = 1;
      random_mac(m.mac);
      pub_msg(to, ch("CONFIG3D"), m);
    } else {
      ggins::nav2d_config_t m{};
      m.run_id = *run_id;
      m.dt_us = 10000;
      m.a_m = m.b_m = 1;
      random_mac(m.mac);
      pub_msg(to, ch("CONFIG"), m);
    }
    ggins::hal_status_t s{};  // hal_sim "stopped", with a later status seq
    s.run_id = *run_id;
    s.seq = 1000000;
    s.state = ggins::hal_status_t::STOPPED;
    s.config_seq = 0;
    random_mac(s.mac);
    pub_msg(from, ch("HAL"), s);
    ggins::run_control_t r{};
    r.run_id = *run_id;
    r.command = ggins::run_control_t::RESEND;
    r.resend_seq = start_seq;
    random_mac(r.mac);
    pub_msg(from, ch("REQUEST"), r);
  }
  void flood(int n) {
    const int64_t k = be64(frame_k->data() + kSeq);
    for (int i = 0; i < n; ++i) {
      std::vector<uint8_t> m = *frame_k;  // frames near the flight's seq, changed readings, random last 32 bytes
      patch_seq(m, k + static_cast<int64_t>(rng() % 2000));
      add_double(m, kF + 5 * 8, 1e-6 * static_cast<double>(i + 1));
      for (size_t j = m.size() - 32; j < m.size(); ++j) m[j] = static_cast<uint8_t>(rng());
      pub(to, ch("FRAME"), m.data(), m.size());
      if (i % 20 == 0 && out_k) {  // outputs and a STOP now and then
        std::vector<uint8_t> b = *out_k;
        patch_seq(b, k + static_cast<int64_t>(rng() % 2000));
        for (size_t j = b.size() - 32; j < b.size(); ++j) b[j] = static_cast<uint8_t>(rng());
        pub(from, ch_nav(), b.data(), b.size());
      }
      if (i % 200 == 0) {
        ggins::run_control_t c{};
        c.run_id = *run_id;
        c.command = ggins::run_control_t::STOP;
        c.seq = 5000 + i;
        c.resend_seq = -1;
        random_mac(c.mac);
        pub_msg(to, ch("CONTROL"), c);
      }
      if (i % 25 == 24) pump(0.0015);  // paced: nothing is lost in socket buffers or LCM queues
    }
  }
};

}  // namespace

int main(int argc, char** argv) {
  long runner_pid = -1;
  int flood_n = 2000;
  double timeout = 20;
  Forger f;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto val = [&]() -> std::string { return i + 1 < argc ? argv[++i] : ""; };
    if (a == "--runner-pid") runner_pid = std::stol(val());
    else if (a == "--mode") f.mode3d = val() == "3d";
    else if (a == "--start-seq") f.start_seq = std::stoll(val());
    else if (a == "--flood") flood_n = std::stoi(val());
    else if (a == "--timeout") timeout = std::stod(val());
    else {
      std::fprintf(stderr, "usage: bus_forger --runner-pid P [--mode 2d|3d] [--start-seq K] [--flood N] [--timeout S]\n");
      return 2;
    }
  }
  const double t_end = now_s() + timeout;
  json out;
  std::string hal;
  while ((hal = find_hal_sim(runner_pid)).empty()) {
    if (now_s() > t_end) {
      std::printf("%s\n", json{{"error", "no hal_sim child of the runner"}}.dump().c_str());
      return 1;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  const std::vector<std::string> cmd = read_cmdline(hal);
  std::string url_to, url_from;  // hal_sim's --lcm-url (it listens) and --lcm-url-out (it publishes)
  for (size_t i = 0; i + 1 < cmd.size(); ++i) {
    if (cmd[i] == "--lcm-url") url_to = cmd[i + 1];
    if (cmd[i] == "--lcm-url-out") url_from = cmd[i + 1];
    if (cmd[i] == "--prefix") f.prefix = cmd[i + 1];
  }
  out["hal_sim_cmdline"] = cmd;
  f.to = lcm_create(url_to.c_str());
  f.from = url_from.empty() || url_from == url_to ? nullptr : lcm_create(url_from.c_str());
  if (!f.to || !f.from) {
    out["error"] = "cannot open the run's two LCM URLs (a run with one URL for both directions is not supported)";
    std::printf("%s\n", out.dump().c_str());
    return 1;
  }
  lcm_subscription_set_queue_capacity(lcm_subscribe(f.to, f.ch("FRAME").c_str(), Forger::on_frame, &f), 100000);
  lcm_subscription_set_queue_capacity(lcm_subscribe(f.from, f.ch_nav().c_str(), Forger::on_nav, &f), 100000);
  // batched lockstep: frames and outputs travel in batches
  lcm_subscription_set_queue_capacity(lcm_subscribe(f.to, f.ch("FRAMES").c_str(), Forger::on_frames, &f), 100000);
  lcm_subscription_set_queue_capacity(lcm_subscribe(f.from, (f.ch_nav() + "S").c_str(), Forger::on_navs, &f), 100000);
  while (!(f.frame_k && f.out_k)) {
    f.pump(0.005);
    if (now_s() > t_end) {
      out["error"] = "did not see frame and output K";
      std::printf("%s\n", out.dump().c_str());
      return 1;
    }
  }
  const int64_t seen_at_start = f.last_seen;
  f.attack_frames();
  f.pump(0.002);
  f.attack_outputs();
  f.pump(0.002);
  f.attack_control();
  f.pump(0.002);
  f.flood(flood_n);
  f.pump(0.05);
  out["run_id"] = *f.run_id;
  out["sent"] = f.sent;
  out["seq_at_start"] = seen_at_start;
  out["seq_at_end"] = f.last_seen;
  int64_t total = 0;
  for (const auto& [c, n] : f.sent) total += n;
  out["sent_total"] = total;
  std::printf("%s\n", out.dump().c_str());
  lcm_destroy(f.to);
  lcm_destroy(f.from);
  return 0;
}
