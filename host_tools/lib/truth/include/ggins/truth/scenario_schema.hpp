// The scenario schema: one row per scenario key (type, unit, default, allowed range,
// meaning), bound to the C++ struct member it fills. The 2-D (truth/scenario.cpp) and
// 3-D (truth3d/scenario3d.cpp) parsers read through it, scenario_to_toml /
// scenario3_to_toml write the effective scenario from it, `ggins scenario-reference`
// writes docs/scenario-reference.md from it.
//
// A table is a Table<T> over the struct T it fills; a section binds a table to the
// scenario (the root struct R) by a member pointer or a projection:
//
//   secs.push_back(sch::section<Scenario3>(aid_ukf_table(), &Scenario3::aid_ukf));
//
// Defaults are not written down twice: a key's default is what it writes from a
// default-constructed R (the struct initialisers). A value is checked for type,
// finiteness and range when read; an error names file:line, the key, the value and
// the allowed range:
//
//   scenario my.toml:12: time.rate_hz = -5: out of range (allowed: > 0 and <= 1e6, Hz)
#pragma once

#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <memory>
#include <optional>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>
#include <toml++/toml.h>

namespace ggins::truth::sch {

// A scenario file's TOML text parsed (the nodes keep their lines in the user's file); a syntax
// error names it as "scenario <source>:<line>: <what> (line <line>, column <column>)".
inline toml::table parse_toml(const std::string& text, const std::string& source) {
  try {
    return toml::parse(text, source);
  } catch (const toml::parse_error& e) {
    std::ostringstream os;
    os << "scenario " << source << ":" << e.source().begin.line << ": " << e.description() << " (line "
       << e.source().begin.line << ", column " << e.source().begin.column << ")";
    throw std::runtime_error(os.str());
  }
}

// ---- errors ---------------------------------------------------------------------

// Where a scenario is read from, for the messages ("scenario <source>:<line>: ...").
struct Ctx {
  std::string source;
  [[noreturn]] void fail(const std::string& what) const { throw std::runtime_error("scenario " + source + ": " + what); }
  // The error at node n (its line) about key path `key`.
  [[noreturn]] void fail_at(const toml::node* n, const std::string& key, const std::string& what) const;
  // Same, with the node found by its dotted path in root (no line if absent).
  [[noreturn]] void fail_key(const toml::table& root, const std::string& key, const std::string& what) const;
};

// A TOML node's value as written (for messages): 1.5, "text", [1, 2], {...}.
std::string value_text(const toml::node& n);

// ---- ranges ---------------------------------------------------------------------

struct Range {
  double lo = -std::numeric_limits<double>::infinity();
  double hi = std::numeric_limits<double>::infinity();
  bool lo_open = false, hi_open = false;
  bool ok(double v) const {
    return (lo_open ? v > lo : v >= lo) && (hi_open ? v < hi : v <= hi);
  }
  std::string text() const;  // "any", ">= 0", "> 0 and <= 1e6", "[0, 1)"
};
inline Range any() { return {}; }
inline Range ge(double a) { return {a, std::numeric_limits<double>::infinity(), false, false}; }
inline Range gt(double a) { return {a, std::numeric_limits<double>::infinity(), true, false}; }
inline Range in(double a, double b) { return {a, b, false, false}; }            // [a, b]
inline Range in_ropen(double a, double b) { return {a, b, false, true}; }       // [a, b)
inline Range in_lopen(double a, double b) { return {a, b, true, false}; }       // (a, b]
inline Range prob() { return in_ropen(0.0, 1.0); }                              // [0, 1)

// ---- value writing ----------------------------------------------------------------

std::string num_text(double v);           // shortest text that reads back to v, TOML float
std::string str_text(const std::string&);  // TOML basic string

// ---- keys and tables ------------------------------------------------------------

// One key of a table over struct T.
template <class T>
struct Key {
  std::string name;     // key inside its table
  std::string type;     // "number", "integer", "bool", "string", "array of 3 numbers", ...
  std::string unit;     // SI unit ("m/s", "m/s^2", "1" dimensionless, "" none)
  std::string range;    // allowed values, as text
  std::string meaning;  // one sentence
  std::string derived;  // the default when the value is "unset": what it is derived from
  std::string dflt_doc;  // the default as documented, when not the written value (e.g. "true when present")
  // read the node into t (the key is present); path = dotted key for messages
  std::function<void(T&, const toml::node&, const Ctx&, const std::string& path)> read;
  // the value as TOML text; nullopt: unset (derived), written as a comment
  std::function<std::optional<std::string>(const T&)> write;
  // whether the key belongs in the table for this value of t (e.g. route keys only for
  // a route); keys that do not are written commented out and refused when read
  std::function<bool(const T&)> applies;
  std::string only_when;  // when it applies, as text
};

// Readers of one value from a node: throw through ctx naming path, the value and range.
double read_num(const toml::node& n, const Ctx& c, const std::string& path, const Range& r, const std::string& unit);
int64_t read_int(const toml::node& n, const Ctx& c, const std::string& path, const Range& r, const std::string& unit);
bool read_bool(const toml::node& n, const Ctx& c, const std::string& path);
std::string read_str(const toml::node& n, const Ctx& c, const std::string& path, const std::vector<std::string>& choices);
// An array of n_min..n_max numbers, each in r.
std::vector<double> read_nums(const toml::node& n, const Ctx& c, const std::string& path, size_t n_min, size_t n_max,
                              const Range& r, const std::string& unit);

std::string choices_text(const std::vector<std::string>& choices);

template <class T>
Key<T> mk(std::string name, std::string type, std::string unit, std::string range, std::string meaning,
          std::string derived) {
  Key<T> k;
  k.name = std::move(name);
  k.type = std::move(type);
  k.unit = std::move(unit);
  k.range = std::move(range);
  k.meaning = std::move(meaning);
  k.derived = std::move(derived);
  return k;
}

template <class T>
class Table {
 public:
  Table(std::string name, std::string meaning) : name_(std::move(name)), meaning_(std::move(meaning)) {}

  // number in range r; `derived`: when the member holds `sentinel` (NaN matches NaN) the
  // key is unset and its value derived as the text says
  Table& num(const std::string& k, double T::*m, const std::string& unit, Range r, const std::string& meaning,
             std::optional<double> sentinel = std::nullopt, const std::string& derived = "") {
    Key<T> key = mk<T>(k, "number", unit, r.text(), meaning, derived);
    key.read = [m, r, unit](T& t, const toml::node& n, const Ctx& c, const std::string& p) {
      t.*m = read_num(n, c, p, r, unit);
    };
    key.write = [m, sentinel](const T& t) -> std::optional<std::string> {
      if (sentinel && (t.*m == *sentinel || (std::isnan(*sentinel) && std::isnan(t.*m)))) return std::nullopt;
      return num_text(t.*m);
    };
    keys_.push_back(std::move(key));
    return *this;
  }
  // integer (int64_t or int member) in range r
  template <class I>
  Table& integer(const std::string& k, I T::*m, const std::string& unit, Range r, const std::string& meaning,
                 bool even = false) {
    Key<T> key = mk<T>(k, "integer", unit, r.text() + (even ? ", even" : ""), meaning, "");
    key.read = [m, r, unit, even](T& t, const toml::node& n, const Ctx& c, const std::string& p) {
      const int64_t v = read_int(n, c, p, r, unit);
      if (even && v % 2 != 0) c.fail_at(&n, p, p + " = " + value_text(n) + ": must be even (allowed: " + r.text() + ", even)");
      t.*m = static_cast<I>(v);
    };
    key.write = [m](const T& t) -> std::optional<std::string> { return std::to_string(t.*m); };
    keys_.push_back(std::move(key));
    return *this;
  }
  // a random-number seed: integer >= 0
  Table& seed(const std::string& k, uint64_t T::*m, const std::string& meaning) {
    const Range r = ge(0);
    Key<T> key = mk<T>(k, "integer", "", ">= 0", meaning, "");
    key.read = [m, r](T& t, const toml::node& n, const Ctx& c, const std::string& p) {
      t.*m = static_cast<uint64_t>(read_int(n, c, p, r, ""));
    };
    key.write = [m](const T& t) -> std::optional<std::string> { return std::to_string(t.*m); };
    keys_.push_back(std::move(key));
    return *this;
  }
  Table& boolean(const std::string& k, bool T::*m, const std::string& meaning) {
    Key<T> key = mk<T>(k, "bool", "", "true, false", meaning, "");
    key.read = [m](T& t, const toml::node& n, const Ctx& c, const std::string& p) { t.*m = read_bool(n, c, p); };
    key.write = [m](const T& t) -> std::optional<std::string> { return std::string(t.*m ? "true" : "false"); };
    keys_.push_back(std::move(key));
    return *this;
  }
  // a bool stored as an int: -1 unset (derived), 0 false, 1 true
  Table& tristate(const std::string& k, int T::*m, const std::string& meaning, const std::string& derived) {
    Key<T> key = mk<T>(k, "bool", "", "true, false", meaning, derived);
    key.read = [m](T& t, const toml::node& n, const Ctx& c, const std::string& p) { t.*m = read_bool(n, c, p) ? 1 : 0; };
    key.write = [m](const T& t) -> std::optional<std::string> {
      if (t.*m < 0) return std::nullopt;
      return std::string(t.*m ? "true" : "false");
    };
    keys_.push_back(std::move(key));
    return *this;
  }
  // a string; choices empty: any string
  Table& str(const std::string& k, std::string T::*m, std::vector<std::string> choices, const std::string& meaning,
             const std::string& derived = "") {
    Key<T> key = mk<T>(k, "string", "", choices.empty() ? "any" : choices_text(choices), meaning, derived);
    key.read = [m, choices](T& t, const toml::node& n, const Ctx& c, const std::string& p) {
      t.*m = read_str(n, c, p, choices);
    };
    const bool has_derived = !derived.empty();
    key.write = [m, has_derived](const T& t) -> std::optional<std::string> {
      if (has_derived && (t.*m).empty()) return std::nullopt;
      return str_text(t.*m);
    };
    keys_.push_back(std::move(key));
    return *this;
  }
  // a fixed-size array of numbers, each in r
  template <size_t N>
  Table& vec(const std::string& k, std::array<double, N> T::*m, const std::string& unit, Range r,
             const std::string& meaning) {
    Key<T> key = mk<T>(k, "array of " + std::to_string(N) + " numbers", unit, "each " + r.text(), meaning, "");
    key.read = [m, r, unit](T& t, const toml::node& n, const Ctx& c, const std::string& p) {
      const std::vector<double> v = read_nums(n, c, p, N, N, r, unit);
      for (size_t i = 0; i < N; ++i) (t.*m)[i] = v[i];
    };
    key.write = [m](const T& t) -> std::optional<std::string> {
      std::string s = "[";
      for (size_t i = 0; i < N; ++i) s += (i ? ", " : "") + num_text((t.*m)[i]);
      return s + "]";
    };
    keys_.push_back(std::move(key));
    return *this;
  }
  // anything else: the caller fills the Key (read and write)
  Table& custom(Key<T> key) {
    keys_.push_back(std::move(key));
    return *this;
  }
  // after the last key added is read, f(t) (e.g. to note that it was given)
  Table& then(std::function<void(T&)> f) {
    auto rd = keys_.back().read;
    keys_.back().read = [rd, f](T& t, const toml::node& n, const Ctx& c, const std::string& p) {
      rd(t, n, c, p);
      f(t);
    };
    return *this;
  }
  // the last key added is derived from other keys unless the file gives it: reading it sets
  // t.*given, and it is written only when given, so that a printed scenario whose inputs are
  // then edited derives it again (derived_doc: how, for the reference)
  Table& derived_unless_given(bool T::*given, const std::string& derived_doc) {
    Key<T>& k = keys_.back();
    auto rd = k.read;
    auto wr = k.write;
    k.read = [rd, given](T& t, const toml::node& n, const Ctx& c, const std::string& p) {
      rd(t, n, c, p);
      t.*given = true;
    };
    k.write = [wr, given](const T& t) -> std::optional<std::string> {
      if (!(t.*given)) return std::nullopt;
      return wr(t);
    };
    k.dflt_doc = derived_doc;
    return *this;
  }
  // the last key added applies only when pred(t); `why` says when (in the error)
  Table& only_if(std::function<bool(const T&)> pred, const std::string& why) {
    keys_.back().applies = std::move(pred);
    keys_.back().only_when = why;
    return *this;
  }
  // every key of table u (over a member U of T, reached by proj), as keys of this table
  template <class U>
  Table& lift(const Table<U>& u, std::function<U&(T&)> proj) {
    for (const auto& k : u.keys()) {
      Key<T> l = mk<T>(k.name, k.type, k.unit, k.range, k.meaning, k.derived);
      l.dflt_doc = k.dflt_doc;
      l.only_when = k.only_when;
      auto rd = k.read;
      auto wr = k.write;
      l.read = [rd, proj](T& t, const toml::node& n, const Ctx& c, const std::string& p) { rd(proj(t), n, c, p); };
      l.write = [wr, proj](const T& t) { return wr(proj(const_cast<T&>(t))); };
      if (k.applies) {
        auto ap = k.applies;
        l.applies = [ap, proj](const T& t) { return ap(proj(const_cast<T&>(t))); };
      }
      keys_.push_back(std::move(l));
    }
    return *this;
  }
  // called when the table is present in the file, before its keys are read
  Table& on_present(std::function<void(T&)> f) {
    on_present_ = std::move(f);
    return *this;
  }
  // text of the default when the table is present (for the reference), e.g. of enable
  Table& default_doc(const std::string& key, const std::string& text) {
    for (auto& k : keys_)
      if (k.name == key) k.dflt_doc = text;
    return *this;
  }

  const std::string& name() const { return name_; }
  const std::string& meaning() const { return meaning_; }
  const std::vector<Key<T>>& keys() const { return keys_; }
  const std::function<void(T&)>& present_hook() const { return on_present_; }

 private:
  std::string name_, meaning_;
  std::vector<Key<T>> keys_;
  std::function<void(T&)> on_present_;
};

// ---- sections: tables bound to the scenario ---------------------------------------

// One documented row (for the reference page and the template).
struct Row {
  std::string key, type, unit, dflt, range, meaning;
  bool derived_default = false;  // the default is derived (commented out in a template)
};

// A table bound to the root struct R (the scenario).
template <class R>
struct Section {
  std::string name;     // dotted table name ("" = the root's own keys)
  std::string meaning;  // what the table describes
  bool delegated = false;        // its reader checks its own keys (arrays of tables inside)
  std::vector<Row> rows;         // documentation, defaults from R{}
  std::set<std::string> key_names;
  // read the present table into r (keys checked, on_present applied)
  std::function<void(R&, const toml::table&, const Ctx&)> read;
  // key = value lines of r; a key unset or not applying is written as "# key = ..."
  std::function<std::vector<std::pair<std::string, std::optional<std::string>>>(const R&)> write;
  // whether r's value needs the table (false: commented out in a template)
  std::function<bool(const R&)> present;
  // the table's presence itself means something (the effective scenario leaves it out
  // when !present(r)); otherwise every key of it is written and its presence is inert
  bool presence_matters = false;
};

// present(r): whether r's table is written (default: always); on_read(r): called when
// the table is in the file, before its keys are read (defaults that depend on other
// sections).
template <class R, class T>
Section<R> section(const Table<T>& tbl, std::function<T&(R&)> proj,
                   std::function<bool(const R&)> present = nullptr, std::function<void(R&)> on_read = nullptr) {
  Section<R> s;
  s.name = tbl.name();
  s.meaning = tbl.meaning();
  const R r0{};
  const T& t0 = proj(const_cast<R&>(r0));
  for (const auto& k : tbl.keys()) {
    s.key_names.insert(k.name);
    std::string d = k.dflt_doc;
    bool derived = !d.empty();
    if (d.empty() && k.write) {
      auto w = k.write(t0);
      d = w ? *w : k.derived;
      derived = !w;
    }
    s.rows.push_back({k.name, k.type, k.unit, d, k.range,
                      k.meaning + (k.only_when.empty() ? "" : " (a key " + k.only_when + ")"), derived});
  }
  s.read = [tbl, proj, on_read](R& r, const toml::table& t, const Ctx& c) {
    if (on_read) on_read(r);
    T& x = proj(r);
    if (tbl.present_hook()) tbl.present_hook()(x);
    for (const auto& k : tbl.keys()) {
      const toml::node* n = t.get(k.name);
      if (!n) continue;
      const std::string path = tbl.name().empty() ? k.name : tbl.name() + "." + k.name;
      if (k.applies && !k.applies(x))
        c.fail_at(n, path, path + " is a key " + k.only_when);
      k.read(x, *n, c, path);
    }
  };
  s.write = [tbl, proj](const R& r) {
    std::vector<std::pair<std::string, std::optional<std::string>>> out;
    const T& x = proj(const_cast<R&>(r));
    for (const auto& k : tbl.keys()) {
      if (k.applies && !k.applies(x)) {
        out.emplace_back(k.name, std::nullopt);
        continue;
      }
      out.emplace_back(k.name, k.write ? k.write(x) : std::nullopt);
    }
    return out;
  };
  s.present = present ? present : [](const R&) { return true; };
  return s;
}

template <class R, class T>
Section<R> section(const Table<T>& tbl, T R::*m, std::function<bool(const R&)> present = nullptr,
                   std::function<void(R&)> on_read = nullptr) {
  return section<R, T>(tbl, std::function<T&(R&)>([m](R& r) -> T& { return r.*m; }), std::move(present),
                       std::move(on_read));
}

// The root's own keys (and tables whose struct is the root itself: [time], [platform]).
template <class R>
Section<R> section(const Table<R>& tbl, std::function<bool(const R&)> present = nullptr) {
  return section<R, R>(tbl, std::function<R&(R&)>([](R& r) -> R& { return r; }), std::move(present));
}

// A section read by its own parser (arrays of tables inside): rows documented by hand.
template <class R>
Section<R> delegated_section(std::string name, std::string meaning, std::vector<Row> rows,
                             std::function<void(R&, const toml::table&, const Ctx&)> read,
                             std::function<std::vector<std::pair<std::string, std::optional<std::string>>>(const R&)> write,
                             std::function<bool(const R&)> present) {
  Section<R> s;
  s.name = std::move(name);
  s.meaning = std::move(meaning);
  s.delegated = true;
  s.rows = std::move(rows);
  for (const auto& r : s.rows)
    if (r.key.find('.') == std::string::npos) s.key_names.insert(r.key);
  s.read = std::move(read);
  s.write = std::move(write);
  s.present = std::move(present);
  return s;
}

// The schema of a scenario type: its sections in reading order.
template <class R>
struct Schema {
  std::string title;
  std::vector<Section<R>> secs;

  const Section<R>* find(const std::string& name) const {
    for (const auto& s : secs)
      if (s.name == name) return &s;
    return nullptr;
  }
  // Read every section present in root (unknown keys/sections refused). Keys of a table
  // are its own keys and the names of its subsections.
  void read(R& r, const toml::table& root, const Ctx& c) const;
  // The scenario as TOML: every section, every key (effective values); with
  // template_comments, each key followed by "# unit; range; meaning".
  std::string to_toml(const R& r, bool template_comments) const;
  // Markdown reference: one table per section.
  std::string reference_markdown() const;
};

// --- implementation of the templates (header: instantiated for Scenario and Scenario3) ---

namespace detail {
std::string allowed_list(const std::set<std::string>& names);
const toml::node* node_at(const toml::table& root, const std::string& dotted);
std::string comment_of(const Row& row);
// An array of tables written by a key's writer as an inline array of inline tables
// ("[{a = 1}, {a = 2}]") as TOML arrays of tables: one "[[table.key]]" header per entry,
// its keys below (each line prefixed with `prefix`, "# " for a commented-out table).
std::string array_of_tables_text(const std::string& table, const std::string& key, const std::string& inline_value,
                                 const std::string& prefix);
std::string md_escape(const std::string& s);
}  // namespace detail

template <class R>
void Schema<R>::read(R& r, const toml::table& root, const Ctx& c) const {
  // allowed keys per table: own keys + direct subsection names
  auto allowed_of = [&](const std::string& tname) {
    std::set<std::string> a;
    if (const auto* s = find(tname)) a = s->key_names;
    for (const auto& s : secs) {
      if (s.name.empty() || s.name == tname) continue;
      const auto dot = s.name.rfind('.');
      const std::string parent = dot == std::string::npos ? "" : s.name.substr(0, dot);
      if (parent == tname) a.insert(dot == std::string::npos ? s.name : s.name.substr(dot + 1));
    }
    return a;
  };
  // check every present table's keys (tables reachable through sections only)
  std::function<void(const toml::table&, const std::string&)> check = [&](const toml::table& t, const std::string& tn) {
    const std::set<std::string> a = allowed_of(tn);
    const Section<R>* own = find(tn);
    if (own && own->delegated) return;  // checked by its reader
    for (const auto& [k, v] : t) {
      const std::string key(k.str());
      const std::string path = tn.empty() ? key : tn + "." + key;
      if (!a.count(key))
        c.fail_at(&v, path, "unknown key '" + path + "' (allowed: " + detail::allowed_list(a) + ")");
      const Section<R>* sub = find(path);
      if (sub && !(own && own->key_names.count(key))) {
        if (!v.is_table()) c.fail_at(&v, path, "'" + path + "' must be a table ([" + path + "])");
        check(*v.as_table(), path);
      }
    }
  };
  check(root, "");
  for (const auto& s : secs) {
    const toml::node* n = s.name.empty() ? &root : detail::node_at(root, s.name);
    if (!n) continue;
    s.read(r, *n->as_table(), c);
  }
}

template <class R>
std::string Schema<R>::to_toml(const R& r, bool tc) const {
  std::string out;
  for (const auto& s : secs) {
    const bool present = s.present(r);
    if (!present && !tc && s.presence_matters) continue;
    const std::string cm = present || !tc ? "" : "# ";
    if (!s.name.empty()) {
      out += "\n";
      if (tc) out += "# " + s.meaning + "\n";
      out += cm + "[" + s.name + "]\n";
    }
    const auto kv = s.write(r);
    std::string tables;  // arrays of tables: after the table's own keys (TOML puts keys below a [[header]] in it)
    for (size_t i = 0; i < kv.size(); ++i) {
      Row row;
      for (const auto& w : s.rows)
        if (w.key == kv[i].first) row = w;
      if (row.type == "array of tables") {
        if (tc) tables += "# " + kv[i].first + ": " + detail::comment_of(row) + "\n";
        if (kv[i].second) tables += detail::array_of_tables_text(s.name, kv[i].first, *kv[i].second, cm);
        continue;
      }
      std::string line;
      if (kv[i].second) {
        line = (tc && row.derived_default ? "# " : cm) + kv[i].first + " = " + *kv[i].second;
      } else {
        if (!tc) continue;
        line = "# " + kv[i].first + " = " + (row.dflt.empty() ? "..." : "(" + row.dflt + ")");
      }
      if (tc) {
        if (line.size() < 40) line.resize(40, ' ');
        line += "  # " + detail::comment_of(row);
      }
      out += line + "\n";
    }
    out += tables;
  }
  return out;
}

template <class R>
std::string Schema<R>::reference_markdown() const {
  std::string out;
  for (const auto& s : secs) {
    out += "\n### " + (s.name.empty() ? std::string("top level") : "[" + s.name + "]") +
           "\n\n" + s.meaning + "\n\n";
    out += "| key | type | unit | default | allowed | meaning |\n|---|---|---|---|---|---|\n";
    for (const auto& row : s.rows)
      out += "| `" + row.key + "` | " + row.type + " | " + detail::md_escape(row.unit.empty() ? "-" : row.unit) + " | " +
             detail::md_escape(row.dflt.empty() ? "-" : row.dflt) + " | " + detail::md_escape(row.range) + " | " +
             detail::md_escape(row.meaning) + " |\n";
  }
  return out;
}

}  // namespace ggins::truth::sch
