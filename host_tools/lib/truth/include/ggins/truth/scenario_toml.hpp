// The scenario parser's entry for a table already parsed, and the key check of a table a
// tool reads beside the scenario (ggins covariance's [initial]); the scenario's own tables
// are read through the schema (scenario_schema.hpp). An error throws
// std::runtime_error("scenario <source>: <what>") naming the offending key as <where>.<key>.
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
                              const std::string& source, const ScenarioAdjust& adjust = {});
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

}  // namespace ggins::truth::scenario_toml
