// Field tables of the navigation output messages (lcmtypes/nav_output_t.lcm,
// nav3d_output_t.lcm) and one comparison over them.
//
// A table lists every field of the message in declaration order: name, element
// type, offset in the generated C struct, array shape, and whether replay
// compares it. covers_message() checks the table against the message's encoded
// size (the 8-byte fingerprint plus every field's elements, LCM encodes no
// padding), so a field added to the .lcm file and not to the table is refused
// at start-up rather than silently left out of the comparison.
#pragma once

#include <cinttypes>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "ggins_nav3d_output_t.h"
#include "ggins_nav_output_t.h"

namespace ggins::replay {

enum class Kind { kI8, kI32, kI64, kF64 };

struct Field {
  const char* name;
  Kind kind;
  size_t offset;
  int rows, cols;  // 1, 1: scalar; n, 1: [n]; n, m: [n][m]
  bool compared;   // false: a field replay cannot reproduce (timing, transport)
};

inline size_t elem_size(Kind k) {
  switch (k) {
    case Kind::kI8: return 1;
    case Kind::kI32: return 4;
    case Kind::kI64: return 8;
    case Kind::kF64: return 8;
  }
  return 0;
}

#define GG_FIELD(T, kind, m, rows, cols, cmp) \
  Field { #m, Kind::kind, offsetof(T, m), rows, cols, cmp }

// nav_output_t: cycles[] is the HAL cycle-counter timing; republished a transport count.
inline const std::vector<Field>& nav2d_fields() {
  using T = ggins_nav_output_t;
  static const std::vector<Field> f = {
      GG_FIELD(T, kI64, utime, 1, 1, true),       GG_FIELD(T, kI64, seq, 1, 1, true),
      GG_FIELD(T, kI64, run_id, 1, 1, true),      GG_FIELD(T, kI32, status, 1, 1, true),
      GG_FIELD(T, kI64, health, 1, 1, true),      GG_FIELD(T, kF64, r_i, 3, 1, true),
      GG_FIELD(T, kF64, v_i, 3, 1, true),         GG_FIELD(T, kF64, g_i, 3, 1, true),
      GG_FIELD(T, kF64, gamma_i, 3, 3, true),     GG_FIELD(T, kF64, f_i, 3, 1, true),
      GG_FIELD(T, kF64, gamma_asym, 1, 1, true),  GG_FIELD(T, kF64, h_ins_m, 1, 1, true),
      GG_FIELD(T, kF64, baro_innov_m, 1, 1, true), GG_FIELD(T, kF64, g_up_corr, 1, 1, true),
      GG_FIELD(T, kI32, n_cycles, 1, 1, true),    GG_FIELD(T, kI64, cycles, 8, 1, false),
      GG_FIELD(T, kI8, republished, 1, 1, false), GG_FIELD(T, kF64, parity_f, 2, 1, true),
      GG_FIELD(T, kI64, acc_excluded, 1, 1, true), GG_FIELD(T, kI64, acc_rebuilt, 1, 1, true),
      GG_FIELD(T, kI64, resync_count, 1, 1, true), GG_FIELD(T, kI64, coast_steps, 1, 1, true),
      GG_FIELD(T, kF64, outage_s, 1, 1, true),    GG_FIELD(T, kF64, state_lag_s, 1, 1, true),
      GG_FIELD(T, kI8, mac, 32, 1, false),  // bus MAC (hal_sim/bus_auth.h): replay has no key
  };
  return f;
}

// nav3d_output_t: likewise.
inline const std::vector<Field>& nav3d_fields() {
  using T = ggins_nav3d_output_t;
  static const std::vector<Field> f = {
      GG_FIELD(T, kI64, utime, 1, 1, true),        GG_FIELD(T, kI64, seq, 1, 1, true),
      GG_FIELD(T, kI64, run_id, 1, 1, true),       GG_FIELD(T, kI32, status, 1, 1, true),
      GG_FIELD(T, kI64, health, 1, 1, true),       GG_FIELD(T, kF64, r_e, 3, 1, true),
      GG_FIELD(T, kF64, r_e_lo, 3, 1, true),       GG_FIELD(T, kF64, v_e, 3, 1, true),
      GG_FIELD(T, kF64, lat_rad, 1, 1, true),      GG_FIELD(T, kF64, lon_rad, 1, 1, true),
      GG_FIELD(T, kF64, h_m, 1, 1, true),          GG_FIELD(T, kF64, v_n, 3, 1, true),
      GG_FIELD(T, kF64, g_e, 3, 1, true),          GG_FIELD(T, kF64, g_e_lo, 3, 1, true),
      GG_FIELD(T, kF64, gamma_e, 3, 3, true),      GG_FIELD(T, kF64, gamma_b, 3, 3, true),
      GG_FIELD(T, kF64, f_b, 3, 1, true),          GG_FIELD(T, kF64, q_b_e, 4, 1, true),
      GG_FIELD(T, kF64, rpy_rad, 3, 1, true),      GG_FIELD(T, kF64, omega_b, 3, 1, true),
      GG_FIELD(T, kF64, omega_dot_b, 3, 1, true),  GG_FIELD(T, kF64, parity, 4, 1, true),
      GG_FIELD(T, kF64, h_ins_m, 1, 1, true),      GG_FIELD(T, kF64, baro_innov_m, 1, 1, true),
      GG_FIELD(T, kF64, g_up_corr, 1, 1, true),    GG_FIELD(T, kF64, t_s, 1, 1, true),
      GG_FIELD(T, kI32, n_cycles, 1, 1, true),     GG_FIELD(T, kI64, cycles, 8, 1, false),
      GG_FIELD(T, kI8, republished, 1, 1, false),  GG_FIELD(T, kI64, resync_count, 1, 1, true),
      GG_FIELD(T, kI64, coast_steps, 1, 1, true),  GG_FIELD(T, kI64, acc_rebuilt, 1, 1, true),
      GG_FIELD(T, kI64, acc_excluded, 1, 1, true),
      GG_FIELD(T, kF64, outage_s, 1, 1, true),     GG_FIELD(T, kF64, state_lag_s, 1, 1, true),
      // the gradient-map aid (aid_mmukf.h)
      GG_FIELD(T, kI32, mm_phase, 1, 1, true),     GG_FIELD(T, kI8, mm_corrected, 1, 1, true),
      GG_FIELD(T, kI64, mm_epochs, 1, 1, true),    GG_FIELD(T, kI64, mm_updates, 1, 1, true),
      GG_FIELD(T, kI64, mm_rejected, 1, 1, true),  GG_FIELD(T, kI64, mm_no_map, 1, 1, true),
      GG_FIELD(T, kF64, mm_nis, 1, 1, true),       GG_FIELD(T, kF64, mm_sigma, 18, 1, true),
      GG_FIELD(T, kF64, mm_bias, 6, 1, true),
      GG_FIELD(T, kF64, mm_corr_m, 3, 1, true),
      GG_FIELD(T, kF64, mm_innov, 6, 1, true),     GG_FIELD(T, kF64, mm_pcov, 18, 1, true),
      GG_FIELD(T, kI32, mm_n_avg, 1, 1, true),
      // the cold-atom particle-filter aid (aid_pf.h)
      GG_FIELD(T, kI32, pf_phase, 1, 1, true),     GG_FIELD(T, kI8, pf_corrected, 1, 1, true),
      GG_FIELD(T, kI64, pf_shots, 1, 1, true),     GG_FIELD(T, kI64, pf_updates, 1, 1, true),
      GG_FIELD(T, kI64, pf_failed, 1, 1, true),    GG_FIELD(T, kI64, pf_invalid, 1, 1, true),
      GG_FIELD(T, kI64, pf_dropped, 1, 1, true),   GG_FIELD(T, kI64, pf_no_map, 1, 1, true),
      GG_FIELD(T, kI64, pf_map_miss, 1, 1, true),  GG_FIELD(T, kI64, pf_degenerate, 1, 1, true),
      GG_FIELD(T, kI64, pf_resampled, 1, 1, true), GG_FIELD(T, kF64, pf_ess, 1, 1, true),
      GG_FIELD(T, kF64, pf_spread_m, 2, 1, true),  GG_FIELD(T, kF64, pf_corr_m, 2, 1, true),
      GG_FIELD(T, kF64, pf_mean_m, 2, 1, true),    GG_FIELD(T, kF64, pf_gzz_s2, 1, 1, true),
      // the aids' integrity monitors (aid_integ.h)
      GG_FIELD(T, kI32, mm_integ, 1, 1, true),     GG_FIELD(T, kF64, mm_integ_ratio, 1, 1, true),
      GG_FIELD(T, kI64, mm_isolated, 1, 1, true),  GG_FIELD(T, kF64, pf_nis, 1, 1, true),
      GG_FIELD(T, kI32, pf_integ, 1, 1, true),     GG_FIELD(T, kF64, pf_integ_ratio, 1, 1, true),
      GG_FIELD(T, kI64, pf_isolated, 1, 1, true),
      GG_FIELD(T, kI64, pf_uninformative, 1, 1, true), GG_FIELD(T, kF64, pf_info, 1, 1, true),
      GG_FIELD(T, kF64, pf_spread_fi_m, 2, 1, true),
      GG_FIELD(T, kI8, mac, 32, 1, false),  // bus MAC (hal_sim/bus_auth.h): replay has no key
  };
  return f;
}

#undef GG_FIELD

// Empty when the table describes a message of `encoded_size` bytes and a C
// struct of `struct_size` bytes exactly (fields in order, no overlap, no field
// missing); else what is wrong.
inline std::string covers_message(const std::vector<Field>& t, int encoded_size, size_t struct_size) {
  size_t bytes = 8, end = 0;  // the fingerprint
  for (const Field& f : t) {
    const size_t n = elem_size(f.kind) * static_cast<size_t>(f.rows) * static_cast<size_t>(f.cols);
    if (f.offset < end) return std::string("field ") + f.name + " overlaps the one before it";
    end = f.offset + n;
    bytes += n;
  }
  if (end > struct_size) return "the last field ends beyond the struct";
  if (bytes != static_cast<size_t>(encoded_size))
    return "the table covers " + std::to_string(bytes) + " of the " + std::to_string(encoded_size) +
           " encoded bytes (a message field is missing from it)";
  return {};
}

struct Mismatch {
  int64_t seq;
  std::string field;
  std::string recorded, replayed;
};

inline std::string fmt_double(double x) {
  uint64_t b;
  std::memcpy(&b, &x, sizeof b);
  char s[96];
  std::snprintf(s, sizeof s, "%.17g (0x%016" PRIx64 ")", x, b);
  return s;
}

inline std::string fmt_int(int64_t x) {
  char s[64];
  std::snprintf(s, sizeof s, "%" PRId64 " (0x%" PRIx64 ")", x, static_cast<uint64_t>(x));
  return s;
}

inline int64_t read_int(Kind k, const uint8_t* p) {
  switch (k) {
    case Kind::kI8: {
      int8_t v;
      std::memcpy(&v, p, 1);
      return v;
    }
    case Kind::kI32: {
      int32_t v;
      std::memcpy(&v, p, 4);
      return v;
    }
    default: {
      int64_t v;
      std::memcpy(&v, p, 8);
      return v;
    }
  }
}

class Comparer {
 public:
  std::vector<Mismatch> list;
  int64_t count = 0;
  size_t keep = 20;

  // A difference that is not one field (e.g. no output from the replay).
  void note(int64_t seq, const std::string& what, const std::string& recorded, const std::string& replayed) {
    add(seq, what, recorded, replayed);
  }

  // Every compared field of the table, element by element: doubles by bit
  // pattern (-0.0 != +0.0, NaN payloads count), integers exactly.
  template <class M>
  void message(const std::vector<Field>& table, int64_t seq, const M& rec, const M& rep) {
    const auto* a = reinterpret_cast<const uint8_t*>(&rec);
    const auto* b = reinterpret_cast<const uint8_t*>(&rep);
    for (const Field& f : table) {
      if (!f.compared) continue;
      const size_t es = elem_size(f.kind);
      for (int r = 0; r < f.rows; ++r)
        for (int c = 0; c < f.cols; ++c) {
          const size_t off = f.offset + es * static_cast<size_t>(r * f.cols + c);
          if (std::memcmp(a + off, b + off, es) == 0) continue;
          std::string name = f.name;
          if (f.rows > 1) name += "[" + std::to_string(r) + "]";
          if (f.cols > 1) name += "[" + std::to_string(c) + "]";
          if (f.kind == Kind::kF64) {
            double x, y;
            std::memcpy(&x, a + off, 8);
            std::memcpy(&y, b + off, 8);
            add(seq, name, fmt_double(x), fmt_double(y));
          } else {
            add(seq, name, fmt_int(read_int(f.kind, a + off)), fmt_int(read_int(f.kind, b + off)));
          }
        }
    }
  }

 private:
  void add(int64_t seq, const std::string& f, std::string a, std::string b) {
    ++count;
    if (list.size() < keep) list.push_back({seq, f, std::move(a), std::move(b)});
  }
};

}  // namespace ggins::replay
