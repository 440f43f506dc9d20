// ggins run3d (ggins-run3d): fly one 3-D scenario (scenarios/3d-*.toml,
// host_tools/lib/truth3d) against the 3-D firmware (nav3d.h): the front-end of the
// runner (hil_common/runner.hpp) with the 3-D task's model. Host-in-the-loop
// over LCM through hal_sim (default) or in process (--direct); writes the
// report (hil_common/report.hpp: summary.json), timeseries.csv, errors.png,
// run.lcmlog.
//
// LCM protocol (hal_sim in 3-D mode, see hal_sim --help): nav3d_config_t on
// P+CONFIG3D until hal_sim reports CONFIGURED, START on P+CONTROL, then the
// shared transport (hil_common/link.hpp): frame batches on P+FRAMES, output
// batches (nav3d_output_batch_t) on P+NAV3DS, negative acknowledgements on
// P+NAK, truth3d_t on P+TRUTH3D (decimated), STOP.
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <Eigen/Cholesky>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "compare3d.hpp"
#include "ggins/coldatom/route_tiles.hpp"
#include "ggins/truth3d/aids3d.hpp"
#include "ggins/truth3d/coldatom3d.hpp"
#include "ggins/truth3d/config3d.hpp"
#include "ggins/nav3d_config_t.hpp"
#include "ggins/nav3d_output_t.hpp"
#include "ggins/sensor_frame_t.hpp"
#include "ggins/truth3d_t.hpp"
#include "integrity.hpp"
#include "runner.hpp"
#include "field_map.hpp"
#include "gravimetry_record.hpp"
#include "map_coverage.hpp"
#include "map_storage.hpp"
#include "pf3d.hpp"

namespace fs = std::filesystem;
using json = nlohmann::json;
using ggins::truth3d::Real;
using ggins::truth3d::Vec3;
using ggins::truth3d::Mat3;
using ggins::hil::Fail;
using ggins::hil::hilo;
using ggins::hil::MaxFinal;
using ggins::hil::wall_us;

namespace {

// The 3-D task for the runner: frames from the 3-D truth generator, the
// firmware configuration, the evaluation of every output against the truth.
class Model3D {
 public:
  using Task = ggins::hil::Task3D;

  // map_cache: the tile cache's folder for map_from_field (gmap/tile_cache.hpp; empty: none)
  Model3D(const ggins::hil::RunOptions& o, const ggins::truth3d::Scenario3& sc, bool reference,
          const std::filesystem::path& out, const std::filesystem::path& map_cache)
      : opt_(o), sc_(sc), gen_(sc), reference_(reference && (sc.aid_ukf.enabled || sc.aid_pf.enabled)) {
    map_cache_ = map_cache;
    // the computer's map storage (map_storage.hpp): the map aid's tile files, then the
    // directory of the cold-atom aid's Gamma_zz tiles (pf3d.hpp)
    using ggins::run3d::MapSource;
    using ggins::run3d::SourceKind;
    const double t_maps = ggins::hil::mono_s();
    if (sc_.aid_ukf.enabled && sc_.aid_ukf.map_from_field) {  // tiles of the scenario's own field (field_map.hpp)
      field_map(ggins::run3d::field_tiles(sc_.aid_ukf), "the map aid's tiles", out / "maps" / "aid_ukf");
    } else if (sc_.aid_ukf.enabled) {
      for (const auto& p : ggins::truth3d::aid_ukf_map_paths(sc_.aid_ukf, sc_.source))
        sources_.push_back({fs::absolute(p).lexically_normal().string(), SourceKind::kFile});
    }
    if (sc_.aid_pf.enabled && sc_.aid_pf.map_from_field && sc_.coldatom.gzz_map == "field") {
      // Gamma_zz tiles of the scenario's field along the route (field_map.hpp)
      field_map(ggins::run3d::field_tiles(sc_.aid_pf), "the cold-atom aid's Gamma_zz tiles", out / "maps" / "aid_pf");
    } else if (sc_.aid_pf.enabled && sc_.aid_pf.map_from_field) {  // Gamma_zz tiles of the sensor's route map (route_tiles.hpp)
      if (!opt_.quiet) std::fprintf(stderr, "%s: the cold-atom aid's tiles from the sensor's route map ...\n", opt_.tool.c_str());
      const fs::path dir = fs::absolute(out / "maps" / "aid_pf").lexically_normal();
      try {
        const auto map = ggins::truth3d::make_gzz_map3(sc_.coldatom);
        std::error_code ec;
        fs::remove_all(dir, ec);
        ggins::coldatom::write_route_tiles(*map, sc_.aid_pf.map_step_m, sc_.aid_pf.map_tile_spacing_m, dir.string());
      } catch (const std::exception& e) {
        throw Fail(std::string("aid_pf.map_from_field: ") + e.what());
      }
      sources_.push_back({dir.string(), SourceKind::kDir});
    } else if (sc_.aid_pf.enabled) {
      sources_.push_back(
          {fs::absolute(ggins::truth3d::aid_pf_map_dir(sc_.aid_pf, sc_.source)).lexically_normal().string(), SourceKind::kDir});
    }
    map_build_s_ = ggins::hil::mono_s() - t_maps;
    if (sources_.size() > static_cast<size_t>(ggins::run3d::kMaxSources))
      throw Fail("the map storage has " + std::to_string(sources_.size()) + " sources; the configuration records " +
                 std::to_string(ggins::run3d::kMaxSources) + " at most (put the tiles into a directory)");
    for (const auto& src : sources_) {
      ggins::run3d::SourceRecord r;
      if (const std::string why = ggins::run3d::read_source(src, r); !why.empty())
        throw Fail("map storage: " + std::string(ggins::run3d::kind_name(src.kind)) + " " + src.path + ": " + why);
      maps_.insert(maps_.end(), r.files.begin(), r.files.end());
      records_.push_back(r);
    }
    if (maps_.size() > static_cast<size_t>(ggins::run3d::kMaxTiles))
      throw Fail("the map storage would hold " + std::to_string(maps_.size()) + " tiles; it holds " +
                 std::to_string(ggins::run3d::kMaxTiles) + " at most");
    // the route against the storage, as each aid will ask it (map_coverage.hpp)
    if (sc_.aid_ukf.enabled || sc_.aid_pf.enabled) {
      const auto pts = ggins::run3d::route_samples(gen_, sc_.duration_s);
      auto check = [&](const ggins::truth3d::Integrity3& a, uint32_t kind, const char* aid, const char* table,
                       ggins::run3d::Coverage& cov) {
        try {
          cov = ggins::run3d::route_coverage(pts, maps_, kind);
        } catch (const std::exception& e) {
          throw Fail(std::string("map storage: ") + e.what());
        }
        if (cov.complete()) return;
        if (a.map_uncovered != "fly")
          throw Fail(std::string("the map storage does not cover the route for the ") + aid + " (" +
                         std::to_string(cov.samples - cov.covered) + " of " + std::to_string(cov.samples) +
                         " route samples, every " + std::to_string(static_cast<int>(ggins::run3d::kCoverageStepS)) +
                         " s):" + cov.text() + "\ngive tiles that cover it, or set " + table +
                         ".map_uncovered = \"fly\" to fly it with the aid off there",
                     ggins::cli::kExitBadArgs);
        if (!opt_.quiet)
          std::fprintf(stderr, "%s: the %s flies %zu uncovered stretches with no update (%s.map_uncovered = \"fly\"):%s\n",
                       opt_.tool.c_str(), aid, cov.gaps.size(), table, cov.text().c_str());
      };
      if (sc_.aid_ukf.enabled) check(sc_.aid_ukf, GG_GMAP_KIND_TENSOR, "map aid", "aid_ukf", mm_cov_);
      if (sc_.aid_pf.enabled) check(sc_.aid_pf, GG_GMAP_KIND_GZZ, "particle filter", "aid_pf", pf_cov_);
    }
  }

  // map_from_field: an aid's tiles of the scenario's field along the route, written into
  // dir, which becomes a source of the map storage; through the tile cache where the field
  // is an EGM96 model (its file's digest names it)
  void field_map(const ggins::run3d::FieldTiles& ft, const char* what, const fs::path& out_dir) {
    if (!opt_.quiet) std::fprintf(stderr, "%s: %s from the scenario's field ...\n", opt_.tool.c_str(), what);
    const fs::path dir = fs::absolute(out_dir).lexically_normal();
    const bool egm = sc_.gravity.model == "egm96";
    const int nmax = egm ? static_cast<int>(sc_.sh.nmax) : 0;  // tile metadata
    const double t0 = ggins::hil::mono_s();
    const bool tty = isatty(2) != 0 && opt_.progress != "off";
    try {
      ggins::run3d::MapBuild mb;
      mb.cache_dir = map_cache_;
      if (egm && !map_cache_.empty()) mb.field_id = ggins::gmap::egm96_field_id(ggins::truth3d::egm96_path(sc_), nmax, false);
      if (!opt_.quiet && tty)
        mb.progress = [&](int done, int total) {
          const int w = 30, k = total > 0 ? w * done / total : w;
          std::fprintf(stderr, "\r  maps [%.*s%*s] %d / %d tiles  %.1f s", k, "##############################", w - k,
                       "", done, total, ggins::hil::mono_s() - t0);
          if (done == total) std::fprintf(stderr, "\n");
        };
      const ggins::run3d::FieldMap fm = ggins::run3d::build_field_map(gen_, sc_.duration_s, nmax, ft, dir, mb);
      if (!opt_.quiet)
        std::fprintf(stderr,
                     "%s: %d tiles (%d built, %d from the cache%s): %d footprints, up to %d height layers over %.0f .. "
                     "%.0f m (%.1f s)\n",
                     opt_.tool.c_str(), fm.tiles, fm.built, fm.cache_hits,
                     fm.cached ? (" " + map_cache_.string()).c_str() : ", not cached", fm.footprints, fm.layers_max,
                     fm.h_min_m, fm.h_max_m, ggins::hil::mono_s() - t0);
      map_tiles_built_ += fm.built;
      map_tiles_cached_ += fm.cache_hits;
    } catch (const std::exception& e) {
      throw Fail(e.what(), ggins::cli::kExitBadArgs);
    }
    sources_.push_back({dir.string(), ggins::run3d::SourceKind::kDir});
  }

  int64_t n_steps() const { return gen_.n_steps(); }
  int64_t dt_us() const { return gen_.dt_us(); }
  double rate_hz() const { return sc_.rate_hz; }
  double duration_s() const { return sc_.duration_s; }
  std::string name() const { return sc_.name; }
  std::string source() const { return sc_.source; }
  std::string description() const { return sc_.description; }
  uint64_t scenario_id() const { return 0; }
  std::vector<std::string> maps() const { return maps_; }
  ggins::hil::Faults faults() const {
    ggins::hil::Faults f;
    f.drop = opt_.drop.value_or(0);
    f.dup = opt_.dup.value_or(0);
    f.reorder = opt_.reorder.value_or(0);
    f.drop_output = opt_.drop_output.value_or(0);
    f.garbage = opt_.garbage.value_or(0);
    f.conflict = opt_.conflict;
    if (opt_.fault_seed) f.seed = *opt_.fault_seed;
    return f;
  }
  std::string truth_channel() const { return opt_.prefix + "TRUTH3D"; }
  int64_t truth_published() const { return truth_published_; }
  double progress_error_m() const { return pos_.final; }

  ggins::nav3d_config_t config();
  void begin(const fs::path& out, ggins::hil::LinkBase* link, int64_t run_id);
  ggins::sensor_frame_t frame(int64_t k);
  void take(const ggins::nav3d_output_t& m, bool latest);
  void end() {
    csv_.close();
    if (ep_csv_.is_open()) ep_csv_.close();
    if (gravrec_) gravrec_->close();
  }
  void report(json& s);
  static std::string final_line(const json& s);
  // The plots' envelopes: with an aid on, the covariance the task itself outputs (the aid's);
  // without, the 3-D error model on the same trajectory (ggins covariance3d, covariance/).
  static void before_plots(const ggins::hil::RunOptions& o, const std::filesystem::path& out, const json& summary);

 private:
  void consume(int64_t k, const ggins::truth3d::Truth3& t, const gg_nav3d_output_t& o, const double* sig_pos);
  static void from_lcm(const ggins::nav3d_output_t& m, gg_nav3d_output_t& o);
  json aid_ukf_block() const;
  void aid_epoch(const ggins::nav3d_output_t& m, bool accepted);

  const ggins::hil::RunOptions& opt_;
  ggins::truth3d::Scenario3 sc_;
  ggins::truth3d::Generator3 gen_;
  std::vector<ggins::run3d::MapSource> sources_;     // the map storage's sources (map_storage.hpp)
  std::vector<ggins::run3d::SourceRecord> records_;  // and their records
  std::vector<std::string> maps_;                    // its tile files in load order
  ggins::run3d::Coverage mm_cov_, pf_cov_;           // the route's coverage for each aid (map_coverage.hpp)
  ggins::hil::LinkBase* link_ = nullptr;  // over LCM (none with --direct)
  int64_t run_id_ = 0;
  int64_t n_ = 0, csv_every_ = 1, truth_every_ = 1, truth_published_ = 0;
  double map_build_s_ = 0;           // wall time of building the maps before the flight, s
  std::filesystem::path map_cache_;  // the tile cache's folder (empty: none)
  int map_tiles_built_ = 0, map_tiles_cached_ = 0;  // map_from_field tiles computed, taken from the cache
  int64_t aid_closed_ = 0;           // map-aid epochs closed (updated or rejected)
  double aid_nis_sum_ = 0;           // sum of their NIS
  ggins::nav3d_output_t aid_last_{};  // the output of the last step flown (the aid's counters)
  ggins::run3d::PfReport3 pf_;        // the cold-atom aid's counters and consistency (pf3d.hpp)
  ggins::hil::IntegrityTrack mm_integ_, pf_integ_;  // each aid's integrity verdict (integrity.hpp)
  bool pf_on_ = false;
  // the ellipse-fit baseline on the weighed shots (pf3d.hpp): the pairs of the frames by step
  std::unique_ptr<ggins::run3d::ShotBaseline3> shots_;
  struct Pair {
    int32_t status = GG_SENSOR_ABSENT;  // ca_status
    double s0 = 0, s1 = 0;              // ca_s
  };
  std::vector<Pair> ca_ring_;  // the cold-atom pair of each step (ring, as truth_ring_)
  static constexpr int64_t kTruthRing = 8192;  // > the transport's largest window (4096)
  std::vector<ggins::truth3d::Truth3> truth_ring_;
  // The unaided reference: the same task with every aid off, stepped in this process on the
  // same sensor frames as they are made (whatever the transport does to the flown task's), so
  // that aided and unaided solutions of one flight sit side by side in the report and the CSV.
  bool reference_ = false;
  ggins::nav3d_config_t ref_cfg_{};
  std::unique_ptr<ggins::hil::Direct<ggins::hil::Task3D>> ref_;
  int64_t ref_next_ = 0, ref_rejected_ = 0;
  uint32_t ref_health_or_ = 0;
  std::vector<std::array<double, 4>> ref_ring_;  // its position error N, E, D, |dr| per step (ring)
  MaxFinal ref_pos_, ref_vel_, ref_att_, ref_grav_;
  std::array<double, 3> ref_fpos_n_{};
  // statistics
  MaxFinal pos_, vel_, att_, grav_, gam_e_, gam_b_, hgt_, par_asym_, par_trace_, wdot_;
  std::array<double, 3> fpos_n_{}, fvel_n_{}, fatt_n_{}, fg_n_{};
  std::ofstream csv_;
  std::ofstream ep_csv_;                  // aid_epochs.csv (map aid on)
  std::unique_ptr<ggins::run3d::GravimetryRecord> gravrec_;  // gravimetry_raw.csv (gravimetry_record.hpp)
  std::array<double, 3> nees_sum_{};      // position, velocity, attitude NEES summed over epochs
  int64_t nees_n_ = 0;
};

// NEES of one 3 x 3 block: d^T P^-1 d with P from its upper triangle (xx yy zz xy xz yz);
// NaN if P is not positive definite.
double nees3(const double* p6, const ggins::truth3d::Vec3& d) {
  Eigen::Matrix3d P;
  P << p6[0], p6[3], p6[4], p6[3], p6[1], p6[5], p6[4], p6[5], p6[2];
  const Eigen::LLT<Eigen::Matrix3d> llt(P);
  if (llt.info() != Eigen::Success) return std::nan("");
  const Eigen::Vector3d dd(static_cast<double>(d(0)), static_cast<double>(d(1)), static_cast<double>(d(2)));
  return dd.dot(llt.solve(dd));
}

// One closed epoch of the map aid against the truth of its step: the aid's error state is
// x = true - estimate in ECI (aid_mmukf.h), so the errors are formed the same way, after the
// correction the step applied, and weighed with the covariance the step reports.
void Model3D::aid_epoch(const ggins::nav3d_output_t& m, bool accepted) {
  const ggins::truth3d::Truth3& t = truth_ring_[static_cast<size_t>(m.seq % kTruthRing)];
  using ggins::truth3d::Vec3;
  const double w_ie = static_cast<double>(ggins::truth3d::kOmegaIe);  // WGS-84, the rate the task uses by default
  Vec3 r, v;
  for (int i = 0; i < 3; ++i) {
    r(i) = static_cast<ggins::truth3d::Real>(m.r_e[i]) + static_cast<ggins::truth3d::Real>(m.r_e_lo[i]);
    v(i) = m.v_e[i];
  }
  const Vec3 w(0, 0, w_ie);
  const Vec3 dr_i = t.s.C_e_i * (t.s.r_e - r);
  const Vec3 dv_i = t.s.v_i - t.s.C_e_i * (v + w.cross(r));
  const Mat3 Cn = ggins::run3d::dcm_from_quat(m.q_b_e);
  const Vec3 psi_i = t.s.C_e_i * ggins::run3d::rotation_vector(t.s.C_b_e * Cn.transpose());
  const double ne[3] = {nees3(&m.mm_pcov[0], dr_i), nees3(&m.mm_pcov[6], dv_i), nees3(&m.mm_pcov[12], psi_i)};
  if (accepted && std::isfinite(ne[0]) && std::isfinite(ne[1]) && std::isfinite(ne[2])) {
    for (int b = 0; b < 3; ++b) nees_sum_[static_cast<size_t>(b)] += ne[b];
    ++nees_n_;
  }
  const ggins::run3d::Errors3 e = ggins::run3d::compare(t, [&] {
    gg_nav3d_output_t o;
    from_lcm(m, o);
    return o;
  }());
  ep_csv_ << m.t_s << "," << m.seq << "," << m.mm_epochs << "," << (accepted ? 1 : 0) << "," << m.mm_n_avg << ","
          << m.mm_nis;
  for (int j = 0; j < 6; ++j) ep_csv_ << "," << m.mm_innov[j] * 1e9;
  for (int j = 0; j < 3; ++j) ep_csv_ << "," << (accepted ? m.mm_corr_m[j] : 0.0);
  for (int j = 0; j < 3; ++j) ep_csv_ << "," << static_cast<double>(e.dr_n(j));
  for (int j = 0; j < 3; ++j) ep_csv_ << "," << std::sqrt(m.mm_pcov[j]);
  ep_csv_ << "," << ne[0] << "," << ne[1] << "," << ne[2];
  for (int j = 0; j < 6; ++j) ep_csv_ << "," << m.mm_bias[j];
  ep_csv_ << "\n";
}

void Model3D::begin(const fs::path& out, ggins::hil::LinkBase* link, int64_t run_id) {
  link_ = link;
  run_id_ = run_id;
  n_ = gen_.n_steps();
  truth_ring_.resize(static_cast<size_t>(kTruthRing));
  if (reference_) {
    // untimed: its step times are this process's scheduling between frames, not the flight's
    // (the flight's own steps carry the DEADLINE check)
    ref_ = std::make_unique<ggins::hil::Direct<ggins::hil::Task3D>>(ref_cfg_, false);
    ref_ring_.resize(static_cast<size_t>(kTruthRing));
  }
  csv_every_ = std::max<int64_t>(1, std::llround(sc_.rate_hz / (opt_.csv_rate ? *opt_.csv_rate : sc_.csv_rate_hz)));
  const double truth_rate = opt_.truth_rate.value_or(10.0);
  truth_every_ = truth_rate > 0 ? std::max<int64_t>(1, std::llround(sc_.rate_hz / truth_rate)) : 1;
  csv_.open(out / "timeseries.csv");
  if (!csv_) throw Fail("cannot write " + (out / "timeseries.csv").string());
  gravrec_ = std::make_unique<ggins::run3d::GravimetryRecord>(gen_.field(), ggins::run3d::gravimetry_model(sc_),
                                                              1.0 / sc_.rate_hz, sc_.nav_gravity == "model");
  if (!gravrec_->open((out / "gravimetry_raw.csv").string()))
    throw Fail("cannot write " + (out / "gravimetry_raw.csv").string());
  csv_ << "t_s,seq,lat_deg,lon_deg,h_m,roll_deg,pitch_deg,yaw_deg,speed_mps,nav_lat_deg,nav_lon_deg,nav_h_m,"
          "err_n_m,err_e_m,err_d_m,err_r_m,err_vn_mps,err_ve_mps,err_vd_mps,err_v_mps,"
          "att_err_n_rad,att_err_e_rad,att_err_d_rad,att_err_rad,err_gn_mps2,err_ge_mps2,err_gd_mps2,err_g_mps2,"
          "err_gamma_e_E,err_gamma_b_E,err_h_m,parity_x_radps2,parity_y_radps2,parity_z_radps2,parity_trace_ps2,"
          "baro_innov_m,a_c_mps2,status,health,health_bits";
  if (sc_.aid_ukf.enabled) csv_ << ",aid_sig_r_x_m,aid_sig_r_y_m,aid_sig_r_z_m,aid_sig_r_rss_m";
  if (reference_) csv_ << ",unaided_err_n_m,unaided_err_e_m,unaided_err_d_m,unaided_err_r_m";
  csv_ << "\n";
  if (sc_.aid_ukf.enabled) {  // one row per closed epoch of the map aid
    ep_csv_.open(out / "aid_epochs.csv");
    if (!ep_csv_) throw Fail("cannot write " + (out / "aid_epochs.csv").string());
    ep_csv_ << std::setprecision(10);
    ep_csv_ << "t_s,seq,epoch,accepted,n_avg,nis,innov_xx_E,innov_yy_E,innov_zz_E,innov_xy_E,innov_xz_E,innov_yz_E,"
               "corr_x_eci_m,corr_y_eci_m,corr_z_eci_m,err_n_m,err_e_m,err_d_m,sig_x_eci_m,sig_y_eci_m,sig_z_eci_m,"
               "nees_pos,nees_vel,nees_att,bias_w_x_radps,bias_w_y_radps,bias_w_z_radps,bias_f_x_mps2,"
               "bias_f_y_mps2,bias_f_z_mps2\n";
  }
}

void Model3D::from_lcm(const ggins::nav3d_output_t& m, gg_nav3d_output_t& o) {
  std::memset(&o, 0, sizeof o);
  o.utime = m.utime;
  o.seq = m.seq;
  o.status = m.status;
  o.health = static_cast<uint32_t>(m.health);
  for (int i = 0; i < 3; ++i) {
    o.r_e[i] = m.r_e[i];
    o.r_e_lo[i] = m.r_e_lo[i];
    o.v_e[i] = m.v_e[i];
    o.v_n[i] = m.v_n[i];
    o.g_e[i] = m.g_e[i];
    o.g_e_lo[i] = m.g_e_lo[i];
    o.f_b[i] = m.f_b[i];
    o.rpy_rad[i] = m.rpy_rad[i];
    o.omega_b[i] = m.omega_b[i];
    o.omega_dot_b[i] = m.omega_dot_b[i];
    for (int j = 0; j < 3; ++j) {
      o.gamma_e[i][j] = m.gamma_e[i][j];
      o.gamma_b[i][j] = m.gamma_b[i][j];
    }
  }
  for (int i = 0; i < 4; ++i) {
    o.q_b_e[i] = m.q_b_e[i];
    o.parity[i] = m.parity[i];
  }
  o.lat_rad = m.lat_rad;
  o.lon_rad = m.lon_rad;
  o.h_m = m.h_m;
  o.h_ins_m = m.h_ins_m;
  o.baro_innov_m = m.baro_innov_m;
  o.g_up_corr = m.g_up_corr;
  o.t_s = m.t_s;
  for (int i = 0; i < GG_MOD_COUNT && i < m.n_cycles && i < 8; ++i) o.cycles[i] = static_cast<uint32_t>(m.cycles[i]);
  ggins::run3d::aid_pf_output_from_lcm(m, o);
}

void Model3D::take(const ggins::nav3d_output_t& m, bool latest) {
  if (m.mm_updates + m.mm_rejected > aid_closed_) {  // a map-aid epoch finished: its NIS
    const bool accepted = m.mm_updates + m.mm_rejected == aid_closed_ + 1 && m.mm_corrected != 0;
    aid_closed_ = m.mm_updates + m.mm_rejected;
    aid_nis_sum_ += m.mm_nis;
    if (ep_csv_.is_open()) aid_epoch(m, accepted);
  }
  if (latest) {
    aid_last_ = m;
    const double dt = 1.0 / sc_.rate_hz;
    if (sc_.aid_ukf.enabled) mm_integ_.take(m.t_s, dt, m.mm_integ, m.mm_integ_ratio, m.mm_no_map);
    if (pf_on_) pf_integ_.take(m.t_s, dt, m.pf_integ, m.pf_integ_ratio, m.pf_no_map);
  }
  gg_nav3d_output_t o;
  from_lcm(m, o);
  consume(m.seq, truth_ring_[static_cast<size_t>(m.seq % kTruthRing)], o, m.mm_sigma);
}

ggins::sensor_frame_t Model3D::frame(int64_t k) {
  gg_frame_t f;
  ggins::truth3d::Truth3 t;
  gen_.frame(k, f, &t);
  const ggins::sensor_frame_t m = ggins::hil::sensor_frame_msg(f, run_id_, 0);
  if (ref_ && k == ref_next_) {  // each frame once, in order (a resent frame is not stepped again)
    gg_nav3d_output_t ro;
    from_lcm(ref_->step(m), ro);
    ++ref_next_;
    if (ro.status != 0) ++ref_rejected_;  // as the flight counts its own
    ref_health_or_ |= ro.health;
    const ggins::run3d::Errors3 e = ggins::run3d::compare(t, ro);
    ref_pos_.add(static_cast<double>(e.dr));
    ref_vel_.add(static_cast<double>(e.dv));
    ref_att_.add(static_cast<double>(e.psi));
    ref_grav_.add(static_cast<double>(e.dg));
    for (int i = 0; i < 3; ++i) ref_fpos_n_[static_cast<size_t>(i)] = static_cast<double>(e.dr_n(i));
    ref_ring_[static_cast<size_t>(k % kTruthRing)] = {static_cast<double>(e.dr_n(0)), static_cast<double>(e.dr_n(1)),
                                                      static_cast<double>(e.dr_n(2)), static_cast<double>(e.dr)};
  }
  if (link_ && (k % truth_every_ == 0 || k == n_ - 1)) {
    ggins::truth3d_t tm{};
    tm.utime = t.utime;
    tm.seq = k;
    tm.run_id = run_id_;
    tm.t_s = static_cast<double>(t.t_s);
    const auto q = ggins::truth3d::quat_from_dcm(t.s.C_b_e);
    for (int j = 0; j < 3; ++j) {
      hilo(t.s.r_e(j), tm.r_e_hi[j], tm.r_e_lo[j]);
      hilo(t.s.r_i(j), tm.r_i_hi[j], tm.r_i_lo[j]);
      hilo(t.g_e(j), tm.g_e_hi[j], tm.g_e_lo[j]);
      tm.v_e[j] = static_cast<double>(t.s.v_e(j));
      tm.a_e[j] = static_cast<double>(t.s.a_e(j));
      tm.v_i[j] = static_cast<double>(t.s.v_i(j));
      tm.a_i[j] = static_cast<double>(t.s.a_i(j));
      tm.omega_b[j] = static_cast<double>(t.s.omega_b(j));
      tm.omega_dot_b[j] = static_cast<double>(t.s.omega_dot_b(j));
      tm.f_b[j] = static_cast<double>(t.f_b(j));
      for (int i = 0; i < 3; ++i) {
        tm.gamma_e[j][i] = static_cast<double>(t.gamma_e(j, i));
        tm.gamma_b[j][i] = static_cast<double>(t.gamma_b(j, i));
      }
    }
    for (int j = 0; j < 4; ++j) tm.q_b_e[j] = static_cast<double>(q[static_cast<size_t>(j)]);
    tm.rpy_rad[0] = static_cast<double>(t.s.roll);
    tm.rpy_rad[1] = static_cast<double>(t.s.pitch);
    tm.rpy_rad[2] = static_cast<double>(t.s.yaw);
    tm.lat_rad = static_cast<double>(t.s.lat);
    tm.lon_rad = static_cast<double>(t.s.lon);
    tm.h_m = static_cast<double>(t.s.h);
    link_->publish(truth_channel(), tm);
    ++truth_published_;
  }
  truth_ring_[static_cast<size_t>(k % kTruthRing)] = t;
  if (shots_) ca_ring_[static_cast<size_t>(k % kTruthRing)] = {f.ca_status, f.ca_s[0], f.ca_s[1]};
  return m;
}

ggins::nav3d_config_t Model3D::config() {
  gg_nav3d_config_t c = ggins::truth3d::config3d(sc_, gen_);  // truth3d/config3d.hpp
  ggins::nav3d_config_t m{};
  m.utime = wall_us();
  m.seq = 0;
  std::memcpy(m.scenario, sc_.name.data(), std::min<size_t>(sc_.name.size(), 63));
  for (int i = 0; i < 3; ++i) {
    m.half_base_m[i] = static_cast<double>(c.geometry.half_base_m[i]);
    hilo(c.r0_e[i], m.r0_hi[i], m.r0_lo[i]);
    hilo(c.v0_e[i], m.v0_hi[i], m.v0_lo[i]);
    hilo(c.g0_e[i], m.g0_hi[i], m.g0_lo[i]);
    m.baro_poles[i] = static_cast<double>(c.baro.poles[i]);
  }
  for (int i = 0; i < 4; ++i) hilo(c.q0_b_e[i], m.q0_hi[i], m.q0_lo[i]);
  m.platform = c.platform;
  m.dt_us = c.dt_us;
  m.dt_tol_us = c.dt_tol_us;
  hilo(c.omega_ie, m.omega_ie_hi, m.omega_ie_lo);
  m.f_max = c.f_max;
  m.asym_max = c.asym_max;
  m.fdi_parity_f_max = c.fdi_parity_f_max;
  m.acc_frozen_frames = c.acc_frozen_frames;
  m.gravity_mode = static_cast<int8_t>(c.gravity_mode);
  hilo(c.model.gm, m.model_gm_hi, m.model_gm_lo);
  m.model_a_m = static_cast<double>(c.model.a_m);
  for (int n = 0; n < 9 && n <= GG_GMODEL_MAX_DEGREE; ++n) m.model_j[n] = static_cast<double>(c.model.j[n]);
  m.baro_enable = static_cast<int8_t>(c.baro_enable);
  m.baro_omega_s2 = static_cast<double>(c.baro.omega_s2);
  m.baro_period_us = c.baro.period_us;
  m.baro_max_age_us = c.baro.max_age_us;
  m.baro_coast_us = c.baro.coast_us;
  m.baro_alt_min_m = c.baro.alt_min_m;
  m.baro_alt_max_m = c.baro.alt_max_m;
  m.baro_gate_m = c.baro.gate_m;
  m.baro_max_rejects = c.baro.max_rejects;
  m.aid_mm_enable = static_cast<int8_t>(c.aid_mm.enable);  // the map aid (truth3d/aids3d.hpp)
  m.aid_mm_update_steps = c.aid_mm.update_steps;
  m.aid_mm_max_passes = c.aid_mm.max_passes;
  m.aid_mm_sigma_meas_s2 = c.aid_mm.sigma_meas_s2;
  m.aid_mm_sigma_db_s2 = c.aid_mm.sigma_db_s2;
  m.aid_mm_offdiag_ratio = c.aid_mm.offdiag_ratio;
  m.aid_mm_sig0_pos_m = c.aid_mm.sig0_pos_m;
  m.aid_mm_sig0_vel_mps = c.aid_mm.sig0_vel_mps;
  m.aid_mm_sig0_att_rad = c.aid_mm.sig0_att_rad;
  m.aid_mm_sig0_g_mps2 = c.aid_mm.sig0_g_mps2;
  m.aid_mm_q_vel_mps_rts = c.aid_mm.q_vel_mps_rts;
  m.aid_mm_q_att_rad_rts = c.aid_mm.q_att_rad_rts;
  m.aid_mm_q_g_mps2_rts = c.aid_mm.q_g_mps2_rts;
  m.aid_mm_lambda = c.aid_mm.lambda;
  m.aid_mm_gate_nis = c.aid_mm.gate_nis;
  m.aid_mm_average_steps = c.aid_mm.average_steps;
  m.aid_mm_sigma_gyro_rps = c.aid_mm.sigma_gyro_rps;
  m.aid_mm_sigma_gyro_bias_rps = c.aid_mm.sigma_gyro_bias_rps;
  m.aid_mm_bias_states = static_cast<int8_t>(c.aid_mm.bias_states);
  m.aid_mm_sig0_gyro_bias_rps = c.aid_mm.sig0_gyro_bias_rps;
  m.aid_mm_sig0_acc_bias_mps2 = c.aid_mm.sig0_acc_bias_mps2;
  m.aid_mm_q_gyro_bias_rps_rts = c.aid_mm.q_gyro_bias_rps_rts;
  m.aid_mm_q_acc_bias_mps2_rts = c.aid_mm.q_acc_bias_mps2_rts;
  m.aid_mm_sigma_baro_m = c.aid_mm.sigma_baro_m;
  m.aid_mm_integ_enable = static_cast<int8_t>(c.aid_mm.integ.enable);
  m.aid_mm_integ_window = c.aid_mm.integ.window;
  m.aid_mm_integ_z = c.aid_mm.integ.z;
  m.aid_mm_integ_isolate = c.aid_mm.integ.isolate_after;
  m.aid_mm_integ_recover = c.aid_mm.integ.recover_after;
  // the map storage as a whole, for a replay to load the same one (map_storage.hpp)
  m.map_n_sources = static_cast<int8_t>(sources_.size());
  for (size_t i = 0; i < sources_.size(); ++i) {
    const std::string& p = sources_[i].path;
    if (p.size() > 255) throw Fail("map storage path longer than 255 bytes: " + p);
    m.map_source_kind[i] = static_cast<int8_t>(sources_[i].kind);
    std::memcpy(m.map_source_path[i], p.data(), p.size());
    m.map_source_tiles[i] = records_[i].tiles;
    m.map_source_bytes[i] = records_[i].bytes;
    std::memcpy(m.map_source_blake2b[i], records_[i].blake2b.data(), 32);
  }
  ggins::run3d::aid_pf_config_to_lcm(c.aid_pf, m);  // the cold-atom aid (pf3d.hpp)
  pf_on_ = c.aid_pf.enable != 0;
  pf_.set_info_min(c.aid_pf.info_min);
  const auto* ca = gen_.coldatom();
  if (pf_on_ && ca && !ca->samples_field()) {
    shots_ = std::make_unique<ggins::run3d::ShotBaseline3>(ca->params().grad.scale());
    ca_ring_.assign(static_cast<size_t>(kTruthRing), Pair{});
  }
  ref_cfg_ = m;  // the unaided reference: the same configuration, every aid off
  ref_cfg_.aid_mm_enable = 0;
  ref_cfg_.aid_pf_enable = 0;
  ref_cfg_.map_n_sources = 0;
  return m;
}

void Model3D::consume(int64_t k, const ggins::truth3d::Truth3& t, const gg_nav3d_output_t& o, const double* sig_pos) {
  const ggins::run3d::Errors3 e = ggins::run3d::compare(t, o);
  if (gravrec_) gravrec_->step(t, o, k % csv_every_ == 0 || k == n_ - 1);
  if (pf_on_) pf_.take(o, static_cast<double>(e.dr_n(0)), static_cast<double>(e.dr_n(1)));
  if (shots_ && o.pf_corrected != 0 && o.pf_gzz_s2 != 0.0) {
    // the shot this end weighed: the last shot step (a shot ends before the next begins)
    const auto* ca = gen_.coldatom();
    const int64_t ks = (k / ca->steps_per_shot()) * ca->steps_per_shot();
    const auto& p = ca_ring_[static_cast<size_t>(ks % kTruthRing)];
    const auto& ts = truth_ring_[static_cast<size_t>(ks % kTruthRing)].s;
    double g = 0;
    if (ks > 0 && p.status == GG_SENSOR_OK &&
        ca->map().gzz(static_cast<double>(ts.lat), static_cast<double>(ts.lon), static_cast<double>(ts.h), &g))
      shots_->take(p.s0, p.s1, g, o.pf_gzz_s2);
  }
  pos_.add(static_cast<double>(e.dr));
  vel_.add(static_cast<double>(e.dv));
  att_.add(static_cast<double>(e.psi));
  grav_.add(static_cast<double>(e.dg));
  hgt_.add(static_cast<double>(e.dh));
  if (k > 0) {  // the first output may carry no gradient yet
    gam_e_.add(static_cast<double>(e.dgamma_e));
    gam_b_.add(static_cast<double>(e.dgamma_b));
    par_asym_.add(std::sqrt(o.parity[0] * o.parity[0] + o.parity[1] * o.parity[1] + o.parity[2] * o.parity[2]));
    par_trace_.add(o.parity[3]);
    const Vec3 wd(o.omega_dot_b[0], o.omega_dot_b[1], o.omega_dot_b[2]);
    wdot_.add(static_cast<double>((wd - t.s.omega_dot_b).norm()));
  }
  for (int i = 0; i < 3; ++i) {
    fvel_n_[static_cast<size_t>(i)] = static_cast<double>(e.dv_n(i));
    fpos_n_[static_cast<size_t>(i)] = static_cast<double>(e.dr_n(i));
    fatt_n_[static_cast<size_t>(i)] = static_cast<double>(e.psi_n(i));
    fg_n_[static_cast<size_t>(i)] = static_cast<double>(e.dg_n(i));
  }
  if (k % csv_every_ == 0 || k == n_ - 1) {
    const double deg = 180.0 / M_PI;
    char line[1024];
    std::snprintf(line, sizeof line,
                  "%.6f,%lld,%.10f,%.10f,%.4f,%.6f,%.6f,%.6f,%.4f,%.10f,%.10f,%.4f,"
                  "%.6e,%.6e,%.6e,%.6e,%.6e,%.6e,%.6e,%.6e,%.6e,%.6e,%.6e,%.6e,%.6e,%.6e,%.6e,%.6e,%.6e,%.6e,"
                  "%.6e,%.6e,%.6e,%.6e,%.6e,%.6e,%.6e,%d,%u,%s",
                  static_cast<double>(t.t_s), static_cast<long long>(k), static_cast<double>(t.s.lat) * deg,
                  static_cast<double>(t.s.lon) * deg, static_cast<double>(t.s.h), static_cast<double>(t.s.roll) * deg,
                  static_cast<double>(t.s.pitch) * deg, static_cast<double>(t.s.yaw) * deg, static_cast<double>(t.s.v_e.norm()),
                  o.lat_rad * deg, o.lon_rad * deg, o.h_m, static_cast<double>(e.dr_n(0)), static_cast<double>(e.dr_n(1)),
                  static_cast<double>(e.dr_n(2)), static_cast<double>(e.dr), static_cast<double>(e.dv_n(0)),
                  static_cast<double>(e.dv_n(1)), static_cast<double>(e.dv_n(2)), static_cast<double>(e.dv),
                  static_cast<double>(e.psi_n(0)), static_cast<double>(e.psi_n(1)), static_cast<double>(e.psi_n(2)),
                  static_cast<double>(e.psi), static_cast<double>(e.dg_n(0)), static_cast<double>(e.dg_n(1)),
                  static_cast<double>(e.dg_n(2)), static_cast<double>(e.dg), static_cast<double>(e.dgamma_e) * 1e9,
                  static_cast<double>(e.dgamma_b) * 1e9, static_cast<double>(e.dh), o.parity[0], o.parity[1], o.parity[2],
                  o.parity[3], o.baro_innov_m, o.g_up_corr, o.status, o.health, ggins::hil::health_csv(o.health).c_str());
    csv_ << line;
    if (sc_.aid_ukf.enabled)  // the aid's one-sigma of the position error (ECI axes) and their root sum square
      csv_ << "," << sig_pos[0] << "," << sig_pos[1] << "," << sig_pos[2] << ","
           << std::sqrt(sig_pos[0] * sig_pos[0] + sig_pos[1] * sig_pos[1] + sig_pos[2] * sig_pos[2]);
    if (ref_) {
      const auto& r = ref_ring_[static_cast<size_t>(k % kTruthRing)];
      char ref[128];  // the format of the flight's own err_*_m columns
      std::snprintf(ref, sizeof ref, ",%e,%e,%e,%e", r[0], r[1], r[2], r[3]);
      csv_ << ref;
    }
    csv_ << "\n";
  }
}


json Model3D::aid_ukf_block() const {  // the map aid's counters at the last step flown
  json a;
  a["name"] = "aid_ukf";
  a["description"] = "gradient-map UKF (aid_mmukf.h)";
  a["epochs"] = aid_last_.mm_epochs;
  a["updates"] = aid_last_.mm_updates;
  a["rejected"] = aid_last_.mm_rejected;
  a["no_map"] = aid_last_.mm_no_map;
  // a mean over no closed epoch is no number: null
  a["nis_mean"] = aid_closed_ > 0 ? json(aid_nis_sum_ / static_cast<double>(aid_closed_)) : json(nullptr);
  a["nis_dof"] = 6;
  if (aid_closed_ > 0) {  // 95 % band of the mean NIS if the epochs were independent: chi^2(6n) / n
    const double k = 6.0 * static_cast<double>(aid_closed_), c = 2.0 / (9.0 * k);
    auto q = [&](double z) { return k * std::pow(1.0 - c + z * std::sqrt(c), 3) / static_cast<double>(aid_closed_); };
    a["nis_band95"] = {q(-1.959963984540054), q(1.959963984540054)};
  }
  // the task's bias estimates at the last step flown (0 without bias states) and the aid's sigmas
  a["bias_states"] = sc_.aid_ukf.bias_states;
  a["bias_estimate"] = {{"gyro_radps", {aid_last_.mm_bias[0], aid_last_.mm_bias[1], aid_last_.mm_bias[2]}},
                        {"accel_mps2", {aid_last_.mm_bias[3], aid_last_.mm_bias[4], aid_last_.mm_bias[5]}},
                        {"frame", "body"}};
  a["sigma_pos_final_m"] = {{"x", aid_last_.mm_sigma[0]}, {"y", aid_last_.mm_sigma[1]}, {"z", aid_last_.mm_sigma[2]}};
  a["sigma_frame"] = "ECI";
  a["tiles"] = maps_.size();
  // NEES per block (3 dof each) against the truth after each accepted epoch's correction,
  // mean over the epochs, and the 95 % band of such a mean if the epochs were independent
  const double n = static_cast<double>(nees_n_);
  json ne;
  ne["epochs"] = nees_n_;
  ne["dof"] = 3;
  ne["frame"] = "ECI (error state of aid_mmukf.h: true - estimate)";
  if (nees_n_ > 0) {
    ne["position"] = nees_sum_[0] / n;
    ne["velocity"] = nees_sum_[1] / n;
    ne["attitude"] = nees_sum_[2] / n;
    // Wilson-Hilferty quantiles of chi^2(3n) / n
    auto q = [&](double z) {
      const double k = 3.0 * n, c = 2.0 / (9.0 * k);
      return k * std::pow(1.0 - c + z * std::sqrt(c), 3) / n;
    };
    ne["band95"] = {q(-1.959963984540054), q(1.959963984540054)};
  }
  a["nees"] = ne;
  a["epochs_csv"] = "aid_epochs.csv";
  return a;
}

void Model3D::report(json& s) {
  using ggins::hil::axes_json;
  s["platform"] = sc_.platform;
  s["trajectory"] = sc_.trajectory.type;
  s["gravity_model"] = sc_.gravity.model;
  s["navigation_gravity"] = sc_.nav_gravity;
  s["baro_loop"] = sc_.baro_loop_enabled();
  json& e = s["errors"];
  e["frame"] = "NED at the true position (north, east, down)";
  e["definition"] = "nav - truth at the same step (run3d/compare3d.hpp); gravity: G estimated - true gravitation at the "
                    "TRUE position; attitude: rotation vector of C_b_e(nav) C_b_e(true)^T; gradient: largest |element|";
  e["position_error_m"] = pos_.json();
  e["position_error_final_m"] = axes_json(fpos_n_, "n", "e", "d");
  e["velocity_error_mps"] = vel_.json();
  e["velocity_error_final_mps"] = axes_json(fvel_n_, "n", "e", "d");
  e["height_error_m"] = hgt_.json();
  e["attitude_error_rad"] = att_.json();
  e["attitude_error_final_rad"] = axes_json(fatt_n_, "n", "e", "d");
  e["gravity_error_mps2"] = grav_.json();
  e["gravity_error_final_mps2"] = axes_json(fg_n_, "n", "e", "d");
  e["gradient_error_ecef_E"] = gam_e_.json(1e9);
  e["gradient_error_body_E"] = gam_b_.json(1e9);
  e["omega_dot_error_radps2"] = wdot_.json();
  s["parity"] = {{"antisym_radps2", par_asym_.json()}, {"trace_ps2", par_trace_.json()}};
  s["acceptance"] = {{"position_below_1cm", pos_.max < 0.01}, {"gamma_below_1e-4_E", gam_e_.max * 1e9 < 1e-4}};
  if (sc_.draw.active()) {  // the run's Monte Carlo draw ([draw]), added to the scenario's fixed errors
    const auto d = ggins::truth3d::draw_errors(sc_.draw);
    s["draw"] = {{"seed", sc_.draw.seed},
                 {"accel_common_bias_mps2", d.accel_common_bias_mps2},
                 {"gyro_bias_radps", d.gyro_bias_radps},
                 {"initial_position_error_ned_m", d.position_ned_m},
                 {"initial_velocity_error_ned_mps", d.velocity_ned_mps},
                 {"initial_attitude_error_ned_rad", d.attitude_ned_rad}};
  }
  json ms = json::array();  // the map storage as the configuration message records it (a replay loads it)
  for (size_t i = 0; i < sources_.size(); ++i)
    ms.push_back({{"path", sources_[i].path}, {"kind", ggins::run3d::kind_name(sources_[i].kind)},
                  {"tiles", records_[i].tiles}, {"bytes", records_[i].bytes},
                  {"blake2b", ggins::run3d::hex(records_[i].blake2b)}});
  s["map_storage"] = ms;
  // the maps built before the flight (map_from_field): wall time apart from setup_s and wall_s
  s["map_build_s"] = map_build_s_;
  s["map_tiles"] = {{"built", map_tiles_built_}, {"from_cache", map_tiles_cached_},
                    {"cache_dir", map_cache_.empty() ? json(nullptr) : json(map_cache_.string())}};
  {  // the along-track gravimetry record and its error model (gravimetry_record.hpp)
    const auto gm = ggins::run3d::gravimetry_model(sc_);
    s["gravimetry"] = {{"file", "gravimetry_raw.csv"},
                       {"mode", sc_.nav_gravity},
                       {"field", sc_.gravity.model},
                       {"sigma_gamma_noise_ps2", gm.sigma_gamma_noise_ps2},
                       {"sigma_gyro_radps", gm.sigma_w_radps},
                       {"sigma_gamma_bias_ps2", gm.sigma_gamma_bias_ps2},
                       {"loop_poles_radps", sc_.baro_loop_enabled() ? json(sc_.nav_baro.poles_radps) : json::array()}};
  }
  // one block per aid of the flight, each named ({"name": ..., its counters})
  std::vector<std::string> why;  // an aid inconsistent or refused for part of the flight: degraded
  if (sc_.aid_ukf.enabled) {
    s["aids"].push_back(aid_ukf_block());
    mm_integ_.set_enabled(sc_.aid_ukf.integrity);
    s["aids"].back()["integrity"] = mm_integ_.json();
    s["aids"].back()["integrity"]["isolated_epochs"] = aid_last_.mm_isolated;
    mm_integ_.reasons("map aid", "epochs", aid_last_.mm_epochs, why);
    s["aids"].back()["map_coverage"] = mm_cov_.json();
    ggins::run3d::coverage_reason("map aid", mm_cov_, why);
  }
  if (pf_on_) {
    s["aids"].push_back(pf_.block(maps_.size()));
    if (shots_) s["aids"].back()["gradient_estimates"] = shots_->block();
    pf_integ_.set_enabled(sc_.aid_pf.integrity);
    s["aids"].back()["integrity"] = pf_integ_.json();
    s["aids"].back()["integrity"]["isolated_shots"] = aid_last_.pf_isolated;
    pf_integ_.reasons("particle filter", "shots", aid_last_.pf_shots, why);
    pf_.info_reason(why);
    s["aids"].back()["map_coverage"] = pf_cov_.json();
    ggins::run3d::coverage_reason("particle filter", pf_cov_, why);
  }
  if (s.value("completed", false))
    for (const auto& w : why) s["degraded_reasons"].push_back(w);
  if (ref_) {
    json r;
    r["description"] = "the same task with every aid off, stepped in this process on the same sensor frames "
                       "(the pure inertial solution of this flight); untimed (no cycle counter: its steps are "
                       "not checked against the frame period, the flight's are)";
    r["steps"] = ref_next_;
    r["steps_rejected"] = ref_rejected_;
    r["health_seen"] = ref_health_or_;
    r["health_seen_bits"] = ggins::hil::health_csv(ref_health_or_);
    r["position_error_m"] = ref_pos_.json();
    r["position_error_final_m"] = axes_json(ref_fpos_n_, "n", "e", "d");
    r["velocity_error_mps"] = ref_vel_.json();
    r["attitude_error_rad"] = ref_att_.json();
    r["gravity_error_mps2"] = ref_grav_.json();
    r["csv_columns"] = "unaided_err_n_m, unaided_err_e_m, unaided_err_d_m, unaided_err_r_m";
    s["unaided_reference"] = r;
  }
}

void Model3D::before_plots(const ggins::hil::RunOptions& o, const std::filesystem::path& out, const json& summary) {
  if (summary.contains("aids") && !summary["aids"].empty()) return;
  ggins::hil::error_model_covariance(o, out, "ggins-covariance3d");
}

std::string Model3D::final_line(const json& s) {
  const json& e = s["errors"];
  char b[512];
  std::snprintf(b, sizeof b,
                "ggins run3d: %s %s: %lld steps, position error %.3e m (max %.3e), attitude %.3e rad, G %.3e m/s^2, "
                "Gamma %.3e E (max %.3e)",
                s["scenario"].get<std::string>().c_str(), s["status"].get<std::string>().c_str(),
                static_cast<long long>(s["steps_flown"].get<int64_t>()), e["position_error_m"]["final"].get<double>(),
                e["position_error_m"]["max"].get<double>(), e["attitude_error_rad"]["final"].get<double>(),
                e["gravity_error_mps2"]["final"].get<double>(), e["gradient_error_ecef_E"]["final"].get<double>(),
                e["gradient_error_ecef_E"]["max"].get<double>());
  std::string line = b;
  if (s.contains("unaided_reference")) {
    std::snprintf(b, sizeof b, "; unaided on the same frames: position error %.3e m",
                  s["unaided_reference"]["position_error_m"]["final"].get<double>());
    line += b;
  }
  return line;
}

}  // namespace

int main(int argc, char** argv) {
  ggins::hil::RunOptions o;
  o.tool = "ggins run3d";
  o.python = GGINS_PLOT_PYTHON;
  o.logger = GGINS_LCM_LOGGER;
  std::string scenario = "3d-stabilized-1h";
  bool no_aids = false, no_reference = false;
  CLI::App app{
      "ggins run3d: fly one 3-D scenario (six tri-axis accelerometers, rotating WGS-84 Earth,\n"
      "stabilized or strapdown platform) against the 3-D firmware (nav3d.h).\n\n"
      "The 3-D truth generator (host_tools/lib/truth3d, this process) evaluates the scenario's\n"
      "analytic trajectory on Taylor jets (r, v, a, attitude, body rate and its derivative\n"
      "mutually exact), each accelerometer's f = C_i_b (a_j - G(r_j)) with the field at the\n"
      "sensor, the gyro rate and the barometer, and sends sensor frames; hal_sim (own process,\n"
      "3-D mode) steps gg_nav3d once per frame in lockstep over LCM. --direct steps the\n"
      "firmware in this process instead (no LCM; same numbers).\n\n"
      "Writes to the output folder (default out/<scenario>-<UTC>/):\n"
      "  summary.json     the flight report (docs/hil.md, the same shape as ggins run's): status\n"
      "                   (completed, degraded, failed, interrupted), steps flown and unflown,\n"
      "                   health seen (raw and named bits), errors (final = last step flown, and\n"
      "                   max): position (NED), velocity, attitude, gravity, gradient (Eotvos);\n"
      "                   parity, step time, transport counters, acceptance, aids (a list)\n"
      "  timeseries.csv   truth, navigation and errors at --csv-rate, units in every column\n"
      "  gravimetry_raw.csv  the gravity disturbance the navigation carries along its track,\n"
      "                   the truth at the nav and the true positions, the predicted error's\n"
      "                   random-walk variance (input of ggins gravimetry)\n"
      "  errors.png       position error N/E/D, attitude error, G error, Gamma error vs time;\n"
      "                   the position error's one-sigma envelope is the aid's covariance\n"
      "                   (with an aid on) or the 3-D error model's (covariance/: ggins\n"
      "                   covariance3d on the scenario as flown)\n"
      "  run.lcmlog       every LCM message of the run (not with --direct or --no-log)\n"
      "  scenario.toml (as flown: effective values, overrides applied), hal_sim.log\n\n"
      "Exit status: 0 completed; 1 failed; 2 bad arguments or scenario; 3 multicast on loopback\n"
      "unavailable; 4 completed but degraded; 130 interrupted (Ctrl-C: hal_sim is stopped, the\n"
      "report is written with status \"interrupted\" and the unflown steps)."};
  app.get_formatter()->column_width(34);
  app.add_option("-s,--scenario", scenario, "3-D scenario: built-in name (--list-scenarios) or TOML path")
      ->capture_default_str();
  ggins::hil::add_run_options(app, o);
  app.add_flag("--no-aids", no_aids,
               "fly the scenario without its aids ([aid_ukf] off): the unaided reference of an aided flight\n"
               "(plot both on one figure: plot_run3d.py AIDED_DIR --unaided THIS_DIR)");
  app.add_flag("--no-reference", no_reference,
               "with an aid on: do not fly the unaided reference (by default the same task with every aid off\n"
               "is stepped in this process on the same frames; summary.json \"unaided_reference\", CSV\n"
               "unaided_err_*, drawn on errors.png)");
  std::string map_cache = ggins::gmap::default_cache_dir().string();
  bool no_map_cache = false;
  app.add_option("--map-cache", map_cache,
                 "folder of the tile cache: map_from_field tiles of an EGM96 field are built once, named by\n"
                 "their content (the coefficient file's digest, degree, area, spacing, heights, noise), and\n"
                 "shared by ggins gmap, run3d and campaign workers (default: $GGINS_MAP_CACHE, else\n"
                 "$XDG_CACHE_HOME/ggins/maps, else ~/.cache/ggins/maps)")
      ->capture_default_str();
  app.add_flag("--no-map-cache", no_map_cache, "build every map_from_field tile afresh and keep none");
  ggins::hil::FrontEndFlags flags;
  ggins::hil::add_scenario_flags(app, flags);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int rc = app.exit(e);
    return rc == 0 ? 0 : 2;
  }
  namespace t3 = ggins::truth3d;
  ggins::hil::ScenarioFrontEnd<t3::Scenario3> fe;
  fe.names = [] { return t3::builtin_scenario3_names(); };
  // (what the 3-D parser derives - the fault threshold, the frozen-reading window - depends on
  // the error sigmas only, not on the seed or the duration: adjusted after the read)
  fe.load = [](const std::string& n, const std::function<void(t3::Scenario3&)>& adjust) {
    t3::Scenario3 s = t3::load_scenario3(n, {GGINS_SCENARIO_DIR});
    if (adjust) adjust(s);
    return s;
  };
  fe.template_toml = [] { return t3::scenario3_to_toml(t3::Scenario3{}, true); };
  fe.apply = [&](t3::Scenario3& sc) {
    if (o.csv_rate) sc.csv_rate_hz = *o.csv_rate;
    if (no_aids) sc.aid_ukf.enabled = false;
    if (no_aids) sc.aid_pf.enabled = false;
  };
  // the scenario as flown: every key, the effective values (overrides applied), every
  // file it names absolute (it flies again from the output folder, or from anywhere)
  fe.as_flown = [](const t3::Scenario3& sc) { return t3::scenario3_to_toml(t3::with_absolute_files(sc)); };
  fe.fly = [&](t3::Scenario3& sc, const std::string& as_flown) {
    return ggins::hil::fly_scenario<Model3D>(
        o, sc.name, sc.source, as_flown, json::object(), GGINS_PLOT3D_SCRIPT,
        [&](const std::filesystem::path& out) {
          return std::make_unique<Model3D>(o, sc, !no_reference, out, no_map_cache ? fs::path() : fs::path(map_cache));
        });
  };
  return ggins::hil::scenario_main(o, scenario, flags, fe);
}
