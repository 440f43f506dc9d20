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

#include "ggins/truth/scenario.hpp"

namespace ggins::truth {
// parse_scenario (scenario.hpp) on a table already parsed from `text` (the nodes keep their lines in the
// source: an error names source:line of the user's file). A reader that takes a table
// of its own out first (ggins covariance's [initial]) passes the rest here.
Scenario parse_scenario_table(const toml::table& root, const std::string& text, const std::string& fallback_name,
                              const std::string& source);
}  // namespace ggins::truth

namespace ggins::truth::scenario_toml {

[[noreturn]] inline void fail(const std::string& source, const std::string& what) {
  throw std::runtime_error("scenario " + source + ": " + what);
}

// Every key of t must be in allowed (where: the table's dotted name, "" for the root).
inline void check_keys(const toml::table& t, const std::string& where, const std::set<std::string>& allowed,
                       const std::string& source) {
  for (const auto& [k, v] : t) {
    const std::string key(k.str());
    if (!allowed.count(key)) {
      std::string list;
      for (const auto& a : allowed) list += (list.empty() ? "" : ", ") + a;
      const auto line = v.source().begin.line;  // the key's line in the file, when known
      fail(source + (line > 0 ? ":" + std::to_string(line) : ""),
           "unknown key '" + (where.empty() ? key : where + "." + key) + "' (allowed: " + list + ")");
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
