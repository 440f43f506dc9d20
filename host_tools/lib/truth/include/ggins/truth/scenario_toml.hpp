// Checked readers of scenario TOML fields, shared by the 2-D (truth/src/scenario.cpp)
// and 3-D (truth3d/src/scenario3d.cpp) scenario parsers. Every error throws
// std::runtime_error("scenario <source>: <what>") naming the offending key as
// <where>.<key>.
#pragma once

#include <cmath>
#include <cstdint>
#include <set>
#include <stdexcept>
#include <string>
#include <toml++/toml.h>

namespace ggins::truth::scenario_toml {

[[noreturn]] inline void fail(const std::string& source, const std::string& what) {
  throw std::runtime_error("scenario " + source + ": " + what);
}

// Every key of t must be in allowed (where: the table's dotted name, "" for the root).
inline void check_keys(const toml::table& t, const std::string& where, const std::set<std::string>& allowed,
                       const std::string& source) {
  for (const auto& [k, v] : t) {
    (void)v;
    const std::string key(k.str());
    if (!allowed.count(key)) {
      std::string list;
      for (const auto& a : allowed) list += (list.empty() ? "" : ", ") + a;
      fail(source, "unknown key '" + (where.empty() ? key : where + "." + key) + "' (allowed: " + list + ")");
    }
  }
}

// t[key] as a finite number (an integer is taken too), dflt if absent.
inline double get_num(const toml::table& t, const std::string& where, const char* key, double dflt,
                      const std::string& source) {
  const toml::node* n = t.get(key);
  if (!n) return dflt;
  if (auto d = n->value<double>()) {
    if (!std::isfinite(*d)) fail(source, where + "." + key + " must be finite");
    return *d;
  }
  fail(source, where + "." + key + " must be a number");
}

inline int64_t get_int(const toml::table& t, const std::string& where, const char* key, int64_t dflt,
                       const std::string& source) {
  const toml::node* n = t.get(key);
  if (!n) return dflt;
  if (n->is_integer()) return n->as_integer()->get();
  fail(source, where + "." + key + " must be an integer");
}

inline bool get_bool(const toml::table& t, const std::string& where, const char* key, bool dflt,
                     const std::string& source) {
  const toml::node* n = t.get(key);
  if (!n) return dflt;
  if (n->is_boolean()) return n->as_boolean()->get();
  fail(source, where + "." + key + " must be true or false");
}

inline std::string get_str(const toml::table& t, const std::string& where, const char* key, const std::string& dflt,
                           const std::string& source) {
  const toml::node* n = t.get(key);
  if (!n) return dflt;
  if (n->is_string()) return n->as_string()->get();
  fail(source, where + "." + key + " must be a string");
}

}  // namespace ggins::truth::scenario_toml
