#include "ggins/truth/scenario_schema.hpp"

#include <cstdio>
#include <cstdlib>
#include <sstream>

namespace ggins::truth::sch {

namespace {
std::string at(const toml::node* n) {
  if (!n) return "";
  const auto line = n->source().begin.line;
  return line > 0 ? ":" + std::to_string(line) : "";
}
}  // namespace

void Ctx::fail_at(const toml::node* n, const std::string& key, const std::string& what) const {
  (void)key;
  throw std::runtime_error("scenario " + source + at(n) + ": " + what);
}

void Ctx::fail_key(const toml::table& root, const std::string& key, const std::string& what) const {
  fail_at(detail::node_at(root, key), key, what);
}

std::string value_text(const toml::node& n) {
  if (n.is_string()) return str_text(n.as_string()->get());
  if (n.is_integer()) return std::to_string(n.as_integer()->get());
  if (n.is_floating_point()) {
    const double v = n.as_floating_point()->get();
    if (std::isnan(v)) return "nan";
    if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
    return num_text(v);
  }
  if (n.is_boolean()) return n.as_boolean()->get() ? "true" : "false";
  if (n.is_array()) {
    std::string s = "[";
    const auto& a = *n.as_array();
    for (size_t i = 0; i < a.size() && i < 8; ++i) s += (i ? ", " : "") + value_text(a[i]);
    if (a.size() > 8) s += ", ...";
    return s + "]";
  }
  if (n.is_table()) return "(a table)";
  std::ostringstream os;
  os << "(a " << n.type() << ")";
  return os.str();
}

std::string num_text(double v) {
  if (std::isnan(v)) return "nan";
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  char b[40];
  if (v == std::trunc(v) && std::fabs(v) < 1e9) {
    std::snprintf(b, sizeof b, "%.0f.0", v);
    return b;
  }
  for (int p = 1; p <= 17; ++p) {
    std::snprintf(b, sizeof b, "%.*g", p, v);
    if (std::strtod(b, nullptr) == v) break;
  }
  std::string s(b);
  if (s.find_first_of(".en") == std::string::npos) s += ".0";
  return s;
}

std::string str_text(const std::string& s) {
  std::string o = "\"";
  for (unsigned char ch : s) {
    if (ch == '"' || ch == '\\') {
      o += '\\';
      o += static_cast<char>(ch);
    } else if (ch == '\n') {
      o += "\\n";
    } else if (ch == '\t') {
      o += "\\t";
    } else if (ch < 0x20 || ch == 0x7f) {
      char b[8];
      std::snprintf(b, sizeof b, "\\u%04x", ch);
      o += b;
    } else {
      o += static_cast<char>(ch);
    }
  }
  return o + "\"";
}

std::string Range::text() const {
  auto f = [](double x) {
    char b[40];
    if (x == std::trunc(x) && std::fabs(x) < 1e5) {
      std::snprintf(b, sizeof b, "%.0f", x);
      return std::string(b);
    }
    for (int p = 1; p <= 17; ++p) {
      std::snprintf(b, sizeof b, "%.*g", p, x);
      if (std::strtod(b, nullptr) == x) break;
    }
    std::string s(b);
    for (const char* from : {"e+0", "e+", "e-0"}) {
      const auto i = s.find(from);
      if (i != std::string::npos) s.replace(i, std::string(from).size(), from[1] == '-' ? "e-" : "e");
    }
    return s;
  };
  const bool has_lo = std::isfinite(lo), has_hi = std::isfinite(hi);
  if (!has_lo && !has_hi) return "any finite";
  if (has_lo && !has_hi) return (lo_open ? "> " : ">= ") + f(lo);
  if (!has_lo && has_hi) return (hi_open ? "< " : "<= ") + f(hi);
  return std::string(lo_open ? "(" : "[") + f(lo) + ", " + f(hi) + (hi_open ? ")" : "]");
}

std::string choices_text(const std::vector<std::string>& choices) {
  std::string s;
  for (const auto& c : choices) s += (s.empty() ? "" : ", ") + ("\"" + c + "\"");
  return s;
}

namespace {
std::string with_unit(const Range& r, const std::string& unit) {
  return r.text() + (unit.empty() || unit == "1" ? "" : " " + unit);
}
}  // namespace

double read_num(const toml::node& n, const Ctx& c, const std::string& path, const Range& r, const std::string& unit) {
  auto d = n.value<double>();
  if (!d || n.is_boolean())
    c.fail_at(&n, path, path + " = " + value_text(n) + ": must be a number (allowed: " + with_unit(r, unit) + ")");
  if (!std::isfinite(*d))
    c.fail_at(&n, path, path + " = " + value_text(n) + ": must be finite (allowed: " + with_unit(r, unit) + ")");
  if (!r.ok(*d))
    c.fail_at(&n, path, path + " = " + value_text(n) + ": out of range (allowed: " + with_unit(r, unit) + ")");
  return *d;
}

int64_t read_int(const toml::node& n, const Ctx& c, const std::string& path, const Range& r, const std::string& unit) {
  if (!n.is_integer())
    c.fail_at(&n, path, path + " = " + value_text(n) + ": must be an integer (allowed: " + with_unit(r, unit) + ")");
  const int64_t v = n.as_integer()->get();
  if (!r.ok(static_cast<double>(v)))
    c.fail_at(&n, path, path + " = " + value_text(n) + ": out of range (allowed: " + with_unit(r, unit) + ")");
  return v;
}

bool read_bool(const toml::node& n, const Ctx& c, const std::string& path) {
  if (!n.is_boolean()) c.fail_at(&n, path, path + " = " + value_text(n) + ": must be true or false");
  return n.as_boolean()->get();
}

std::string read_str(const toml::node& n, const Ctx& c, const std::string& path,
                     const std::vector<std::string>& choices) {
  if (!n.is_string())
    c.fail_at(&n, path,
              path + " = " + value_text(n) + ": must be a string" +
                  (choices.empty() ? std::string() : " (allowed: " + choices_text(choices) + ")"));
  const std::string v = n.as_string()->get();
  if (choices.empty()) return v;
  for (const auto& ch : choices)
    if (ch == v) return v;
  c.fail_at(&n, path, path + " = " + value_text(n) + ": unknown value (allowed: " + choices_text(choices) + ")");
}

std::vector<double> read_nums(const toml::node& n, const Ctx& c, const std::string& path, size_t n_min, size_t n_max,
                              const Range& r, const std::string& unit) {
  const toml::array* a = n.as_array();
  const std::string count =
      n_min == n_max ? std::to_string(n_min) : std::to_string(n_min) + ".." + std::to_string(n_max);
  if (!a || a->size() < n_min || a->size() > n_max)
    c.fail_at(&n, path, path + " = " + value_text(n) + ": must be an array of " + count + " numbers (each " +
                            with_unit(r, unit) + ")");
  std::vector<double> v;
  for (size_t i = 0; i < a->size(); ++i) v.push_back(read_num((*a)[i], c, path + "[" + std::to_string(i) + "]", r, unit));
  return v;
}

namespace detail {

std::string allowed_list(const std::set<std::string>& names) {
  std::string list;
  for (const auto& a : names) list += (list.empty() ? "" : ", ") + a;
  return list;
}

const toml::node* node_at(const toml::table& root, const std::string& dotted) {
  const toml::table* t = &root;
  size_t p = 0;
  for (;;) {
    const size_t q = dotted.find('.', p);
    const std::string part = dotted.substr(p, q == std::string::npos ? std::string::npos : q - p);
    const toml::node* n = t->get(part);
    if (!n || q == std::string::npos) return n;
    t = n->as_table();
    if (!t) return nullptr;
    p = q + 1;
  }
}

std::string comment_of(const Row& row) {
  std::string s;
  if (!row.unit.empty() && row.unit != "1") s += row.unit + "; ";
  s += row.range + "; " + row.meaning;
  return s;
}

namespace {
// A node as TOML text, complete (value_text shortens long arrays for messages).
std::string toml_text(const toml::node& n) {
  if (const toml::array* a = n.as_array()) {
    std::string s = "[";
    for (size_t i = 0; i < a->size(); ++i) s += (i ? ", " : "") + toml_text((*a)[i]);
    return s + "]";
  }
  if (const toml::table* t = n.as_table()) {
    std::string s = "{";
    bool first = true;
    for (const auto& [k, v] : *t) {
      s += (first ? "" : ", ") + std::string(k.str()) + " = " + toml_text(v);
      first = false;
    }
    return s + "}";
  }
  return value_text(n);
}
}  // namespace

std::string array_of_tables_text(const std::string& table, const std::string& key, const std::string& inline_value,
                                 const std::string& prefix) {
  const toml::table doc = toml::parse(key + " = " + inline_value);  // the writers' own text: well-formed
  const toml::array* a = doc[key].as_array();
  if (!a) return "";
  const std::string head = prefix + "[[" + (table.empty() ? key : table + "." + key) + "]]\n";
  std::string out;
  for (const auto& e : *a) {
    const toml::table* t = e.as_table();
    if (!t) continue;
    out += "\n" + head;
    for (const auto& [k, v] : *t) out += prefix + std::string(k.str()) + " = " + toml_text(v) + "\n";
  }
  return out;
}

std::string md_escape(const std::string& s) {
  std::string o;
  for (char ch : s) {
    if (ch == '|') o += "\\|";
    else if (ch == '\n') o += ' ';
    else o += ch;
  }
  return o;
}

}  // namespace detail

}  // namespace ggins::truth::sch
